//! Controller input shared by the controller tools ([`crate::interact::CsgTool`],
//! [`crate::interact::BrushTool`]): one hand's buttons and poses per frame, press
//! edges, and stick flicks (undo / redo, cycling a list).

use super::pick::Ray;
use super::ToolContext;
use crate::interact::input::{Hand, Pose};

/// One controller's input this frame (all released when absent).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) struct CtlInput {
    /// Grip pose and buttons usable this frame.
    pub tracked: bool,
    pub grip: Option<Pose>,
    pub ray: Option<Ray>,
    /// Trigger value in `[0, 1]`.
    pub select: f64,
    pub grab: bool,
    pub primary: bool,
    pub secondary: bool,
    pub menu: bool,
    pub stick: [f64; 2],
    /// The sanitizer flagged a jump faster than a hand can move.
    pub teleported: bool,
}

impl CtlInput {
    /// `hand`'s controller in `cx`'s frame.
    pub fn read(cx: &ToolContext, hand: Hand) -> CtlInput {
        let Some(c) = cx.frame.controller(hand) else {
            return CtlInput::default();
        };
        let b = c.buttons.unwrap_or_default();
        CtlInput {
            tracked: c.grip.is_some() && c.buttons.is_some(),
            grip: c.grip,
            ray: c.aim.map(|a| Ray {
                origin: a.position,
                dir: a.forward(),
            }),
            select: b.select.clamp(0.0, 1.0),
            grab: b.grab > 0.5,
            primary: b.primary,
            secondary: b.secondary,
            menu: b.menu,
            stick: b.stick,
            teleported: c.teleported,
        }
    }
}

/// A stick axis flicked past 0.8 fires once, and re-arms below 0.3.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Flick {
    armed: [[bool; 2]; 2],
}

impl Default for Flick {
    fn default() -> Self {
        Self {
            armed: [[true; 2]; 2],
        }
    }
}

impl Flick {
    /// The sign (`-1` or `1`) of a flick of `hand`'s stick `axis` (0 = x,
    /// 1 = y) this frame.
    pub fn fired(&mut self, hand: Hand, axis: usize, input: &CtlInput) -> Option<i32> {
        let v = input.stick[axis];
        let armed = &mut self.armed[hand.index()][axis];
        if v.abs() < 0.3 {
            *armed = true;
        }
        if *armed && v.abs() > 0.8 {
            *armed = false;
            return Some(if v < 0.0 { -1 } else { 1 });
        }
        None
    }
}

/// Steps `index` by `dir` through a list of `len` items, wrapping.
pub(crate) fn cycle(index: usize, dir: i32, len: usize) -> usize {
    if len == 0 {
        return 0;
    }
    (index as i64 + dir as i64).rem_euclid(len as i64) as usize
}

/// Keeps the previous input of hands only while tracked, so a controller
/// that comes back with a button held does not fire a fresh press.
pub(crate) fn remember(prev: &mut [CtlInput; 2], now: &[CtlInput; 2]) {
    for (p, n) in prev.iter_mut().zip(now) {
        if n.tracked {
            *p = *n;
        }
    }
}
