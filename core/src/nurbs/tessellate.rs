//! Tessellation helpers: parameter samples that contain every distinct
//! knot of the domain (so creases at knots of multiplicity `p`, e.g. the
//! corners of a polygon section, are sampled exactly) plus a uniform
//! subdivision of each knot span.

use super::basis::knot_multiplicities;
use super::NurbsCurve;
use glam::DVec3;

/// Samples over the domain of a knot vector of degree `p`: every distinct
/// knot in `[knots[p], knots[n]]` plus interior points, so that each knot
/// span of relative length `f` gets `max(1, ceil(f * per_domain))`
/// segments. Sorted, first = domain start, last = domain end.
pub fn knot_aligned_samples(knots: &[f64], p: usize, per_domain: usize) -> Vec<f64> {
    let n = knots.len() - p - 1;
    let (a, b) = (knots[p], knots[n]);
    let breaks: Vec<f64> = knot_multiplicities(knots)
        .into_iter()
        .map(|(v, _)| v)
        .filter(|v| *v >= a && *v <= b)
        .collect();
    let mut out = Vec::new();
    for w in breaks.windows(2) {
        let f = (w[1] - w[0]) / (b - a);
        let segs = ((f * per_domain as f64).ceil() as usize).max(1);
        for s in 0..segs {
            out.push(w[0] + (w[1] - w[0]) * s as f64 / segs as f64);
        }
    }
    out.push(b);
    out
}

/// Uniform samples `a + (b - a) i / n`, `i = 0..=n`, with exact ends.
pub fn uniform_samples(a: f64, b: f64, n: usize) -> Vec<f64> {
    let n = n.max(1);
    (0..=n)
        .map(|i| {
            if i == n {
                b
            } else {
                a + (b - a) * i as f64 / n as f64
            }
        })
        .collect()
}

/// A polyline of the curve at knot-aligned samples.
pub fn curve_polyline(c: &NurbsCurve, per_domain: usize) -> Vec<DVec3> {
    knot_aligned_samples(&c.knots, c.degree, per_domain)
        .into_iter()
        .map(|u| c.point(u))
        .collect()
}
