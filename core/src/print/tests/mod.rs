//! Tests of the print path's parts that need its private items.

mod progress;
mod scale;
