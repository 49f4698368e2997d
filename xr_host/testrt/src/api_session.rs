//! Session-level functions: events, lifecycle, action sync and states,
//! spaces, hand tracking.

use openxr_sys as sys;
use sys::Handle as _;

use crate::api_instance::inst;
use crate::script::{pose, Fault, Keyframe, ScriptHand, ScriptPose, SENTINEL};
use crate::state::{InstanceData, QueuedEvent, Runtime, SessionData, SpaceInfo, SpaceKind};
use crate::{done, input, output, with_rt};

type Pose = ([f32; 3], [f32; 4]);

/// The instance holding this live, not-lost session.
pub(crate) fn sess(rt: &mut Runtime, h: sys::Session) -> Result<&mut InstanceData, sys::Result> {
    let i = rt
        .instance
        .as_mut()
        .ok_or(sys::Result::ERROR_HANDLE_INVALID)?;
    match &i.session {
        Some(s) if s.handle == h.into_raw() => {
            if i.lost {
                Err(sys::Result::ERROR_INSTANCE_LOST)
            } else if s.lost {
                Err(sys::Result::ERROR_SESSION_LOST)
            } else {
                Ok(i)
            }
        }
        _ => Err(sys::Result::ERROR_HANDLE_INVALID),
    }
}

pub(crate) fn session_of(i: &mut InstanceData) -> &mut SessionData {
    i.session.as_mut().expect("checked by sess()")
}

fn queue(i: &mut InstanceData, st: sys::SessionState) {
    if let Some(s) = &i.session {
        i.events.push_back(QueuedEvent::State(s.handle, st));
    }
}

/// The last state queued (what the session is heading to).
fn heading(i: &InstanceData) -> sys::SessionState {
    let h = i.session.as_ref().map(|s| s.handle).unwrap_or(0);
    i.events
        .iter()
        .rev()
        .find_map(|e| match e {
            QueuedEvent::State(s, st) if *s == h => Some(*st),
            _ => None,
        })
        .or(i.session.as_ref().map(|s| s.state))
        .unwrap_or(sys::SessionState::UNKNOWN)
}

/// FOCUSED → VISIBLE → SYNCHRONIZED → STOPPING, from wherever it is.
fn wind_down(i: &mut InstanceData) {
    let h = heading(i);
    if h == sys::SessionState::FOCUSED {
        queue(i, sys::SessionState::VISIBLE);
    }
    if h == sys::SessionState::FOCUSED || h == sys::SessionState::VISIBLE {
        queue(i, sys::SessionState::SYNCHRONIZED);
    }
    queue(i, sys::SessionState::STOPPING);
}

pub(crate) unsafe extern "system" fn poll_event(
    instance: sys::Instance,
    buffer: *mut sys::EventDataBuffer,
) -> sys::Result {
    if buffer.is_null() {
        return sys::Result::ERROR_VALIDATION_FAILURE;
    }
    with_rt(|rt| {
        let i = match inst(rt, instance) {
            Ok(i) => i,
            Err(e) => return e,
        };
        while let Some(ev) = i.events.pop_front() {
            match ev {
                QueuedEvent::State(h, st) => {
                    let Some(s) = i.session.as_mut().filter(|s| s.handle == h) else {
                        continue; // the session was destroyed meanwhile
                    };
                    s.state = st;
                    if st == sys::SessionState::LOSS_PENDING {
                        s.lost = true;
                    }
                    let e = sys::EventDataSessionStateChanged {
                        ty: sys::EventDataSessionStateChanged::TYPE,
                        next: std::ptr::null(),
                        session: sys::Session::from_raw(h),
                        state: st,
                        time: now(),
                    };
                    // SAFETY: the buffer is an XrEventDataBuffer (4000+ bytes),
                    // larger than any event struct; written unaligned-safe.
                    unsafe {
                        std::ptr::write_unaligned(
                            buffer.cast::<sys::EventDataSessionStateChanged>(),
                            e,
                        )
                    };
                    return sys::Result::SUCCESS;
                }
                QueuedEvent::InstanceLoss => {
                    i.lost = true;
                    let e = sys::EventDataInstanceLossPending {
                        ty: sys::EventDataInstanceLossPending::TYPE,
                        next: std::ptr::null(),
                        loss_time: now(),
                    };
                    // SAFETY: as above.
                    unsafe {
                        std::ptr::write_unaligned(
                            buffer.cast::<sys::EventDataInstanceLossPending>(),
                            e,
                        )
                    };
                    return sys::Result::SUCCESS;
                }
            }
        }
        sys::Result::EVENT_UNAVAILABLE
    })
}

pub(crate) fn now() -> sys::Time {
    let d = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .unwrap_or_default();
    sys::Time::from_nanos(d.as_nanos() as i64)
}

pub(crate) unsafe extern "system" fn create_session(
    instance: sys::Instance,
    info: *const sys::SessionCreateInfo,
    session: *mut sys::Session,
) -> sys::Result {
    // SAFETY: caller pointers, null-checked.
    let (info, out) = match unsafe { (input(info), output(session)) } {
        (Ok(i), Ok(o)) => (i, o),
        _ => return sys::Result::ERROR_VALIDATION_FAILURE,
    };
    with_rt(|rt| {
        let h = rt.handle();
        done(inst(rt, instance).and_then(|i| {
            if info.ty != sys::SessionCreateInfo::TYPE {
                return Err(sys::Result::ERROR_VALIDATION_FAILURE);
            }
            if info.system_id.into_raw() != 1 {
                return Err(sys::Result::ERROR_SYSTEM_INVALID);
            }
            // Headless (no binding, XR_MND_headless) or Vulkan (a
            // XrGraphicsBindingVulkan2KHR on the device made through
            // xrCreateVulkanDeviceKHR).
            let graphics = if info.next.is_null() {
                if !i.extensions.iter().any(|e| e == "XR_MND_headless") {
                    return Err(sys::Result::ERROR_GRAPHICS_DEVICE_INVALID);
                }
                false
            } else {
                // SAFETY: `next` is a valid structure chain per the spec.
                crate::api_vulkan::check_binding(i, unsafe {
                    &*(info.next as *const sys::GraphicsBindingVulkanKHR)
                })?;
                true
            };
            if i.session.is_some() {
                return Err(sys::Result::ERROR_LIMIT_REACHED);
            }
            i.session = Some(SessionData {
                handle: h,
                state: sys::SessionState::UNKNOWN,
                running: false,
                exit_requested: false,
                lost: false,
                attached: Vec::new(),
                synced: None,
                graphics,
                frame: Default::default(),
                local_origin: None,
                haptics: [0; 2],
            });
            queue(i, sys::SessionState::IDLE);
            queue(i, sys::SessionState::READY);
            *out = sys::Session::from_raw(h);
            Ok(sys::Result::SUCCESS)
        }))
    })
}

pub(crate) unsafe extern "system" fn destroy_session(session: sys::Session) -> sys::Result {
    with_rt(|rt| {
        let Some(i) = rt.instance.as_ref() else {
            return sys::Result::ERROR_HANDLE_INVALID;
        };
        if i.session.as_ref().map(|s| s.handle) != Some(session.into_raw()) {
            return sys::Result::ERROR_HANDLE_INVALID;
        }
        if let Some(s) = &i.session {
            crate::api_vulkan::write_stats(&rt.script, s);
        }
        let i = rt.instance.as_mut().expect("checked above");
        crate::api_vulkan::destroy_swapchains(i, session.into_raw());
        i.session = None;
        i.spaces.retain(|_, s| s.session != session.into_raw());
        i.trackers.retain(|_, t| t.0 != session.into_raw());
        sys::Result::SUCCESS
    })
}

pub(crate) unsafe extern "system" fn begin_session(
    session: sys::Session,
    info: *const sys::SessionBeginInfo,
) -> sys::Result {
    // SAFETY: caller pointer, null-checked.
    let info = match unsafe { input(info) } {
        Ok(i) => i,
        Err(e) => return e,
    };
    with_rt(|rt| {
        done(sess(rt, session).and_then(|i| {
            if info.ty != sys::SessionBeginInfo::TYPE {
                return Err(sys::Result::ERROR_VALIDATION_FAILURE);
            }
            let s = session_of(i);
            if s.running {
                return Err(sys::Result::ERROR_SESSION_RUNNING);
            }
            if s.state != sys::SessionState::READY {
                return Err(sys::Result::ERROR_SESSION_NOT_READY);
            }
            s.running = true;
            queue(i, sys::SessionState::SYNCHRONIZED);
            queue(i, sys::SessionState::VISIBLE);
            queue(i, sys::SessionState::FOCUSED);
            Ok(sys::Result::SUCCESS)
        }))
    })
}

pub(crate) unsafe extern "system" fn end_session(session: sys::Session) -> sys::Result {
    with_rt(|rt| {
        done(sess(rt, session).and_then(|i| {
            let s = session_of(i);
            if !s.running {
                return Err(sys::Result::ERROR_SESSION_NOT_RUNNING);
            }
            if s.state != sys::SessionState::STOPPING {
                return Err(sys::Result::ERROR_SESSION_NOT_STOPPING);
            }
            s.running = false;
            s.synced = None;
            let exiting = s.exit_requested;
            queue(i, sys::SessionState::IDLE);
            if exiting {
                queue(i, sys::SessionState::EXITING);
            }
            Ok(sys::Result::SUCCESS)
        }))
    })
}

pub(crate) unsafe extern "system" fn request_exit_session(session: sys::Session) -> sys::Result {
    with_rt(|rt| {
        done(sess(rt, session).and_then(|i| {
            let s = session_of(i);
            if !s.running {
                return Err(sys::Result::ERROR_SESSION_NOT_RUNNING);
            }
            if !s.exit_requested {
                s.exit_requested = true;
                wind_down(i);
            }
            Ok(sys::Result::SUCCESS)
        }))
    })
}

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

enum Value {
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
fn bound_values(
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

pub(crate) unsafe extern "system" fn create_hand_tracker(
    session: sys::Session,
    info: *const sys::HandTrackerCreateInfoEXT,
    tracker: *mut sys::HandTrackerEXT,
) -> sys::Result {
    // SAFETY: caller pointers, null-checked.
    let (info, out) = match unsafe { (input(info), output(tracker)) } {
        (Ok(i), Ok(o)) => (i, o),
        _ => return sys::Result::ERROR_VALIDATION_FAILURE,
    };
    with_rt(|rt| {
        let h = rt.handle();
        let supported = rt.script.hands_supported;
        let refuse = rt.script.refuse.clone();
        done(sess(rt, session).and_then(|i| {
            if info.ty != sys::HandTrackerCreateInfoEXT::TYPE {
                return Err(sys::Result::ERROR_VALIDATION_FAILURE);
            }
            if !supported {
                return Err(sys::Result::ERROR_FEATURE_UNSUPPORTED);
            }
            if refuse.hand_trackers {
                return Err(sys::Result::ERROR_RUNTIME_FAILURE);
            }
            if !info.next.is_null() && refuse.hand_data_source {
                return Err(sys::Result::ERROR_VALIDATION_FAILURE);
            }
            if !info.next.is_null() {
                // SAFETY: a valid chain per the spec.
                let ty = unsafe { (*(info.next as *const sys::BaseInStructure)).ty };
                let ok = ty == sys::HandTrackingDataSourceInfoEXT::TYPE
                    && i.extensions
                        .iter()
                        .any(|e| e == "XR_EXT_hand_tracking_data_source");
                if !ok {
                    return Err(sys::Result::ERROR_VALIDATION_FAILURE);
                }
            }
            if info.hand != sys::HandEXT::LEFT && info.hand != sys::HandEXT::RIGHT {
                return Err(sys::Result::ERROR_VALIDATION_FAILURE);
            }
            if info.hand_joint_set != sys::HandJointSetEXT::DEFAULT {
                return Err(sys::Result::ERROR_VALIDATION_FAILURE);
            }
            i.trackers.insert(h, (session.into_raw(), info.hand));
            *out = sys::HandTrackerEXT::from_raw(h);
            Ok(sys::Result::SUCCESS)
        }))
    })
}

pub(crate) unsafe extern "system" fn destroy_hand_tracker(
    tracker: sys::HandTrackerEXT,
) -> sys::Result {
    with_rt(|rt| {
        match rt
            .instance
            .as_mut()
            .and_then(|i| i.trackers.remove(&tracker.into_raw()))
        {
            Some(_) => sys::Result::SUCCESS,
            None => sys::Result::ERROR_HANDLE_INVALID,
        }
    })
}

pub(crate) unsafe extern "system" fn locate_hand_joints(
    tracker: sys::HandTrackerEXT,
    info: *const sys::HandJointsLocateInfoEXT,
    locations: *mut sys::HandJointLocationsEXT,
) -> sys::Result {
    // SAFETY: caller pointers, null-checked.
    let (info, out) = match unsafe { (input(info), output(locations)) } {
        (Ok(i), Ok(o)) => (i, o),
        _ => return sys::Result::ERROR_VALIDATION_FAILURE,
    };
    with_rt(|rt| {
        let source = rt.script.hand_source.clone();
        let profile = rt.script.profile.clone();
        let Some(&(session, hand)) = rt
            .instance
            .as_ref()
            .and_then(|i| i.trackers.get(&tracker.into_raw()))
        else {
            return sys::Result::ERROR_HANDLE_INVALID;
        };
        let i = match sess(rt, sys::Session::from_raw(session)) {
            Ok(i) => i,
            Err(e) => return e,
        };
        if info.ty != sys::HandJointsLocateInfoEXT::TYPE
            || out.ty != sys::HandJointLocationsEXT::TYPE
        {
            return sys::Result::ERROR_VALIDATION_FAILURE;
        }
        let Some(base_space) = i.spaces.get(&info.base_space.into_raw()).copied() else {
            return sys::Result::ERROR_HANDLE_INVALID;
        };
        if info.time.as_nanos() <= 0 {
            return sys::Result::ERROR_TIME_INVALID;
        }
        if out.joint_count as usize != sys::HAND_JOINT_COUNT_EXT || out.joint_locations.is_null() {
            return sys::Result::ERROR_VALIDATION_FAILURE;
        }
        let s = i.session.as_ref().expect("checked by sess()");
        let h = s.synced.as_ref().map(|f| {
            if hand == sys::HandEXT::LEFT {
                &f.left
            } else {
                &f.right
            }
        });
        let wrist = h.and_then(|h| h.joints);
        out.is_active = wrist.is_some().into();
        let mut next = out.next as *mut sys::BaseOutStructure;
        while !next.is_null() {
            // SAFETY: a valid chain per the spec.
            let ty = unsafe { (*next).ty };
            if ty == sys::HandTrackingDataSourceStateEXT::TYPE {
                // SAFETY: the type says which struct this is.
                let st = unsafe { &mut *(next as *mut sys::HandTrackingDataSourceStateEXT) };
                st.is_active = wrist.is_some().into();
                st.data_source = match source.as_deref() {
                    Some("controller") => sys::HandTrackingDataSourceEXT::CONTROLLER,
                    _ => sys::HandTrackingDataSourceEXT::UNOBSTRUCTED,
                };
            }
            // SAFETY: as above.
            next = unsafe { (*next).next };
        }
        let Some(w) = wrist else {
            return sys::Result::SUCCESS;
        };
        let invalid = h.map(|h| h.invalid_joints.clone()).unwrap_or_default();
        let frame = s.synced.clone().unwrap_or_default();
        let base = world_pose(i, &profile, &frame, &base_space);
        for k in 0..sys::HAND_JOINT_COUNT_EXT {
            let ok = w.valid && !invalid.contains(&k) && base.is_some();
            let p = pose::compose(
                (w.p, w.q),
                ([0.01 * k as f32, 0.0, 0.0], [0.0, 0.0, 0.0, 1.0]),
            );
            let p = base.map_or(p, |(b, _)| relative(b, p));
            let loc = sys::HandJointLocationEXT {
                location_flags: if ok {
                    all_valid()
                } else {
                    sys::SpaceLocationFlags::EMPTY
                },
                pose: if ok { tracked(p, w.nan) } else { untracked() },
                radius: 0.008,
            };
            // SAFETY: `joint_locations` holds joint_count == 26 elements.
            unsafe { *out.joint_locations.add(k) = loc };
        }
        sys::Result::SUCCESS
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
