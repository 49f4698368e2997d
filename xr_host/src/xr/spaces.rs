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
//!
//! **Refusals fall back, never end the session.** Runtimes and layers
//! differ in what they accept (Debian's OpenXR 1.0.20 validation layer
//! rejects LOCAL_FLOOR, which it predates; a runtime may offer STAGE and
//! refuse it while the play area is not set up). A refused creation, or a
//! refused locate while measuring, steps down one rung of the chain above
//! with a [`Fallback`] line saying what was refused and what is used
//! instead; the host logs it and puts it in the report. Only LOCAL itself
//! (which every runtime must offer) ending in a refusal ends the session.

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

/// A rung the host gave up, for the log and the report.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Fallback(pub String);

impl Fallback {
    /// `WHAT refused (XR_CODE): INSTEAD`, with the result's name as the
    /// spec spells it (the text an issue report or a search needs).
    pub fn refused(what: &str, r: xr::sys::Result, instead: &str) -> Self {
        let code = format!("{r:?}");
        let code = if code.chars().all(|c| c.is_ascii_uppercase() || c == '_') {
            format!("XR_{code}")
        } else {
            format!("XrResult {}", r.into_raw())
        };
        Fallback(format!("{what} refused ({code}): {instead}"))
    }
}

impl std::fmt::Display for Fallback {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
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

/// The rung below a refusal: measuring against STAGE when that is next
/// (`stage_next`), else LOCAL at the assumed eye height.
fn next_rung(stage_next: bool) -> String {
    if stage_next {
        "measuring LOCAL against STAGE".into()
    } else {
        format!("LOCAL at an assumed eye height of {ASSUMED_EYE_HEIGHT} m")
    }
}

/// Chooses the base space for `session` (see the module doc): the plan,
/// the reference spaces offered, and the rungs given up on the way.
pub fn plan<G>(
    session: &xr::Session<G>,
    local_floor_enabled: bool,
) -> xr::Result<(BasePlan, Vec<String>, Vec<Fallback>)> {
    let mut fallbacks = Vec::new();
    let offered = match session.enumerate_reference_spaces() {
        Ok(o) => o,
        Err(r) if super::is_loss(r) => return Err(r),
        Err(r) => {
            fallbacks.push(Fallback::refused(
                "xrEnumerateReferenceSpaces",
                r,
                "assuming only the required VIEW and LOCAL",
            ));
            vec![xr::ReferenceSpaceType::VIEW, xr::ReferenceSpaceType::LOCAL]
        }
    };
    let names = offered.iter().map(|s| format!("{s:?}")).collect();
    let id = xr::Posef::IDENTITY;
    let has_stage = offered.contains(&xr::ReferenceSpaceType::STAGE);
    if local_floor_enabled && offered.contains(&xr::ReferenceSpaceType::LOCAL_FLOOR) {
        match session.create_reference_space(xr::ReferenceSpaceType::LOCAL_FLOOR, id) {
            Ok(s) => {
                return Ok((
                    BasePlan::Ready(s, BaseKind::LocalFloor, 0.0),
                    names,
                    fallbacks,
                ))
            }
            Err(r) if super::is_loss(r) => return Err(r),
            Err(r) => fallbacks.push(Fallback::refused("LOCAL_FLOOR", r, &next_rung(has_stage))),
        }
    }
    if has_stage {
        let pair = session
            .create_reference_space(xr::ReferenceSpaceType::LOCAL, id)
            .and_then(|local| {
                let stage = session.create_reference_space(xr::ReferenceSpaceType::STAGE, id)?;
                Ok((local, stage))
            });
        match pair {
            Ok((local, stage)) => {
                return Ok((BasePlan::Measure { local, stage }, names, fallbacks))
            }
            Err(r) if super::is_loss(r) => return Err(r),
            Err(r) => fallbacks.push(Fallback::refused(
                "STAGE (with LOCAL)",
                r,
                &next_rung(false),
            )),
        }
    }
    let s = local_assumed(session)?;
    Ok((
        BasePlan::Ready(s, BaseKind::LocalAssumed, ASSUMED_EYE_HEIGHT),
        names,
        fallbacks,
    ))
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_refusal_names_the_result_as_the_spec_spells_it() {
        let f = Fallback::refused(
            "LOCAL_FLOOR",
            xr::sys::Result::ERROR_VALIDATION_FAILURE,
            &next_rung(true),
        );
        assert_eq!(
            f.to_string(),
            "LOCAL_FLOOR refused (XR_ERROR_VALIDATION_FAILURE): measuring LOCAL against STAGE"
        );
        let odd = Fallback::refused(
            "STAGE",
            xr::sys::Result::from_raw(-987_654),
            &next_rung(false),
        );
        assert_eq!(
            odd.to_string(),
            "STAGE refused (XrResult -987654): LOCAL at an assumed eye height of 1.6 m"
        );
    }
}
