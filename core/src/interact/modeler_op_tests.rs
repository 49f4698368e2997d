//! The SPEC ops issue 19 asks to reach from the headset, each driven the
//! way a user does it: the tool and its choice picked from the palette by
//! the dominant controller's ray, then the puppet's hands acting; each
//! test checks the op was emitted, applied, and did what it is for.

use crate::doc::{AddSolid, Object, ObjectId, ObjectKind, Op, OpLog, ScriptCommand};
use crate::interact::testkit::{Button, Driver};
use crate::interact::{Hand, Pose};
use crate::math::{DQuat, DVec3, Transform};
use crate::solid::SolidShape;

const R: Hand = Hand::Right;
const L: Hand = Hand::Left;

/// The index of group `name` of the active tool and of its option `label`.
fn choice(d: &Driver, name: &str, label: &str) -> (usize, usize) {
    let groups = d.session().tool().choices();
    let g = groups
        .iter()
        .position(|g| g.name == name)
        .unwrap_or_else(|| panic!("no group {name}"));
    let o = groups[g]
        .options
        .iter()
        .position(|o| o == label)
        .unwrap_or_else(|| panic!("no {label} in {name}: {:?}", groups[g].options));
    (g, o)
}

fn pick(d: &mut Driver, name: &str, label: &str) {
    d.open_palette();
    let (g, o) = choice(d, name, label);
    d.pick_choice(g, o).unwrap();
}

/// Loads an op script of `tests/data` into the driver's log.
fn load(d: &mut Driver, name: &str) {
    let text = std::fs::read_to_string(
        std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../tests/data")
            .join(name),
    )
    .unwrap();
    for l in text
        .lines()
        .filter(|l| !l.trim().is_empty() && !l.starts_with('#'))
    {
        d.log.apply(serde_json::from_str(l).unwrap()).unwrap();
    }
}

fn object(log: &OpLog, id: ObjectId) -> &Object {
    log.document().get(id).unwrap()
}

fn grip(d: &Driver, hand: Hand) -> Pose {
    d.puppet.frames().last().unwrap().controllers[hand.index()]
        .unwrap()
        .grip
}

fn closed(mesh: &crate::mesh::TriMesh) -> bool {
    crate::mesh::validate(mesh, &Default::default()).is_closed_manifold()
}

fn last_op(d: &Driver) -> &Op {
    match d.commands.last() {
        Some(ScriptCommand::Op(op)) => op,
        other => panic!("no op: {other:?}"),
    }
}

/// A sculpt sphere (the tool's `primary`), returning its id. The desk
/// puts the model origin at (0, 0.8, -0.5), model +Z up.
fn sculpt_sphere(d: &mut Driver) -> ObjectId {
    d.pick_tool("sculpt").unwrap().close_palette();
    d.puppet.click(R, Button::Primary);
    d.sync();
    let (id, _) = d.log.document().objects().last().unwrap();
    assert!(matches!(object(&d.log, id).kind, ObjectKind::SculptMesh(_)));
    id
}

/// A stroke with the right controller from `from` along `path` (world
/// offsets), trigger fully down.
fn stroke(d: &mut Driver, from: DVec3, path: &[DVec3]) {
    d.close_palette();
    d.puppet
        .move_to(R, Pose::new(from, DQuat::IDENTITY), 0.2)
        .set(R, Button::Select, true);
    for p in path {
        d.puppet
            .move_to(R, Pose::new(from + *p, DQuat::IDENTITY), 0.15);
    }
    d.puppet.set(R, Button::Select, false).wait(0.1);
    d.sync();
}

/// Paper 4 §4.4: "explode" pushes the surface away from a brush inside
/// the sphere (its volume grows), "collapse" pulls it in (it shrinks).
#[test]
pub(crate) fn explode_and_collapse_presets_grow_and_shrink_the_sculpt() {
    let mut d = Driver::new(72.0, "object");
    let id = sculpt_sphere(&mut d);
    let volume = |d: &Driver| object(&d.log, id).mesh.signed_volume();
    let v0 = volume(&d);
    // Brush centre 4 cm below the top of the 10 cm sphere, moved 2 cm.
    let inside = DVec3::new(0.0, 0.86, -0.5);
    let path = [DVec3::new(0.01, 0.0, 0.0), DVec3::new(0.02, 0.0, 0.01)];
    let mut volumes = vec![v0];
    for (preset, sign) in [("explode", 1.0), ("collapse", -1.0)] {
        pick(&mut d, "Brush", preset);
        stroke(&mut d, inside, &path);
        let Op::SculptStroke(s) = last_op(&d) else {
            panic!("no stroke: {:?}", d.commands.last())
        };
        let crate::sculpt::Warp::Explode { delta } = s.settings.warp else {
            panic!("{preset}: {:?}", s.settings.warp)
        };
        assert!(delta * sign > 0.0, "{preset}: delta {delta}");
        assert!(
            s.samples.len() >= 3,
            "{preset}: {} samples",
            s.samples.len()
        );
        volumes.push(volume(&d));
    }
    assert!(d.rejected.is_empty(), "{:?}", d.rejected);
    let [v0, v1, v2] = volumes[..] else {
        unreachable!()
    };
    assert!(v1 > v0 * 1.01, "explode: {v0} -> {v1}");
    assert!(v2 < v1 * 0.99, "collapse: {v1} -> {v2}");
    let mesh = &object(&d.log, id).mesh;
    assert!(closed(mesh), "the sculpt stays closed");
}

/// Paper 4 §4.5: a brush made from another object of the document. The
/// stroke names the object, is sized like the preset, and pulls the
/// sphere's top up.
#[test]
fn a_brush_made_from_a_document_object_deforms_the_sculpt() {
    let mut d = Driver::new(72.0, "object");
    // A small box beside the sphere (model x = 0.3).
    d.log
        .apply(Op::AddSolid(AddSolid {
            shape: SolidShape::Box {
                size: [0.04, 0.02, 0.03],
            },
            segments: 16,
            transform: Transform::translation([0.3, 0.0, 0.0]),
        }))
        .unwrap();
    let box_id = d.log.document().objects().next().unwrap().0;
    let id = sculpt_sphere(&mut d);
    let top = |d: &Driver| object(&d.log, id).mesh.bbox().map(|(_, hi)| hi.z).unwrap();
    let z0 = top(&d);
    pick(&mut d, "Brush", "pull");
    pick(&mut d, "Brush from", &format!("solid #{}", box_id.0));
    let (g, o) = choice(&d, "Brush from", &format!("solid #{}", box_id.0));
    assert_eq!(d.session().tool().choices()[g].active, o, "a state");
    // Pull the sphere's top (world y 0.9) up 3 cm.
    stroke(
        &mut d,
        DVec3::new(0.0, 0.9, -0.5),
        &[DVec3::new(0.0, 0.015, 0.0), DVec3::new(0.0, 0.03, 0.0)],
    );
    assert!(d.rejected.is_empty(), "{:?}", d.rejected);
    let Op::SculptStroke(s) = last_op(&d) else {
        panic!("no stroke: {:?}", d.commands.last())
    };
    let crate::sculpt::BrushShape::Mesh(b) = &s.settings.brush else {
        panic!("not a mesh brush: {:?}", s.settings.brush)
    };
    assert_eq!(
        b.source,
        crate::sculpt::MeshSource::Object { id: box_id },
        "the box is the brush"
    );
    // Sized like the "pull" preset (bounding radius 4.5 cm): the box's
    // half diagonal times the brush scale.
    let half_diagonal = DVec3::new(0.04, 0.02, 0.03).length() / 2.0;
    let radius = half_diagonal * s.settings.brush_scale;
    assert!((radius - 0.045).abs() < 1e-3, "brush radius {radius}");
    let grid = b.to_grid(Some(&object(&d.log, box_id).mesh)).unwrap();
    let samples: u64 = grid.dims.iter().map(|&n| u64::from(n)).product();
    assert!(samples <= crate::sculpt::mesh_brush::MAX_BRUSH_SAMPLES);
    let z1 = top(&d);
    assert!(z1 > z0 + 0.01, "the top rose from {z0} to {z1}");
    assert!(closed(&object(&d.log, id).mesh));
    // Back to the preset: strokes use the preset's sphere again.
    pick(&mut d, "Brush from", "preset");
    stroke(&mut d, DVec3::new(0.0, 0.86, -0.5), &[DVec3::X * 0.01]);
    let Op::SculptStroke(s) = last_op(&d) else {
        panic!()
    };
    assert!(matches!(
        s.settings.brush,
        crate::sculpt::BrushShape::Sphere { .. }
    ));
}

fn volume_of(d: &Driver) -> (ObjectId, &crate::sdf::SdfVolume) {
    d.log
        .document()
        .objects()
        .find_map(|(id, o)| match &o.kind {
            ObjectKind::SdfVolume(v) => Some((id, v)),
            _ => None,
        })
        .unwrap()
}

fn centre(mesh: &crate::mesh::TriMesh) -> DVec3 {
    let (lo, hi) = mesh.bbox().unwrap();
    (lo + hi) / 2.0
}

/// "Grab moves: fused result", then a grab on the cup and a 5 cm move:
/// one `sdf_move_fused`, and the cup's surface moved 5 cm.
#[test]
pub(crate) fn a_grab_moves_the_fused_result_as_such() {
    let mut d = Driver::new(72.0, "csg");
    load(&mut d, "csg_cup.jsonl");
    let (id, _) = volume_of(&d);
    let c0 = centre(&object(&d.log, id).mesh);
    pick(&mut d, "Grab moves", "fused result");
    let (g, o) = choice(&d, "Grab moves", "fused result");
    assert_eq!(d.session().tool().choices()[g].active, o, "a state");
    d.close_palette();
    // Desk: model (x, y, z) is world (x, 0.8 + z, -0.5 - y).
    let world = DVec3::new(c0.x, 0.8 + c0.z, -0.5 - c0.y);
    d.puppet
        .aim(R, world + DVec3::new(0.0, 0.1, 0.3), world, 0.3)
        .set(R, Button::Grab, true);
    let at = grip(&d, R);
    d.puppet
        .move_to(
            R,
            Pose::new(at.position + DVec3::X * 0.05, at.orientation),
            0.4,
        )
        .set(R, Button::Grab, false)
        .wait(0.1);
    d.sync();
    assert!(d.rejected.is_empty(), "{:?}", d.rejected);
    let Op::SdfMoveFused(m) = last_op(&d) else {
        panic!("no sdf_move_fused: {:?}", d.commands)
    };
    assert!((m.edit.transform.translate[0] - 0.05).abs() < 1e-6);
    let c1 = centre(&object(&d.log, id).mesh);
    let moved = c1 - c0;
    let step = volume_of(&d).1.step;
    assert!(
        (moved.x - 0.05).abs() <= step && moved.y.abs() <= step && moved.z.abs() <= step,
        "moved {moved:?}"
    );
    // Undo puts it back.
    d.log.undo().unwrap();
    assert_eq!(centre(&object(&d.log, id).mesh), c0);
}

/// "Component from" a sphere of the document: `sdf_component_from_object`
/// applies, the component becomes the active one, and SceneOperate then
/// places it.
#[test]
pub(crate) fn any_object_becomes_the_active_csg_component() {
    let mut d = Driver::new(72.0, "csg");
    load(&mut d, "csg_cup.jsonl");
    d.log
        .apply(Op::AddSolid(AddSolid {
            shape: SolidShape::Sphere { radius: 0.03 },
            segments: 24,
            transform: Transform::translation([0.3, 0.0, 0.0]),
        }))
        .unwrap();
    let (sphere, _) = d.log.document().objects().last().unwrap();
    let label = format!("solid #{}", sphere.0);
    d.open_palette();
    d.puppet.wait(0.05);
    d.sync();
    pick(&mut d, "Component from", &label);
    let Op::SdfComponentFromObject(c) = last_op(&d) else {
        panic!("no sdf_component_from_object: {:?}", d.commands.last())
    };
    assert_eq!(c.edit.object, sphere);
    let name = c.edit.name.clone();
    assert!(d.rejected.is_empty(), "{:?}", d.rejected);
    assert!(volume_of(&d).1.user_components.contains_key(&name));
    d.puppet.wait(0.05);
    d.sync();
    let groups = d.session().tool().choices();
    let comp = &groups[0];
    assert_eq!(
        comp.options.get(comp.active),
        Some(&name),
        "active component"
    );
    let from = groups.iter().find(|g| g.name == "Component from").unwrap();
    assert!(from.active >= from.options.len(), "an action, not a state");
    // SceneOperate (union) places it at the right controller.
    d.close_palette();
    d.puppet.click(R, Button::Primary);
    d.sync();
    let Op::SdfAddOperand(a) = last_op(&d) else {
        panic!("no sdf_add_operand: {:?}", d.commands.last())
    };
    assert_eq!(a.edit.component, crate::sdf::Component::User { name });
    assert!(d.rejected.is_empty(), "{:?}", d.rejected);
}

fn assembly(d: &Driver, id: ObjectId) -> crate::gc::GcAssembly {
    match &object(&d.log, id).kind {
        ObjectKind::GcAssembly(a) => a.clone(),
        k => panic!("not an assembly: {}", k.name()),
    }
}

/// The relations (kind, pair) recorded with part `part`.
fn relations_of(
    a: &crate::gc::GcAssembly,
    part: usize,
) -> Vec<(crate::assembly::RelationKind, (usize, usize))> {
    use crate::assembly::RelationKind as K;
    let mut a = a.clone();
    crate::assembly::ensure_recorded(&mut a);
    let r = a.relations.unwrap_or_default();
    [
        (K::Coplanar, r.coplanar),
        (K::Concentric, r.concentric),
        (K::Symmetric, r.symmetric),
    ]
    .into_iter()
    .flat_map(|(k, l)| l.into_iter().map(move |p| (k, p)))
    .filter(|(_, (a, b))| *a == part || *b == part)
    .collect()
}

/// The GC tool's ray points at the mug's body; "Release" then releases a
/// relation recorded with it (`gc_release`, applied: the relation is no
/// longer recorded), and "Resolution: fine" re-meshes every part of the
/// mug finer (one `gc_set_resolution` per part).
#[test]
pub(crate) fn gc_relations_are_released_and_resolution_set_from_the_palette() {
    let mut d = Driver::new(72.0, "gc");
    load(&mut d, "mug.jsonl");
    let (id, _) = d.log.document().objects().next().unwrap();
    let before = relations_of(&assembly(&d, id), 0);
    let (kind, pair) = *before.first().expect("the mug records a relation");
    // Point at the body (model z 0..0.1 is world y 0.8..0.9) with an open
    // hand (a controller with no button down).
    d.close_palette();
    d.puppet.aim(
        R,
        DVec3::new(0.0, 0.85, -0.2),
        DVec3::new(0.0, 0.85, -0.5),
        0.3,
    );
    d.puppet.wait(0.3);
    d.sync();
    assert_eq!(d.session().preview().highlighted, Some(id), "the body");
    // Releasing a relation the part does not have is nothing.
    for other in ["coplanar", "concentric", "symmetric"] {
        if other != kind.to_string() && !before.iter().any(|(k, _)| k.to_string() == other) {
            let n = d.commands.len();
            pick(&mut d, "Release", other);
            assert_eq!(d.commands.len(), n, "{other}: nothing to release");
        }
    }
    pick(&mut d, "Release", &kind.to_string());
    let Op::GcRelease(r) = last_op(&d) else {
        panic!("no gc_release: {:?}", d.commands.last())
    };
    assert_eq!(r.edit.relation, kind);
    assert!(d.rejected.is_empty(), "{:?}", d.rejected);
    let after = relations_of(&assembly(&d, id), 0);
    assert!(!after.contains(&(kind, pair)), "{after:?}");
    assert_eq!(after.len(), before.len() - 1);
    let (g, _) = choice(&d, "Release", "coplanar");
    assert!(d.session().tool().choices()[g].active >= 3, "an action");

    let triangles = object(&d.log, id).mesh.triangles.len();
    let n = d.commands.len();
    pick(&mut d, "Resolution", "fine");
    d.puppet.wait(0.2);
    d.sync();
    let parts = assembly(&d, id).parts.len();
    let set: Vec<_> = d.commands[n..]
        .iter()
        .map(|c| match c {
            ScriptCommand::Op(Op::GcSetResolution(s)) => s.edit.part.0,
            other => panic!("{other:?}"),
        })
        .collect();
    assert_eq!(set, (0..parts).collect::<Vec<_>>());
    assert!(d.rejected.is_empty(), "{:?}", d.rejected);
    let fine = crate::interact::tools::gc_tool::RESOLUTIONS[2].1;
    assert!(assembly(&d, id)
        .parts
        .iter()
        .all(|p| p.gc.resolution == fine));
    let mesh = &object(&d.log, id).mesh;
    assert!(mesh.triangles.len() > triangles, "finer mesh");
    assert!(closed(mesh));
    let (g, o) = choice(&d, "Resolution", "fine");
    assert_eq!(d.session().tool().choices()[g].active, o, "a state");
}

/// "Wall" and "Overlaps" set the document's print settings; the palette
/// then shows them as the active options.
#[test]
pub(crate) fn print_settings_are_set_from_the_palette() {
    use crate::print::SelfIntersectionPolicy;
    let mut d = Driver::new(72.0, "object");
    pick(&mut d, "Wall", "3 mm");
    assert!(matches!(last_op(&d), Op::SetWallThickness(_)));
    pick(&mut d, "Overlaps", "refuse");
    assert!(matches!(last_op(&d), Op::SetSelfIntersectionPolicy(_)));
    pick(&mut d, "Printer", "Bambu X1");
    assert!(matches!(last_op(&d), Op::SetPrinter(_)));
    assert!(d.rejected.is_empty(), "{:?}", d.rejected);
    let setup = *d.log.document().print_setup();
    assert_eq!(setup.wall_thickness, 0.003);
    assert_eq!(setup.on_self_intersection, SelfIntersectionPolicy::Refuse);
    assert_eq!(setup.printer.size, [0.256; 3]);
    d.puppet.wait(0.05);
    d.sync();
    for (g, o) in [
        choice(&d, "Wall", "3 mm"),
        choice(&d, "Overlaps", "refuse"),
        choice(&d, "Printer", "Bambu X1"),
    ] {
        assert_eq!(d.session().tool().choices()[g].active, o);
    }
    // Picking the current setting again is no op.
    let n = d.commands.len();
    pick(&mut d, "Wall", "3 mm");
    assert_eq!(d.commands.len(), n);
}

/// Both hands on a box with "Scale: x": the hands pulled apart stretch it
/// along its own x only (one `set_transform` with a per-axis scale).
#[test]
pub(crate) fn a_two_hand_grab_scales_along_the_chosen_axis() {
    let mut d = Driver::new(72.0, "object");
    d.close_palette();
    d.puppet.click(R, Button::Primary);
    d.sync();
    let (id, _) = d.log.document().objects().next().unwrap();
    // Extents along the object's own axes (the hands also turn it).
    let size = |d: &Driver| {
        let o = object(&d.log, id);
        let q = DQuat::from_array(o.transform().rotate);
        let axes = [DVec3::X, DVec3::Y, DVec3::Z].map(|a| q * a);
        let ext = axes.map(|a| {
            let proj = o
                .mesh
                .positions
                .iter()
                .map(|p| DVec3::from_array(*p).dot(a));
            proj.clone().fold(f64::MIN, f64::max) - proj.fold(f64::MAX, f64::min)
        });
        DVec3::from_array(ext)
    };
    let s0 = size(&d);
    pick(&mut d, "Scale", "x");
    d.close_palette();
    let boxed = DVec3::new(0.2, 1.1, -0.3); // where the right hand placed it
    d.puppet
        .aim(R, boxed + DVec3::new(0.0, 0.0, 0.2), boxed, 0.3)
        .set(R, Button::Grab, true)
        .set(L, Button::Grab, true);
    let (r, l) = (grip(&d, R), grip(&d, L));
    d.puppet
        .move_to(
            R,
            Pose::new(r.position + DVec3::X * 0.1, r.orientation),
            0.4,
        )
        .set(R, Button::Grab, false)
        .set(L, Button::Grab, false)
        .wait(0.1);
    let _ = l;
    d.sync();
    assert!(d.rejected.is_empty(), "{:?}", d.rejected);
    let Op::SetTransform(t) = last_op(&d).clone() else {
        panic!("no set_transform: {:?}", d.commands.last())
    };
    let [sx, sy, sz] = t.transform.scale;
    assert!(
        sx > 1.1 && sy == 1.0 && sz == 1.0,
        "{:?}",
        t.transform.scale
    );
    let s1 = size(&d);
    assert!((s1.x / s0.x - sx).abs() < 1e-9, "{s0:?} -> {s1:?}");
    assert!(
        (s1.y - s0.y).abs() < 1e-9 && (s1.z - s0.z).abs() < 1e-9,
        "{s0:?} -> {s1:?}"
    );
    // Uniform again: the same gesture scales every axis.
    pick(&mut d, "Scale", "uniform");
    d.close_palette();
    let desk = crate::interact::ModelPlacement::desk()
        .similarity()
        .unwrap();
    let at = desk.apply(DVec3::from_array(t.transform.translate));
    d.puppet
        .aim(R, at + DVec3::new(0.0, 0.0, 0.2), at, 0.3)
        .set(R, Button::Grab, true)
        .set(L, Button::Grab, true);
    let r = grip(&d, R);
    d.puppet
        .move_to(
            R,
            Pose::new(r.position + DVec3::X * 0.1, r.orientation),
            0.4,
        )
        .set(R, Button::Grab, false)
        .set(L, Button::Grab, false)
        .wait(0.1);
    d.sync();
    let Op::SetTransform(t) = last_op(&d) else {
        panic!("no set_transform: {:?}", d.commands.last())
    };
    let [a, b, c] = t.transform.scale;
    assert!(
        b > 1.05 && (b - c).abs() < 1e-12 && (a / sx - b).abs() < 1e-9,
        "{:?}",
        t.transform.scale
    );
}

/// "Snap to objects" in the palette: a part dragged down to 1.5 cm above
/// a slab comes to rest on it (its lowest point on the slab's top), and
/// the readout says so; without it the same drag leaves the gap.
#[test]
fn a_dragged_part_snaps_onto_the_surface_below() {
    for snapping in [true, false] {
        let mut d = Driver::new(72.0, "object");
        d.close_palette();
        // The default shape at the right hand (model (0.2, -0.2, 0.3)).
        d.puppet.click(R, Button::Primary);
        d.sync();
        let (part, _) = d.log.document().objects().next().unwrap();
        let bottom = |d: &Driver| object(&d.log, part).mesh.bbox().unwrap().0.z;
        let b0 = bottom(&d);
        // A slab under it whose top is 10 cm below the part's bottom.
        let top = b0 - 0.10;
        d.log
            .apply(Op::AddSolid(AddSolid {
                shape: SolidShape::Box {
                    size: [0.4, 0.4, 0.05],
                },
                segments: 32,
                transform: Transform::translation([0.2, -0.2, top - 0.025]),
            }))
            .unwrap();
        if snapping {
            d.pick(|i| i.action == crate::interact::PaletteAction::Objects)
                .unwrap();
            assert!(d.session().snap().objects);
        }
        d.close_palette();
        // Grab it and lower the hand by 8.5 cm (model -Z is world -Y).
        let held = DVec3::new(0.2, 1.1, -0.3);
        d.puppet
            .aim(R, held + DVec3::new(0.0, 0.0, 0.2), held, 0.3)
            .set(R, Button::Grab, true);
        let r = grip(&d, R);
        d.puppet
            .move_to(
                R,
                Pose::new(r.position - DVec3::Y * 0.085, r.orientation),
                0.4,
            )
            .wait(0.05);
        d.sync();
        let readout = d.session().preview().readout.clone();
        d.puppet.set(R, Button::Grab, false).wait(0.1);
        d.sync();
        assert!(d.rejected.is_empty(), "{:?}", d.rejected);
        let Op::SetTransform(_) = last_op(&d) else {
            panic!("no set_transform: {:?}", d.commands.last())
        };
        let gap = bottom(&d) - top;
        println!("snapping {snapping}: gap {gap:.6} m; readout `{readout}`");
        if snapping {
            assert!(gap.abs() < 1e-9, "rests on the slab: gap {gap}");
            assert!(readout.contains("snapped to surface of #"), "{readout}");
        } else {
            assert!((gap - 0.015).abs() < 0.003, "gap {gap}");
            assert!(!readout.contains("snapped"), "{readout}");
        }
    }
}

/// The palette's mirror plane (issue 19, precision): "Mirror" cycles off,
/// x, y, z (through the sculpt's origin), at the off hand, off. A stroke
/// pulling the sphere's +x side out with the x plane set pulls the -x
/// side out alike, in one op (one undo).
#[test]
fn the_palette_mirror_plane_mirrors_sculpt_strokes() {
    use crate::interact::palette::MirrorMode;
    let mut d = Driver::new(72.0, "object");
    let id = sculpt_sphere(&mut d);
    let mirror = |d: &mut Driver| {
        d.pick(|i| i.action == crate::interact::PaletteAction::Mirror)
            .unwrap();
        d.session().snap().mirror
    };
    let m = mirror(&mut d).expect("mirror on");
    assert_eq!(m.mode, MirrorMode::X);
    let origin = DVec3::from_array(object(&d.log, id).transform().translate);
    assert!(DVec3::from_array(m.plane.point).distance(origin) < 1e-12);
    assert_eq!(m.plane.normal, [1.0, 0.0, 0.0]);
    let label = |d: &Driver| {
        d.session()
            .palette()
            .and_then(|v| {
                v.items
                    .iter()
                    .find(|i| i.action == crate::interact::PaletteAction::Mirror)
                    .map(|i| i.label.clone())
            })
            .unwrap_or_default()
    };
    d.sync();
    assert_eq!(label(&d), "Mirror x");
    // A pull on the +x side (the sphere: radius 10 cm at the model
    // origin, world (0, 0.8, -0.5); model x is world x).
    let at = DVec3::new(0.085, 0.8, -0.5);
    let out = [DVec3::new(0.02, 0.0, 0.0), DVec3::new(0.04, 0.0, 0.0)];
    let before = d.log.len();
    stroke(&mut d, at, &out);
    assert!(d.rejected.is_empty(), "{:?}", d.rejected);
    assert_eq!(d.log.len(), before + 1, "one op for both sides");
    let Op::SculptStroke(s) = last_op(&d) else {
        panic!("no stroke: {:?}", d.commands.last())
    };
    assert_eq!(s.mirror.as_deref(), Some(&m.plane));
    let (lo, hi) = object(&d.log, id).mesh.bbox().unwrap();
    let (lo, hi) = (lo - origin, hi - origin);
    println!("x reach: +{:.4} / -{:.4}", hi.x, -lo.x);
    assert!(hi.x > 0.11, "pulled out: {}", hi.x);
    assert!(
        (hi.x + lo.x).abs() < 2e-3,
        "both sides alike: {} {}",
        hi.x,
        lo.x
    );
    assert!(closed(&object(&d.log, id).mesh));
    // The rest of the cycle.
    assert_eq!(mirror(&mut d).unwrap().plane.normal, [0.0, 1.0, 0.0]);
    assert_eq!(mirror(&mut d).unwrap().plane.normal, [0.0, 0.0, 1.0]);
    let hand = mirror(&mut d).unwrap();
    assert_eq!(hand.mode, MirrorMode::Hand);
    let l = grip(&d, L);
    let to_doc = d
        .session()
        .tool()
        .preview()
        .view
        .unwrap_or(*d.session().model())
        .inverse();
    assert!(DVec3::from_array(hand.plane.point).distance(to_doc.apply(l.position)) < 1e-9);
    let n = to_doc.apply_dir(l.orientation * DVec3::X).normalize();
    assert!(DVec3::from_array(hand.plane.normal).distance(n) < 1e-9);
    assert!(mirror(&mut d).is_none(), "and off again");
    // Off: a stroke has no plane.
    stroke(&mut d, at, &out);
    let Op::SculptStroke(s) = last_op(&d) else {
        panic!("no stroke: {:?}", d.commands.last())
    };
    assert_eq!(s.mirror, None);
}

/// The same palette plane mirrors the curve tool's strokes: a stroke
/// drawn on the right gets a twin across model x = 0 (the empty
/// document's centre), as the held symmetry plane gives.
#[test]
fn the_palette_mirror_plane_mirrors_drawn_curves() {
    let mut d = Driver::new(72.0, "object");
    d.pick_tool("curve").unwrap();
    d.pick(|i| i.action == crate::interact::PaletteAction::Mirror)
        .unwrap();
    let plane = d.session().snap().mirror.unwrap().plane;
    assert_eq!((plane.point, plane.normal), ([0.0; 3], [1.0, 0.0, 0.0]));
    let path: Vec<DVec3> = (1..=8)
        .map(|k| DVec3::new(0.015 * k as f64, 0.004 * k as f64, 0.0))
        .collect();
    stroke(&mut d, DVec3::new(0.05, 1.0, -0.4), &path);
    d.puppet.wait(0.1);
    d.sync();
    assert!(d.rejected.is_empty(), "{:?}", d.rejected);
    let draws: Vec<&Vec<[f64; 3]>> = d
        .commands
        .iter()
        .filter_map(|c| match c {
            ScriptCommand::Op(Op::CurveDraw(c)) => Some(&c.samples),
            _ => None,
        })
        .collect();
    assert_eq!(draws.len(), 2, "{:?}", d.commands);
    assert_eq!(draws[0].len(), draws[1].len());
    assert!(draws[0].iter().all(|p| p[0] > 0.01), "drawn on the right");
    for (a, b) in draws[0].iter().zip(draws[1]) {
        assert!((a[0] + b[0]).abs() < 1e-9 && a[1] == b[1] && a[2] == b[2]);
    }
}
