//! Issue 33: no valid sculpt op leaves degenerate triangles or a surface
//! that crosses itself, mirrored or not. Random pairs of strokes made from
//! the headset's brush presets (random scale, path, pressure and turn),
//! near the mirror plane of a 10 cm sculpt sphere, each pair applied twice
//! (a, b, a, b) with and without the mirror; after every op the mesh has
//! no degenerate triangle and no self-intersecting triangle pair.
//!
//! `SCULPT_PROP_CASES` sets the number of seeds (default 32 in CI, each
//! with and without the mirror: 256 strokes, about 10 s; the longer runs
//! reported with issue 33 used 140 and 1,000).

use glam::{DQuat, DVec3};
use shapewright::doc::{Create, Edit, ObjectId, Op, OpLog};
use shapewright::interact::{BrushPreset, BrushToolSettings};
use shapewright::math::fm::DetMath as _;
use shapewright::math::MirrorPlane;
use shapewright::mesh::validate;
use shapewright::sculpt::{SculptBase, SculptCreate, SculptStroke, StrokeSample};

/// xorshift64: the same cases on every machine.
struct Rng(u64);

impl Rng {
    fn f(&mut self) -> f64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }

    fn r(&mut self, a: f64, b: f64) -> f64 {
        a + (b - a) * self.f()
    }

    fn v(&mut self) -> DVec3 {
        DVec3::new(self.r(-1.0, 1.0), self.r(-1.0, 1.0), self.r(-1.0, 1.0))
    }
}

/// A stroke of a random preset starting on the sphere near x = 0.
fn stroke(rng: &mut Rng, presets: &[BrushPreset], mirror: bool) -> SculptStroke {
    let p = &presets[(rng.f() * presets.len() as f64) as usize % presets.len()];
    let mut settings = p.settings.clone();
    let k = rng.r(0.6, 1.6);
    settings.brush_scale *= k;
    settings.influence *= k;
    let th = rng.r(0.0, std::f64::consts::TAU);
    let x0 = rng.r(-0.03, 0.03);
    let dir = DVec3::new(x0 / 0.1, th.fcos(), th.fsin()).normalize();
    let mut pos = dir * rng.r(0.08, 0.11);
    let n = 2 + (rng.f() * 14.0) as usize;
    let step = rng.v() * 0.006;
    let mut q = DQuat::IDENTITY;
    let spin = rng.v() * rng.r(0.0, 0.15);
    let mut samples = Vec::new();
    for _ in 0..n {
        samples.push(StrokeSample {
            position: pos.to_array(),
            rotation: q.to_array(),
            pressure: rng.r(0.5, 1.0),
        });
        pos += step + rng.v() * 0.002;
        q = (DQuat::from_scaled_axis(spin) * q).normalize();
    }
    SculptStroke {
        settings,
        samples,
        mirror: mirror.then(|| Box::new(MirrorPlane::new(DVec3::ZERO, DVec3::X).unwrap())),
    }
}

/// Applies seed `seed`'s stroke pair twice (a, b, a, b) to a fresh 10 cm
/// sculpt sphere, mirrored or not; returns a line for every op after
/// which the mesh has a degenerate triangle or crosses itself.
fn problems(seed: u64, mirror: bool, presets: &[BrushPreset]) -> Vec<String> {
    let mut rng = Rng(seed * 7919 + 13);
    let mut log = OpLog::new();
    log.apply(Op::SculptCreate(Create(SculptCreate {
        base: SculptBase::Sphere {
            radius: 0.1,
            edge_length: 0.006,
        },
        transform: Default::default(),
    })))
    .unwrap();
    let a = stroke(&mut rng, presets, mirror);
    let b = stroke(&mut rng, presets, mirror);
    let mut bad = Vec::new();
    for (i, s) in [&a, &b, &a, &b].into_iter().enumerate() {
        // A refusal (budget) is allowed; it leaves the mesh as it was.
        if log
            .apply(Op::SculptStroke(Edit::new(ObjectId(1), s.clone())))
            .is_err()
        {
            continue;
        }
        let m = &log.document().get(ObjectId(1)).unwrap().mesh;
        let v = validate(m, &Default::default());
        let crossing = v.self_intersecting_pairs.unwrap_or(0);
        if v.degenerate_triangles > 0 || crossing > 0 {
            bad.push(format!(
                "seed {seed} mirror {mirror} op {i}: {} degenerate triangles, {crossing} crossing pairs",
                v.degenerate_triangles
            ));
        }
    }
    bad
}

#[test]
fn repeated_stroke_pairs_leave_no_degenerate_or_crossing_triangles() {
    let presets = BrushToolSettings::default().presets;
    let cases: u64 = std::env::var("SCULPT_PROP_CASES")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(32);
    let mut bad = Vec::new();
    for seed in 1..=cases {
        for mirror in [true, false] {
            bad.extend(problems(seed, mirror, &presets));
        }
    }
    assert!(bad.is_empty(), "{}", bad.join("\n"));
}

/// The cases of the longer runs that still crossed themselves. Of 140
/// seeds, after the fold guard saw every triangle sharing a vertex: seed
/// 75 (a large pull and the flat brush, 56 crossing pairs after the fourth
/// op) and seed 134 (a large pull and an explode across the mirror plane,
/// 45, 42 and 164 pairs after ops 2 to 4), both mirrored; none without the
/// mirror. Fixed by the crossing guard (`sculpt::crossing_guard`). Of
/// 1,000 seeds with that guard: seed 595, mirrored, 5 pairs after the
/// fourth op, left by a collapse of the frame's adaptation after both
/// guards had passed the frame; fixed by searching a collapse's new fan
/// for crossings before it is made.
#[test]
fn mirrored_pairs_that_crossed_themselves_no_longer_do() {
    let presets = BrushToolSettings::default().presets;
    let bad: Vec<String> = [75, 134, 595]
        .into_iter()
        .flat_map(|seed| problems(seed, true, &presets))
        .collect();
    assert!(bad.is_empty(), "{}", bad.join("\n"));
}
