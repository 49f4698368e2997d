//! Hand tracking (XR_EXT_hand_tracking): trackers and the script's hand
//! joints.

use openxr_sys as sys;
use sys::Handle as _;

use crate::api_session::sess;
use crate::api_spaces::{all_valid, relative, tracked, untracked, world_pose};
use crate::script::pose;
use crate::{done, input, output, with_rt};

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
