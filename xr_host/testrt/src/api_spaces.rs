//! Space functions: reference and action spaces, where a space is in
//! another at a time (the script's poses, LOCAL settled on the first
//! frame), and the pose helpers the frame loop shares.

use openxr_sys as sys;
use sys::Handle as _;

use crate::api_actions::{bound_values, Value};
use crate::api_session::sess;
use crate::script::{pose, Keyframe, SENTINEL};
use crate::state::{InstanceData, SpaceInfo, SpaceKind};
use crate::{done, input, output, with_rt};

type Pose = ([f32; 3], [f32; 4]);

/// The reference spaces this session offers: VIEW and LOCAL always,
/// STAGE if the script says so, LOCAL_FLOOR with XR_EXT_local_floor.
fn reference_spaces(i: &InstanceData, script_stage: bool) -> Vec<sys::ReferenceSpaceType> {
    let mut v = vec![
        sys::ReferenceSpaceType::VIEW,
        sys::ReferenceSpaceType::LOCAL,
    ];
    if script_stage {
        v.push(sys::ReferenceSpaceType::STAGE);
    }
    if i.extensions.iter().any(|e| e == "XR_EXT_local_floor") {
        v.push(sys::ReferenceSpaceType::LOCAL_FLOOR);
    }
    v
}

pub(crate) unsafe extern "system" fn enumerate_reference_spaces(
    session: sys::Session,
    capacity: u32,
    count: *mut u32,
    spaces: *mut sys::ReferenceSpaceType,
) -> sys::Result {
    // SAFETY: caller pointer, null-checked.
    let count = match unsafe { output(count) } {
        Ok(c) => c,
        Err(e) => return e,
    };
    with_rt(|rt| {
        let stage = rt.script.stage;
        done(sess(rt, session).and_then(|i| {
            let types = reference_spaces(i, stage);
            *count = types.len() as u32;
            if capacity == 0 {
                return Ok(sys::Result::SUCCESS);
            }
            if (capacity as usize) < types.len() {
                return Err(sys::Result::ERROR_SIZE_INSUFFICIENT);
            }
            if spaces.is_null() {
                return Err(sys::Result::ERROR_VALIDATION_FAILURE);
            }
            for (k, t) in types.iter().enumerate() {
                // SAFETY: `spaces` holds `capacity` >= types.len() elements.
                unsafe { *spaces.add(k) = *t };
            }
            Ok(sys::Result::SUCCESS)
        }))
    })
}

fn pose_ok(p: &sys::Posef) -> bool {
    let q = p.orientation;
    let n = (q.x * q.x + q.y * q.y + q.z * q.z + q.w * q.w).sqrt();
    [p.position.x, p.position.y, p.position.z, n]
        .iter()
        .all(|c| c.is_finite())
        && (n - 1.0).abs() < 0.01
}

fn to_pose(p: &sys::Posef) -> Pose {
    (
        [p.position.x, p.position.y, p.position.z],
        [
            p.orientation.x,
            p.orientation.y,
            p.orientation.z,
            p.orientation.w,
        ],
    )
}

pub(crate) unsafe extern "system" fn create_reference_space(
    session: sys::Session,
    info: *const sys::ReferenceSpaceCreateInfo,
    space: *mut sys::Space,
) -> sys::Result {
    // SAFETY: caller pointers, null-checked.
    let (info, out) = match unsafe { (input(info), output(space)) } {
        (Ok(i), Ok(o)) => (i, o),
        _ => return sys::Result::ERROR_VALIDATION_FAILURE,
    };
    with_rt(|rt| {
        let h = rt.handle();
        let stage = rt.script.stage;
        let refuse = rt.script.refuse.clone();
        done(sess(rt, session).and_then(|i| {
            if info.ty != sys::ReferenceSpaceCreateInfo::TYPE {
                return Err(sys::Result::ERROR_VALIDATION_FAILURE);
            }
            let t = info.reference_space_type;
            if !reference_spaces(i, stage).contains(&t) {
                return Err(sys::Result::ERROR_REFERENCE_SPACE_UNSUPPORTED);
            }
            // Offered, then refused (see script::Refusals).
            if t == sys::ReferenceSpaceType::LOCAL_FLOOR && refuse.local_floor {
                return Err(sys::Result::ERROR_VALIDATION_FAILURE);
            }
            if t == sys::ReferenceSpaceType::STAGE && refuse.stage {
                return Err(sys::Result::ERROR_RUNTIME_FAILURE);
            }
            if !pose_ok(&info.pose_in_reference_space) {
                return Err(sys::Result::ERROR_POSE_INVALID);
            }
            i.spaces.insert(
                h,
                SpaceInfo {
                    session: session.into_raw(),
                    kind: SpaceKind::Reference(t),
                    offset: to_pose(&info.pose_in_reference_space),
                },
            );
            *out = sys::Space::from_raw(h);
            Ok(sys::Result::SUCCESS)
        }))
    })
}

pub(crate) unsafe extern "system" fn create_action_space(
    session: sys::Session,
    info: *const sys::ActionSpaceCreateInfo,
    space: *mut sys::Space,
) -> sys::Result {
    // SAFETY: caller pointers, null-checked.
    let (info, out) = match unsafe { (input(info), output(space)) } {
        (Ok(i), Ok(o)) => (i, o),
        _ => return sys::Result::ERROR_VALIDATION_FAILURE,
    };
    with_rt(|rt| {
        let h = rt.handle();
        done(sess(rt, session).and_then(|i| {
            if info.ty != sys::ActionSpaceCreateInfo::TYPE {
                return Err(sys::Result::ERROR_VALIDATION_FAILURE);
            }
            let a = i
                .actions
                .get(&info.action.into_raw())
                .ok_or(sys::Result::ERROR_HANDLE_INVALID)?;
            if a.ty != sys::ActionType::POSE_INPUT {
                return Err(sys::Result::ERROR_ACTION_TYPE_MISMATCH);
            }
            let sub = info.subaction_path.into_raw();
            if sub != 0 && !a.subaction_paths.contains(&sub) {
                return Err(sys::Result::ERROR_PATH_UNSUPPORTED);
            }
            if !pose_ok(&info.pose_in_action_space) {
                return Err(sys::Result::ERROR_POSE_INVALID);
            }
            i.spaces.insert(
                h,
                SpaceInfo {
                    session: session.into_raw(),
                    kind: SpaceKind::Action {
                        action: info.action.into_raw(),
                        subaction: sub,
                    },
                    offset: to_pose(&info.pose_in_action_space),
                },
            );
            *out = sys::Space::from_raw(h);
            Ok(sys::Result::SUCCESS)
        }))
    })
}

pub(crate) unsafe extern "system" fn destroy_space(space: sys::Space) -> sys::Result {
    with_rt(|rt| {
        match rt
            .instance
            .as_mut()
            .and_then(|i| i.spaces.remove(&space.into_raw()))
        {
            Some(_) => sys::Result::SUCCESS,
            None => sys::Result::ERROR_HANDLE_INVALID,
        }
    })
}

/// Sets LOCAL's origin from the head in `frame` if it is not set yet (the
/// session's first locate, as Monado and headsets do): the head's
/// position, eye height included, and its yaw.
pub(crate) fn settle_local_origin(i: &mut InstanceData, frame: &Keyframe) {
    let Some(s) = i.session.as_mut() else { return };
    if s.local_origin.is_some() {
        return;
    }
    if let Some(h) = frame.head.filter(|h| h.valid && !h.nan) {
        s.local_origin = Some((h.p, pose::yaw(h.q)));
    }
}

/// A space's pose in STAGE: None if untracked, Some((pose, nan)) otherwise.
pub(crate) fn world_pose(
    i: &InstanceData,
    profile: &str,
    frame: &Keyframe,
    sp: &SpaceInfo,
) -> Option<(Pose, bool)> {
    let origin = || i.session.as_ref().and_then(|s| s.local_origin);
    let (base, nan) = match sp.kind {
        SpaceKind::Reference(sys::ReferenceSpaceType::VIEW) => {
            let h = frame.head.filter(|h| h.valid)?;
            ((h.p, h.q), h.nan)
        }
        SpaceKind::Reference(sys::ReferenceSpaceType::LOCAL) => (origin()?, false),
        SpaceKind::Reference(sys::ReferenceSpaceType::LOCAL_FLOOR) => {
            let (p, q) = origin()?;
            (([p[0], 0.0, p[2]], q), false)
        }
        SpaceKind::Reference(_) => (pose::IDENTITY, false),
        SpaceKind::Action { action, subaction } => {
            let p = bound_values(i, profile, frame, action, subaction)
                .into_iter()
                .find_map(|v| match v {
                    Value::Pose(Some(p)) => Some(p),
                    _ => None,
                })?;
            if !p.valid {
                return None;
            }
            ((p.p, p.q), p.nan)
        }
    };
    Some((compose_exact(base, sp.offset), nan))
}

/// `a ∘ b`, exactly `b` (or `a`) when the other is the identity: the
/// floor-level spaces of the usual start pose then pass scripted poses
/// through bit for bit.
pub(crate) fn compose_exact(a: Pose, b: Pose) -> Pose {
    if a == pose::IDENTITY {
        b
    } else if b == pose::IDENTITY {
        a
    } else {
        pose::compose(a, b)
    }
}

/// The pose of `a` relative to `base` (both in STAGE).
pub(crate) fn relative(base: Pose, a: Pose) -> Pose {
    if base == pose::IDENTITY {
        a
    } else {
        pose::compose(pose::inverse(base), a)
    }
}

pub(crate) fn untracked() -> sys::Posef {
    sys::Posef {
        orientation: sys::Quaternionf {
            x: 0.0,
            y: 0.0,
            z: 0.0,
            w: 1.0,
        },
        position: sys::Vector3f {
            x: SENTINEL,
            y: SENTINEL,
            z: SENTINEL,
        },
    }
}

pub(crate) fn tracked(p: Pose, nan: bool) -> sys::Posef {
    let x = if nan { f32::NAN } else { p.0[0] };
    sys::Posef {
        orientation: sys::Quaternionf {
            x: p.1[0],
            y: p.1[1],
            z: p.1[2],
            w: p.1[3],
        },
        position: sys::Vector3f {
            x,
            y: p.0[1],
            z: p.0[2],
        },
    }
}

pub(crate) fn all_valid() -> sys::SpaceLocationFlags {
    sys::SpaceLocationFlags::POSITION_VALID
        | sys::SpaceLocationFlags::ORIENTATION_VALID
        | sys::SpaceLocationFlags::POSITION_TRACKED
        | sys::SpaceLocationFlags::ORIENTATION_TRACKED
}

/// Whether the two spaces are LOCAL and STAGE, in either order.
fn is_local_and_stage(a: SpaceKind, b: SpaceKind) -> bool {
    use sys::ReferenceSpaceType as R;
    let kind = |k| match k {
        SpaceKind::Reference(t) => Some(t),
        SpaceKind::Action { .. } => None,
    };
    let pair = [kind(a), kind(b)];
    pair == [Some(R::LOCAL), Some(R::STAGE)] || pair == [Some(R::STAGE), Some(R::LOCAL)]
}

pub(crate) unsafe extern "system" fn locate_space(
    space: sys::Space,
    base: sys::Space,
    time: sys::Time,
    location: *mut sys::SpaceLocation,
) -> sys::Result {
    // SAFETY: caller pointer, null-checked.
    let out = match unsafe { output(location) } {
        Ok(o) => o,
        Err(e) => return e,
    };
    with_rt(|rt| {
        let profile = rt.script.profile.clone();
        let current = rt.script.live(rt.step);
        let Some(i) = rt.instance.as_mut() else {
            return sys::Result::ERROR_HANDLE_INVALID;
        };
        let (Some(sp), Some(bp)) = (
            i.spaces.get(&space.into_raw()).copied(),
            i.spaces.get(&base.into_raw()).copied(),
        ) else {
            return sys::Result::ERROR_HANDLE_INVALID;
        };
        if let Err(e) = sess(rt, sys::Session::from_raw(sp.session)) {
            return e;
        }
        if out.ty != sys::SpaceLocation::TYPE {
            return sys::Result::ERROR_VALIDATION_FAILURE;
        }
        if time.as_nanos() <= 0 {
            return sys::Result::ERROR_TIME_INVALID;
        }
        let frame = rt
            .instance
            .as_ref()
            .and_then(|i| i.session.as_ref())
            .and_then(|s| s.synced.clone())
            .unwrap_or_else(|| current.clone());
        if let Some(i) = rt.instance.as_mut() {
            settle_local_origin(i, &frame);
        }
        // Refused after LOCAL's origin is set, as a runtime sets it whatever
        // the app asks.
        if rt.script.refuse.locate_stage && is_local_and_stage(sp.kind, bp.kind) {
            return sys::Result::ERROR_RUNTIME_FAILURE;
        }
        let i = rt.instance.as_ref().expect("checked above");
        let s = i.session.as_ref().expect("checked by sess()");
        let frame = match (&sp.kind, &s.synced) {
            // Action spaces follow the last sync; reference spaces track live.
            (SpaceKind::Action { .. }, Some(f)) => f.clone(),
            (SpaceKind::Action { .. }, None) => {
                out.location_flags = sys::SpaceLocationFlags::EMPTY;
                out.pose = untracked();
                return sys::Result::SUCCESS;
            }
            _ => s.synced.clone().unwrap_or(current),
        };
        match (
            world_pose(i, &profile, &frame, &sp),
            world_pose(i, &profile, &frame, &bp),
        ) {
            (Some((a, na)), Some((b, nb))) => {
                out.location_flags = all_valid();
                out.pose = tracked(relative(b, a), na || nb);
            }
            _ => {
                out.location_flags = sys::SpaceLocationFlags::EMPTY;
                out.pose = untracked();
            }
        }
        sys::Result::SUCCESS
    })
}
