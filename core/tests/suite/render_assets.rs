//! Writes the meshes of issue 18's renders (ignored in the suite; run by
//! `scripts/render_issue18.sh`, which renders them to `docs/images/`):
//!
//! - `teapot_before.stl`, `teapot_edited.stl`: the teapot example, then
//!   its body's spine replaced by a bent one (`gc_replace_spine`) and its
//!   spout slid 3 cm down the body (`gc_transform_part`): the handle and
//!   spout follow the body, the spout turns with the surface (the body
//!   assembly only: the lid is a separate object);
//! - `hexagon.stl`, `hexagon_shaped.stl`: the documents made by
//!   `scripts/styling/make_ngon_patch.py` (in `SHAPEWRIGHT_NGON_DIR`),
//!   whose caps are 6-sided patches (the second pulled into a dome,
//!   sharpened and smoothed);
//! - `library_sheet.stl`: every library component, each scaled into a cell
//!   of a grid, in catalogue order (rows of 10).
//!
//! `SHAPEWRIGHT_RENDER_DIR` names the output directory.

use crate::common;

use glam::{DAffine3, DVec3};
use shapewright::doc::{Edit, ObjectId, ObjectKind, Op, OpLog};
use shapewright::gc::{GcReplaceSpine, PartId};
use shapewright::mesh::{validate, write_stl, TriMesh};

fn out_dir() -> std::path::PathBuf {
    std::path::PathBuf::from(
        std::env::var("SHAPEWRIGHT_RENDER_DIR").expect("SHAPEWRIGHT_RENDER_DIR"),
    )
}

fn save(mesh: &TriMesh, name: &str) {
    let path = out_dir().join(name);
    let mut f = std::io::BufWriter::new(std::fs::File::create(&path).expect("create"));
    write_stl(mesh, &mut f).expect("write");
    eprintln!(
        "wrote {} ({} triangles)",
        path.display(),
        mesh.triangles.len()
    );
}

/// The teapot assembly's union (object 1; the lid is another object and
/// does not follow the body's edits).
fn body_union(log: &OpLog) -> TriMesh {
    let ObjectKind::GcAssembly(asm) = &log.document().get(ObjectId(1)).expect("teapot").kind else {
        panic!("not an assembly")
    };
    shapewright::assembly::union_mesh(asm).expect("union")
}

#[test]
#[ignore = "writes render inputs; run by scripts/render_issue18.sh"]
fn write_render_meshes() {
    std::fs::create_dir_all(out_dir()).expect("out dir");
    // The teapot, then a spine replace and a spout slide.
    let path = format!("{}/../tests/data/teapot.jsonl", env!("CARGO_MANIFEST_DIR"));
    let mut log = common::run(&std::fs::read_to_string(path).expect("teapot"));
    save(&body_union(&log), "teapot_before.stl");
    log.apply(Op::GcReplaceSpine(Edit::new(
        ObjectId(1),
        GcReplaceSpine {
            part: PartId(0),
            points: vec![
                DVec3::ZERO,
                DVec3::new(-0.01, 0.0, 0.09),
                DVec3::new(0.0, 0.0, 0.18),
            ],
            plane_normal: DVec3::Y,
        },
    )))
    .expect("replace spine");
    let ObjectKind::GcAssembly(asm) = &log.document().get(ObjectId(1)).expect("teapot").kind else {
        panic!("not an assembly")
    };
    let surf = asm.parts[0].gc.surface().expect("surface");
    let att = asm.parts[1].attach.expect("anchored");
    let anchor = surf.point(att.start.u, att.start.v);
    common::slide(&mut log, ObjectId(1), 1, &surf, anchor, -DVec3::Z * 0.03).expect("slide");
    let edited = body_union(&log);
    let r = validate(&edited, &Default::default());
    eprintln!(
        "edited teapot: closed {}, components {}, genus {:?}",
        r.is_closed(),
        r.components,
        r.genus
    );
    save(&edited, "teapot_edited.stl");

    // The 6-sided patches.
    if let Ok(dir) = std::env::var("SHAPEWRIGHT_NGON_DIR") {
        for name in ["hexagon", "hexagon_shaped"] {
            let p = std::path::Path::new(&dir).join(format!("{name}.jsonl"));
            let log = common::run(&std::fs::read_to_string(p).expect("ngon script"));
            save(&log.document().combined_mesh(), &format!("{name}.stl"));
        }
    }

    // The library sheet.
    let mut sheet = TriMesh::default();
    let cell = 1.0;
    for (i, e) in shapewright::sdf::library::catalog().iter().enumerate() {
        let mut m = e.mesh();
        let Some((lo, hi)) = m.bbox() else { continue };
        let size = (hi - lo).max_element().max(1e-9);
        let centre = (lo + hi) * 0.5;
        let (row, col) = (i / 10, i % 10);
        let at = DVec3::new(col as f64 * cell, -(row as f64) * 1.3 * cell, 0.0);
        m.transform(
            &(DAffine3::from_translation(at)
                * DAffine3::from_scale(DVec3::splat(0.8 * cell / size))
                * DAffine3::from_translation(-centre)),
        );
        sheet.append(&m);
    }
    eprintln!("{} components", shapewright::sdf::library::catalog().len());
    save(&sheet, "library_sheet.stl");
}
