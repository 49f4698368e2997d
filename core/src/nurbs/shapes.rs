//! Exact closed curves in the `xy` plane, counter-clockwise, starting on
//! the `+x` axis, on the domain `[0, 1]`: the rational quadratic ellipse
//! (9 control points, The NURBS Book §7.5) and polylines (degree 1) with
//! knots at the vertices' polar angle / 2π, so that corresponding
//! parameters of different templates lie at about the same angle (which
//! keeps lofts between circles and polygons untwisted).

use crate::math::fm::DetMath as _;
use glam::DVec3;

use super::curve::homogeneous;
use super::{NurbsCurve, NurbsError};

/// The ellipse `x = rx cos t, y = ry sin t` as an exact rational quadratic.
pub fn ellipse(rx: f64, ry: f64) -> NurbsCurve {
    let w = std::f64::consts::FRAC_1_SQRT_2;
    let pts = [
        (1.0, 0.0, 1.0),
        (1.0, 1.0, w),
        (0.0, 1.0, 1.0),
        (-1.0, 1.0, w),
        (-1.0, 0.0, 1.0),
        (-1.0, -1.0, w),
        (0.0, -1.0, 1.0),
        (1.0, -1.0, w),
        (1.0, 0.0, 1.0),
    ];
    let control = pts
        .iter()
        .map(|(x, y, wt)| homogeneous(DVec3::new(x * rx, y * ry, 0.0), *wt))
        .collect();
    NurbsCurve {
        degree: 2,
        knots: vec![
            0.0, 0.0, 0.0, 0.25, 0.25, 0.5, 0.5, 0.75, 0.75, 1.0, 1.0, 1.0,
        ],
        control,
    }
}

/// A closed polyline through `vertices` (not repeated at the end), degree
/// 1, with knots at each vertex's polar angle about the origin / 2π when
/// the angles increase strictly from the first vertex (star-shaped about
/// the origin), else at normalized cumulative chord length.
pub fn closed_polyline(vertices: &[DVec3]) -> Result<NurbsCurve, NurbsError> {
    closed_polyline_with(vertices, None)
}

fn closed_polyline_with(
    vertices: &[DVec3],
    params: Option<Vec<f64>>,
) -> Result<NurbsCurve, NurbsError> {
    let n = vertices.len();
    if n < 3 {
        return Err(NurbsError::TooFewPoints { got: n, need: 3 });
    }
    if vertices.iter().any(|v| !v.is_finite()) {
        return Err(NurbsError::NonFinite("vertex"));
    }
    let a0 = vertices[0].y.fatan2(vertices[0].x);
    let ang: Vec<f64> = vertices
        .iter()
        .map(|v| (v.y.fatan2(v.x) - a0).rem_euclid(std::f64::consts::TAU))
        .collect();
    let by_angle = ang.windows(2).all(|w| w[1] > w[0]) && ang[0] == 0.0;
    let mut t: Vec<f64> = if let Some(p) = params {
        p
    } else if by_angle {
        ang.iter().map(|a| a / std::f64::consts::TAU).collect()
    } else {
        let mut acc = vec![0.0];
        let mut s = 0.0;
        for i in 0..n {
            let d = (vertices[(i + 1) % n] - vertices[i]).length();
            if !(d > 0.0) {
                return Err(NurbsError::CoincidentPoints(i, (i + 1) % n));
            }
            s += d;
            acc.push(s);
        }
        acc.pop();
        acc.iter().map(|x| x / s).collect()
    };
    t.push(1.0);
    let mut knots = vec![0.0];
    knots.extend_from_slice(&t);
    knots.push(1.0);
    let mut pts: Vec<DVec3> = vertices.to_vec();
    pts.push(vertices[0]);
    NurbsCurve::from_points(1, knots, &pts)
}

/// The regular polygon with `sides` vertices on the circle of radius `r`,
/// the first at `(r, 0)`.
pub fn regular_polygon(sides: usize, r: f64) -> Result<NurbsCurve, NurbsError> {
    let v: Vec<DVec3> = (0..sides)
        .map(|i| {
            let a = std::f64::consts::TAU * i as f64 / sides as f64;
            DVec3::new(r * a.fcos(), r * a.fsin(), 0.0)
        })
        .collect();
    // Exact knots i / n (not recomputed from the vertices' angles).
    let t = (0..sides).map(|i| i as f64 / sides as f64).collect();
    closed_polyline_with(&v, Some(t))
}

/// The axis-aligned `w x h` rectangle centered at the origin, starting at
/// the middle of its `+x` side.
pub fn rectangle(w: f64, h: f64) -> Result<NurbsCurve, NurbsError> {
    let (x, y) = (w / 2.0, h / 2.0);
    closed_polyline(&[
        DVec3::new(x, 0.0, 0.0),
        DVec3::new(x, y, 0.0),
        DVec3::new(-x, y, 0.0),
        DVec3::new(-x, -y, 0.0),
        DVec3::new(x, -y, 0.0),
    ])
}
