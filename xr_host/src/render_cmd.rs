//! `render FILE.(stl|obj) --png OUT.png`: draws a mesh with the host's own
//! Vulkan renderer (lavapipe works) and writes a PNG.

use std::path::Path;

use anyhow::{Context, Result};
use shapewright_xr::render::{render_mesh_png, RenderSettings};

use crate::cmd::read_mesh;

/// Renders `file` to `png` at `width`×`height`.
pub fn render(file: &Path, png: &Path, width: u32, height: u32) -> Result<()> {
    let mut mesh = read_mesh(file)?;
    mesh.ensure_normals();
    let settings = RenderSettings {
        width,
        height,
        ..Default::default()
    };
    let image = render_mesh_png(&mesh, png, &settings)
        .with_context(|| format!("rendering {}", file.display()))?;
    let background = image.pixel(0, 0).unwrap_or_default();
    let covered = image
        .pixels
        .chunks_exact(4)
        .filter(|p| **p != background)
        .count();
    println!(
        "{} -> {} ({}x{}, {} triangles, {:.1}% of pixels covered)",
        file.display(),
        png.display(),
        image.width,
        image.height,
        mesh.triangle_count(),
        100.0 * covered as f64 / (image.width * image.height) as f64
    );
    Ok(())
}
