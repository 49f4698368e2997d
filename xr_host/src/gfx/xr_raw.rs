//! OpenXR calls the `openxr` crate does not wrap with the structures we
//! need chained: system properties with `XrSystemHandTrackingPropertiesEXT`
//! and `XrSystemEyeGazeInteractionPropertiesEXT`, hand trackers created
//! with `XrHandTrackingDataSourceInfoEXT`, and joint locations with
//! `XrHandTrackingDataSourceStateEXT`. Each `unsafe` block builds the
//! chain on the stack, calls the function pointer the crate loaded, and
//! reads the outputs only after a success code.

use std::mem::MaybeUninit;
use std::ptr;

use openxr as xr;
use xr::sys;
use xr::sys::Handle as _;

/// What the system says it can do.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct SystemCaps {
    /// `systemName`.
    pub name: String,
    /// `vendorId`.
    pub vendor_id: u32,
    /// Orientation / position tracking of the HMD.
    pub tracking: (bool, bool),
    /// `supportsHandTracking` (None: XR_EXT_hand_tracking not enabled).
    pub hand_tracking: Option<bool>,
    /// `supportsEyeGazeInteraction` (None: the extension is not enabled).
    pub eye_gaze: Option<bool>,
}

/// xrGetSystemProperties, called once plain and once per extension
/// property struct (hand tracking, eye gaze) when its extension is enabled.
/// One struct per call: older validation layers (Debian's 1.0.20) reject
/// two extension structs in one chain.
pub fn system_caps(
    instance: &xr::Instance,
    system: xr::SystemId,
    hand_tracking: bool,
    eye_gaze: bool,
) -> xr::Result<SystemCaps> {
    let props = get_system_properties(instance, system, ptr::null_mut())?;
    let name = {
        let bytes: Vec<u8> = props
            .system_name
            .iter()
            .take_while(|&&c| c != 0)
            .map(|&c| c as u8)
            .collect();
        String::from_utf8_lossy(&bytes).into_owned()
    };
    let hands = if hand_tracking {
        let mut h = sys::SystemHandTrackingPropertiesEXT {
            ty: sys::SystemHandTrackingPropertiesEXT::TYPE,
            next: ptr::null_mut(),
            supports_hand_tracking: sys::FALSE,
        };
        get_system_properties(instance, system, &mut h as *mut _ as *mut _)?;
        Some(h.supports_hand_tracking.into())
    } else {
        None
    };
    let gaze = if eye_gaze {
        let mut g = sys::SystemEyeGazeInteractionPropertiesEXT {
            ty: sys::SystemEyeGazeInteractionPropertiesEXT::TYPE,
            next: ptr::null_mut(),
            supports_eye_gaze_interaction: sys::FALSE,
        };
        get_system_properties(instance, system, &mut g as *mut _ as *mut _)?;
        Some(g.supports_eye_gaze_interaction.into())
    } else {
        None
    };
    Ok(SystemCaps {
        name,
        vendor_id: props.vendor_id,
        tracking: (
            props.tracking_properties.orientation_tracking.into(),
            props.tracking_properties.position_tracking.into(),
        ),
        hand_tracking: hands,
        eye_gaze: gaze,
    })
}

/// One xrGetSystemProperties call with `next` chained (null or one
/// extension struct whose extension is enabled).
fn get_system_properties(
    instance: &xr::Instance,
    system: xr::SystemId,
    next: *mut std::ffi::c_void,
) -> xr::Result<sys::SystemProperties> {
    let mut props = MaybeUninit::<sys::SystemProperties>::zeroed();
    // SAFETY: zeroed is a valid bit pattern for this plain C struct; we set
    // its type and chain before the call. `next` is null or a struct on the
    // caller's frame that lives across the call, of a type the caller's
    // enabled extension defines (the runtime may only write structs it
    // knows).
    unsafe {
        let p = props.as_mut_ptr();
        (*p).ty = sys::SystemProperties::TYPE;
        (*p).next = next;
        let r = (instance.fp().get_system_properties)(instance.as_raw(), system, p);
        if r.into_raw() < 0 {
            return Err(r);
        }
        Ok(props.assume_init())
    }
}

/// Where joints came from (`XrHandTrackingDataSourceEXT`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DataSource {
    /// Optical tracking of the bare hand.
    Unobstructed,
    /// Derived from a held controller.
    Controller,
    /// A value this build does not know.
    Other(i32),
}

/// xrCreateHandTrackerEXT; with `data_source`, chains
/// `XrHandTrackingDataSourceInfoEXT` asking for both sources (optical and
/// controller-derived), so the runtime reports which one it used.
pub fn create_hand_tracker<G: xr::Graphics>(
    session: &xr::Session<G>,
    hand: xr::Hand,
    data_source: bool,
) -> xr::Result<xr::HandTracker> {
    if !data_source {
        return session.create_hand_tracker(hand);
    }
    let Some(fp) = session.instance().exts().ext_hand_tracking.as_ref() else {
        return Err(sys::Result::ERROR_EXTENSION_NOT_PRESENT);
    };
    let mut sources = [
        sys::HandTrackingDataSourceEXT::UNOBSTRUCTED,
        sys::HandTrackingDataSourceEXT::CONTROLLER,
    ];
    let source_info = sys::HandTrackingDataSourceInfoEXT {
        ty: sys::HandTrackingDataSourceInfoEXT::TYPE,
        next: ptr::null(),
        requested_data_source_count: sources.len() as u32,
        requested_data_sources: sources.as_mut_ptr(),
    };
    let info = sys::HandTrackerCreateInfoEXT {
        ty: sys::HandTrackerCreateInfoEXT::TYPE,
        next: &source_info as *const _ as *const _,
        hand,
        hand_joint_set: sys::HandJointSetEXT::DEFAULT,
    };
    let mut out = sys::HandTrackerEXT::NULL;
    // SAFETY: the create info and its chained source list live across the
    // call; the data-source extension is enabled (the caller's flag comes
    // from the enabled extension list), so the runtime accepts the chain.
    let r = unsafe { (fp.create_hand_tracker)(session.as_raw(), &info, &mut out) };
    if r.into_raw() < 0 {
        return Err(r);
    }
    // SAFETY: `out` was just created on `session` and is owned by nobody
    // else; HandTracker destroys it on drop.
    Ok(unsafe { xr::HandTracker::from_raw(session, out) })
}

/// Joint locations of one hand.
pub struct Joints {
    /// `isActive`.
    pub active: bool,
    /// The 26 joints (meaningful only when `active`).
    pub joints: [xr::HandJointLocation; xr::HAND_JOINT_COUNT],
    /// The data source, when XR_EXT_hand_tracking_data_source reported one.
    pub source: Option<DataSource>,
}

/// xrLocateHandJointsEXT relative to `base` at `time`, with the
/// data-source state chained when `data_source` is set.
pub fn locate_hand_joints(
    base: &xr::Space,
    tracker: &xr::HandTracker,
    time: xr::Time,
    data_source: bool,
) -> xr::Result<Joints> {
    let Some(fp) = base.instance().exts().ext_hand_tracking.as_ref() else {
        return Err(sys::Result::ERROR_EXTENSION_NOT_PRESENT);
    };
    let mut state = sys::HandTrackingDataSourceStateEXT {
        ty: sys::HandTrackingDataSourceStateEXT::TYPE,
        next: ptr::null_mut(),
        is_active: sys::FALSE,
        data_source: sys::HandTrackingDataSourceEXT::UNOBSTRUCTED,
    };
    let info = sys::HandJointsLocateInfoEXT {
        ty: sys::HandJointsLocateInfoEXT::TYPE,
        next: ptr::null(),
        base_space: base.as_raw(),
        time,
    };
    // Zeroed joints are a valid (untracked) value for every field.
    let mut joints = [sys::HandJointLocationEXT {
        location_flags: xr::SpaceLocationFlags::EMPTY,
        pose: xr::Posef::IDENTITY,
        radius: 0.0,
    }; xr::HAND_JOINT_COUNT];
    let mut locations = sys::HandJointLocationsEXT {
        ty: sys::HandJointLocationsEXT::TYPE,
        next: if data_source {
            &mut state as *mut _ as *mut _
        } else {
            ptr::null_mut()
        },
        is_active: sys::FALSE,
        joint_count: xr::HAND_JOINT_COUNT as u32,
        joint_locations: joints.as_mut_ptr(),
    };
    // SAFETY: every struct lives on this frame across the call; the joint
    // array holds `joint_count` initialized elements; the tracker and the
    // space belong to the same session (both come from one SessionInput).
    let r = unsafe { (fp.locate_hand_joints)(tracker.as_raw(), &info, &mut locations) };
    if r.into_raw() < 0 {
        return Err(r);
    }
    let source = (data_source && bool::from(state.is_active)).then(|| match state.data_source {
        sys::HandTrackingDataSourceEXT::UNOBSTRUCTED => DataSource::Unobstructed,
        sys::HandTrackingDataSourceEXT::CONTROLLER => DataSource::Controller,
        other => DataSource::Other(other.into_raw()),
    });
    Ok(Joints {
        active: locations.is_active.into(),
        joints,
        source,
    })
}
