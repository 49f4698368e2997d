//! The USD layer's integration tests, one module per subject, in one test
//! binary (as the core's `tests/suite`, which says why: each file under
//! `tests/` is a crate of its own, compiled and linked against everything
//! it uses; one crate compiles and links once).
//!
//! A subject runs alone with its module as the filter:
//! `cargo test -p shapewright-usd --test suite roundtrip::`. The crash test
//! starts this binary again as its killed writer, naming that test by its
//! module path (`crash::crash_child_writer`).

mod common;

mod abuse;
mod crash;
mod fuzz;
mod parametric;
mod roundtrip;
