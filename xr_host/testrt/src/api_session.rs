//! Session-level functions: events and the session's lifecycle. Actions,
//! spaces and hand tracking are in `api_actions`, `api_spaces`, `api_hands`.

use openxr_sys as sys;
use sys::Handle as _;

use crate::api_instance::{check_system, inst};
use crate::state::{InstanceData, QueuedEvent, Runtime, SessionData};
use crate::{done, input, output, with_rt};

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

pub(crate) fn queue(i: &mut InstanceData, st: sys::SessionState) {
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
pub(crate) fn wind_down(i: &mut InstanceData) {
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
            check_system(info.system_id)?;
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
            crate::api_frame::write_stats(&rt.script, s);
        }
        let i = rt.instance.as_mut().expect("checked above");
        crate::api_swapchain::destroy_swapchains(i, session.into_raw());
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
