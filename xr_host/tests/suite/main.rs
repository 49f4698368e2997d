//! The headset host's integration tests that compute (the command line,
//! crash-safe writers, replays, rendering on lavapipe), one module per
//! subject, in one test binary: as the core's `tests/suite`, which says
//! why, each file under `tests/` is a crate of its own, and each of these
//! links the whole host.
//!
//! The tests that mostly wait (`monado`, `testrt`, `shared_session`: a
//! runtime's frames, a server's timeouts) stay binaries of their own, so
//! `scripts/test_lanes.py` runs them beside this one. A subject runs alone
//! with its module as the filter:
//! `cargo test -p shapewright-xr --test suite render::`. The crash test
//! starts this binary again as its killed writer, naming that test by its
//! module path (`crash_writers::crash_child_writer`).

mod crash_cli;
mod crash_writers;
mod headset_view;
mod render;
mod replay;
mod sdf_cache;
