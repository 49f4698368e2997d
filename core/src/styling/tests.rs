//! Tests of the styling system: curves, energies, tools.

use super::curve::{check_samples, fit_curve, FitMode, SplineCurve};
use super::energy::{curve_pattern, flatten, CurveSystem, Weight};
use super::solver::{FixedSolver, SymPattern};
use super::tools::{CurveSession, PullParams, SharpenLimits, SmoothParams, StopReason};
use super::StylingError;
use crate::math::fm::DetMath as _;
use crate::math::DVec3;

/// A wavy space curve with a little deterministic noise.
pub(crate) fn wavy_samples(count: usize, noise: f64) -> Vec<[f64; 3]> {
    (0..count)
        .map(|i| {
            let s = i as f64 / (count - 1) as f64;
            let jitter = noise * ((i * 7919 % 13) as f64 / 13.0 - 0.5);
            [
                0.3 * s,
                0.03 * (12.0 * s).fsin() + jitter,
                0.02 * (5.0 * s).fcos() - jitter,
            ]
        })
        .collect()
}

fn wavy_curve() -> SplineCurve {
    fit_curve(&wavy_samples(60, 0.0), FitMode::Interpolate, None).unwrap()
}

fn max_dev(a: &SplineCurve, b: &SplineCurve, ts: impl Iterator<Item = f64>) -> f64 {
    ts.map(|t| a.point(t).distance(b.point(t)))
        .fold(0.0, f64::max)
}

#[test]
fn fit_interpolates_and_approximates() {
    let s = wavy_samples(40, 0.0);
    let c = fit_curve(&s, FitMode::Interpolate, None).unwrap();
    for p in &s {
        let (_, d) = c.closest(DVec3::from_array(*p));
        assert!(d < 1e-9, "interpolant misses a sample by {d}");
    }
    let noisy = wavy_samples(200, 0.002);
    let a = fit_curve(&noisy, FitMode::Approximate { tol: 0.003 }, Some(0.005)).unwrap();
    assert!(a.n() < 100, "approximation kept {} control points", a.n());
    for p in &noisy {
        let (_, d) = a.closest(DVec3::from_array(*p));
        assert!(d < 0.003 + 0.002, "approximation off by {d}");
    }
}

#[test]
fn bad_samples_are_typed_errors() {
    let s = wavy_samples(10, 0.0);
    assert_eq!(
        fit_curve(&s[..3], FitMode::Interpolate, None),
        Err(StylingError::TooFewSamples(3))
    );
    let mut dup = s.clone();
    dup[4] = dup[3];
    assert_eq!(
        check_samples(&dup).unwrap_err(),
        StylingError::CoincidentSamples(3, 4)
    );
    let mut nan = s.clone();
    nan[2][1] = f64::NAN;
    assert_eq!(
        fit_curve(&nan, FitMode::Interpolate, None),
        Err(StylingError::NonFiniteSample(2))
    );
}

#[test]
fn solver_holds_fixed_values_exactly_and_reuses_factors() {
    // 1D Laplacian with both ends fixed: solution is linear.
    let n = 50;
    let pattern = SymPattern::new(n, (1..n).map(|i| (i, i - 1)));
    let mut values = vec![0.0; pattern.nnz()];
    for i in 0..n {
        values[pattern.slot(i, i).unwrap()] = 2.0;
        if i > 0 {
            values[pattern.slot(i, i - 1).unwrap()] = -1.0;
        }
    }
    let mut fixed = vec![false; n];
    fixed[0] = true;
    fixed[n - 1] = true;
    let mut e = vec![0.0; n];
    e[0] = 1.0;
    e[n - 1] = 3.0;
    let mut s = FixedSolver::new(pattern).unwrap();
    s.factor(&values, &fixed).unwrap();
    s.factor(&values, &fixed).unwrap();
    assert_eq!(s.refactor_count, 1);
    let x = s.solve(&vec![0.0; n], &e, 1).unwrap();
    assert_eq!(x[0], 1.0);
    assert_eq!(x[n - 1], 3.0);
    for (i, xi) in x.iter().enumerate() {
        let want = 1.0 + 2.0 * i as f64 / (n - 1) as f64;
        assert!((xi - want).abs() < 1e-12);
    }
    // A stable solve of this well-conditioned system is at rounding level
    // at once: no refinement step (issue 37: it cost 40% of a frame).
    assert_eq!(s.refinements.load(std::sync::atomic::Ordering::Relaxed), 0);
}

/// `∫ w(s) f(t) dt` over the curve's domain by composite Simpson (a rule
/// independent of the Gauss quadrature the energies use).
fn simpson(c: &SplineCurve, w: Weight, f: impl Fn(f64) -> f64) -> f64 {
    let (a, b) = c.domain();
    let m = 4000;
    let h = (b - a) / m as f64;
    (0..=m)
        .map(|i| {
            let t = a + h * i as f64;
            let k = if i == 0 || i == m {
                1.0
            } else if i % 2 == 1 {
                4.0
            } else {
                2.0
            };
            k * w.at((t - a) / (b - a)) * f(t)
        })
        .sum::<f64>()
        * h
        / 3.0
}

#[test]
fn energies_match_direct_integrals() {
    let c = wavy_curve();
    let mut sys = CurveSystem::new(&c, curve_pattern(c.n()));
    sys.add_bend(1.0, Weight::Uniform);
    let e = sys.energy(&flatten(&c.ctrl));
    assert!((e - c.bend_energy()).abs() < 1e-9 * c.bend_energy());
    // Each attractor at weight 2, uniform and local: the quadratic form's
    // energy differences between two curves equal the direct integrals of
    // the weighted squared distances (the constant term cancels).
    let mut c2 = c.clone();
    for (i, p) in c2.ctrl.iter_mut().enumerate() {
        p[1] += 0.01 * (i as f64 * 0.7).fsin();
        p[2] -= 0.02 * (i as f64 * 0.3).fcos();
    }
    let (n, a) = (
        DVec3::new(0.2, 0.1, 1.0).normalize(),
        DVec3::new(0.0, 0.01, 0.02),
    );
    let dir = DVec3::new(1.0, 0.3, 0.1).normalize();
    let q = DVec3::new(0.1, 0.05, -0.02);
    let other = fit_curve(&wavy_samples(17, 0.0), FitMode::Interpolate, None).unwrap();
    let (oa, ob) = other.domain();
    let (ca, cb) = c.domain();
    let y = |t: f64| other.point(oa + (ob - oa) * (t - ca) / (cb - ca));
    type Dist<'a> = Box<dyn Fn(DVec3, f64) -> f64 + 'a>;
    type AddTerm<'a> = Box<dyn Fn(&mut CurveSystem) + 'a>;
    for weight in [Weight::Uniform, Weight::gaussian(0.4, 30.0)] {
        let cases: Vec<(&str, AddTerm, Dist)> = vec![
            (
                "plane",
                Box::new(move |s| s.add_plane_attractor(2.0, weight, a, n)),
                Box::new(move |x, _| (x - a).dot(n).fpowi(2)),
            ),
            (
                "line",
                Box::new(move |s| s.add_line_attractor(2.0, weight, a, dir)),
                Box::new(move |x, _| {
                    let v = x - a;
                    (v - dir * v.dot(dir)).length_squared()
                }),
            ),
            (
                "point",
                Box::new(move |s| s.add_point_attractor(2.0, weight, q)),
                Box::new(move |x, _| x.distance_squared(q)),
            ),
            (
                "curve",
                Box::new(|s| s.add_curve_attractor(2.0, weight, &other)),
                Box::new(|x, t| x.distance_squared(y(t))),
            ),
        ];
        for (name, add, dist) in cases {
            let mut sys = CurveSystem::new(&c, curve_pattern(c.n()));
            add(&mut sys);
            let got = sys.energy(&flatten(&c.ctrl)) - sys.energy(&flatten(&c2.ctrl));
            let want = 2.0
                * (simpson(&c, weight, |t| dist(c.point(t), t))
                    - simpson(&c2, weight, |t| dist(c2.point(t), t)));
            // Gauss-Legendre is exact for the polynomial integrands; the
            // gaussian weight (truncated) and the other curve's knots are
            // not polynomial on a span.
            let exact = name != "curve" && weight == Weight::Uniform;
            let tol = if exact { 1e-9 } else { 1e-4 };
            assert!(
                (got - want).abs() <= tol * want.abs().max(1e-6),
                "{name} {weight:?}: {got} vs {want}"
            );
        }
    }
    // Minimizing the plane attractor alone puts every point on the plane.
    let mut sys = CurveSystem::new(&c, curve_pattern(c.n()));
    sys.add_plane_attractor(1.0, Weight::Uniform, DVec3::ZERO, DVec3::Z);
    let mut s = FixedSolver::new(curve_pattern(c.n())).unwrap();
    s.factor(&sys.values, &vec![false; 3 * c.n()]).unwrap_err();
    sys.add_shape(0, 1e-6, &c);
    s.factor(&sys.values, &vec![false; 3 * c.n()]).unwrap();
    let x = s.solve(&sys.rhs, &flatten(&c.ctrl), 1).unwrap();
    let z = x.chunks(3).map(|p| p[2].abs()).fold(0.0, f64::max);
    assert!(z < 1e-5 * 0.03, "plane attractor left z = {z}");
}

pub(crate) fn smooth_params() -> SmoothParams {
    SmoothParams {
        wb: 1e-5,
        ws: 0.0,
        wp0: 1.0,
        wp1: 0.0,
        wp2: 0.0,
        alpha: 60.0,
    }
}

#[test]
fn smoother_lowers_bend_energy_and_is_local() {
    let c0 = wavy_curve();
    let mut s = CurveSession::new(c0.clone()).unwrap();
    let (a, b) = c0.domain();
    let t0 = a + 0.5 * (b - a);
    let p = smooth_params();
    let mut prev = c0.bend_energy();
    for _ in 0..10 {
        s.curve.ctrl = s.smooth_step(&p, t0, 1.0).unwrap();
        let e = s.curve.bend_energy();
        assert!(e < prev, "bend energy rose: {e} >= {prev}");
        prev = e;
    }
    assert_eq!(s.refactor_count(), 1, "same t0 must reuse the factors");
    assert!(prev < 0.9 * c0.bend_energy());
    // Outside the gaussian support the curve is unchanged.
    let hw = (1e3f64.fln() / p.alpha).sqrt();
    let ts = (0..400).map(|i| a + (b - a) * i as f64 / 399.0);
    let outside = ts.filter(|t| ((t - a) / (b - a) - 0.5).abs() > hw);
    let dev = max_dev(&s.curve, &c0, outside);
    assert!(dev <= 1e-9, "curve moved outside the support by {dev}");
    // End control points (constraints) exactly fixed.
    assert_eq!(s.curve.ctrl[0], c0.ctrl[0]);
    assert_eq!(s.curve.ctrl[c0.n() - 1], c0.ctrl[c0.n() - 1]);
}

#[test]
fn sharpener_raises_energy_and_stops_safely() {
    let c0 = wavy_curve();
    let mut s = CurveSession::new(c0.clone()).unwrap();
    let (a, b) = c0.domain();
    let q = c0.point(a + 0.4 * (b - a));
    let limits = SharpenLimits {
        max_step: 0.01,
        max_growth: 3.0,
    };
    let gentle = SmoothParams {
        wb: 1e-5,
        wp2: 5e-5,
        ..smooth_params()
    };
    let (frames, stop) = s.sharpen(&gentle, &limits, &vec![q; 5000]).unwrap();
    let e = s.curve.bend_energy();
    eprintln!(
        "sharpener: {frames} frames, stop {stop:?}, bend {:.4} -> {e:.4}",
        c0.bend_energy()
    );
    assert!(e > c0.bend_energy(), "sharpening did not raise the energy");
    assert!(e <= 3.0 * c0.bend_energy());
    assert!(
        stop.is_some(),
        "held 5000 frames it must stop, ran {frames}"
    );
    // Frame by frame (same t0, PD matrix) the bend energy rises.
    let mut s2 = CurveSession::new(c0.clone()).unwrap();
    let t0 = a + 0.4 * (b - a);
    let mut prev = c0.bend_energy();
    for _ in 0..5 {
        s2.curve.ctrl = s2.smooth_step(&gentle, t0, -1.0).unwrap();
        let e = s2.curve.bend_energy();
        assert!(e > prev, "sharpener frame lowered the energy");
        prev = e;
    }
    assert!(frames < 5000);
    assert!(s.curve.ctrl.iter().flatten().all(|v| v.is_finite()));
    // Huge negative weights: stops, never NaN.
    let mut s = CurveSession::new(c0.clone()).unwrap();
    // Without curvature preservation the matrix is indefinite: the
    // frame blows up and the limits stop it.
    let wild = SmoothParams {
        wb: 1e-3,
        ..smooth_params()
    };
    let (frames, stop) = s.sharpen(&wild, &limits, &vec![q; 50]).unwrap();
    assert!(matches!(
        stop,
        Some(StopReason::StepTooLarge | StopReason::Unstable | StopReason::EnergyGrowth)
    ));
    assert!(frames < 50);
    assert!(s.curve.ctrl.iter().flatten().all(|v| v.is_finite()));
}

#[test]
fn puller_reaches_target_and_preserves_shape() {
    let c0 = wavy_curve();
    let (a, b) = c0.domain();
    let t0 = a + 0.3 * (b - a);
    let start = c0.point(t0);
    let target = start + DVec3::new(0.0, 0.05, 0.02);
    let path: Vec<DVec3> = (1..=10)
        .map(|k| start.lerp(target, k as f64 / 10.0))
        .collect();
    let mut s = CurveSession::new(c0.clone()).unwrap();
    let p = PullParams {
        wpp: 1e3,
        wp0: 1.0,
        wp1: 1e-3,
    };
    s.pull(&p, t0, &path).unwrap();
    assert_eq!(s.refactor_count(), 1, "puller matrix is constant");
    let miss = s.curve.point(t0).distance(target);
    assert!(miss < 1e-3, "puller missed the target by {miss}");
    // Shape preservation: far from t0 the curve barely moves.
    let far = (0..200)
        .map(|i| a + (b - a) * i as f64 / 199.0)
        .filter(|t| ((t - t0) / (b - a)).abs() > 0.4);
    let dev = max_dev(&s.curve, &c0, far);
    eprintln!(
        "puller: miss {miss:.2e}, max deviation beyond 0.4 of the domain {dev:.2e} (pull 5.4e-2)"
    );
    assert!(dev < 0.01);
    assert_eq!(s.curve.ctrl[0], c0.ctrl[0]);
}
