//! Skinning (lofting) through section curves, The NURBS Book §10.3:
//! the sections are made compatible (raised to a common degree, refined
//! to a common knot vector), each column of corresponding homogeneous
//! control points is interpolated in `v` at the sections' parameters, and
//! the result is a surface with `S(u, v_k) = C_k(u)` exactly (to rounding).
//!
//! Two `v` schemes: [`SkinV::NaturalCubic`] (knots at the section
//! parameters; inserting a section taken from the surface leaves it
//! unchanged, which the GC insert edit needs) and [`SkinV::Averaged`]
//! (P&T's global interpolation with averaged knots, eq. 9.8).

use glam::DVec4;
use serde::{Deserialize, Serialize};

use super::basis::{averaged_knots, basis_funs, find_span, knot_multiplicities};
use super::interp::{natural_knots, natural_matrix};
use super::linalg::solve;
use super::{NurbsCurve, NurbsError, NurbsSurface};

/// How the surface interpolates the sections in `v`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum SkinV {
    /// Natural cubic interpolation with knots at the section parameters.
    NaturalCubic,
    /// Global interpolation of degree `min(q, K - 1)` with averaged knots.
    Averaged {
        /// Degree in `v`.
        q: usize,
    },
}

/// Knots of different curves closer than this (relative to the domain) are
/// snapped to one value before the union is taken.
pub const KNOT_SNAP: f64 = 1e-12;

/// Raises all curves to their highest degree and refines them to the union
/// of their knot vectors (each value with its largest multiplicity). The
/// curves must be clamped and share one domain. Knots closer than
/// [`KNOT_SNAP`] are first snapped together (a shape change below 1e-12).
pub fn make_compatible(curves: &[NurbsCurve]) -> Result<Vec<NurbsCurve>, NurbsError> {
    if curves.is_empty() {
        return Ok(Vec::new());
    }
    for c in curves {
        c.validate()?;
    }
    let dom = curves[0].domain();
    if curves.iter().any(|c| c.domain() != dom) {
        return Err(NurbsError::DomainMismatch);
    }
    let p = curves.iter().map(|c| c.degree).max().unwrap_or(1);
    let raised: Vec<NurbsCurve> = curves
        .iter()
        .map(|c| c.clamped().elevate_degree(p - c.degree))
        .collect();
    // Canonical knot values: values closer than KNOT_SNAP (relative to the
    // domain) are one knot (e.g. i/n computed two ways), else refinement
    // would create spans of a few ulps.
    let tol = KNOT_SNAP * (dom.1 - dom.0);
    let mut values: Vec<f64> = raised
        .iter()
        .flat_map(|c| c.knots.iter().copied())
        .collect();
    values.sort_by(|a, b| a.total_cmp(b));
    let mut canon: Vec<f64> = Vec::new();
    for v in values {
        match canon.last() {
            Some(last) if v - *last <= tol => {}
            _ => canon.push(v),
        }
    }
    let snap = |v: f64| -> f64 {
        let i = canon.partition_point(|c| *c < v - tol);
        if i < canon.len() && (canon[i] - v).abs() <= tol {
            canon[i]
        } else {
            v
        }
    };
    let raised: Vec<NurbsCurve> = raised
        .into_iter()
        .map(|mut c| {
            for k in &mut c.knots {
                *k = snap(*k);
            }
            c
        })
        .collect();
    // Union knot vector.
    let mut union: Vec<(f64, usize)> = Vec::new();
    for c in &raised {
        for (v, m) in knot_multiplicities(&c.knots) {
            match union.iter_mut().find(|(u, _)| *u == v) {
                Some((_, um)) => *um = (*um).max(m),
                None => union.push((v, m)),
            }
        }
    }
    union.sort_by(|a, b| a.0.total_cmp(&b.0));
    let target: Vec<f64> = union
        .iter()
        .flat_map(|(v, m)| std::iter::repeat_n(*v, *m))
        .collect();
    Ok(raised
        .into_iter()
        .map(|mut c| {
            c.refine_to(&target);
            c
        })
        .collect())
}

/// Skins a surface through `sections` at strictly increasing `v_params`.
pub fn skin(
    sections: &[NurbsCurve],
    v_params: &[f64],
    scheme: SkinV,
) -> Result<NurbsSurface, NurbsError> {
    let k = sections.len();
    if k < 2 {
        return Err(NurbsError::TooFewPoints { got: k, need: 2 });
    }
    if v_params.len() != k {
        return Err(NurbsError::ParamCount {
            curves: k,
            params: v_params.len(),
        });
    }
    if v_params.iter().any(|v| !v.is_finite()) {
        return Err(NurbsError::NonFinite("v parameter"));
    }
    if let Some(i) = v_params.windows(2).position(|w| !(w[1] > w[0])) {
        return Err(NurbsError::BadParameters(i + 1));
    }
    let comp = make_compatible(sections)?;
    let n_u = comp[0].control.len();
    let (knots_v, matrix, n_v, pad) = match scheme {
        SkinV::NaturalCubic => {
            let kv = natural_knots(v_params);
            let m = natural_matrix(v_params, &kv);
            (kv, m, k + 2, true)
        }
        SkinV::Averaged { q } => {
            let q = q.min(k - 1).max(1);
            let kv = averaged_knots(v_params, q);
            let mut m = vec![0.0; k * k];
            for (r, &t) in v_params.iter().enumerate() {
                let span = find_span(k, q, t, &kv);
                let b = basis_funs(span, t, q, &kv);
                for (j, bj) in b.iter().enumerate() {
                    m[r * k + span - q + j] = *bj;
                }
            }
            (kv, m, k, false)
        }
    };
    let degree_v = knots_v.len() - n_v - 1;
    let mut control = vec![DVec4::ZERO; n_u * n_v];
    for i in 0..n_u {
        let mut rhs: Vec<DVec4> = Vec::with_capacity(n_v);
        if pad {
            rhs.push(DVec4::ZERO);
        }
        rhs.extend(comp.iter().map(|c| c.control[i]));
        if pad {
            rhs.push(DVec4::ZERO);
        }
        let col = solve(matrix.clone(), rhs)?;
        control[i * n_v..(i + 1) * n_v].copy_from_slice(&col);
    }
    NurbsSurface::new(
        comp[0].degree,
        degree_v,
        comp[0].knots.clone(),
        knots_v,
        n_u,
        n_v,
        control,
    )
}

/// The `v`-parameters of §10.3 (eq. 10.8 generalized): for each column of
/// corresponding control points of the compatible sections, normalized
/// chord lengths between consecutive sections, averaged over the columns.
/// In `[0, 1]`, strictly increasing unless two sections coincide.
pub fn skin_params(sections: &[NurbsCurve]) -> Result<Vec<f64>, NurbsError> {
    let k = sections.len();
    if k < 2 {
        return Err(NurbsError::TooFewPoints { got: k, need: 2 });
    }
    let comp = make_compatible(sections)?;
    let n = comp[0].control.len();
    let mut v = vec![0.0; k];
    let mut columns = 0usize;
    for i in 0..n {
        let pts: Vec<_> = comp
            .iter()
            .map(|c| super::euclidean(c.control[i]))
            .collect();
        let d: Vec<f64> = pts.windows(2).map(|w| (w[1] - w[0]).length()).collect();
        let total: f64 = d.iter().sum();
        if !(total > 0.0) {
            continue;
        }
        columns += 1;
        let mut acc = 0.0;
        for (j, dj) in d.iter().enumerate() {
            acc += dj;
            v[j + 1] += acc / total;
        }
    }
    if columns == 0 {
        return Err(NurbsError::CoincidentPoints(0, 1));
    }
    for x in &mut v {
        *x /= columns as f64;
    }
    v[k - 1] = 1.0;
    if let Some(j) = v.windows(2).position(|w| !(w[1] > w[0])) {
        return Err(NurbsError::CoincidentPoints(j, j + 1));
    }
    Ok(v)
}
