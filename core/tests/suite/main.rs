//! The core's integration tests, one module per subject, in one test
//! binary.
//!
//! Why one binary: each file under `tests/` is a crate of its own, compiled
//! and linked against the whole core and its dependencies. Twenty-two such
//! crates cost a cold CI run most of the time of its test build, the
//! critical path of the run; one crate compiles the shared helpers
//! (`common`, `gc_props`) once and links once. Its tests run on the test
//! harness's threads as they did in their own binaries; the tests that
//! measure the process's CPU time are the other binary, `timed`, where
//! they run one at a time.
//!
//! A subject runs alone with its module as the filter:
//! `cargo test -p shapewright --test suite print_props::`. Property-test
//! regressions are in `tests/proptest-regressions/` (proptest's layout
//! for a test crate with a `main.rs`).

#[path = "../common/mod.rs"]
mod common;
mod gc_props;

mod abuse_budgets;
mod fixture_hashes;
mod gc_assembly;
mod gc_junctions;
mod gc_ops;
mod gc_proptest;
mod gc_structure_props;
mod mesh_io_fuzz;
mod object_ops;
mod op_schema;
mod oplog;
mod oplog_props;
mod print_cases;
mod print_props;
mod print_setup;
mod render_assets;
mod sculpt_mirror_props;
mod sdf_export;
mod sdf_reuse;
mod sketch_gc;
mod styling_example;
mod union_cache;
