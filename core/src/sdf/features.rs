//! Sharp features in the extracted surface: the edges and corners that CSG
//! of boxes, cylinders and cones makes (a cup's rim, a chair's edges).
//!
//! Marching cubes cuts every sharp edge with a chamfer whose width depends
//! on where the edge passes through each cell, so an edge comes out as a
//! sawtooth at the grid step. Following Kobbelt et al., "Feature sensitive
//! surface extraction from volume data" (SIGGRAPH 2001), a cell whose
//! surface normals disagree gets its polygon fanned around a vertex at the
//! point nearest (least squares) to all the tangent planes at its edge
//! crossings: on the edge, or at the corner, instead of at the polygon's
//! centroid. The fan vertex belongs to the cell alone, like the centroid
//! fan of [`super::mc`], so the mesh stays a closed 2-manifold.
//!
//! Choices:
//! - **Exact normals.** The grid's own gradient blurs across the very edge
//!   it should find, so the normals come from the operands themselves: the
//!   scene field at a point is the fold of the fused operands (clamped, in
//!   order, as the fusion made the grid), and the normal is the gradient of
//!   the operand that decides the fold there ([`ExactField`]).
//! - **Cheap test first.** Only cells whose 8 samples are clearly not a
//!   linear field (a trilinear cross term above a fifth of the step) ask
//!   for exact normals; smooth surfaces of radius above a few steps never
//!   do.
//! - **Feature** when two crossing normals differ by more than 30°. The
//!   quadric is solved around the crossings' mean with small eigenvalues
//!   (below a tenth of the largest) dropped: along an edge the vertex stays
//!   at the mean, across it it goes to the edge.
//! - **Safe or not at all.** The vertex must lie inside the cell (one on
//!   a face, as where an edge runs along a grid plane, is pulled a
//!   thousandth of a step inside), and every
//!   fan triangle must face the way its crossings' normals say and have a
//!   non-degenerate area; otherwise the cell keeps the plain fan.
//! - Incremental extraction equals a full one: the fold depends only on the
//!   point and the operand list, and an update re-extracts every brick
//!   with surface whose cells meet a new operand's box.

use std::sync::Arc;

use super::csg::CsgOp;
use super::placement::PlacedField;
use crate::math::DVec3;

/// Normals of two crossings this far apart (cosine) mark a feature.
const FEATURE_COS: f64 = 0.866;
/// A trilinear cross term above this fraction of the step asks for exact
/// normals.
const NONLINEAR_REL: f32 = 0.2;
/// Quadric eigenvalues below this fraction of the largest are dropped.
const EIGEN_REL: f64 = 0.1;
/// Tangent planes that miss the quadric point by more than this fraction
/// of the step are a curved surface, not a crease.
const RESIDUAL_REL: f64 = 0.15;

/// The scene field of a volume as its fused operands define it, for exact
/// normals.
#[derive(Clone, Debug, Default)]
pub struct ExactField {
    fields: Vec<(Arc<PlacedField>, CsgOp)>,
    band: f64,
}

impl ExactField {
    /// The fold of `fields` (in fusion order) with values clamped to
    /// `band`.
    pub fn new(fields: Vec<(Arc<PlacedField>, CsgOp)>, band: f64) -> Self {
        Self { fields, band }
    }

    /// The field's value at `p` (clamped to the band), or `None` where no
    /// operand decides (empty space far from everything).
    pub fn value(&self, p: DVec3) -> Option<f64> {
        self.active(p).map(|(_, _, v)| v)
    }

    /// The fields, in fusion order.
    pub fn fields(&self) -> &[(Arc<PlacedField>, CsgOp)] {
        &self.fields
    }

    /// The operand deciding the fold at `p`, the sign it enters with (`-1`
    /// for a subtracted one) and the fold's value, if any operand decides.
    fn active(&self, p: DVec3) -> Option<(usize, f64, f64)> {
        let band = self.band;
        let mut acc = band;
        let mut active = None;
        for (k, (f, op)) in self.fields.iter().enumerate() {
            let (lo, hi) = f.world_box;
            let b = if p.cmpge(lo).all() && p.cmple(hi).all() {
                f.value(p).map_or(band, |v| v.clamp(-band, band))
            } else {
                band
            };
            match op {
                CsgOp::Union if b < acc => (acc, active) = (b, Some((k, 1.0))),
                CsgOp::Intersect if b > acc => (acc, active) = (b, Some((k, 1.0))),
                CsgOp::Subtract if -b > acc => (acc, active) = (-b, Some((k, -1.0))),
                _ => {}
            }
        }
        active.map(|(k, sign)| (k, sign, acc))
    }

    /// The field's value at `p` and the outward unit normal there: the
    /// gradient of the deciding operand (exact for a grid component, by
    /// central differences of step `h` for an analytic solid).
    pub fn value_normal(&self, p: DVec3, h: f64) -> Option<(f64, DVec3)> {
        let (k, sign, value) = self.active(p)?;
        let f = &self.fields[k].0;
        // A grid field's gradient is its trilinear cell's derivative; an
        // analytic solid's is differenced.
        let g = match f.value_gradient(p) {
            Some((_, g)) => g,
            None => {
                let mut g = DVec3::ZERO;
                for a in 0..3 {
                    let mut e = DVec3::ZERO;
                    e[a] = h;
                    g[a] = f.value(p + e)? - f.value(p - e)?;
                }
                g
            }
        };
        Some((value, (g * sign).try_normalize()?))
    }
}

/// Whether the cell's samples are clearly not a linear field (a surface
/// bent within the cell): the largest trilinear cross term against
/// `step`. Corner `i` of `v` is at offset `(i & 1, i >> 1 & 1, i >> 2 & 1)`.
pub(crate) fn nonlinear(v: &[f32; 8], step: f64) -> bool {
    let t = [
        v[0] - v[1] - v[2] + v[3],
        v[4] - v[5] - v[6] + v[7],
        v[0] - v[1] - v[4] + v[5],
        v[2] - v[3] - v[6] + v[7],
        v[0] - v[2] - v[4] + v[6],
        v[1] - v[3] - v[5] + v[7],
    ];
    let limit = NONLINEAR_REL * step as f32;
    t.iter().any(|x| x.abs() > limit)
}

/// Eigen-decomposition of a symmetric 3×3 matrix by Jacobi rotations:
/// eigenvalues and the eigenvectors as columns.
fn eigen_sym(mut a: [[f64; 3]; 3]) -> ([f64; 3], [[f64; 3]; 3]) {
    let mut v = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    for _ in 0..16 {
        let off = a[0][1] * a[0][1] + a[0][2] * a[0][2] + a[1][2] * a[1][2];
        if off < 1e-30 {
            break;
        }
        for (p, q) in [(0, 1), (0, 2), (1, 2)] {
            if a[p][q].abs() < 1e-300 {
                continue;
            }
            let theta = (a[q][q] - a[p][p]) / (2.0 * a[p][q]);
            let t = theta.signum() / (theta.abs() + (theta * theta + 1.0).sqrt());
            let t = if theta == 0.0 { 1.0 } else { t };
            let c = 1.0 / (t * t + 1.0).sqrt();
            let s = t * c;
            for row in &mut a {
                let (akp, akq) = (row[p], row[q]);
                row[p] = c * akp - s * akq;
                row[q] = s * akp + c * akq;
            }
            let (rp, rq) = (a[p], a[q]);
            for k in 0..3 {
                a[p][k] = c * rp[k] - s * rq[k];
                a[q][k] = s * rp[k] + c * rq[k];
            }
            for row in &mut v {
                let (vp, vq) = (row[p], row[q]);
                row[p] = c * vp - s * vq;
                row[q] = s * vp + c * vq;
            }
        }
    }
    ([a[0][0], a[1][1], a[2][2]], v)
}

/// The point nearest (least squares) to the planes through `points` with
/// `normals`, solved around their mean with small eigenvalues dropped.
fn quadric_point(points: &[DVec3], normals: &[DVec3]) -> DVec3 {
    let c = points.iter().copied().sum::<DVec3>() / points.len() as f64;
    let mut a = [[0.0; 3]; 3];
    let mut b = DVec3::ZERO;
    for (p, n) in points.iter().zip(normals) {
        let d = n.dot(*p - c);
        for i in 0..3 {
            for j in 0..3 {
                a[i][j] += n[i] * n[j];
            }
        }
        b += *n * d;
    }
    let (ev, vecs) = eigen_sym(a);
    let max = ev.iter().copied().fold(0.0, f64::max);
    let mut x = DVec3::ZERO;
    for k in 0..3 {
        if ev[k] > EIGEN_REL * max {
            let e = DVec3::new(vecs[0][k], vecs[1][k], vecs[2][k]);
            x += e * (e.dot(b) / ev[k]);
        }
    }
    c + x
}

/// The fan vertex of a feature cell, or `None` to keep the plain fan: the
/// cell at `lo` (world position of its lower corner) of size `step`, its
/// loop's crossing points in loop order. `min_twice_area` is the fan
/// triangles' degeneracy threshold.
pub(crate) fn feature_apex(
    field: &ExactField,
    lo: DVec3,
    step: f64,
    loop_points: &[[f64; 3]],
    min_twice_area: f64,
) -> Option<[f64; 3]> {
    let h = 1e-3 * step;
    // The crossings come from linear interpolation on the grid, which cuts
    // the corner near an edge: one Newton step along the exact normal puts
    // each on the surface for the quadric.
    let mut pts = Vec::with_capacity(loop_points.len());
    let mut normals = Vec::with_capacity(loop_points.len());
    for p in loop_points {
        let p = DVec3::from_array(*p);
        let (v, n) = field.value_normal(p, h)?;
        pts.push(p - n * v);
        normals.push(n);
    }
    let sharp = normals
        .iter()
        .enumerate()
        .any(|(i, a)| normals[i + 1..].iter().any(|b| a.dot(*b) < FEATURE_COS));
    if !sharp {
        return None;
    }
    let x = quadric_point(&pts, &normals);
    // A crease: the tangent planes meet (nearly) in one point or line. On
    // a surface merely curved more tightly than the cell they do not; its
    // plain fan is better there.
    let residual = pts
        .iter()
        .zip(&normals)
        .map(|(p, n)| n.dot(x - *p).abs())
        .fold(0.0, f64::max);
    if residual > RESIDUAL_REL * step {
        return None;
    }
    // Edges often run along grid planes (a cap at a round height): a point
    // on (or just past) a face of the cell is pulled inside by a hair; one
    // farther out belongs to another cell's feature.
    let margin = 1e-3 * step;
    let reach = 0.1 * step;
    let inside = (0..3).all(|a| x[a] > lo[a] - reach && x[a] < lo[a] + step + reach);
    if !inside {
        return None;
    }
    let x = x.clamp(lo + DVec3::splat(margin), lo + DVec3::splat(step - margin));
    // The fan [x, p(k+1), p(k)] (against the loop direction, as marching
    // cubes emits it, with the mesh's own crossings) must face the way the
    // crossings' normals say. Where the feature point folds a triangle
    // over, a point partway towards the crossings' centroid may not (a
    // blunter edge, still sharper than the plain fan).
    let mesh_pts: Vec<DVec3> = loop_points.iter().map(|p| DVec3::from_array(*p)).collect();
    let n = mesh_pts.len();
    let centroid = mesh_pts.iter().copied().sum::<DVec3>() / n as f64;
    let fan_ok = |x: DVec3| {
        (0..n).all(|k| {
            let (a, b) = (mesh_pts[(k + 1) % n], mesh_pts[k]);
            let area = (a - x).cross(b - x);
            area.length() > min_twice_area && area.dot(normals[k] + normals[(k + 1) % n]) > 0.0
        })
    };
    [1.0, 0.6, 0.3]
        .iter()
        .map(|t| centroid + (x - centroid) * *t)
        .find(|x| fan_ok(*x))
        .map(|x| x.to_array())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn eigen_decomposition_reconstructs_the_matrix() {
        let a = [[4.0, 1.0, 0.5], [1.0, 3.0, -0.2], [0.5, -0.2, 1.0]];
        let (ev, v) = eigen_sym(a);
        for i in 0..3 {
            for j in 0..3 {
                let r: f64 = (0..3).map(|k| v[i][k] * ev[k] * v[j][k]).sum();
                assert!((r - a[i][j]).abs() < 1e-12, "{i}{j}: {r} vs {}", a[i][j]);
            }
        }
    }

    #[test]
    fn the_quadric_point_of_two_planes_lies_on_their_edge() {
        // Planes z = 0.3 (normal +z) and x = 0.6 (normal +x): crossings on
        // both; the point goes to the edge x = 0.6, z = 0.3, and stays at
        // the crossings' mean along it (y).
        let pts = [
            DVec3::new(0.2, 0.1, 0.3),
            DVec3::new(0.4, 0.9, 0.3),
            DVec3::new(0.6, 0.5, 0.0),
            DVec3::new(0.6, 0.3, 0.1),
        ];
        let ns = [DVec3::Z, DVec3::Z, DVec3::X, DVec3::X];
        let x = quadric_point(&pts, &ns);
        assert!(
            (x.x - 0.6).abs() < 1e-12 && (x.z - 0.3).abs() < 1e-12,
            "{x}"
        );
        assert!((x.y - 0.45).abs() < 1e-12, "{x}");
    }

    #[test]
    fn linear_cells_are_not_candidates() {
        let lin = |x: f64, y: f64, z: f64| (0.3 * x - 0.5 * y + 0.2 * z - 0.1) as f32;
        let v =
            std::array::from_fn(|i| lin((i & 1) as f64, (i >> 1 & 1) as f64, (i >> 2 & 1) as f64));
        assert!(!nonlinear(&v, 1.0));
        // max(x, z) - 0.5: a right-angled edge through the cell.
        let edge = |x: f64, _y: f64, z: f64| (x.max(z) - 0.5) as f32;
        let v =
            std::array::from_fn(|i| edge((i & 1) as f64, (i >> 1 & 1) as f64, (i >> 2 & 1) as f64));
        assert!(nonlinear(&v, 1.0));
    }
}
