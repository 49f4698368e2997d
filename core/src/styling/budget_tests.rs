//! Budgets and hostile input (issue 22): what used to abort or panic is a
//! typed error naming the parameter, the estimate and the limit, and the
//! document is left as it was.

use super::budget::Budget;
use super::curve::{fit_curve, fit_curve_within, resample, FitMode};
use super::ngon_tests::prism;
use super::tests::wavy_samples;
use super::tools::{CurveSession, PullParams};
use super::StylingError;
use crate::doc::{LogError, Op, OpError, OpLog};
use crate::math::DVec3;

fn over(e: &StylingError) -> Option<(&str, f64, f64)> {
    match e {
        StylingError::OverBudget(crate::budget::OverBudget {
            parameter,
            estimate,
            limit,
            ..
        }) => Some((parameter, *estimate, *limit)),
        _ => None,
    }
}

/// The reproducer of the panic at `curve.rs:249` (issue 22): one sample of
/// a drawn stroke 1e12 m away, resampled at 5 mm. The resample count
/// overflowed `usize`, wrapped to 0 and indexed an empty vector. Through the
/// op log the document's door refuses it first (a typed `BadField` naming
/// the sample); the fit itself, called directly, refuses it by its budget.
/// Either way nothing changes and nothing panics.
#[test]
fn a_far_sample_is_refused_not_a_panic() {
    let mut log = OpLog::new();
    log.apply(
        serde_json::from_str(r#"{"op":"curve_network_create","resolution":8,"surface_n":6}"#)
            .unwrap(),
    )
    .unwrap();
    let hash = log.document().content_hash();
    let samples = [
        [0.0, 0.0, 0.0],
        [0.1, 0.0, 0.0],
        [1e12, 0.0, 0.0],
        [0.3, 0.0, 0.0],
    ];
    for resample in [Some(0.005), None] {
        let line = format!(
            r#"{{"op":"curve_draw","id":1,"samples":{},"fit":{{"mode":"interpolate"}},"resample":{},"snap_tol":0.001}}"#,
            serde_json::to_string(&samples).unwrap(),
            serde_json::to_string(&resample).unwrap(),
        );
        let op: Op = serde_json::from_str(&line).unwrap();
        match log.apply(op).unwrap_err() {
            LogError::Op(OpError::BadField { field, .. }) => assert_eq!(field, "samples[2][0]"),
            e => panic!("{e:?}"),
        }
        assert_eq!(log.document().content_hash(), hash);
        let e = fit_curve(&samples, FitMode::Interpolate, resample).unwrap_err();
        let (parameter, estimate, limit) = over(&e).unwrap_or_else(|| panic!("{e:?}"));
        assert_eq!(parameter, "samples");
        assert_eq!(estimate, 1e12);
        assert_eq!(limit, Budget::default().max_extent);
        assert!(e.to_string().contains("samples"), "{e}");
    }
}

#[test]
fn resampling_is_counted_before_it_allocates() {
    // A 1 m stroke at a 1e-9 spacing would be 1e9 points.
    let s: Vec<[f64; 3]> = (0..5).map(|i| [0.25 * i as f64, 0.0, 0.0]).collect();
    let e = fit_curve(&s, FitMode::Interpolate, Some(1e-9)).unwrap_err();
    let (parameter, estimate, limit) = over(&e).unwrap();
    assert_eq!(parameter, "resample");
    assert!((estimate - 1e9).abs() < 2.0, "{estimate}");
    assert_eq!(limit, 2048.0);
    // Beyond what f64 can count (the old code wrapped to 0 points here).
    let huge = [
        DVec3::ZERO,
        DVec3::new(1e308, 0.0, 0.0),
        DVec3::new(-1e308, 0.0, 0.0),
    ];
    let e = resample(&huge, 1e-300, 1_000).unwrap_err();
    assert_eq!(over(&e).unwrap().0, "resample");
    assert!(over(&e).unwrap().1.is_infinite());
    // Within budget, resampling still keeps the end points and spacing.
    let pts: Vec<DVec3> = s.iter().map(|p| DVec3::from_array(*p)).collect();
    let r = resample(&pts, 0.01, 2048).unwrap();
    assert_eq!(r.len(), 101);
    assert_eq!(r[100], pts[4]);
    // Too many raw samples to interpolate without resampling.
    let many = wavy_samples(3000, 0.0);
    let e = fit_curve(&many, FitMode::Interpolate, None).unwrap_err();
    assert_eq!(over(&e).unwrap(), ("samples", 3000.0, 2048.0));
    // A custom budget is honoured.
    let tight = Budget {
        max_fit_points: 100,
        ..Budget::default()
    };
    let e =
        fit_curve_within(&wavy_samples(101, 0.0), FitMode::Interpolate, None, &tight).unwrap_err();
    assert_eq!(over(&e).unwrap(), ("samples", 101.0, 100.0));
    assert!(fit_curve_within(&wavy_samples(100, 0.0), FitMode::Interpolate, None, &tight).is_ok());
}

#[test]
fn held_tools_refuse_work_past_the_budget() {
    let c = fit_curve(&wavy_samples(500, 0.0), FitMode::Interpolate, None).unwrap();
    let mut s = CurveSession::new(c.clone()).unwrap();
    let p = PullParams {
        wpp: 10.0,
        wp0: 1.0,
        wp1: 0.0,
    };
    // 100,000 frames of a 500-point curve: 1.5e8 unknowns solved.
    let path = vec![DVec3::new(0.1, 0.0, 0.0); 100_000];
    let e = s.pull(&p, 0.5, &path).unwrap_err();
    let (parameter, estimate, _) = over(&e).unwrap();
    assert_eq!(parameter, "path");
    assert_eq!(estimate, 100_000.0 * 1500.0);
    assert_eq!(s.curve, c, "nothing ran");
    // A pointer 1e9 m away.
    let e = s.pull(&p, 0.5, &[DVec3::new(1e9, 0.0, 0.0)]).unwrap_err();
    assert_eq!(over(&e).unwrap().0, "path");
    // Surface tools: the same limit on frames × unknowns.
    let mut net = prism(5, 0.1, 0.1, 0.0, 8);
    net.fill_all().unwrap();
    let w = super::surface::SurfaceWeights { wb: 1.0, ws: 0.0 };
    let mut sys = net.surface_system(0, &w).unwrap();
    let d0 = net.patches[0].disp.clone();
    let e = sys
        .equilibrium_frames(&d0, 0.5, 10_000_000, 1.0)
        .unwrap_err();
    assert_eq!(over(&e).unwrap().0, "path");
}

#[test]
fn the_loop_search_has_a_budget() {
    let net = prism(6, 0.1, 0.1, 0.0, 8);
    let tight = Budget {
        max_loop_search: 10,
        ..Budget::default()
    };
    let e = net.try_find_loops(&tight).unwrap_err();
    assert_eq!(over(&e).unwrap().0, "curve network");
    let loops = net.try_find_loops(&Budget::default()).unwrap();
    let count = |n: usize| loops.iter().filter(|l| l.len() == n).count();
    assert_eq!((count(4), count(6)), (6, 2), "6 quads and 2 hexagons");
}
