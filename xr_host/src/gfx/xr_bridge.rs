//! The unsafe edge between OpenXR and graphics: session creation (the
//! openxr crate marks it unsafe because the graphics binding's handles
//! must be valid).

use openxr as xr;

/// Creates an `XR_MND_headless` session (no graphics binding). The frame
/// waiter and stream are dropped: a headless loop makes no frame calls.
pub fn create_headless_session(
    instance: &xr::Instance,
    system: xr::SystemId,
) -> xr::Result<xr::Session<xr::Headless>> {
    // SAFETY: a headless session has no graphics handles to be valid; the
    // instance enabling XR_MND_headless is checked by the runtime, which
    // returns XR_ERROR_GRAPHICS_DEVICE_INVALID otherwise.
    let (session, _waiter, _stream) = unsafe {
        instance.create_session::<xr::Headless>(system, &xr::headless::SessionCreateInfo {})
    }?;
    Ok(session)
}
