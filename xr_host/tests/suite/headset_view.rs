//! The headset view of the lamp session (issue 19) with the palette open
//! and a drag in progress, rendered by the host's own renderer on
//! lavapipe: the palette's panel, its active (blue) buttons and their
//! white labels are on screen where the core placed the palette, next to
//! the model; the status line and drag readout are drawn too. The image
//! is written to `target/headset_view.png` (the README's picture).

use shapewright::math::fm::DetMath as _;
use std::sync::Arc;

use glam::Vec4;
use shapewright::doc::OpLog;
use shapewright::interact::Trace;
use shapewright_xr::gfx::GpuContext;
use shapewright_xr::interaction::Interaction;
use shapewright_xr::render::{render_scene, write_png};

#[test]
fn the_headset_view_shows_the_palette_with_labels_next_to_the_model() {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let text = std::fs::read_to_string(root.join("tests/data/lamp_session.trace.jsonl")).unwrap();
    let trace = Trace::from_jsonl(&text).unwrap();
    let session = trace.header.session().unwrap();
    let mut it = Interaction::with_session(session, OpLog::new(), None).unwrap();
    let t0 = trace.frames[0].time;
    // 43.5 s: the shade is being dragged, the palette is open.
    for f in trace.frames.iter().take_while(|f| f.time - t0 <= 43.5) {
        it.step(f);
        it.flush();
    }
    let view = it
        .session()
        .palette()
        .cloned()
        .expect("the palette is open");
    assert!(
        it.session().preview().moving.is_some(),
        "a drag in progress"
    );
    assert!(!it.session().preview().readout.is_empty());
    let head = it.session().last_frame().unwrap().head.unwrap();
    let pose = (head.position.as_vec3(), head.orientation.as_quat());
    let (w, h) = (1280u32, 800u32);
    let ctx = Arc::new(GpuContext::new_offscreen().expect("a Vulkan 1.1 device (lavapipe)"));
    let img = render_scene(&ctx, it.scene(), pose, w, h, 70.0).unwrap();
    write_png(&img, &root.join("target/headset_view.png")).unwrap();
    // Where the palette's centre lands on screen (the camera render_scene
    // uses: 70 degrees vertical).
    let half_y = 35f32.to_radians();
    let half_x = (half_y.ftan() * w as f32 / h as f32).fatan();
    let cam = shapewright_xr::render::eye_camera(
        pose.0,
        pose.1,
        [-half_x, half_x, half_y, -half_y],
        0.05,
        50.0,
    );
    let c = cam.view_proj * Vec4::from((view.pose.position.as_vec3(), 1.0));
    let (cx, cy) = (
        ((c.x / c.w) * 0.5 + 0.5) * w as f32,
        ((c.y / c.w) * 0.5 + 0.5) * h as f32,
    );
    assert!(cx > 0.0 && cx < w as f32 && cy > 0.0 && cy < h as f32);
    // Around it: blue active buttons, white label pixels, the dark panel.
    let (mut blue, mut white, mut panel) = (0, 0, 0);
    let r = 160i64;
    for y in (cy as i64 - r).max(0)..(cy as i64 + r).min(h as i64) {
        for x in (cx as i64 - r).max(0)..(cx as i64 + r).min(w as i64) {
            let [pr, pg, pb, _] = img.pixel(x as u32, y as u32).unwrap();
            let (pr, pg, pb) = (pr as i32, pg as i32, pb as i32);
            if pb > 150 && pb > pr + 60 && pg < pb {
                blue += 1;
            }
            if pr > 220 && pg > 220 && pb > 220 {
                white += 1;
            }
            if (pr - pg).abs() < 12 && pb > pr && pr < 80 && pr > 40 {
                panel += 1;
            }
        }
    }
    println!("palette at ({cx:.0}, {cy:.0}): blue {blue}, white {white}, panel {panel}");
    assert!(blue > 500, "active buttons: {blue} blue pixels");
    assert!(white > 200, "labels: {white} white pixels");
    assert!(panel > 2000, "panel: {panel} pixels");
    // The model is drawn too (its grey, away from the palette).
    let model = (0..h)
        .flat_map(|y| (0..w).map(move |x| (x, y)))
        .filter(|&(x, y)| {
            let [r, _, b, _] = img.pixel(x, y).unwrap();
            (x as f32 - cx).abs() > 200.0 && r > 120 && (r as i32 - b as i32).abs() < 40
        })
        .count();
    assert!(model > 3000, "model: {model} pixels");
    // The dragged shade is drawn once, as the yellow preview moved by the
    // drag's matrix: the document leaves exactly its triangles out.
    let moving = it.session().preview().moving.as_ref().unwrap().id;
    let scene = it.scene().clone();
    assert_eq!(scene.hidden, Some(moving));
    let log = it.log();
    let doc = log.document();
    let mut next = 0;
    for (id, r) in &scene.document_objects {
        assert_eq!(r.start, next, "object ranges are contiguous");
        let tris = doc.get(*id).unwrap().mesh.triangles.len() as u32;
        assert_eq!(r.end - r.start, tris, "object {id:?}'s triangles");
        next = r.end;
    }
    let drawn = scene.document.as_ref().unwrap().triangles.len() as u32;
    assert_eq!(next, drawn, "every triangle belongs to one object");
    let (a, b) = scene.hidden_vertices().unwrap();
    let shade = doc.get(moving).unwrap().mesh.triangles.len() as u32;
    assert_eq!(b - a, 3 * shade);
    let yellow = (0..h)
        .flat_map(|y| (0..w).map(move |x| (x, y)))
        .filter(|&(x, y)| {
            let [r, g, b, _] = img.pixel(x, y).unwrap();
            r > 150 && g > 110 && (r as i32) > b as i32 + 50
        })
        .count();
    assert!(yellow > 2000, "the dragged shade: {yellow} yellow pixels");
}

/// The palette's mirror plane in the headset (issue 19): a sculpt sphere,
/// "Mirror x" picked, the right controller held beside the sphere: the
/// plane is drawn (violet square) and so is the mirrored brush, across
/// the plane from the real one. The image is `target/headset_mirror.png`.
#[test]
fn the_mirror_plane_and_the_mirrored_brush_are_drawn() {
    use shapewright::interact::testkit::{Button, Driver};
    use shapewright::interact::{Hand, PaletteAction, Pose};
    let mut d = Driver::new(72.0, "object");
    d.pick_tool("sculpt").unwrap().close_palette();
    d.puppet.click(Hand::Right, Button::Primary);
    d.sync();
    d.pick(|i| i.action == PaletteAction::Mirror).unwrap();
    d.close_palette();
    // The brush 12 cm right of the sphere's centre (world (0, 0.8, -0.5)).
    let brush = glam::DVec3::new(0.12, 0.82, -0.5);
    d.puppet
        .move_to(Hand::Right, Pose::new(brush, glam::DQuat::IDENTITY), 0.3)
        .wait(0.1);
    d.sync();
    let trace = d.trace("mirror plane");
    let mut it =
        Interaction::with_session(trace.header.session().unwrap(), OpLog::new(), None).unwrap();
    for f in &trace.frames {
        it.step(f);
        it.flush();
    }
    assert!(it.session().snap().mirror.is_some(), "mirror on");
    let violet = [0.85f32, 0.45, 1.0];
    let lines = &it.scene().lines;
    let plane: Vec<_> = lines.iter().filter(|v| v.color == violet).collect();
    assert_eq!(plane.len(), 12, "a square and a cross");
    // The plane x = 0 (model x is world x on the desk).
    assert!(plane.iter().all(|v| v.pos[0].abs() < 1e-5), "{plane:?}");
    // Brush circles on both sides of it, mirror images of each other.
    let brush_color = [0.5f32, 0.85, 1.0];
    let (mut right, mut left) = (Vec::new(), Vec::new());
    for v in lines.iter().filter(|v| v.color == brush_color) {
        if v.pos[0] > 0.0 {
            right.push(v.pos);
        } else {
            left.push(v.pos);
        }
    }
    assert!(!right.is_empty() && right.len() == left.len());
    // The same circles, mirrored: bounds mirrored across x = 0.
    let bounds = |pts: &[[f32; 3]], sx: f32| {
        pts.iter()
            .fold([f32::MAX, f32::MIN, f32::MAX, f32::MIN], |b, p| {
                [
                    b[0].min(sx * p[0]),
                    b[1].max(sx * p[0]),
                    b[2].min(p[1]),
                    b[3].max(p[1]),
                ]
            })
    };
    let (br, bl) = (bounds(&right, 1.0), bounds(&left, -1.0));
    println!("brush bounds {br:?}, mirrored {bl:?}");
    assert!(br.iter().zip(&bl).all(|(a, b)| (a - b).abs() < 1e-4));
    assert!(
        (br[0] + br[1]) / 2.0 > 0.1,
        "the brush is right of the plane"
    );
    // Seen from the right and above (the user's own head sees the plane
    // edge on): eye 45 cm from the sphere, looking at it.
    let (eye, at) = (
        glam::Vec3::new(0.3, 1.1, -0.25),
        glam::Vec3::new(0.0, 0.8, -0.5),
    );
    let z = (eye - at).normalize();
    let x = glam::Vec3::Y.cross(z).normalize();
    let look = glam::Quat::from_mat3(&glam::Mat3::from_cols(x, z.cross(x), z));
    let ctx = Arc::new(GpuContext::new_offscreen().expect("a Vulkan 1.1 device (lavapipe)"));
    let img = render_scene(&ctx, it.scene(), (eye, look), 1280, 800, 70.0).unwrap();
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    write_png(&img, &root.join("target/headset_mirror.png")).unwrap();
    let on_screen = (0..800)
        .flat_map(|y| (0..1280).map(move |x| (x, y)))
        .filter(|&(x, y)| {
            let [r, g, b, _] = img.pixel(x, y).unwrap();
            r > 150 && b > 200 && (g as i32) < r as i32 - 30
        })
        .count();
    assert!(
        on_screen > 100,
        "the plane on screen: {on_screen} violet pixels"
    );
}
