//! The random edit sequences of the GC property tests
//! (`gc_structure_props`): the edits, the checks of relations and of
//! each op's effect, and the union's topology.

// Each test binary uses a subset.
#![allow(dead_code)]

pub mod checks;
pub mod edits;
pub mod topology;
