//! Property tests (issue 5): network invariants after random edits (on
//! nets with quads and pentagons), the sharpener's safety, the smoother's
//! monotonicity.

use crate::math::fm::DetMath as _;
use std::sync::OnceLock;

use proptest::prelude::*;

use super::curve::{fit_curve, FitMode, SplineCurve};
use super::network::CurveNetwork;
use super::ngon_tests::{boundary_gap, prism, worst_seam_angle};
use super::tools::{CurveSession, SharpenLimits, SmoothParams};
use super::StylingError;
use crate::math::DVec3;
use crate::mesh::validate;

#[test]
fn pentagonal_prism_fills_and_meshes_closed() {
    let mut net = prism(5, 0.1, 0.12, 0.0, 10);
    assert_eq!(net.nodes.len(), 10);
    let filled = net.fill_all().unwrap();
    assert_eq!(filled.len(), 7, "5 quads and 2 pentagons");
    let sides: Vec<usize> = net.patches.iter().map(|p| p.pieces.len()).collect();
    assert_eq!(sides, [4, 4, 4, 4, 4, 5, 5]);
    assert!(boundary_gap(&net) < 1e-9, "gap {}", boundary_gap(&net));
    let m = net.mesh();
    let r = validate(&m, &Default::default());
    assert!(r.is_closed_manifold(), "{}", r.problems());
    assert_eq!(r.genus, Some(0));
    if let Ok(file) = std::env::var("SHAPEWRIGHT_NGON_STL_OUT") {
        let mut f = std::fs::File::create(file).unwrap();
        crate::mesh::write_stl(&m, &mut f).unwrap();
    }
    // Volume: the straight prism is 5/2 r² sin 72° h; the bows add a little.
    let straight = 2.5 * 0.01 * (72f64.to_radians()).fsin() * 0.12;
    let v = m.signed_volume();
    assert!(v > straight && v < 1.25 * straight, "{v} vs {straight}");
    // A hexagonal and an octagonal prism too.
    for n in [6, 8] {
        let mut net = prism(n, 0.1, 0.1, 0.0, 8);
        assert_eq!(net.fill_all().unwrap().len(), n + 2);
        let r = validate(&net.mesh(), &Default::default());
        assert!(r.is_closed_manifold(), "{n}: {}", r.problems());
    }
    // A cube's chordless hexagons are not filled: 6 faces only.
    let mut cube = prism(4, 0.1, 0.14, 0.0, 8);
    assert_eq!(cube.fill_all().unwrap().len(), 6);
}

fn base(pentagons: bool) -> &'static CurveNetwork {
    static NETS: OnceLock<[CurveNetwork; 2]> = OnceLock::new();
    let nets = NETS.get_or_init(|| {
        [4, 5].map(|n| {
            let mut net = prism(n, 0.1, 0.12, 0.01, 8);
            net.fill_all().unwrap();
            net
        })
    });
    &nets[pentagons as usize]
}

#[derive(Clone, Debug)]
enum Edit {
    Pull { s: f64, by: [f64; 3] },
    Smooth { s: f64 },
    Sharpen { s: f64, frames: usize },
}

fn edit() -> impl Strategy<Value = (usize, Edit)> {
    let s = 0.15..0.85f64;
    let d = -0.03..0.03f64;
    (
        0usize..15,
        prop_oneof![
            (s.clone(), [d.clone(), d.clone(), d]).prop_map(|(s, by)| Edit::Pull { s, by }),
            s.clone().prop_map(|s| Edit::Smooth { s }),
            (s, 1usize..6).prop_map(|(s, frames)| Edit::Sharpen { s, frames }),
        ],
    )
}

fn apply(net: &mut CurveNetwork, curve: usize, e: &Edit) -> Result<(), StylingError> {
    let c = net.curve(curve)?.clone();
    let (a, b) = c.domain();
    let mut session = CurveSession::new(c.clone())?;
    // The curve tool's weights.
    let tool = crate::interact::CurveToolSettings::default();
    match e {
        Edit::Pull { s, by } => {
            let t0 = a + (b - a) * s;
            let p = tool.pull;
            session.pull(&p, t0, &[c.point(t0) + DVec3::from_array(*by)])?;
        }
        Edit::Smooth { s } => {
            let q = c.point(a + (b - a) * s);
            session.smooth(&super::tests::smooth_params(), &[q; 3])?;
        }
        Edit::Sharpen { s, frames } => {
            let q = c.point(a + (b - a) * s);
            let (p, lim) = (tool.sharpen, tool.sharpen_limits);
            session.sharpen(&p, &lim, &vec![q; *frames])?;
        }
    }
    net.set_curve(curve, session.curve)
}

/// A random wavy curve of `count` interpolated samples.
fn random_curve() -> impl Strategy<Value = SplineCurve> {
    (
        8usize..40,
        0.0..0.05f64,
        0.0..0.05f64,
        1.0..15.0f64,
        0.0..6.0f64,
    )
        .prop_map(|(count, a1, a2, f, ph)| {
            let samples: Vec<[f64; 3]> = (0..count)
                .map(|i| {
                    let s = i as f64 / (count - 1) as f64;
                    [0.3 * s, a1 * (f * s + ph).fsin(), a2 * (0.7 * f * s).fcos()]
                })
                .collect();
            fit_curve(&samples, FitMode::Interpolate, None).unwrap()
        })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    /// After any sequence of edits, junction points are shared to 1e-9 and
    /// every patch boundary (quads, and n-gons' split quads) lies on its
    /// curves to 1e-9; the mesh stays closed.
    #[test]
    fn network_invariants_after_random_edits(
        pentagons in any::<bool>(),
        edits in proptest::collection::vec(edit(), 1..4),
    ) {
        let mut net = base(pentagons).clone();
        let count = net.curves.len();
        for (curve, e) in &edits {
            let mut next = net.clone();
            // A refused edit (degenerate junctions) leaves the net as it was.
            if apply(&mut next, curve % count, e).is_ok() {
                net = next;
            }
            prop_assert!(net.junction_gap() < 1e-9, "gap {}", net.junction_gap());
            let g = boundary_gap(&net);
            prop_assert!(g < 1e-9, "boundary gap {g}");
        }
        for k in 0..net.patches.len() {
            if net.patches[k].pieces.len() > 4 {
                let a = worst_seam_angle(&net, k, 20);
                prop_assert!(a < 1.0, "patch {k} creased {a} degrees");
            }
        }
        let r = validate(&net.mesh(), &Default::default());
        prop_assert!(r.is_closed_manifold(), "{}", r.problems());
    }

    /// The sharpener never yields NaN, never moves a control point more
    /// than `max_step` per applied frame, and never lets the bend energy
    /// pass `max_growth` times its start, whatever the weights (also
    /// indefinite ones, `wp2 < wb`).
    #[test]
    fn sharpener_never_nan_and_bounded(
        curve in random_curve(),
        wb in 1e-7..1e-4f64,
        wp2 in 0.0..2e-4f64,
        wp0 in 0.1..10.0f64,
        alpha in 5.0..60.0f64,
        max_step in 1e-4..0.05f64,
        max_growth in 1.01..10.0f64,
        at in proptest::collection::vec(0.0..1.0f64, 1..40),
    ) {
        let p = SmoothParams { wb, ws: 0.0, wp0, wp1: 0.0, wp2, alpha };
        let lim = SharpenLimits { max_step, max_growth };
        let (a, b) = curve.domain();
        let path: Vec<DVec3> = at.iter().map(|s| curve.point(a + (b - a) * s)).collect();
        let e0 = curve.bend_energy();
        let mut s = CurveSession::new(curve.clone()).unwrap();
        let (frames, _) = s.sharpen(&p, &lim, &path).unwrap();
        prop_assert!(frames <= path.len());
        prop_assert!(s.curve.ctrl.iter().flatten().all(|v| v.is_finite()));
        let e = s.curve.bend_energy();
        prop_assert!(e.is_finite() && e <= max_growth * e0 * (1.0 + 1e-12), "{e} vs {e0}");
        let moved = s.curve.ctrl.iter().zip(&curve.ctrl)
            .map(|(x, y)| DVec3::from_array(*x).distance(DVec3::from_array(*y)))
            .fold(0.0, f64::max);
        prop_assert!(moved <= frames as f64 * max_step * (1.0 + 1e-12), "{moved}");
    }

    /// Every smoother frame leaves the bend energy no higher than before.
    #[test]
    fn smoother_never_raises_bend_energy(
        curve in random_curve(),
        wb in 1e-7..1e-3f64,
        wp0 in 0.1..10.0f64,
        wp1 in 0.0..1e-2f64,
        wp2 in 0.0..1e-4f64,
        alpha in 5.0..60.0f64,
        at in proptest::collection::vec(0.0..1.0f64, 1..10),
    ) {
        let p = SmoothParams { wb, ws: 0.0, wp0, wp1, wp2, alpha };
        let (a, b) = curve.domain();
        let mut s = CurveSession::new(curve).unwrap();
        for u in at {
            let before = s.curve.bend_energy();
            let next = s.smooth_step(&p, a + (b - a) * u, 1.0).unwrap();
            s.curve.ctrl = next;
            let after = s.curve.bend_energy();
            prop_assert!(after <= before * (1.0 + 1e-9) + 1e-15, "{before} -> {after}");
        }
    }
}
