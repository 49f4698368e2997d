//! The document's print setup (issue 17): the wall thickness that makes
//! surfaces solid (`set_wall_thickness`), and what a GC or sculpt edit that
//! folds its object through itself does (`set_self_intersection_policy`:
//! refused by default, or applied and flagged so every print exit names the
//! object).
//!
//! Asserted: the thickened lampshade's volume is its area times the
//! document's thickness (so it scales with the setting); the setting is
//! range-checked with the field's name, survives a snapshot round trip,
//! replay and undo bit-identically; a crossing GC spine and a folding
//! sculpt stroke are refused with a typed error naming the object and leave
//! the document unchanged; under `flag` they apply and printing refuses
//! naming the object.

use shapewright::doc::{document_size, print_document, print_document_scaled, PrintScale};
use shapewright::doc::{Document, LogError, Op, OpError, OpLog};
use shapewright::mesh::{
    manifold_accepts, read_stl, self_intersections, validate, write_stl, ValidationSettings,
};
use shapewright::print::{
    PrintControl, PrintError, PrintSettings, SelfIntersectionPolicy, SetWallThickness, Treatment,
    MAX_WALL_THICKNESS, MIN_WALL_THICKNESS,
};

use crate::common;
use common::{crossing_sculpt, data, run};

fn op(json: &str) -> Op {
    serde_json::from_str(json).unwrap_or_else(|e| panic!("{json}: {e}"))
}

fn thickness_op(thickness: f64) -> Op {
    Op::SetWallThickness(SetWallThickness { thickness })
}

/// The printed volume of `log`'s document, after writing and reading back
/// the STL and checking it with both checkers.
fn printed_volume(log: &OpLog) -> f64 {
    let p = print_document(log.document(), &PrintSettings::default()).unwrap();
    let mut bytes = Vec::new();
    write_stl(&p.mesh, &mut bytes).unwrap();
    let back = read_stl(&bytes).unwrap();
    let r = validate(&back, &ValidationSettings::default());
    assert!(r.is_printable(), "{}", r.problems());
    assert!(manifold_accepts(&back));
    r.signed_volume
}

#[test]
fn the_thickened_lampshade_volume_scales_with_the_document_wall_thickness() {
    let base = run(&data("lampshade.jsonl"));
    let doc = base.document();
    assert_eq!(doc.print_setup().wall_thickness, 0.002, "default 2 mm");
    let (_, obj) = doc.objects().next().unwrap();
    let area = validate(&obj.mesh, &ValidationSettings::topology_only()).area;
    let mut vols = Vec::new();
    for t in [0.001, 0.002, 0.004] {
        let mut log = base.clone();
        log.apply(thickness_op(t)).unwrap();
        let p = print_document(log.document(), &PrintSettings::default()).unwrap();
        assert_eq!(
            p.report.parts[0].treatment,
            Treatment::Thickened {
                thickness: t,
                offset: Default::default(),
                boundary_edges: match p.report.parts[0].treatment {
                    Treatment::Thickened { boundary_edges, .. } => boundary_edges,
                    _ => 0,
                },
            }
        );
        let v = printed_volume(&log);
        // Area x thickness, up to the rim walls and curvature.
        assert!(
            (v - area * t).abs() / (area * t) < 0.03,
            "t = {t}: volume {v} vs {}",
            area * t
        );
        vols.push(v);
    }
    // Doubling the wall doubles the volume (to the same few percent).
    assert!((vols[1] / vols[0] - 2.0).abs() < 0.06, "{vols:?}");
    assert!((vols[2] / vols[1] - 2.0).abs() < 0.06, "{vols:?}");
}

/// Scale to fit with open surfaces: the walls keep their thickness, so the
/// scale taken from the objects' box leaves the thickened lampshade a wall
/// too big for a bed exactly half its size; the print shrinks the scale
/// until the printed model fits, and no further than a few tenths of a
/// percent below what fits. A model that fits stays at true size; a given
/// factor is printed as given.
#[test]
fn scale_to_fit_fits_the_printed_model_walls_included() {
    let mut log = run(&data("lampshade.jsonl"));
    let e = document_size(log.document()).unwrap().extent();
    let bed = e.map(|v| v * 0.5);
    log.apply(op(&format!(
        r#"{{"op": "set_printer", "printer": "custom", "size": [{}, {}, {}]}}"#,
        bed[0], bed[1], bed[2]
    )))
    .unwrap();
    let doc = log.document();
    let control = PrintControl::default();
    let settings = PrintSettings::default();
    let fitted = print_document_scaled(doc, &settings, PrintScale::ToFit, &control).unwrap();
    let printed = fitted.printable.report.size().unwrap();
    let fit = printed.fit(&doc.print_setup().printer);
    assert!(
        fit.fits,
        "scaled to {} the print is {:?} mm for a {:?} mm bed",
        fitted.scale,
        printed.extent_mm(),
        bed.map(|v| v * 1e3)
    );
    // The box alone gave 0.5; the 2 mm wall (4 mm across) pushes it down.
    assert!(
        fitted.scale < 0.5 && fitted.scale > 0.45,
        "{}",
        fitted.scale
    );
    assert_eq!((fitted.scale * 1000.0).round(), fitted.scale * 1000.0);
    let line = fitted.scaled_line().expect("a scaled model says so");
    assert!(
        line.starts_with(&format!("scaled to {:.1}%", fitted.scale * 100.0)),
        "{line}"
    );

    let mut true_size = run(&data("lampshade.jsonl"));
    true_size
        .apply(op(
            r#"{"op": "set_printer", "printer": "custom", "size": [1, 1, 1]}"#,
        ))
        .unwrap();
    let asis = print_document_scaled(true_size.document(), &settings, PrintScale::ToFit, &control)
        .unwrap();
    assert_eq!((asis.scale, asis.too_big.is_none()), (1.0, true));
    // A bed exactly the objects' box: the box fits, the walls do not, so
    // the fitted print is scaled down and says so.
    let mut snug = run(&data("lampshade.jsonl"));
    snug.apply(op(&format!(
        r#"{{"op": "set_printer", "printer": "custom", "size": [{}, {}, {}]}}"#,
        e[0], e[1], e[2]
    )))
    .unwrap();
    let snugged =
        print_document_scaled(snug.document(), &settings, PrintScale::ToFit, &control).unwrap();
    assert!(snugged.scale < 1.0, "{}", snugged.scale);
    let line = snugged
        .scaled_line()
        .expect("a model scaled to fit says so");
    assert!(line.contains("at true size it is"), "{line}");
    let half = print_document_scaled(doc, &settings, PrintScale::By(0.5), &control).unwrap();
    assert_eq!((half.scale, half.scaled_line()), (0.5, None));
}

#[test]
fn the_wall_thickness_is_range_checked_naming_the_field() {
    let mut log = run(&data("lampshade.jsonl"));
    let before = log.document().content_hash();
    for bad in [
        0.0,
        -0.002,
        MIN_WALL_THICKNESS * 0.99,
        MAX_WALL_THICKNESS * 1.01,
        2.0,
        f64::INFINITY,
        f64::NAN,
    ] {
        let e = log.apply(thickness_op(bad)).unwrap_err().to_string();
        assert!(e.contains("thickness"), "{bad}: {e}");
        assert_eq!(log.document().content_hash(), before);
    }
    // The bounds themselves apply.
    for ok in [MIN_WALL_THICKNESS, MAX_WALL_THICKNESS] {
        log.clone().apply(thickness_op(ok)).unwrap();
    }
    // A snapshot holding an out-of-range setting is refused naming it.
    let bad = r#"{"last_id":0,"print":{"wall_thickness":5.0},"objects":[]}"#;
    let e = serde_json::from_str::<Document>(bad)
        .unwrap_err()
        .to_string();
    assert!(e.contains("wall_thickness"), "{e}");
}

#[test]
fn the_setting_survives_snapshot_replay_and_undo_bit_identically() {
    let mut log = run(&data("lampshade.jsonl"));
    let default_hash = log.document().content_hash();
    // A default setup serializes as before the setting existed.
    let text = serde_json::to_string(log.document()).unwrap();
    assert!(!text.contains("\"print\""), "{text}");
    log.apply(thickness_op(0.003)).unwrap();
    log.apply(op(REFUSE)).unwrap();
    let doc = log.document();
    assert_ne!(doc.content_hash(), default_hash, "the setting is content");
    assert_eq!(doc.print_setup().wall_thickness, 0.003);
    assert_eq!(
        doc.print_setup().on_self_intersection,
        SelfIntersectionPolicy::Refuse
    );
    let vol = printed_volume(&log);
    // Snapshot (what a USD file stores beside the ops).
    let text = serde_json::to_string(doc).unwrap();
    let back: Document = serde_json::from_str(&text).unwrap();
    assert_eq!(back.content_hash(), doc.content_hash());
    assert_eq!(back.print_setup(), doc.print_setup());
    // Replay of the recorded ops (each as its JSON line).
    let lines: Vec<Op> = log
        .ops()
        .iter()
        .map(|o| serde_json::from_str(&serde_json::to_string(o).unwrap()).unwrap())
        .collect();
    let replayed = OpLog::replay(lines, log.cursor()).unwrap();
    assert_eq!(replayed.document().content_hash(), doc.content_hash());
    assert_eq!(printed_volume(&replayed).to_bits(), vol.to_bits());
    // Undo restores the previous setting, redo the new one.
    log.undo().unwrap();
    log.undo().unwrap();
    assert_eq!(log.document().content_hash(), default_hash);
    log.redo().unwrap();
    assert_eq!(log.document().print_setup().wall_thickness, 0.003);
}

/// A straight tube 8 cm in radius, 20 cm long.
fn tube() -> &'static str {
    r#"{"op":"gc_create","spine":[[0,0,0],[0,0,0.2]],"plane_normal":[0,1,0],"sections":[{"profile":{"template":"circle","radius":0.08},"v":0.0},{"profile":{"template":"circle","radius":0.08},"v":1.0}]}"#
}
/// A right-angle bend whose radius (about 5 cm) is tighter than the tube
/// (8 cm): the inner side of the bend passes through itself (the mesh
/// stays closed and positive, so only the intersection search sees it).
const CROSSING_SPINE: &str = r#"{"op":"gc_replace_spine","id":1,"points":[[0,0,0],[0,0,0.1],[0.1,0,0.1]],"plane_normal":[0,1,0]}"#;
const MILD_SPINE: &str = r#"{"op":"gc_replace_spine","id":1,"points":[[0,0,0],[0.01,0,0.1],[0,0,0.2]],"plane_normal":[0,1,0]}"#;

const REFUSE: &str = r#"{"op":"set_self_intersection_policy","policy":"refuse"}"#;

fn refused_as_folding(r: Result<shapewright::doc::OpOutcome, LogError>, label: &str) {
    match r {
        Err(LogError::Op(OpError::Print(e @ PrintError::SelfIntersecting { .. }))) => {
            assert!(e.to_string().contains(label), "{e}")
        }
        other => panic!("expected a self-intersection refusal naming {label}, got {other:?}"),
    }
}

#[test]
fn a_gc_spine_bent_tighter_than_its_sections_is_refused_under_refuse() {
    assert_eq!(
        Document::new().print_setup().on_self_intersection,
        SelfIntersectionPolicy::Flag,
        "flag is the default"
    );
    let mut log = run(&format!("{REFUSE}\n{}", tube()));
    log.apply(op(MILD_SPINE)).unwrap();
    let before = log.document().content_hash();
    let (ops_before, cursor_before) = (log.ops().len(), log.cursor());
    refused_as_folding(log.apply(op(CROSSING_SPINE)), "#1 gc_assembly");
    assert_eq!(log.document().content_hash(), before, "document unchanged");
    assert_eq!((log.ops().len(), log.cursor()), (ops_before, cursor_before));
    // Under `flag` the same edit applies, and printing names the object.
    log.apply(op(
        r#"{"op":"set_self_intersection_policy","policy":"flag"}"#,
    ))
    .unwrap();
    log.apply(op(CROSSING_SPINE)).unwrap();
    let (_, obj) = log.document().objects().next().unwrap();
    assert!(!self_intersections(&obj.mesh).pairs.is_empty());
    match print_document(log.document(), &PrintSettings::default()) {
        Err(e @ PrintError::SelfIntersecting { .. }) => {
            assert!(e.to_string().contains("#1 gc_assembly"), "{e}")
        }
        Err(e) => panic!("expected a self-intersection, got {e}"),
        Ok(_) => panic!("a self-intersecting GC printed"),
    }
    // Back under `refuse`, an object that already intersects itself can
    // still be edited (here: unfolded), and the unfolded one prints.
    log.apply(op(
        r#"{"op":"set_self_intersection_policy","policy":"refuse"}"#,
    ))
    .unwrap();
    log.apply(op(MILD_SPINE)).unwrap();
    print_document(log.document(), &PrintSettings::default()).unwrap();
}

#[test]
fn a_gc_created_bent_through_itself_is_refused() {
    let text = r#"{"op":"gc_create","spine":[[0,0,0],[0,0,0.1],[0.1,0,0.1]],"plane_normal":[0,1,0],"sections":[{"profile":{"template":"circle","radius":0.08},"v":0.0},{"profile":{"template":"circle","radius":0.08},"v":1.0}]}"#;
    let mut log = run(REFUSE);
    refused_as_folding(log.apply(op(text)), "#1 gc_assembly");
    assert!(log.document().is_empty());
}

/// One drag frame pulls the top of the sphere straight down through the
/// bottom. Each triangle could keep its shape, but the surface would pass
/// through itself: until issue 33's crossing guard it did, and `refuse`
/// refused the stroke.
const THROUGH_STROKE: &str = "{\"op\":\"sculpt_stroke\",\"id\":1,\"settings\":{\"brush\":{\"kind\":\"sphere\",\"radius\":0.3},\"brush_scale\":1.0,\"influence\":0.2,\"falloff\":\"smooth\",\"warp\":{\"kind\":\"drag\"},\"max_edge_rel\":0.5,\"min_edge_rel\":0.1},\"samples\":[\
    {\"position\":[0,0,1],\"rotation\":[0,0,0,1],\"pressure\":1},\
    {\"position\":[0,0,-1.6],\"rotation\":[0,0,0,1],\"pressure\":1}]}";
const SPHERE: &str =
    r#"{"op":"sculpt_create","base":{"kind":"sphere","radius":1.0,"edge_length":0.1}}"#;

#[test]
fn a_stroke_through_the_sculpt_stops_short_and_a_crossing_sculpt_is_refused_under_refuse() {
    // The stroke applies under either policy: the sculpt's guards put back
    // the steps that would make the surface cross, and the result prints.
    let mut log = run(&format!("{REFUSE}\n{SPHERE}"));
    let before = log.document().content_hash();
    log.apply(op(THROUGH_STROKE)).unwrap();
    assert_ne!(
        log.document().content_hash(),
        before,
        "the stroke did something"
    );
    let (_, obj) = log.document().objects().next().unwrap();
    assert!(self_intersections(&obj.mesh).pairs.is_empty());
    print_document(log.document(), &PrintSettings::default()).unwrap();
    // A sculpt whose base already crosses itself: refused under `refuse`,
    // naming it, with the document unchanged; by default (flag) it applies
    // and printing names it.
    let crossing = crossing_sculpt();
    let mut log = run(REFUSE);
    let before = log.document().content_hash();
    refused_as_folding(log.apply(op(&crossing)), "#1 sculpt_mesh");
    assert_eq!(log.document().content_hash(), before);
    let free = run(&crossing);
    match print_document(free.document(), &PrintSettings::default()) {
        Err(e @ PrintError::SelfIntersecting { .. }) => {
            assert!(e.to_string().contains("#1 sculpt_mesh"), "{e}")
        }
        other => panic!("expected a self-intersection naming the sculpt, got {other:?}"),
    }
}
