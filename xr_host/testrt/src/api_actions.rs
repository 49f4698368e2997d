//! Action functions: attaching action sets, syncing actions and reading
//! their states from the script's keyframes, the interaction profile in
//! use, haptics.

use openxr_sys as sys;
use sys::Handle as _;

use crate::api_session::{queue, sess, session_of, wind_down};
use crate::script::{Fault, Keyframe, ScriptHand, ScriptPose};
use crate::state::{InstanceData, QueuedEvent, Runtime};
use crate::{done, input, output, with_rt};

pub(crate) unsafe extern "system" fn attach_session_action_sets(
    session: sys::Session,
    info: *const sys::SessionActionSetsAttachInfo,
) -> sys::Result {
    // SAFETY: caller pointer, null-checked.
    let info = match unsafe { input(info) } {
        Ok(i) => i,
        Err(e) => return e,
    };
    let mut sets = Vec::new();
    for k in 0..info.count_action_sets as usize {
        if info.action_sets.is_null() {
            return sys::Result::ERROR_VALIDATION_FAILURE;
        }
        // SAFETY: the array holds count_action_sets handles.
        sets.push(unsafe { *info.action_sets.add(k) }.into_raw());
    }
    with_rt(|rt| {
        done(sess(rt, session).and_then(|i| {
            if info.ty != sys::SessionActionSetsAttachInfo::TYPE || sets.is_empty() {
                return Err(sys::Result::ERROR_VALIDATION_FAILURE);
            }
            if sets.iter().any(|s| !i.action_sets.contains_key(s)) {
                return Err(sys::Result::ERROR_HANDLE_INVALID);
            }
            let s = session_of(i);
            if !s.attached.is_empty() {
                return Err(sys::Result::ERROR_ACTIONSETS_ALREADY_ATTACHED);
            }
            s.attached = sets.clone();
            Ok(sys::Result::SUCCESS)
        }))
    })
}

pub(crate) unsafe extern "system" fn sync_actions(
    session: sys::Session,
    info: *const sys::ActionsSyncInfo,
) -> sys::Result {
    // SAFETY: caller pointer, null-checked.
    let info = match unsafe { input(info) } {
        Ok(i) => i,
        Err(e) => return e,
    };
    let mut sets = Vec::new();
    for k in 0..info.count_active_action_sets as usize {
        if info.active_action_sets.is_null() {
            return sys::Result::ERROR_VALIDATION_FAILURE;
        }
        // SAFETY: the array holds count_active_action_sets entries.
        sets.push(
            unsafe { *info.active_action_sets.add(k) }
                .action_set
                .into_raw(),
        );
    }
    with_rt(|rt| {
        if let Err(e) = sess(rt, session) {
            return e;
        }
        let Runtime {
            script,
            instance,
            step,
            fired,
            refuse_remaining,
            ..
        } = rt;
        let Some(i) = instance.as_mut() else {
            return sys::Result::ERROR_HANDLE_INVALID;
        };
        if info.ty != sys::ActionsSyncInfo::TYPE {
            return sys::Result::ERROR_VALIDATION_FAILURE;
        }
        let s = session_of(i);
        if sets.iter().any(|a| !s.attached.contains(a)) {
            return sys::Result::ERROR_ACTIONSET_NOT_ATTACHED;
        }
        if !s.running {
            return sys::Result::ERROR_SESSION_NOT_RUNNING;
        }
        *step += 1;
        for (k, f) in script.faults.iter().enumerate() {
            if f.at > *step || fired.get(k).copied().unwrap_or(true) {
                continue;
            }
            fired[k] = true;
            match f.fault {
                Fault::LossPending => queue(i, sys::SessionState::LOSS_PENDING),
                Fault::InstanceLoss => {
                    i.events.push_back(QueuedEvent::InstanceLoss);
                    *refuse_remaining = script.refuse_creates;
                }
                Fault::RuntimeExit => {
                    session_of(i).exit_requested = true;
                    wind_down(i);
                }
            }
        }
        let s = session_of(i);
        if s.state == sys::SessionState::FOCUSED {
            s.synced = Some(script.at(*step));
            sys::Result::SUCCESS
        } else {
            s.synced = None;
            sys::Result::SESSION_NOT_FOCUSED
        }
    })
}

pub(crate) enum Value {
    Pose(Option<ScriptPose>),
    Float(f32),
    Bool(bool),
}

fn component(hand: &ScriptHand, comp: &str) -> Option<Value> {
    Some(match comp {
        "input/grip/pose" => Value::Pose(hand.grip),
        "input/aim/pose" => Value::Pose(hand.aim),
        "input/trigger/value"
        | "input/select/click"
        | "input/select/value"
        | "input/pinch_ext/value" => Value::Float(hand.select),
        "input/squeeze/value"
        | "input/squeeze/click"
        | "input/squeeze/force"
        | "input/grasp_ext/value" => Value::Float(hand.squeeze),
        "input/menu/click" | "input/thumbstick/click" => Value::Bool(hand.menu),
        "input/b/click" | "input/y/click" => Value::Bool(hand.secondary),
        "input/a/click" | "input/x/click" | "input/trackpad/click" => Value::Bool(hand.primary),
        "input/thumbstick/x" | "input/trackpad/x" => Value::Float(hand.stick[0]),
        "input/thumbstick/y" | "input/trackpad/y" => Value::Float(hand.stick[1]),
        _ => return None,
    })
}

/// The values bound to `action` for `subaction` (0 = any hand) under the
/// script's profile, from the last synced frame.
pub(crate) fn bound_values(
    i: &InstanceData,
    profile: &str,
    frame: &Keyframe,
    action: u64,
    subaction: u64,
) -> Vec<Value> {
    let Some(pid) = i
        .paths
        .iter()
        .position(|p| p == profile)
        .map(|k| k as u64 + 1)
    else {
        return Vec::new();
    };
    let Some(pairs) = i.bindings.get(&pid) else {
        return Vec::new();
    };
    let sub = if subaction == 0 {
        None
    } else {
        i.path(subaction)
    };
    let mut out = Vec::new();
    for (a, p) in pairs {
        if *a != action {
            continue;
        }
        let Some(path) = i.path(*p) else { continue };
        for (prefix, hand) in [
            ("/user/hand/left", &frame.left),
            ("/user/hand/right", &frame.right),
        ] {
            if sub.is_some_and(|s| s != prefix) {
                continue;
            }
            if let Some(comp) = path.strip_prefix(prefix).and_then(|r| r.strip_prefix('/')) {
                out.extend(component(hand, comp));
            }
        }
    }
    out
}

/// Validates a state query; returns the bound values (empty: inactive).
fn state_query(
    rt: &mut Runtime,
    session: sys::Session,
    info: &sys::ActionStateGetInfo,
    ty: sys::ActionType,
) -> Result<Vec<Value>, sys::Result> {
    let profile = rt.script.profile.clone();
    let i = sess(rt, session)?;
    if info.ty != sys::ActionStateGetInfo::TYPE {
        return Err(sys::Result::ERROR_VALIDATION_FAILURE);
    }
    let a = i
        .actions
        .get(&info.action.into_raw())
        .ok_or(sys::Result::ERROR_HANDLE_INVALID)?;
    if a.ty != ty {
        return Err(sys::Result::ERROR_ACTION_TYPE_MISMATCH);
    }
    let sub = info.subaction_path.into_raw();
    if sub != 0 && !a.subaction_paths.contains(&sub) {
        return Err(sys::Result::ERROR_PATH_UNSUPPORTED);
    }
    let s = i
        .session
        .as_ref()
        .ok_or(sys::Result::ERROR_HANDLE_INVALID)?;
    if !s.attached.contains(&a.set) {
        return Err(sys::Result::ERROR_ACTIONSET_NOT_ATTACHED);
    }
    Ok(match &s.synced {
        Some(f) => bound_values(i, &profile, f, info.action.into_raw(), sub),
        None => Vec::new(),
    })
}

pub(crate) unsafe extern "system" fn get_action_state_boolean(
    session: sys::Session,
    info: *const sys::ActionStateGetInfo,
    state: *mut sys::ActionStateBoolean,
) -> sys::Result {
    // SAFETY: caller pointers, null-checked.
    let (info, out) = match unsafe { (input(info), output(state)) } {
        (Ok(i), Ok(o)) => (i, o),
        _ => return sys::Result::ERROR_VALIDATION_FAILURE,
    };
    with_rt(|rt| {
        done(
            state_query(rt, session, info, sys::ActionType::BOOLEAN_INPUT).map(|v| {
                let vals: Vec<bool> = v
                    .iter()
                    .filter_map(|x| match x {
                        Value::Bool(b) => Some(*b),
                        Value::Float(f) => Some(*f > 0.5),
                        Value::Pose(_) => None,
                    })
                    .collect();
                out.is_active = (!vals.is_empty()).into();
                out.current_state = vals.iter().any(|b| *b).into();
                out.changed_since_last_sync = false.into();
                out.last_change_time = sys::Time::from_nanos(0);
                sys::Result::SUCCESS
            }),
        )
    })
}

pub(crate) unsafe extern "system" fn get_action_state_float(
    session: sys::Session,
    info: *const sys::ActionStateGetInfo,
    state: *mut sys::ActionStateFloat,
) -> sys::Result {
    // SAFETY: caller pointers, null-checked.
    let (info, out) = match unsafe { (input(info), output(state)) } {
        (Ok(i), Ok(o)) => (i, o),
        _ => return sys::Result::ERROR_VALIDATION_FAILURE,
    };
    with_rt(|rt| {
        done(
            state_query(rt, session, info, sys::ActionType::FLOAT_INPUT).map(|v| {
                let vals: Vec<f32> = v
                    .iter()
                    .filter_map(|x| match x {
                        Value::Float(f) => Some(*f),
                        Value::Bool(b) => Some(if *b { 1.0 } else { 0.0 }),
                        Value::Pose(_) => None,
                    })
                    .collect();
                out.is_active = (!vals.is_empty()).into();
                // Several bound sources combine to the one of largest
                // magnitude (spec §11.5.1), keeping its sign (axes are -1..1).
                out.current_state =
                    vals.iter()
                        .copied()
                        .fold(0.0, |a: f32, b| if b.abs() > a.abs() { b } else { a });
                out.changed_since_last_sync = false.into();
                out.last_change_time = sys::Time::from_nanos(0);
                sys::Result::SUCCESS
            }),
        )
    })
}

pub(crate) unsafe extern "system" fn get_action_state_pose(
    session: sys::Session,
    info: *const sys::ActionStateGetInfo,
    state: *mut sys::ActionStatePose,
) -> sys::Result {
    // SAFETY: caller pointers, null-checked.
    let (info, out) = match unsafe { (input(info), output(state)) } {
        (Ok(i), Ok(o)) => (i, o),
        _ => return sys::Result::ERROR_VALIDATION_FAILURE,
    };
    with_rt(|rt| {
        done(
            state_query(rt, session, info, sys::ActionType::POSE_INPUT).map(|v| {
                let active = v.iter().any(|x| matches!(x, Value::Pose(Some(_))));
                out.is_active = active.into();
                sys::Result::SUCCESS
            }),
        )
    })
}

pub(crate) unsafe extern "system" fn get_current_interaction_profile(
    session: sys::Session,
    top_level_user_path: sys::Path,
    state: *mut sys::InteractionProfileState,
) -> sys::Result {
    // SAFETY: caller pointer, null-checked.
    let state = match unsafe { output(state) } {
        Ok(s) => s,
        Err(e) => return e,
    };
    with_rt(|rt| {
        let profile = rt.script.profile.clone();
        done(sess(rt, session).and_then(|i| {
            if state.ty != sys::InteractionProfileState::TYPE {
                return Err(sys::Result::ERROR_VALIDATION_FAILURE);
            }
            let user = i
                .path(top_level_user_path.into_raw())
                .ok_or(sys::Result::ERROR_PATH_INVALID)?
                .to_string();
            let s = i
                .session
                .as_ref()
                .ok_or(sys::Result::ERROR_HANDLE_INVALID)?;
            if s.attached.is_empty() {
                return Err(sys::Result::ERROR_ACTIONSET_NOT_ATTACHED);
            }
            // Bound once synced, if the app suggested the script's profile
            // and the hand's controller is there.
            let pid = i
                .paths
                .iter()
                .position(|p| *p == profile)
                .map(|k| k as u64 + 1);
            let suggested = pid.is_some_and(|p| i.bindings.contains_key(&p));
            let hand = s.synced.as_ref().map(|f| match user.as_str() {
                "/user/hand/left" => &f.left,
                _ => &f.right,
            });
            let present = hand.is_some_and(|h| h.grip.is_some() || h.aim.is_some());
            state.interaction_profile = match (suggested && present, pid) {
                (true, Some(p)) => sys::Path::from_raw(p),
                _ => sys::Path::NULL,
            };
            Ok(sys::Result::SUCCESS)
        }))
    })
}

pub(crate) unsafe extern "system" fn apply_haptic_feedback(
    session: sys::Session,
    info: *const sys::HapticActionInfo,
    feedback: *const sys::HapticBaseHeader,
) -> sys::Result {
    // SAFETY: caller pointers, null-checked.
    let (info, fb) = match unsafe { (input(info), input(feedback)) } {
        (Ok(i), Ok(f)) => (i, f),
        _ => return sys::Result::ERROR_VALIDATION_FAILURE,
    };
    with_rt(|rt| {
        done(sess(rt, session).and_then(|i| {
            if info.ty != sys::HapticActionInfo::TYPE || fb.ty != sys::HapticVibration::TYPE {
                return Err(sys::Result::ERROR_VALIDATION_FAILURE);
            }
            let a = i
                .actions
                .get(&info.action.into_raw())
                .ok_or(sys::Result::ERROR_HANDLE_INVALID)?;
            if a.ty != sys::ActionType::VIBRATION_OUTPUT {
                return Err(sys::Result::ERROR_ACTION_TYPE_MISMATCH);
            }
            let sub = info.subaction_path.into_raw();
            let hand = match i.path(sub) {
                Some("/user/hand/left") => 0,
                Some("/user/hand/right") => 1,
                _ => return Err(sys::Result::ERROR_PATH_UNSUPPORTED),
            };
            let s = i
                .session
                .as_mut()
                .ok_or(sys::Result::ERROR_HANDLE_INVALID)?;
            if !s.running {
                return Err(sys::Result::ERROR_SESSION_NOT_RUNNING);
            }
            s.haptics[hand] += 1;
            Ok(sys::Result::SUCCESS)
        }))
    })
}
