//! `run --headless`: an `XR_MND_headless` session, input only; the
//! graphics half of the one frame loop ([`super::frame_loop`]).
//!
//! It never calls xrWaitFrame/xrBeginFrame (a headless runtime may refuse
//! them); it paces itself with a sleep of [`RunConfig::frame_period`] and
//! takes the time from `xrConvertTimespecTimeToTimeKHR`.

use std::time::Instant;

use openxr as xr;

use super::actions::SessionInput;
use super::frame_loop::{self, sleep_until, FrameTime, Graphics, Overlay, TickError};
use super::input::FrameSink;
use super::instance::InstanceCaps;
use super::{RunConfig, RunReport, XrHostError};
use crate::gfx::xr_bridge::create_headless_session;

/// No graphics: a clock.
pub struct Headless {
    next: Option<Instant>,
    ticks: u64,
}

impl Graphics for Headless {
    type Api = xr::Headless;
    const HEADLESS: bool = true;

    fn instance_created(&mut self, _caps: &InstanceCaps) -> Result<(), XrHostError> {
        Ok(())
    }

    fn create_session(&mut self, caps: &InstanceCaps) -> xr::Result<xr::Session<xr::Headless>> {
        create_headless_session(&caps.instance, caps.system)
    }

    fn session_created(
        &mut self,
        _caps: &InstanceCaps,
        _session: &xr::Session<xr::Headless>,
    ) -> Result<(), TickError> {
        Ok(())
    }

    fn wait_frame(&mut self, caps: &InstanceCaps, cfg: &RunConfig) -> Result<FrameTime, TickError> {
        let next = self.next.get_or_insert_with(Instant::now);
        sleep_until(next, cfg.frame_period);
        let time = caps
            .instance
            .now()
            .map_err(|r| TickError::Xr("xrConvertTimespecTimeToTimeKHR", r))?;
        Ok(FrameTime {
            time,
            should_render: false,
        })
    }

    fn end_frame(
        &mut self,
        _session: &xr::Session<xr::Headless>,
        _input: &SessionInput,
        _ft: FrameTime,
        _sink: &dyn FrameSink,
        _overlay: &Overlay<'_>,
    ) -> Result<(), TickError> {
        self.ticks += 1;
        Ok(())
    }

    fn frames_submitted(&self) -> u64 {
        self.ticks
    }

    fn idle(&mut self, cfg: &RunConfig) {
        let next = self.next.get_or_insert_with(Instant::now);
        sleep_until(next, cfg.frame_period);
    }

    fn session_ended(&mut self) {}

    fn instance_ended(&mut self) {}
}

/// Runs the headless loop (see [`frame_loop::run`]).
pub fn run_headless(cfg: &RunConfig, sink: &mut dyn FrameSink) -> Result<RunReport, XrHostError> {
    let mut gfx = Headless {
        next: None,
        ticks: 0,
    };
    frame_loop::run(cfg, &mut gfx, sink)
}
