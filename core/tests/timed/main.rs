//! The core's tests that measure time: the budgets estimate an op's time
//! right (a run at the limit finishes within it) and refuse what is over
//! it at once.
//!
//! They measure this process's CPU time (`common::timed`), so they are a
//! binary apart from the other integration tests (`suite`), and each takes
//! [`serial`] for its whole run: one at a time, with nothing else of this
//! binary computing beside it.

#[path = "../common/mod.rs"]
mod common;

mod gc_time;
mod sculpt_time;
mod sdf_budget;
mod styling_time;

use std::sync::{Mutex, MutexGuard};

/// Held by every timing test for its whole run (CPU time is the
/// process's). A test that failed while holding it does not fail the
/// others.
pub fn serial() -> MutexGuard<'static, ()> {
    static SERIAL: Mutex<()> = Mutex::new(());
    SERIAL.lock().unwrap_or_else(|e| e.into_inner())
}
