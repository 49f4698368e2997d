//! The Vulkan renderer on lavapipe (or any Vulkan 1.1 device): a box is
//! drawn where the camera puts it, shaded (several face brightnesses),
//! stereo eyes see it shifted the right way, lines land on their pixels.

use std::sync::Arc;

use glam::Vec3;
use shapewright::solid::{tessellate, SolidShape};
use shapewright_xr::gfx::{GpuContext, LineVertex, RgbaImage};
use shapewright_xr::render::{framing_camera, render_mesh, write_png, RenderSettings};

fn ctx() -> Arc<GpuContext> {
    Arc::new(
        GpuContext::new_offscreen().expect("a Vulkan 1.1 device (lavapipe: mesa-vulkan-drivers)"),
    )
}

fn object_pixels(img: &RgbaImage) -> Vec<(u32, u32, [u8; 4])> {
    let bg = img.pixel(0, 0).unwrap();
    let mut v = Vec::new();
    for y in 0..img.height {
        for x in 0..img.width {
            let p = img.pixel(x, y).unwrap();
            if p != bg {
                v.push((x, y, p));
            }
        }
    }
    v
}

fn centroid(px: &[(u32, u32, [u8; 4])]) -> (f64, f64) {
    let n = px.len() as f64;
    (
        px.iter().map(|p| p.0 as f64).sum::<f64>() / n,
        px.iter().map(|p| p.1 as f64).sum::<f64>() / n,
    )
}

fn cube() -> shapewright::mesh::TriMesh {
    let mut m = tessellate(
        &SolidShape::Box {
            size: [1.0, 1.0, 1.0],
        },
        16,
    )
    .unwrap();
    m.compute_normals();
    m
}

#[test]
fn box_renders_shaded_and_centered() {
    let ctx = ctx();
    let settings = RenderSettings {
        width: 160,
        height: 120,
        ..Default::default()
    };
    let img = render_mesh(&ctx, &cube(), &[], &settings, false)
        .unwrap()
        .remove(0);
    assert_eq!(img.pixels.len(), 160 * 120 * 4);
    let out = std::env::temp_dir().join("shapewright_xr_render_box.png");
    write_png(&img, &out).unwrap();
    assert!(std::fs::metadata(&out).unwrap().len() > 100);

    let bg = img.pixel(0, 0).unwrap();
    for (x, y) in [(0, 0), (159, 0), (0, 119), (159, 119)] {
        assert_eq!(
            img.pixel(x, y).unwrap(),
            bg,
            "corner ({x},{y}) is background"
        );
    }
    let center = img.pixel(80, 60).unwrap();
    assert_ne!(center, bg, "the box covers the image center");
    let px = object_pixels(&img);
    let coverage = px.len() as f64 / (160.0 * 120.0);
    // The bounding sphere of the box fills the smaller image side; a cube
    // seen from a corner covers roughly 10-40% of such a frame.
    assert!((0.08..0.45).contains(&coverage), "coverage {coverage}");
    let (cx, cy) = centroid(&px);
    assert!(
        (cx - 80.0).abs() < 8.0 && (cy - 60.0).abs() < 8.0,
        "centroid ({cx},{cy})"
    );
    // Three visible faces, three distinct flat shades (count shades that
    // cover at least 3% of the object).
    let mut counts = std::collections::HashMap::new();
    for p in &px {
        *counts.entry(p.2).or_insert(0usize) += 1;
    }
    let big = counts.values().filter(|&&c| c * 33 > px.len()).count();
    assert!(big >= 3, "expected 3 face shades, got {big}: {counts:?}");
    // Opaque and not clipped to black.
    assert!(px.iter().all(|p| p.2[3] == 255));
    assert!(px.iter().any(|p| p.2[0] > 100));
}

#[test]
fn stereo_eyes_see_parallax() {
    let ctx = ctx();
    let settings = RenderSettings {
        width: 128,
        height: 96,
        ..Default::default()
    };
    let imgs = render_mesh(&ctx, &cube(), &[], &settings, true).unwrap();
    assert_eq!(imgs.len(), 2);
    let (lx, _) = centroid(&object_pixels(&imgs[0]));
    let (rx, _) = centroid(&object_pixels(&imgs[1]));
    // The left eye sits left of the right eye, so the object appears
    // further right in the left image.
    assert!(lx > rx + 1.0, "left {lx} right {rx}");
    assert_ne!(imgs[0], imgs[1]);
}

#[test]
fn lines_land_on_projected_pixels() {
    let ctx = ctx();
    let settings = RenderSettings {
        width: 100,
        height: 100,
        ..Default::default()
    };
    let mesh = cube();
    // A vertical red segment from the box's top face center upwards: its
    // projected endpoints bound the red pixels.
    let (lo, hi) = mesh.bbox().unwrap();
    let top =
        (lo.as_vec3() + hi.as_vec3()) * 0.5 * Vec3::new(1.0, 1.0, 0.0) + Vec3::Z * hi.z as f32;
    let a = top;
    let b = top + Vec3::Z * 0.25;
    let red = [1.0, 0.0, 0.0];
    let lines = [
        LineVertex {
            pos: a.to_array(),
            color: red,
        },
        LineVertex {
            pos: b.to_array(),
            color: red,
        },
    ];
    let img = render_mesh(&ctx, &mesh, &lines, &settings, false)
        .unwrap()
        .remove(0);
    let reds: Vec<_> = object_pixels(&img)
        .into_iter()
        .filter(|p| p.2[0] > 200 && p.2[1] < 40 && p.2[2] < 40)
        .collect();
    assert!(reds.len() >= 5, "{} red pixels", reds.len());
    // Same camera as render_mesh uses: project the endpoints.
    let cam = framing_camera(lo.as_vec3(), hi.as_vec3(), &settings, 0.0);
    let to_px = |p: Vec3| {
        let c = cam.view_proj * p.extend(1.0);
        let n = c / c.w;
        ((n.x + 1.0) * 50.0, (n.y + 1.0) * 50.0)
    };
    let (ax, ay) = to_px(a);
    let (bx, by) = to_px(b);
    for (x, y, _) in &reds {
        let (x, y) = (*x as f32 + 0.5, *y as f32 + 0.5);
        assert!(
            x >= ax.min(bx) - 2.0 && x <= ax.max(bx) + 2.0,
            "x {x} outside [{ax},{bx}]"
        );
        assert!(
            y >= ay.min(by) - 2.0 && y <= ay.max(by) + 2.0,
            "y {y} outside [{ay},{by}]"
        );
    }
}

#[test]
fn bad_input_gets_typed_errors() {
    let ctx = ctx();
    let empty = shapewright::mesh::TriMesh::default();
    let e = render_mesh(&ctx, &empty, &[], &RenderSettings::default(), false).unwrap_err();
    assert!(e.to_string().contains("no triangles"), "{e}");
    let mut nan = cube();
    nan.positions[0][0] = f64::NAN;
    let e = render_mesh(&ctx, &nan, &[], &RenderSettings::default(), false).unwrap_err();
    assert!(e.to_string().contains("non-finite"), "{e}");
    let zero = RenderSettings {
        width: 0,
        ..Default::default()
    };
    let e = render_mesh(&ctx, &cube(), &[], &zero, false).unwrap_err();
    assert!(e.to_string().contains("bad image size"), "{e}");
}

/// Pixels where red clearly dominates (the back-face tint).
fn reddish(px: &[(u32, u32, [u8; 4])]) -> usize {
    px.iter()
        .filter(|p| p.2[0] as u32 > 2 * p.2[1] as u32 + 10 && p.2[0] > 40)
        .count()
}

#[test]
fn back_faces_are_tinted_by_winding_not_by_smooth_normals() {
    let ctx = ctx();
    let settings = RenderSettings {
        width: 160,
        height: 120,
        ..Default::default()
    };
    // A smooth sphere: its vertex normals turn away from the eye just
    // inside the silhouette, but every visible triangle is a front face.
    let mut sphere = tessellate(&SolidShape::Sphere { radius: 1.0 }, 48).unwrap();
    sphere.compute_normals();
    let img = render_mesh(&ctx, &sphere, &[], &settings, false)
        .unwrap()
        .remove(0);
    let px = object_pixels(&img);
    assert!(px.len() > 1000);
    assert_eq!(reddish(&px), 0, "front faces drawn as back faces");
    // Turned inside out, every visible triangle is a back face.
    for t in &mut sphere.triangles {
        t.swap(1, 2);
    }
    let img = render_mesh(&ctx, &sphere, &[], &settings, false)
        .unwrap()
        .remove(0);
    let px = object_pixels(&img);
    assert!(
        reddish(&px) * 10 > px.len() * 8,
        "{} of {}",
        reddish(&px),
        px.len()
    );
}
