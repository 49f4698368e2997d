//! `run` (headset): a Vulkan session through `XR_KHR_vulkan_enable2`,
//! the openxr crate's `FrameWaiter`/`FrameStream` frame protocol, one
//! stereo swapchain (2-layer array, multiview), the model and the aim rays
//! drawn each frame. The lifecycle handling is the headless loop's.
//!
//! Views whose pose VALID bits are unset are not rendered (an empty frame
//! is submitted), as with input poses.

use std::sync::Arc;
use std::time::Instant;

use ash::vk;
use glam::{Mat4, Quat, Vec3};
use openxr as xr;
use shapewright::mesh::TriMesh;

use super::actions::{Actions, DropCounts, SessionInput};
use super::events::{end_or_error, Lifecycle, SessionEnd};
use super::input::{FrameSink, InputFrame, LifecycleEvent};
use super::lifecycle::{reads_input, Phase};
use super::{create_instance, RunConfig, RunReport, XrHostError};
use crate::gfx::xr_bridge::{create_vulkan_for_openxr, create_vulkan_session, SwapchainTargets};
use crate::gfx::{GpuContext, GpuMesh, LineVertex, MeshDraw, Renderer};
use crate::render::eye_camera;

const VIEW_TYPE: xr::ViewConfigurationType = xr::ViewConfigurationType::PRIMARY_STEREO;

fn gfx_err(e: crate::gfx::GfxError) -> XrHostError {
    XrHostError::Graphics(e.to_string())
}

/// World (LOCAL, Y-up, meters) from model (Z-up): the model's bounding
/// sphere scaled to 25 cm radius, 70 cm in front of and 30 cm below the
/// starting head position.
pub fn model_placement(mesh: &TriMesh) -> Mat4 {
    let Some((lo, hi)) = mesh.bbox() else {
        return Mat4::IDENTITY;
    };
    let (lo, hi) = (lo.as_vec3(), hi.as_vec3());
    let radius = ((hi - lo).length() * 0.5).max(1e-6);
    let center = (lo + hi) * 0.5;
    Mat4::from_translation(Vec3::new(0.0, -0.3, -0.7))
        * Mat4::from_rotation_x(-std::f32::consts::FRAC_PI_2)
        * Mat4::from_scale(Vec3::splat(0.25 / radius))
        * Mat4::from_translation(-center)
}

/// The aim rays (1 m along each aim pose's -Z) as line segments.
pub fn aim_rays(frame: &InputFrame) -> Vec<LineVertex> {
    let mut v = Vec::new();
    for (h, color) in frame.hands.iter().zip([[0.3, 0.6, 1.0], [1.0, 0.5, 0.2]]) {
        if let Some(aim) = h.aim {
            let p = Vec3::from_array(aim.position);
            let q = Quat::from_array(aim.orientation);
            let end = p + q * Vec3::NEG_Z;
            v.push(LineVertex {
                pos: p.to_array(),
                color,
            });
            v.push(LineVertex {
                pos: end.to_array(),
                color,
            });
        }
    }
    v
}

struct Stereo {
    swapchain: xr::Swapchain<xr::Vulkan>,
    targets: SwapchainTargets,
    renderer: Renderer,
}

fn make_stereo(
    caps: &super::InstanceCaps,
    session: &xr::Session<xr::Vulkan>,
    ctx: &Arc<GpuContext>,
) -> Result<Stereo, XrHostError> {
    let views = caps
        .instance
        .enumerate_view_configuration_views(caps.system, VIEW_TYPE)
        .map_err(|r| XrHostError::call("xrEnumerateViewConfigurationViews", r))?;
    let (w, h) = match views.as_slice() {
        [a, b] => (
            a.recommended_image_rect_width
                .max(b.recommended_image_rect_width),
            a.recommended_image_rect_height
                .max(b.recommended_image_rect_height),
        ),
        _ => {
            return Err(XrHostError::GaveUp(format!(
                "expected 2 stereo views, got {}",
                views.len()
            )))
        }
    };
    let formats = session
        .enumerate_swapchain_formats()
        .map_err(|r| XrHostError::call("xrEnumerateSwapchainFormats", r))?;
    let format = [vk::Format::R8G8B8A8_SRGB, vk::Format::B8G8R8A8_SRGB]
        .into_iter()
        .find(|f| formats.contains(&(f.as_raw() as u32)))
        .ok_or_else(|| {
            XrHostError::GaveUp("the runtime offers no 8-bit sRGB swapchain format".into())
        })?;
    let swapchain = session
        .create_swapchain(&xr::SwapchainCreateInfo {
            create_flags: xr::SwapchainCreateFlags::EMPTY,
            usage_flags: xr::SwapchainUsageFlags::COLOR_ATTACHMENT,
            format: format.as_raw() as u32,
            sample_count: 1,
            width: w,
            height: h,
            face_count: 1,
            array_size: 2,
            mip_count: 1,
        })
        .map_err(|r| XrHostError::call("xrCreateSwapchain", r))?;
    let images = swapchain
        .enumerate_images()
        .map_err(|r| XrHostError::call("xrEnumerateSwapchainImages", r))?;
    let renderer = Renderer::new(ctx, format, 2, vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL)
        .map_err(gfx_err)?;
    let targets = SwapchainTargets::new(
        &renderer,
        &images,
        format,
        vk::Extent2D {
            width: w,
            height: h,
        },
    )
    .map_err(gfx_err)?;
    Ok(Stereo {
        swapchain,
        targets,
        renderer,
    })
}

/// Runs the headset session until the limits in `cfg`, EXITING, or
/// retries are exhausted; `model` is drawn in front of the user.
pub fn run_headset(
    cfg: &RunConfig,
    model: Option<&TriMesh>,
    sink: &mut dyn FrameSink,
) -> Result<RunReport, XrHostError> {
    let start = Instant::now();
    let mut report = RunReport::default();
    loop {
        let caps = match create_instance(cfg, false) {
            Ok(c) => c,
            Err(e)
                if e.is_retryable()
                    && report.instances_created > 0
                    && report.instance_retries < cfg.max_instance_retries =>
            {
                report.instance_retries += 1;
                std::thread::sleep(cfg.retry_delay);
                continue;
            }
            Err(e) => return Err(e),
        };
        report.instances_created += 1;
        let ctx = create_vulkan_for_openxr(&caps.instance, caps.system).map_err(gfx_err)?;
        let actions = Actions::new(&caps.instance, &caps.enabled)
            .map_err(|r| XrHostError::call("creating actions", r))?;
        report.profiles = actions
            .accepted_profiles
            .iter()
            .map(|s| s.to_string())
            .collect();
        let blend = caps
            .instance
            .enumerate_environment_blend_modes(caps.system, VIEW_TYPE)
            .map_err(|r| XrHostError::call("xrEnumerateEnvironmentBlendModes", r))?
            .first()
            .copied()
            .unwrap_or(xr::EnvironmentBlendMode::OPAQUE);
        let mut recreations = 0;
        let instance_end = loop {
            let end = run_session(
                &caps,
                &ctx,
                &actions,
                blend,
                model,
                cfg,
                sink,
                &mut report,
                start,
            )?;
            match end {
                SessionEnd::Exit => return Ok(report),
                SessionEnd::InstanceLost => break SessionEnd::InstanceLost,
                SessionEnd::Lost => {
                    report.session_losses += 1;
                    sink.lifecycle(&LifecycleEvent::SessionLost);
                    recreations += 1;
                    if !cfg.recreate_lost_sessions || recreations > cfg.max_session_recreations {
                        report.exit_reason = "session lost".into();
                        return Ok(report);
                    }
                }
            }
        };
        debug_assert_eq!(instance_end, SessionEnd::InstanceLost);
        report.instance_losses += 1;
        sink.lifecycle(&LifecycleEvent::InstanceLost);
        // The session and swapchain are gone; the Vulkan context goes
        // before the instance that created it.
        drop(actions);
        drop(ctx);
        drop(caps);
        if report.instance_losses > cfg.max_instance_retries {
            return Err(XrHostError::GaveUp(
                "the instance was lost too often".into(),
            ));
        }
        std::thread::sleep(cfg.retry_delay);
    }
}

#[allow(clippy::too_many_arguments)]
fn run_session(
    caps: &super::InstanceCaps,
    ctx: &Arc<GpuContext>,
    actions: &Actions,
    blend: xr::EnvironmentBlendMode,
    model: Option<&TriMesh>,
    cfg: &RunConfig,
    sink: &mut dyn FrameSink,
    report: &mut RunReport,
    start: Instant,
) -> Result<SessionEnd, XrHostError> {
    let (session, mut waiter, mut stream) =
        match create_vulkan_session(&caps.instance, caps.system, ctx) {
            Ok(s) => s,
            Err(e) => return end_or_error("xrCreateSession", e),
        };
    report.sessions_created += 1;
    sink.lifecycle(&LifecycleEvent::SessionCreated);
    let input = match SessionInput::new(&session, actions, caps.hand_tracking) {
        Ok(i) => i,
        Err(e) => return end_or_error("creating spaces", e),
    };
    let mut stereo = match make_stereo(caps, &session, ctx) {
        Ok(s) => s,
        Err(XrHostError::Call { result, call }) => return end_or_error(call, result),
        Err(e) => return Err(e),
    };
    let gpu_model: Option<(GpuMesh, Mat4)> = match model {
        Some(m) => Some((
            stereo.renderer.upload_mesh(m).map_err(gfx_err)?,
            model_placement(m),
        )),
        None => None,
    };
    let mut gpu_doc: Option<(u64, GpuMesh)> = None;
    let mut life = Lifecycle::new(session);
    let mut buf = xr::EventDataBuffer::new();
    let mut drops = DropCounts::default();
    macro_rules! xr_try {
        ($lt:lifetime, $what:expr, $e:expr) => {
            match $e {
                Ok(v) => v,
                Err(err) => break $lt end_or_error($what, err)?,
            }
        };
    }
    let end = 'tick: loop {
        if let Some(end) = life.drain(&caps.instance, &mut buf, report, sink)? {
            break end;
        }
        let Some(Phase::Running(running)) = &life.phase else {
            std::thread::sleep(std::time::Duration::from_millis(20));
            continue;
        };
        // xrWaitFrame / xrBeginFrame / xrEndFrame, typed by the crate.
        let fs = xr_try!('tick, "xrWaitFrame", waiter.wait());
        xr_try!('tick, "xrBeginFrame", stream.begin());
        let time = fs.predicted_display_time;
        let mut frame = None;
        if reads_input(life.state) {
            let t0 = Instant::now();
            let f = xr_try!('tick, "reading input", input.read(running, actions, time, report.frames, &mut drops));
            sink.frame(&f);
            report.frame_cpu_us.push(t0.elapsed().as_secs_f64() * 1e6);
            report.frames += 1;
            frame = Some(f);
        }
        let (flags, views) = xr_try!(
            'tick,
            "xrLocateViews",
            running.session().locate_views(VIEW_TYPE, time, input.base())
        );
        let views_valid = flags
            .contains(xr::ViewStateFlags::POSITION_VALID | xr::ViewStateFlags::ORIENTATION_VALID);
        if !fs.should_render || !views_valid || views.len() != 2 {
            xr_try!('tick, "xrEndFrame", stream.end(time, blend, &[]));
        } else {
            let cams: Vec<_> = views
                .iter()
                .map(|v| {
                    let p = v.pose.position;
                    let o = v.pose.orientation;
                    eye_camera(
                        Vec3::new(p.x, p.y, p.z),
                        Quat::from_xyzw(o.x, o.y, o.z, o.w).normalize(),
                        [
                            v.fov.angle_left,
                            v.fov.angle_right,
                            v.fov.angle_up,
                            v.fov.angle_down,
                        ],
                        0.05,
                        100.0,
                    )
                })
                .collect();
            let index = xr_try!('tick, "xrAcquireSwapchainImage", stream_acquire(&mut stereo));
            xr_try!(
                'tick,
                "xrWaitSwapchainImage",
                stereo.swapchain.wait_image(xr::Duration::INFINITE)
            );
            let scene = sink.scene();
            let rays = match scene {
                Some(s) => s.lines.clone(),
                None => frame.as_ref().map(aim_rays).unwrap_or_default(),
            };
            let render = (|| -> Result<(), crate::gfx::GfxError> {
                stereo.renderer.set_views(&cams)?;
                let lines = if rays.is_empty() {
                    None
                } else {
                    Some(stereo.renderer.upload_lines(&rays)?)
                };
                // The document is uploaded again only when it changed; the
                // drag preview (small, short-lived) every frame.
                if let Some(s) = scene {
                    if gpu_doc.as_ref().map(|d| d.0) != Some(s.version) {
                        gpu_doc = None;
                        if let Some(m) = &s.document {
                            gpu_doc = Some((s.version, stereo.renderer.upload_mesh(m)?));
                        }
                    }
                }
                let preview = match scene.and_then(|s| s.preview.as_ref()) {
                    Some(m) => Some(stereo.renderer.upload_mesh(m)?),
                    None => None,
                };
                let to_world = scene.map(|s| s.model_to_world).unwrap_or_default();
                let mut draws: Vec<MeshDraw> = gpu_model
                    .iter()
                    .map(|(m, placement)| MeshDraw {
                        mesh: m,
                        model: *placement,
                        color: [0.55, 0.62, 0.75, 1.0],
                    })
                    .collect();
                for (m, color) in [
                    (gpu_doc.as_ref().map(|d| &d.1), [0.62, 0.66, 0.72, 1.0]),
                    (preview.as_ref(), [0.95, 0.75, 0.35, 1.0]),
                ] {
                    if let Some(mesh) = m {
                        draws.push(MeshDraw {
                            mesh,
                            model: to_world,
                            color,
                        });
                    }
                }
                let Some(fb) = stereo.targets.framebuffer(index) else {
                    return Ok(());
                };
                stereo.renderer.context().submit_and_wait(|_, cmd| {
                    stereo.renderer.record(
                        cmd,
                        fb,
                        [0.02, 0.025, 0.035, 1.0],
                        &draws,
                        lines.as_ref(),
                    );
                })
            })();
            xr_try!('tick, "xrReleaseSwapchainImage", stereo.swapchain.release_image());
            render.map_err(gfx_err)?;
            let rect = xr::Rect2Di {
                offset: xr::Offset2Di { x: 0, y: 0 },
                extent: xr::Extent2Di {
                    width: stereo.targets.extent.width as i32,
                    height: stereo.targets.extent.height as i32,
                },
            };
            let proj_views: Vec<_> = views
                .iter()
                .enumerate()
                .map(|(i, v)| {
                    xr::CompositionLayerProjectionView::new()
                        .pose(v.pose)
                        .fov(v.fov)
                        .sub_image(
                            xr::SwapchainSubImage::new()
                                .swapchain(&stereo.swapchain)
                                .image_array_index(i as u32)
                                .image_rect(rect),
                        )
                })
                .collect();
            let layer = xr::CompositionLayerProjection::new()
                .space(input.base())
                .views(&proj_views);
            xr_try!('tick, "xrEndFrame", stream.end(time, blend, &[&layer]));
        }
        let done = cfg.max_frames.is_some_and(|n| report.frames >= n)
            || cfg.max_duration.is_some_and(|d| start.elapsed() >= d);
        if done && !life.exit_requested {
            xr_try!('tick, "xrRequestExitSession", running.session().request_exit());
            life.exit_requested = true;
        }
    };
    report.poses_dropped += drops.poses;
    report.joints_dropped += drops.joints;
    drop(gpu_model);
    drop(gpu_doc);
    drop(stereo);
    drop(input);
    drop(stream);
    drop(waiter);
    drop(life);
    Ok(end)
}

fn stream_acquire(stereo: &mut Stereo) -> xr::Result<u32> {
    stereo.swapchain.acquire_image()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::xr::input::{HandInput, Pose};

    #[test]
    fn placement_puts_the_model_in_front_at_25cm_radius() {
        let mesh = shapewright::solid::tessellate(
            &shapewright::solid::SolidShape::Box {
                size: [2.0, 2.0, 2.0],
            },
            16,
        )
        .unwrap();
        let m = model_placement(&mesh);
        let (lo, hi) = mesh.bbox().unwrap();
        let c = m.transform_point3(((lo + hi) * 0.5).as_vec3());
        assert!((c - Vec3::new(0.0, -0.3, -0.7)).length() < 1e-5, "{c}");
        // Model +Z (up) maps to world +Y (up).
        let up = m.transform_vector3(Vec3::Z).normalize();
        assert!((up - Vec3::Y).length() < 1e-5, "{up}");
        let corner = m.transform_point3(hi.as_vec3());
        assert!(((corner - c).length() - 0.25).abs() < 1e-4);
    }

    #[test]
    fn rays_start_at_the_aim_pose_and_point_along_minus_z() {
        let mut f = InputFrame::default();
        f.hands[1] = HandInput {
            aim: Some(Pose {
                position: [0.1, 1.0, -0.2],
                orientation: [0.0, 0.0, 0.0, 1.0],
            }),
            ..Default::default()
        };
        let r = aim_rays(&f);
        assert_eq!(r.len(), 2);
        assert_eq!(r[0].pos, [0.1, 1.0, -0.2]);
        assert!((Vec3::from_array(r[1].pos) - Vec3::new(0.1, 1.0, -1.2)).length() < 1e-6);
    }
}
