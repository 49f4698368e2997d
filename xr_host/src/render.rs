//! Offscreen rendering of meshes to PNG: camera framing, projections in
//! Vulkan conventions (also used for OpenXR's asymmetric eye frusta), and
//! PNG encoding. Safe code on top of [`crate::gfx`].

use shapewright::math::fm::DetMath as _;
use std::path::Path;
use std::sync::Arc;

use glam::{Mat4, Quat, Vec3};
use shapewright::mesh::TriMesh;

use crate::gfx::{
    GfxError, GpuContext, LineVertex, MeshDraw, OffscreenTarget, RgbaImage, ViewCamera,
};

/// What can go wrong rendering a mesh to a file.
#[derive(Debug, thiserror::Error)]
pub enum RenderError {
    /// The GPU side failed.
    #[error(transparent)]
    Gfx(#[from] GfxError),
    /// The mesh has no triangles or non-finite coordinates.
    #[error("nothing to render: {0}")]
    BadMesh(String),
    /// The PNG could not be written.
    #[error("writing {path}: {message}")]
    Png {
        /// The output path.
        path: String,
        /// What failed.
        message: String,
    },
}

/// How to frame and draw a mesh offscreen.
#[derive(Clone, Debug, PartialEq)]
pub struct RenderSettings {
    /// Image width in pixels.
    pub width: u32,
    /// Image height in pixels.
    pub height: u32,
    /// Linear RGB base color of the model.
    pub color: [f32; 3],
    /// Linear RGBA background.
    pub background: [f32; 4],
    /// Direction from the model's center towards the camera (any length).
    pub view_dir: [f32; 3],
    /// Vertical field of view in degrees.
    pub fov_y_deg: f32,
    /// The model's up axis (Shapewright models are Z-up).
    pub up: [f32; 3],
}

impl Default for RenderSettings {
    fn default() -> Self {
        Self {
            width: 640,
            height: 480,
            color: [0.55, 0.62, 0.75],
            background: [0.02, 0.025, 0.035, 1.0],
            view_dir: [1.0, -1.6, 1.1],
            fov_y_deg: 35.0,
            up: [0.0, 0.0, 1.0],
        }
    }
}

/// A perspective projection in Vulkan clip space (y down, depth 0..1) from
/// OpenXR-style half-angles in radians (left and down negative).
pub fn projection_from_fov(left: f32, right: f32, up: f32, down: f32, near: f32, far: f32) -> Mat4 {
    let (tl, tr, tu, td) = (left.ftan(), right.ftan(), up.ftan(), down.ftan());
    let w = tr - tl;
    let h = td - tu; // Vulkan: y points down in clip space
    Mat4::from_cols_array(&[
        2.0 / w,
        0.0,
        0.0,
        0.0,
        0.0,
        2.0 / h,
        0.0,
        0.0,
        (tr + tl) / w,
        (tu + td) / h,
        -far / (far - near),
        -1.0,
        0.0,
        0.0,
        -(far * near) / (far - near),
        0.0,
    ])
}

/// The camera for an eye at `position` looking along `orientation`'s -Z
/// (OpenXR view conventions) with the given half-angle field of view.
pub fn eye_camera(
    position: Vec3,
    orientation: Quat,
    fov: [f32; 4],
    near: f32,
    far: f32,
) -> ViewCamera {
    let world_from_eye = Mat4::from_rotation_translation(orientation, position);
    let proj = projection_from_fov(fov[0], fov[1], fov[2], fov[3], near, far);
    ViewCamera {
        view_proj: proj * world_from_eye.inverse(),
        eye: position,
    }
}

/// A camera that frames the bounding sphere of `[lo, hi]` from `settings`'
/// direction; `eye_offset` shifts it sideways (half the interpupillary
/// distance for stereo, in units of the bounding radius).
pub fn framing_camera(
    lo: Vec3,
    hi: Vec3,
    settings: &RenderSettings,
    eye_offset: f32,
) -> ViewCamera {
    let center = (lo + hi) * 0.5;
    let radius = ((hi - lo).length() * 0.5).max(1e-6);
    let dir =
        Vec3::from_array(settings.view_dir).normalize_or(Vec3::new(1.0, -1.0, 1.0).normalize());
    let up = Vec3::from_array(settings.up).normalize_or(Vec3::Z);
    let aspect = settings.width as f32 / settings.height.max(1) as f32;
    let half_y = (settings.fov_y_deg.clamp(5.0, 150.0) * 0.5).to_radians();
    let half_x = (half_y.ftan() * aspect).fatan();
    let dist = radius / half_y.min(half_x).fsin() * 1.05;
    let right = up.cross(dir).normalize_or(Vec3::X);
    // Parallel eyes (as in a headset): both the eye and its target shift.
    let shift = right * (eye_offset * radius);
    let eye = center + dir * dist + shift;
    let view = Mat4::look_at_rh(eye, center + shift, up);
    let near = (dist - radius * 1.5).max(dist * 0.01);
    let far = dist + radius * 1.5;
    let proj = projection_from_fov(-half_x, half_x, half_y, -half_y, near, far);
    ViewCamera {
        view_proj: proj * view,
        eye,
    }
}

fn check_mesh(mesh: &TriMesh) -> Result<(Vec3, Vec3), RenderError> {
    if mesh.triangles.is_empty() {
        return Err(RenderError::BadMesh("the mesh has no triangles".into()));
    }
    if mesh.positions.iter().flatten().any(|c| !c.is_finite()) {
        return Err(RenderError::BadMesh(
            "the mesh has non-finite coordinates".into(),
        ));
    }
    let (lo, hi) = mesh
        .bbox()
        .ok_or_else(|| RenderError::BadMesh("the mesh has no vertices".into()))?;
    Ok((lo.as_vec3(), hi.as_vec3()))
}

/// Renders `mesh` (plus optional line segments) with one camera (`stereo =
/// false`) or two eyes side by side (`stereo = true`, one multiview pass),
/// returning one image per view.
pub fn render_mesh(
    ctx: &Arc<GpuContext>,
    mesh: &TriMesh,
    lines: &[LineVertex],
    settings: &RenderSettings,
    stereo: bool,
) -> Result<Vec<RgbaImage>, RenderError> {
    let (lo, hi) = check_mesh(mesh)?;
    let views = if stereo { 2 } else { 1 };
    let target = OffscreenTarget::new(ctx, settings.width, settings.height, views)?;
    let gpu = target.renderer().upload_mesh(mesh)?;
    let gpu_lines = if lines.is_empty() {
        None
    } else {
        Some(target.renderer().upload_lines(lines)?)
    };
    let cams: Vec<ViewCamera> = if stereo {
        vec![
            framing_camera(lo, hi, settings, -0.08),
            framing_camera(lo, hi, settings, 0.08),
        ]
    } else {
        vec![framing_camera(lo, hi, settings, 0.0)]
    };
    let [r, g, b] = settings.color;
    let draw = MeshDraw {
        mesh: &gpu,
        model: Mat4::IDENTITY,
        color: [r, g, b, 1.0],
        hidden: None,
    };
    Ok(target.render(
        &cams,
        settings.background,
        &[draw],
        None,
        gpu_lines.as_ref(),
    )?)
}

/// Encodes `image` as an 8-bit RGBA PNG at `path` (parent folders
/// created), crash-safely ([`crate::files`]).
pub fn write_png(image: &RgbaImage, path: &Path) -> Result<(), RenderError> {
    let err = |message: String| RenderError::Png {
        path: path.display().to_string(),
        message,
    };
    shapewright_atomic::write_with(path, |file| {
        let mut enc = png::Encoder::new(file, image.width, image.height);
        enc.set_color(png::ColorType::Rgba);
        enc.set_depth(png::BitDepth::Eight);
        enc.set_source_srgb(png::SrgbRenderingIntent::Perceptual);
        let mut w = enc.write_header().map_err(std::io::Error::other)?;
        w.write_image_data(&image.pixels)
            .map_err(std::io::Error::other)?;
        w.finish().map_err(std::io::Error::other)
    })
    .map(|_| ())
    .map_err(|e| err(e.to_string()))
}

/// Renders `mesh` to a PNG at `path` with a fresh offscreen Vulkan context
/// (the library entry point other commands call, e.g. the demo's replay).
pub fn render_mesh_png(
    mesh: &TriMesh,
    path: &Path,
    settings: &RenderSettings,
) -> Result<RgbaImage, RenderError> {
    let ctx = Arc::new(GpuContext::new_offscreen()?);
    let mut images = render_mesh(&ctx, mesh, &[], settings, false)?;
    let image = images.remove(0);
    write_png(&image, path)?;
    Ok(image)
}

/// Renders what the headset shows of `scene` from a head at `head` (an
/// eye between the two, `fov_y_deg` vertical, the image's aspect): the
/// document, the drag preview, the palette and text, rays and sketches,
/// with the headset's colours — the view a test or the README shows.
pub fn render_scene(
    ctx: &Arc<GpuContext>,
    scene: &crate::gfx::Scene,
    head: (Vec3, Quat),
    width: u32,
    height: u32,
    fov_y_deg: f32,
) -> Result<RgbaImage, RenderError> {
    let target = OffscreenTarget::new(ctx, width, height, 1)?;
    let r = target.renderer();
    let half_y = (fov_y_deg.clamp(5.0, 150.0) * 0.5).to_radians();
    let half_x = (half_y.ftan() * width as f32 / height.max(1) as f32).fatan();
    let cam = eye_camera(
        head.0,
        head.1,
        [-half_x, half_x, half_y, -half_y],
        0.05,
        50.0,
    );
    let doc = scene
        .document
        .as_ref()
        .map(|m| r.upload_mesh(m))
        .transpose()?;
    let preview = scene
        .preview
        .as_ref()
        .map(|m| r.upload_mesh(m))
        .transpose()?;
    let draws = scene_draws(scene, doc.as_ref(), preview.as_ref());
    let upload = |v: &[LineVertex]| (!v.is_empty()).then(|| r.upload_lines(v)).transpose();
    let ui = upload(&scene.ui)?;
    let lines = upload(&scene.lines)?;
    let mut images = target.render(&[cam], CLEAR, &draws, ui.as_ref(), lines.as_ref())?;
    Ok(images.remove(0))
}

/// The draws of `scene`'s uploaded document and preview: the document
/// without the hidden (dragged) object, the preview moved by the drag.
pub fn scene_draws<'a>(
    scene: &crate::gfx::Scene,
    doc: Option<&'a crate::gfx::GpuMesh>,
    preview: Option<&'a crate::gfx::GpuMesh>,
) -> Vec<MeshDraw<'a>> {
    let mut draws = Vec::new();
    if let Some(mesh) = doc {
        draws.push(MeshDraw {
            mesh,
            model: scene.model_to_world,
            color: DOC_COLOR,
            hidden: scene.hidden_vertices(),
        });
    }
    if let Some(mesh) = preview {
        draws.push(MeshDraw {
            mesh,
            model: scene.model_to_world * scene.preview_motion,
            color: PREVIEW_COLOR,
            hidden: None,
        });
    }
    draws
}

/// The headset's background (opaque blend).
pub const CLEAR: [f32; 4] = [0.02, 0.025, 0.035, 1.0];
/// The document's colour in the headset.
pub const DOC_COLOR: [f32; 4] = [0.62, 0.66, 0.72, 1.0];
/// The drag preview's colour in the headset.
pub const PREVIEW_COLOR: [f32; 4] = [0.95, 0.75, 0.35, 1.0];
