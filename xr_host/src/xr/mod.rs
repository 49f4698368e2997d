//! The OpenXR host: instance and capabilities ([`instance`]), actions
//! from the core's binding data and input read into the core's own frame
//! type ([`actions`]), the floor-level base space ([`spaces`]), the session
//! lifecycle as types ([`lifecycle`], [`events`]), the one frame loop both
//! modes run ([`frame_loop`]) with its two graphics halves ([`headless`],
//! [`headset`]), paced runs through a real runtime ([`pace`]) and what
//! differs by OS ([`platform`]). Unsafe
//! OpenXR and Vulkan calls live in `crate::gfx`.
//!
//! Imports run one way: `xr` uses `gfx` (the scene it draws); the
//! interaction step (`crate::interaction`) uses `xr` (it is a
//! [`FrameSink`]); `xr` never uses the interaction step.

pub mod actions;
pub mod events;
pub mod frame_loop;
pub mod headless;
pub mod headset;
pub mod input;
pub mod instance;
pub mod lifecycle;
pub mod pace;
pub mod platform;
pub mod spaces;

pub use headless::run_headless;
pub use headset::run_headset;
pub use input::{CollectSink, FrameSink, Haptic, LifecycleEvent, Notice};
pub use instance::{create_instance, InstanceCaps, RuntimeInfo};
pub use spaces::SpaceReport;

mod error;
mod run;

pub use error::XrHostError;
pub(crate) use error::{classify, is_loss, Failure};
pub use run::{quantile, RunConfig, RunReport};
