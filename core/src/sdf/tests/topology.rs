//! SDF topology is right at every allowed grid step (issue 33): the
//! paper's scenes (Table 1's Cube–Sphere, Chair and Cup from library
//! components; the op-script cup, chair and pedestal) fused and extracted
//! at every step from 4 to 12 mm, half a millimetre apart, have the genus
//! and the number of pieces of the exact CSG of the same operands'
//! meshes (Manifold booleans of the finely tessellated solids and of the
//! library meshes as the library normalizes them).

use crate::doc::{parse_script, run_script, ObjectId, ObjectKind, OpLog};
use crate::math::DVec3;
use crate::mesh::{difference, union, validate, TriMesh};
use crate::sdf::library;
use crate::sdf::mesh_sdf::normalize_component;
use crate::sdf::sample::sample_operand;
use crate::sdf::scenes::table1;
use crate::sdf::volume::BAND_STEPS;
use crate::sdf::{Component, CsgOp, Operand, SdfVolume};
use crate::solid::{tessellate, SolidShape};

/// Every allowed step from 4 to 12 mm, half a millimetre apart.
fn steps() -> Vec<f64> {
    (0..17)
        .map(|i| (40.0 + 5.0 * i as f64) / 10_000.0)
        .collect()
}

/// The operand's surface as a closed mesh in model space: a solid
/// tessellated finely, a library component normalized as its SDF is.
fn operand_mesh(o: &Operand) -> TriMesh {
    let mut m = match &o.component {
        Component::Solid { shape } => tessellate(shape, 256).unwrap(),
        Component::Library { name } => {
            normalize_component(&library::entry(name).unwrap().mesh()).unwrap()
        }
        Component::User { .. } => panic!("no user components in these scenes"),
    };
    m.transform(&o.transform.to_affine().unwrap());
    m
}

/// The exact CSG of the operands, fused in order, as (genus, pieces).
fn exact_topology(operands: &[Operand]) -> (i64, usize) {
    let mut acc = TriMesh::default();
    for o in operands {
        let m = operand_mesh(o);
        acc = match o.csg {
            CsgOp::Union => union(&[&acc, &m]).unwrap(),
            CsgOp::Subtract => difference(&acc, &[&m]).unwrap(),
            CsgOp::Intersect => difference(&acc, &[&difference(&acc, &[&m]).unwrap()]).unwrap(),
        };
    }
    let r = validate(&acc, &Default::default());
    assert!(r.is_closed_manifold(), "{}", r.problems());
    (r.genus.unwrap(), r.components)
}

/// Genus and pieces of the volume's fused surface.
fn sdf_topology(v: &SdfVolume) -> (i64, usize) {
    let m = v.evaluate().unwrap();
    let r = validate(&m, &Default::default());
    assert!(r.is_closed_manifold(), "step {}: {}", v.step, r.problems());
    (r.genus.unwrap(), r.components)
}

fn script_volume(text: &str, step: f64) -> SdfVolume {
    let text = text.replace("\"step\": 0.01", &format!("\"step\": {step}"));
    let mut log = OpLog::new();
    run_script(&mut log, &parse_script(&text).unwrap()).unwrap();
    let ObjectKind::SdfVolume(v) = &log.document().get(ObjectId(1)).unwrap().kind else {
        panic!("object 1 is no volume")
    };
    v.clone()
}

/// Checks a scene at every step against its exact CSG; returns the steps
/// where it differs, with what the SDF gave.
fn wrong_steps(name: &str, at_step: &dyn Fn(f64) -> SdfVolume) -> Vec<(f64, (i64, usize))> {
    let exact = exact_topology(&at_step(0.01).fused);
    let mut wrong = Vec::new();
    for step in steps() {
        let v = at_step(step);
        let got = sdf_topology(&v);
        if got != exact {
            wrong.push((step, got));
        }
    }
    eprintln!("{name}: exact CSG (genus, pieces) {exact:?}, wrong at {wrong:?}");
    wrong
}

#[test]
fn the_cup_script_has_one_tunnel_at_every_step() {
    let text = include_str!("../../../../tests/data/csg_cup.jsonl");
    let wrong = wrong_steps("csg_cup", &|s| script_volume(text, s));
    assert!(wrong.is_empty(), "csg_cup: {wrong:?}");
}

#[test]
fn the_chair_and_pedestal_scripts_keep_their_topology_at_every_step() {
    for (name, text) in [
        (
            "csg_chair",
            include_str!("../../../../tests/data/csg_chair.jsonl"),
        ),
        (
            "csg_pedestal",
            include_str!("../../../../tests/data/csg_pedestal.jsonl"),
        ),
    ] {
        let wrong = wrong_steps(name, &|s| script_volume(text, s));
        assert!(wrong.is_empty(), "{name}: {wrong:?}");
    }
}

#[test]
fn table1_scenes_keep_their_topology_at_every_step() {
    for scene in table1() {
        let wrong = wrong_steps(scene.name, &|step| {
            let mut v = SdfVolume::new(step).unwrap();
            v.pending = scene.operands.clone();
            v.updated().unwrap()
        });
        assert!(wrong.is_empty(), "{}: {wrong:?}", scene.name);
    }
}

/// The cause of the cup's tunnels: lattice points exactly on an operand's
/// surface (its wall at radius 0.12, a multiple of the 4 mm step) got a
/// value of rounding noise, some -1e-17 (inside), some -0 (outside). Each
/// of them must be on the surface: +0.
#[test]
fn samples_on_a_surface_are_exactly_zero() {
    let step = 0.004;
    let cylinder = Operand::new(
        Component::Solid {
            shape: SolidShape::Cylinder {
                radius: 0.12,
                height: 0.24,
            },
        },
        CsgOp::Union,
        Default::default(),
    );
    let v = SdfVolume::new(step).unwrap();
    let f = v.placed(&cylinder).unwrap();
    let s = sample_operand(&f, step, (BAND_STEPS * step) as f32);
    let g = s.as_grid();
    let mut on_wall = 0;
    // (30, 0), (0, 30), (18, 24), (24, 18) and their mirrors: radius 0.12.
    for (i, j) in [
        (30, 0),
        (0, 30),
        (18, 24),
        (24, 18),
        (-30, 0),
        (0, -30),
        (-18, 24),
        (24, -18),
    ] {
        for k in -29..=29 {
            let p = DVec3::new(i as f64, j as f64, k as f64) * step;
            if (p.truncate().length() - 0.12).abs() > 1e-15 {
                continue;
            }
            let x = g.sample([i, j, k]);
            assert_eq!(x.to_bits(), 0, "({i}, {j}, {k}): {x:e} is not +0");
            on_wall += 1;
        }
    }
    assert!(on_wall > 200, "{on_wall}");
}
