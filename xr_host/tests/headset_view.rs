//! The headset view of the lamp session (issue 19) with the palette open
//! and a drag in progress, rendered by the host's own renderer on
//! lavapipe: the palette's panel, its active (blue) buttons and their
//! white labels are on screen where the core placed the palette, next to
//! the model; the status line and drag readout are drawn too. The image
//! is written to `target/headset_view.png` (the README's picture).

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
    let half_x = (half_y.tan() * w as f32 / h as f32).atan();
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
