//! The base space: floor level, centred on the user.
//!
//! Tools and the model placement ([`shapewright::interact::ModelPlacement`])
//! work in floor-level coordinates (+Y up, the floor at y = 0, the user
//! near the origin looking down -Z). Real runtimes put LOCAL's origin at
//! the head's first pose, eye height (issue 16: objects landed 1.5 m too
//! low), so the base space is chosen, in order:
//!
//! 1. `LOCAL_FLOOR` (XR_EXT_local_floor, core in OpenXR 1.1): exactly this.
//! 2. LOCAL lowered by the height of its origin above STAGE's floor,
//!    measured once when both locate (the extension's own emulation
//!    recipe): LOCAL_FLOOR by another road. STAGE itself is not the base,
//!    since its origin is the play area's centre, wherever the user stands.
//!    A runtime that offers STAGE but cannot locate LOCAL in it within
//!    [`MEASURE_PATIENCE_S`] of display time or [`MEASURE_PATIENCE_FRAMES`]
//!    frames, whichever comes first (tracking lost at start, a play area
//!    never set up, a clock that only moves with input) gets the fallback
//!    below rather than a session without input.
//! 3. LOCAL lowered by an assumed standing eye height
//!    ([`ASSUMED_EYE_HEIGHT`]), said plainly in the log and the report.
//!
//! Either way the model sits at the same place relative to the user, and
//! the report says which space was used and the offset.

use openxr as xr;
use serde::{Deserialize, Serialize};

/// Eye height assumed when nothing measures it (metres).
pub const ASSUMED_EYE_HEIGHT: f32 = 1.6;

/// How long (runtime display time, seconds) the host tries to measure
/// LOCAL in STAGE before it falls back to [`ASSUMED_EYE_HEIGHT`].
pub const MEASURE_PATIENCE_S: f64 = 2.0;

/// How many frames the host tries to measure LOCAL in STAGE before it
/// falls back (2 s at 90 Hz).
pub const MEASURE_PATIENCE_FRAMES: u32 = 180;

/// Which base space a session uses.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum BaseKind {
    /// `LOCAL_FLOOR`, from the runtime.
    LocalFloor,
    /// LOCAL lowered by the head height measured in STAGE.
    LocalMeasured,
    /// LOCAL lowered by [`ASSUMED_EYE_HEIGHT`].
    LocalAssumed,
}

/// The report's account of the spaces.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct SpaceReport {
    /// Reference spaces the session offers.
    pub offered: Vec<String>,
    /// The base space: `local_floor`, `local_measured` or `local_assumed`.
    pub base: String,
    /// How far LOCAL was lowered (0 for LOCAL_FLOOR), metres.
    pub floor_offset_m: f32,
}

/// The plan for a session's base space.
pub enum BasePlan {
    /// Ready now.
    Ready(xr::Space, BaseKind, f32),
    /// Measure LOCAL's height in STAGE first.
    Measure {
        /// LOCAL.
        local: xr::Space,
        /// STAGE.
        stage: xr::Space,
    },
}

/// LOCAL lowered by [`ASSUMED_EYE_HEIGHT`].
pub fn local_assumed<G>(session: &xr::Session<G>) -> xr::Result<xr::Space> {
    local_lowered(session, ASSUMED_EYE_HEIGHT)
}

fn local_lowered<G>(session: &xr::Session<G>, h: f32) -> xr::Result<xr::Space> {
    let pose = xr::Posef {
        orientation: xr::Quaternionf::IDENTITY,
        position: xr::Vector3f {
            x: 0.0,
            y: -h,
            z: 0.0,
        },
    };
    session.create_reference_space(xr::ReferenceSpaceType::LOCAL, pose)
}

/// Chooses the base space for `session` (see the module doc).
pub fn plan<G>(
    session: &xr::Session<G>,
    local_floor_enabled: bool,
) -> xr::Result<(BasePlan, Vec<String>)> {
    let offered = session.enumerate_reference_spaces()?;
    let names = offered.iter().map(|s| format!("{s:?}")).collect();
    let id = xr::Posef::IDENTITY;
    let plan = if local_floor_enabled && offered.contains(&xr::ReferenceSpaceType::LOCAL_FLOOR) {
        let s = session.create_reference_space(xr::ReferenceSpaceType::LOCAL_FLOOR, id)?;
        BasePlan::Ready(s, BaseKind::LocalFloor, 0.0)
    } else if offered.contains(&xr::ReferenceSpaceType::STAGE) {
        BasePlan::Measure {
            local: session.create_reference_space(xr::ReferenceSpaceType::LOCAL, id)?,
            stage: session.create_reference_space(xr::ReferenceSpaceType::STAGE, id)?,
        }
    } else {
        let s = local_assumed(session)?;
        BasePlan::Ready(s, BaseKind::LocalAssumed, ASSUMED_EYE_HEIGHT)
    };
    Ok((plan, names))
}

/// Measures LOCAL's origin height in STAGE at `time`; Some(base) once both
/// locate (position valid), None while they do not yet.
pub fn measure<G>(
    session: &xr::Session<G>,
    local: &xr::Space,
    stage: &xr::Space,
    time: xr::Time,
) -> xr::Result<Option<(xr::Space, f32)>> {
    let loc = local.locate(stage, time)?;
    if !loc
        .location_flags
        .contains(xr::SpaceLocationFlags::POSITION_VALID)
        || !loc.pose.position.y.is_finite()
    {
        return Ok(None);
    }
    let h = loc.pose.position.y;
    Ok(Some((local_lowered(session, h)?, h)))
}
