//! Unit tests of the assembly module (op-level tests are in
//! core/tests/gc_assembly.rs).
