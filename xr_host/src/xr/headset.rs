//! `run` (headset): the graphics half of the one frame loop
//! ([`super::frame_loop`]) for a Vulkan session through
//! `XR_KHR_vulkan_enable2`: the openxr crate's `FrameWaiter`/`FrameStream`
//! frame protocol, one stereo swapchain (2-layer array, multiview), the
//! document, the drag preview, rays and headset messages drawn each frame.
//!
//! Views whose pose VALID bits are unset are not rendered (an empty frame
//! is submitted), as with input poses. The environment blend mode is the
//! runtime's first choice (opaque on a VR headset, additive or alpha blend
//! on see-through ones); the clear colour is transparent black on the
//! latter so passthrough shows.

use std::sync::Arc;

use ash::vk;
use glam::{Mat4, Quat, Vec3};
use openxr as xr;
use shapewright::interact::InputFrame;
use shapewright::mesh::TriMesh;

use super::actions::SessionInput;
use super::frame_loop::{self, FrameTime, Graphics, Overlay, TickError};
use super::input::FrameSink;
use super::instance::InstanceCaps;
use super::{RunConfig, RunReport, XrHostError};
use crate::gfx::hud::notice_lines;
use crate::gfx::xr_bridge::{create_vulkan_for_openxr, create_vulkan_session, SwapchainTargets};
use crate::gfx::{GpuContext, GpuMesh, LineVertex, MeshDraw, Renderer, ViewCamera};
use crate::render::eye_camera;

const VIEW_TYPE: xr::ViewConfigurationType = xr::ViewConfigurationType::PRIMARY_STEREO;

fn gfx_err(e: crate::gfx::GfxError) -> XrHostError {
    XrHostError::Graphics(e.to_string())
}

/// Where `--model` is shown: 1.3 m above the floor (30 cm below a
/// standing user's eyes), 70 cm in front of the user's starting position.
pub const MODEL_CENTER: Vec3 = Vec3::new(0.0, 1.3, -0.7);

/// World (the floor-level base space, Y-up, meters) from model (Z-up): the
/// model's bounding sphere scaled to 25 cm radius around [`MODEL_CENTER`].
pub fn model_placement(mesh: &TriMesh) -> Mat4 {
    let Some((lo, hi)) = mesh.bbox() else {
        return Mat4::IDENTITY;
    };
    let (lo, hi) = (lo.as_vec3(), hi.as_vec3());
    let radius = ((hi - lo).length() * 0.5).max(1e-6);
    let center = (lo + hi) * 0.5;
    Mat4::from_translation(MODEL_CENTER)
        * Mat4::from_rotation_x(-std::f32::consts::FRAC_PI_2)
        * Mat4::from_scale(Vec3::splat(0.25 / radius))
        * Mat4::from_translation(-center)
}

/// The aim rays (1 m along each aim pose's -Z) as line segments.
pub fn aim_rays(frame: &InputFrame) -> Vec<LineVertex> {
    let mut v = Vec::new();
    for (c, color) in frame
        .controllers
        .iter()
        .zip([[0.3, 0.6, 1.0], [1.0, 0.5, 0.2]])
    {
        if let Some(c) = c.as_ref().filter(|c| c.aim_valid && c.aim.is_finite()) {
            let p = c.aim.position.as_vec3();
            let q = c.aim.orientation.as_quat().normalize();
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

/// The eyes' cameras from the located views, and the head: midway
/// between the eyes, with the first eye's orientation.
fn eye_cameras(views: &[xr::View]) -> (Vec<ViewCamera>, (Vec3, Quat)) {
    let cams = views
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
    let (a, b) = (views[0].pose, views[1].pose);
    let o = a.orientation;
    let head = (
        Vec3::new(
            (a.position.x + b.position.x) * 0.5,
            (a.position.y + b.position.y) * 0.5,
            (a.position.z + b.position.z) * 0.5,
        ),
        Quat::from_xyzw(o.x, o.y, o.z, o.w).normalize(),
    );
    (cams, head)
}

/// The meshes on the GPU: the `--model` file, and the document and drag
/// preview with the versions they were uploaded at.
struct GpuScene<'a> {
    model: &'a Option<(GpuMesh, Mat4)>,
    doc: &'a mut Option<(u64, GpuMesh)>,
    preview: &'a mut Option<(u64, GpuMesh)>,
}

/// Draws both eyes into swapchain image `index`: uploads what changed,
/// then records and submits one pass.
fn draw_eyes(
    stereo: &mut Stereo,
    gpu: GpuScene<'_>,
    cams: &[ViewCamera],
    scene: Option<&crate::gfx::Scene>,
    lines: &[LineVertex],
    clear: [f32; 4],
    index: u32,
) -> Result<(), crate::gfx::GfxError> {
    let GpuScene {
        model,
        doc: gpu_doc,
        preview: gpu_preview,
    } = gpu;
    stereo.renderer.set_views(cams)?;
    let lines = if lines.is_empty() {
        None
    } else {
        Some(stereo.renderer.upload_lines(lines)?)
    };
    // The document is uploaded again only when it changed; the drag
    // preview (small, short-lived) every frame.
    if let Some(s) = scene {
        if gpu_doc.as_ref().map(|d| d.0) != Some(s.version) {
            *gpu_doc = None;
            if let Some(m) = &s.document {
                *gpu_doc = Some((s.version, stereo.renderer.upload_mesh(m)?));
            }
        }
    }
    let ui = match scene.filter(|s| !s.ui.is_empty()) {
        Some(s) => Some(stereo.renderer.upload_lines(&s.ui)?),
        None => None,
    };
    // The preview is uploaded again only when it is another mesh (a drag
    // that only moves it changes its matrix).
    if let Some(s) = scene {
        let want = s.preview.as_ref().map(|_| s.preview_version);
        if gpu_preview.as_ref().map(|p| p.0) != want {
            *gpu_preview = None;
            if let (Some(v), Some(m)) = (want, &s.preview) {
                *gpu_preview = Some((v, stereo.renderer.upload_mesh(m)?));
            }
        }
    }
    let mut draws: Vec<MeshDraw> = model
        .iter()
        .map(|(m, placement)| MeshDraw {
            mesh: m,
            model: *placement,
            color: [0.55, 0.62, 0.75, 1.0],
            hidden: None,
        })
        .collect();
    if let Some(s) = scene {
        draws.extend(crate::render::scene_draws(
            s,
            gpu_doc.as_ref().map(|d| &d.1),
            gpu_preview.as_ref().map(|p| &p.1),
        ));
    }
    let Some(fb) = stereo.targets.framebuffer(index) else {
        return Ok(());
    };
    stereo.renderer.context().submit_and_wait(|_, cmd| {
        stereo
            .renderer
            .record(cmd, fb, clear, &draws, ui.as_ref(), lines.as_ref());
    })
}

fn make_stereo(
    caps: &InstanceCaps,
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

/// The Vulkan headset.
pub struct Headset<'m> {
    model: Option<&'m TriMesh>,
    ctx: Option<Arc<GpuContext>>,
    blend: xr::EnvironmentBlendMode,
    waiter: Option<xr::FrameWaiter>,
    stream: Option<xr::FrameStream<xr::Vulkan>>,
    stereo: Option<Stereo>,
    gpu_model: Option<(GpuMesh, Mat4)>,
    gpu_doc: Option<(u64, GpuMesh)>,
    gpu_preview: Option<(u64, GpuMesh)>,
    submitted: u64,
}

fn gfx_tick(e: crate::gfx::GfxError) -> TickError {
    TickError::Host(gfx_err(e))
}

impl Graphics for Headset<'_> {
    type Api = xr::Vulkan;
    const HEADLESS: bool = false;

    fn instance_created(&mut self, caps: &InstanceCaps) -> Result<(), XrHostError> {
        self.ctx = Some(create_vulkan_for_openxr(&caps.instance, caps.system).map_err(gfx_err)?);
        self.blend = caps
            .instance
            .enumerate_environment_blend_modes(caps.system, VIEW_TYPE)
            .map_err(|r| XrHostError::call("xrEnumerateEnvironmentBlendModes", r))?
            .first()
            .copied()
            .unwrap_or(xr::EnvironmentBlendMode::OPAQUE);
        Ok(())
    }

    fn create_session(&mut self, caps: &InstanceCaps) -> xr::Result<xr::Session<xr::Vulkan>> {
        let Some(ctx) = &self.ctx else {
            return Err(xr::sys::Result::ERROR_GRAPHICS_DEVICE_INVALID);
        };
        let (session, waiter, stream) = create_vulkan_session(&caps.instance, caps.system, ctx)?;
        self.waiter = Some(waiter);
        self.stream = Some(stream);
        Ok(session)
    }

    fn session_created(
        &mut self,
        caps: &InstanceCaps,
        session: &xr::Session<xr::Vulkan>,
    ) -> Result<(), TickError> {
        let Some(ctx) = &self.ctx else {
            return Err(TickError::Host(XrHostError::Graphics(
                "no Vulkan device".into(),
            )));
        };
        let stereo = match make_stereo(caps, session, ctx) {
            Ok(s) => s,
            Err(XrHostError::Call { result, call }) => return Err(TickError::Xr(call, result)),
            Err(e) => return Err(TickError::Host(e)),
        };
        self.gpu_model = match self.model {
            Some(m) => Some((
                stereo.renderer.upload_mesh(m).map_err(gfx_tick)?,
                model_placement(m),
            )),
            None => None,
        };
        self.gpu_doc = None;
        self.gpu_preview = None;
        self.stereo = Some(stereo);
        Ok(())
    }

    fn wait_frame(
        &mut self,
        _caps: &InstanceCaps,
        _cfg: &RunConfig,
    ) -> Result<FrameTime, TickError> {
        let (Some(waiter), Some(stream)) = (&mut self.waiter, &mut self.stream) else {
            return Err(TickError::Host(XrHostError::Graphics(
                "no frame stream".into(),
            )));
        };
        let fs = waiter.wait().map_err(|r| TickError::Xr("xrWaitFrame", r))?;
        stream
            .begin()
            .map_err(|r| TickError::Xr("xrBeginFrame", r))?;
        Ok(FrameTime {
            time: fs.predicted_display_time,
            should_render: fs.should_render,
        })
    }

    fn end_frame(
        &mut self,
        session: &xr::Session<xr::Vulkan>,
        input: &SessionInput,
        ft: FrameTime,
        sink: &dyn FrameSink,
        overlay: &Overlay<'_>,
    ) -> Result<(), TickError> {
        let (Some(stream), Some(stereo)) = (&mut self.stream, &mut self.stereo) else {
            return Err(TickError::Host(XrHostError::Graphics(
                "no frame stream".into(),
            )));
        };
        let time = ft.time;
        let blend = self.blend;
        let Some(base) = input.base() else {
            // The floor is not measured yet: nothing to place things in.
            stream
                .end(time, blend, &[])
                .map_err(|r| TickError::Xr("xrEndFrame", r))?;
            self.submitted += 1;
            return Ok(());
        };
        let (flags, views) = session
            .locate_views(VIEW_TYPE, time, base)
            .map_err(|r| TickError::Xr("xrLocateViews", r))?;
        let views_valid = flags
            .contains(xr::ViewStateFlags::POSITION_VALID | xr::ViewStateFlags::ORIENTATION_VALID);
        if !ft.should_render || !views_valid || views.len() != 2 {
            stream
                .end(time, blend, &[])
                .map_err(|r| TickError::Xr("xrEndFrame", r))?;
            self.submitted += 1;
            return Ok(());
        }
        let (cams, head) = eye_cameras(&views);
        let index = stereo
            .swapchain
            .acquire_image()
            .map_err(|r| TickError::Xr("xrAcquireSwapchainImage", r))?;
        stereo
            .swapchain
            .wait_image(xr::Duration::INFINITE)
            .map_err(|r| TickError::Xr("xrWaitSwapchainImage", r))?;
        let scene = sink.scene();
        let mut lines = match scene {
            Some(s) => s.lines.clone(),
            None => overlay.frame.map(aim_rays).unwrap_or_default(),
        };
        let messages: Vec<(String, bool)> = overlay
            .notices
            .iter()
            .map(|n| (n.text.clone(), n.warning))
            .collect();
        lines.extend(notice_lines(&messages, head));
        let clear = if blend == xr::EnvironmentBlendMode::OPAQUE {
            crate::render::CLEAR
        } else {
            [0.0, 0.0, 0.0, 0.0]
        };
        let gpu = GpuScene {
            model: &self.gpu_model,
            doc: &mut self.gpu_doc,
            preview: &mut self.gpu_preview,
        };
        let render = draw_eyes(stereo, gpu, &cams, scene, &lines, clear, index);
        stereo
            .swapchain
            .release_image()
            .map_err(|r| TickError::Xr("xrReleaseSwapchainImage", r))?;
        render.map_err(gfx_tick)?;
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
            .space(base)
            .views(&proj_views);
        stream
            .end(time, blend, &[&layer])
            .map_err(|r| TickError::Xr("xrEndFrame", r))?;
        self.submitted += 1;
        Ok(())
    }

    fn frames_submitted(&self) -> u64 {
        self.submitted
    }

    fn idle(&mut self, _cfg: &RunConfig) {
        std::thread::sleep(std::time::Duration::from_millis(20));
    }

    fn session_ended(&mut self) {
        // GPU objects first, then the swapchain, then the frame protocol.
        self.gpu_model = None;
        self.gpu_doc = None;
        self.gpu_preview = None;
        self.stereo = None;
        self.stream = None;
        self.waiter = None;
    }

    fn instance_ended(&mut self) {
        self.session_ended();
        // The Vulkan context goes before the instance that created it.
        self.ctx = None;
    }
}

/// Runs the headset session (see [`frame_loop::run`]); `model` is drawn
/// in front of the user.
pub fn run_headset(
    cfg: &RunConfig,
    model: Option<&TriMesh>,
    sink: &mut dyn FrameSink,
) -> Result<RunReport, XrHostError> {
    let mut gfx = Headset {
        model,
        ctx: None,
        blend: xr::EnvironmentBlendMode::OPAQUE,
        waiter: None,
        stream: None,
        stereo: None,
        gpu_model: None,
        gpu_doc: None,
        gpu_preview: None,
        submitted: 0,
    };
    let r = frame_loop::run(cfg, &mut gfx, sink);
    gfx.instance_ended();
    r
}

#[cfg(test)]
mod tests {
    use super::*;
    use shapewright::interact::{ControllerSample, Pose};
    use shapewright::math::{DQuat, DVec3};

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
        assert!((c - MODEL_CENTER).length() < 1e-5, "{c}");
        // Model +Z (up) maps to world +Y (up).
        let up = m.transform_vector3(Vec3::Z).normalize();
        assert!((up - Vec3::Y).length() < 1e-5, "{up}");
        let corner = m.transform_point3(hi.as_vec3());
        assert!(((corner - c).length() - 0.25).abs() < 1e-4);
    }

    #[test]
    fn rays_start_at_the_aim_pose_and_point_along_minus_z() {
        let mut f = InputFrame::default();
        let aim = Pose::new(DVec3::new(0.1, 1.0, -0.2), DQuat::IDENTITY);
        f.controllers[1] = Some(ControllerSample {
            grip: aim,
            grip_valid: true,
            aim,
            aim_valid: true,
            buttons: Default::default(),
            buttons_valid: true,
        });
        // An aim the runtime did not mark valid draws no ray.
        f.controllers[0] = Some(ControllerSample {
            aim_valid: false,
            ..f.controllers[1].unwrap()
        });
        let r = aim_rays(&f);
        assert_eq!(r.len(), 2);
        assert_eq!(r[0].pos, [0.1, 1.0, -0.2]);
        assert!((Vec3::from_array(r[1].pos) - Vec3::new(0.1, 1.0, -1.2)).length() < 1e-6);
    }
}
