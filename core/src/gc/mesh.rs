//! Meshing a GC to a closed, oriented 2-manifold (§3.1 shape types).
//!
//! The side surface is sampled on a grid whose `u` samples contain every
//! knot of the common section knot vector (so polygon corners are exact)
//! and whose `v` samples contain every section parameter. The topology is
//! built by index (rings of `m` vertices, the seam shared), so the mesh is
//! a closed manifold by construction:
//! - solid: side + the faces enclosed by the first and last rings, each a
//!   fan around the ring centroid;
//! - shell: side + inner wall (the side offset inwards by τ along the
//!   mitred normal, exact wall thickness at polygon corners) + two annuli;
//! - container: shell whose inner wall stops at the floor (the spine point
//!   at arc length τ from the closed end) + the outer cap + the floor cap.
//!
//! The topology is closed and oriented by construction; a final geometric
//! check (finite, no degenerate triangle, positive volume, as
//! [`crate::mesh::validate`] defines them) makes the result a closed,
//! oriented, positive-volume 2-manifold or [`GcError::InvalidMesh`] (a
//! side surface folded inside out by a bend much tighter than the
//! sections are wide ends here). Self-intersections that keep the volume
//! positive are not detected (no triangle-triangle test).
//!
//! Thickness checks: τ must be below the inscribed radius of every sampled
//! ring (distance from the ring centroid to its nearest edge), every inner
//! edge must keep the direction of its outer edge (no swallowtail where
//! the section curves more tightly than τ), and a container needs a spine
//! longer than τ. Otherwise [`GcError::ThicknessTooLarge`].

use glam::{DVec3, DVec4};

use super::{ClosedEnd, Gc, GcError, ShapeType};
use crate::mesh::{TriMesh, ValidationSettings};
use crate::nurbs::{knot_aligned_samples, knot_multiplicities, NurbsSurface};

/// Samples over `[breaks[0], breaks[last]]` containing every break, with
/// `per_range` segments over the whole range (at least one per interval).
pub fn samples_between(breaks: &[f64], per_range: usize) -> Vec<f64> {
    let (a, b) = (breaks[0], breaks[breaks.len() - 1]);
    let mut out = Vec::new();
    for w in breaks.windows(2) {
        let segs = (((w[1] - w[0]) / (b - a) * per_range as f64).ceil() as usize).max(1);
        for s in 0..segs {
            out.push(w[0] + (w[1] - w[0]) * s as f64 / segs as f64);
        }
    }
    out.push(b);
    out
}

fn rows_at(surf: &NurbsSurface, us: &[f64], vs: &[f64]) -> Result<Vec<Vec<DVec3>>, GcError> {
    let mut rows = Vec::with_capacity(vs.len());
    for &v in vs {
        let c = surf.iso_curve_v(v);
        let mut row = Vec::with_capacity(us.len());
        for &u in us {
            let h: DVec4 = c.point_h(u);
            if !(h.w > 0.0) || !h.is_finite() {
                return Err(GcError::DegenerateSurface(v));
            }
            row.push(DVec3::new(h.x / h.w, h.y / h.w, h.z / h.w));
        }
        rows.push(row);
    }
    Ok(rows)
}

fn centroid(ring: &[DVec3]) -> DVec3 {
    ring.iter().copied().sum::<DVec3>() / ring.len() as f64
}

fn seg_dist(p: DVec3, a: DVec3, b: DVec3) -> f64 {
    let ab = b - a;
    let t = if ab.length_squared() > 0.0 {
        ((p - a).dot(ab) / ab.length_squared()).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (a + ab * t - p).length()
}

/// Distance from the ring centroid to the nearest ring edge.
pub fn inscribed_radius(ring: &[DVec3]) -> f64 {
    let c = centroid(ring);
    let m = ring.len();
    (0..m)
        .map(|i| seg_dist(c, ring[i], ring[(i + 1) % m]))
        .fold(f64::INFINITY, f64::min)
}

/// Rows offset inwards by `tau`. Each vertex moves along its mitred
/// normal (`(n0 + n1) / (1 + n0 . n1)` of its two edge normals), which
/// keeps the wall thickness exact at sharp corners. Samples next to a
/// crease (`creases`: ring indices of C0 knots) can overshoot the inner
/// corner; so along each run between two creases the offset samples that
/// overshoot are dropped and the run's inner samples are re-placed along
/// the remaining inner polyline at the outer samples' arc-length
/// fractions (on a straight run: proportionally between the inner
/// corners; on a circle: where they were). A remaining reversed inner
/// edge is reported as [`GcError::ThicknessTooLarge`].
fn offset_rows(
    rows: &[Vec<DVec3>],
    vs: &[f64],
    tau: f64,
    creases: &[usize],
) -> Result<Vec<Vec<DVec3>>, GcError> {
    let nr = rows.len();
    let m = rows[0].len();
    let mut out = Vec::with_capacity(nr);
    for j in 0..nr {
        let too_thick = |r: f64| GcError::ThicknessTooLarge {
            thickness: tau,
            inscribed_radius: r,
            v: vs[j],
        };
        let ring = &rows[j];
        let r_in = inscribed_radius(ring);
        if tau >= r_in {
            return Err(too_thick(r_in));
        }
        let (jp, jn) = (j.saturating_sub(1), (j + 1).min(nr - 1));
        // Edge normals: edge i goes from vertex i to i + 1.
        let mut en = Vec::with_capacity(m);
        for i in 0..m {
            let i1 = (i + 1) % m;
            let tv = (rows[jn][i] - rows[jp][i]) + (rows[jn][i1] - rows[jp][i1]);
            let n = (ring[i1] - ring[i]).cross(tv).try_normalize();
            en.push(n.ok_or(GcError::DegenerateSurface(vs[j]))?);
        }
        let mut inner = Vec::with_capacity(m);
        for i in 0..m {
            let (n0, n1) = (en[(i + m - 1) % m], en[i]);
            let d = n0.dot(n1);
            if d < -0.9 {
                // Adjacent faces turn by more than ~154 degrees (a
                // needle-sharp crease or a fold at this resolution): no
                // inward offset of any useful thickness exists there.
                return Err(too_thick(0.0));
            }
            inner.push(ring[i] - (n0 + n1) * (tau / (1.0 + d)));
        }
        let naive = inner.clone();
        // Anchors: the creases, thinned so that no two are closer than 2τ
        // along the ring (of a close pair the smoother one is dropped).
        let arc = |a: usize, b: usize| -> f64 {
            let len = if b > a { b - a } else { b + m - a };
            (0..len)
                .map(|t| (ring[(a + t + 1) % m] - ring[(a + t) % m]).length())
                .sum()
        };
        let turn = |i: usize| en[(i + m - 1) % m].dot(en[i]);
        let mut creases: Vec<usize> = creases.to_vec();
        while creases.len() > 1 {
            let n = creases.len();
            let close = (0..n).find(|&k| arc(creases[k], creases[(k + 1) % n]) < 2.0 * tau);
            let Some(k) = close else { break };
            let (i0, i1) = (creases[k], creases[(k + 1) % n]);
            let drop = if turn(i0) > turn(i1) { k } else { (k + 1) % n };
            creases.remove(drop);
        }
        for (k, &a) in creases.iter().enumerate() {
            let b = creases[(k + 1) % creases.len()];
            let len = if b > a { b - a } else { b + m - a };
            let len = if creases.len() == 1 { m } else { len };
            if len < 2 {
                continue;
            }
            let at = |t: usize| (a + t) % m;
            // Outer arc-length fractions along the run.
            let mut cum = vec![0.0; len + 1];
            for t in 0..len {
                cum[t + 1] = cum[t] + (ring[at(t + 1)] - ring[at(t)]).length();
            }
            // The inner run without the samples that overshoot a corner.
            let (ia, ib) = (naive[a], naive[b]);
            let ta = ring[at(1)] - ring[a];
            let tb = ring[b] - ring[at(len - 1)];
            let mut kept = vec![ia];
            for t in 1..len {
                let q = naive[at(t)];
                let last = kept[kept.len() - 1];
                if (q - ia).dot(ta) > 0.0
                    && (q - ib).dot(tb) < 0.0
                    && (q - last).dot(ring[at(t)] - ring[at(t - 1)]) > 0.0
                {
                    kept.push(q);
                }
            }
            kept.push(ib);
            let mut kcum = vec![0.0; kept.len()];
            for t in 1..kept.len() {
                kcum[t] = kcum[t - 1] + (kept[t] - kept[t - 1]).length();
            }
            let total = kcum[kept.len() - 1];
            if !(total > 0.0) || !(cum[len] > 0.0) {
                return Err(too_thick(r_in.min(tau)));
            }
            // Place the inner samples at the outer fractions along it.
            let mut seg = 1;
            for t in 1..len {
                let target = cum[t] / cum[len] * total;
                while seg + 1 < kept.len() && kcum[seg] < target {
                    seg += 1;
                }
                let (l0, l1) = (kcum[seg - 1], kcum[seg]);
                let f = if l1 > l0 {
                    ((target - l0) / (l1 - l0)).clamp(0.0, 1.0)
                } else {
                    0.0
                };
                inner[at(t)] = kept[seg - 1] + (kept[seg] - kept[seg - 1]) * f;
            }
        }
        for i in 0..m {
            let (a, b) = (inner[i], inner[(i + 1) % m]);
            let (oa, ob) = (ring[i], ring[(i + 1) % m]);
            if (b - a).dot(ob - oa) <= 0.0 {
                return Err(too_thick(r_in.min(tau)));
            }
        }
        out.push(inner);
    }
    Ok(out)
}

#[derive(Default)]
struct Builder {
    pos: Vec<[f64; 3]>,
    tris: Vec<[u32; 3]>,
    m: usize,
}

impl Builder {
    fn rows(&mut self, rows: &[Vec<DVec3>]) -> u32 {
        let base = self.pos.len() as u32;
        for r in rows {
            self.pos.extend(r.iter().map(|p| p.to_array()));
        }
        base
    }
    fn side(&mut self, base: u32, nrows: usize, flip: bool) {
        let m = self.m as u32;
        for j in 0..nrows as u32 - 1 {
            for i in 0..m {
                let a = base + j * m + i;
                let b = base + j * m + (i + 1) % m;
                let c = base + (j + 1) * m + (i + 1) % m;
                let d = base + (j + 1) * m + i;
                // Split along the shorter diagonal: better-shaped
                // triangles, and the choice does not depend on the ring's
                // direction, so a mirrored GC meshes to the mirror image
                // (a fixed diagonal flips under reflection and changes
                // the volume at the resolution scale).
                let quad = if self.diag2(a, c) <= self.diag2(b, d) {
                    [[a, b, c], [a, c, d]]
                } else {
                    [[a, b, d], [b, c, d]]
                };
                for [p, q, r] in quad {
                    self.tris.push(if flip { [p, r, q] } else { [p, q, r] });
                }
            }
        }
    }
    /// Squared distance between vertices `i` and `j`.
    fn diag2(&self, i: u32, j: u32) -> f64 {
        let (p, q) = (self.pos[i as usize], self.pos[j as usize]);
        (0..3).map(|k| (p[k] - q[k]) * (p[k] - q[k])).sum()
    }
    /// Fan over a ring; `plus_t` faces along the spine direction.
    fn cap(&mut self, ring_base: u32, ring: &[DVec3], plus_t: bool) {
        let c = self.pos.len() as u32;
        self.pos.push(centroid(ring).to_array());
        let m = self.m as u32;
        for i in 0..m {
            let (a, b) = (ring_base + i, ring_base + (i + 1) % m);
            self.tris.push(if plus_t { [c, a, b] } else { [c, b, a] });
        }
    }
    fn annulus(&mut self, outer: u32, inner: u32, top: bool) {
        let m = self.m as u32;
        for i in 0..m {
            let (o0, o1) = (outer + i, outer + (i + 1) % m);
            let (n0, n1) = (inner + i, inner + (i + 1) % m);
            if top {
                self.tris.push([o0, o1, n1]);
                self.tris.push([o0, n1, n0]);
            } else {
                self.tris.push([o0, n1, o1]);
                self.tris.push([o0, n0, n1]);
            }
        }
    }
}

/// The spine parameter at arc length `len` from `from` towards `to`
/// (piecewise linear over 1024 steps), or `None` when the range is shorter.
fn param_at_arc_length(gc: &Gc, from: f64, to: f64, len: f64) -> Option<f64> {
    let steps = 1024;
    let mut acc = 0.0;
    let mut prev = gc.spine.curve.point(from);
    for i in 1..=steps {
        let v = from + (to - from) * i as f64 / steps as f64;
        let p = gc.spine.curve.point(v);
        let d = (p - prev).length();
        if acc + d >= len && d > 0.0 {
            let f = (len - acc) / d;
            let v0 = from + (to - from) * (i - 1) as f64 / steps as f64;
            return Some(v0 + (v - v0) * f);
        }
        acc += d;
        prev = p;
    }
    None
}

/// Meshes `gc` at its resolution.
/// A GC's side surface sampled on the meshing grid.
struct Sampled {
    surf: NurbsSurface,
    us: Vec<f64>,
    /// Samples per ring.
    m: usize,
    /// Ring indices of polygon corners (mitred offsets there).
    creases: Vec<usize>,
    vs: Vec<f64>,
    rows: Vec<Vec<DVec3>>,
}

fn sample(gc: &Gc) -> Result<Sampled, GcError> {
    let surf = gc.surface()?;
    let res = gc.resolution;
    let mut us = knot_aligned_samples(&surf.knots_u, surf.degree_u, res.u as usize);
    us.pop(); // u = 1 is the seam, the same points as u = 0
    let m = us.len();
    let crease_u: Vec<f64> = knot_multiplicities(&surf.knots_u)
        .into_iter()
        .filter(|(_, mult)| *mult >= surf.degree_u)
        .map(|(u, _)| u)
        .collect();
    let mut creases: Vec<usize> = vec![0];
    creases.extend((1..m).filter(|i| crease_u.contains(&us[*i])));
    let v_breaks: Vec<f64> = gc.sections.iter().map(|s| s.v).collect();
    let vs = samples_between(&v_breaks, res.v as usize);
    let rows = rows_at(&surf, &us, &vs)?;
    for (j, r) in rows.iter().enumerate() {
        for i in 0..m {
            if (r[(i + 1) % m] - r[i]).length_squared() == 0.0 {
                return Err(GcError::DegenerateSurface(vs[j]));
            }
        }
    }
    Ok(Sampled {
        surf,
        us,
        m,
        creases,
        vs,
        rows,
    })
}

/// The rings of a hollow GC's inner wall: the side offset inwards by τ,
/// over the whole spine for a shell, up to the floor (τ of arc length
/// from the closed end) for a container; `None` for a solid. With a
/// positive `grow` the space inside is grown by it on every side: the wall and
/// the floor are `τ - grow` thick, and the open ends' rings are moved out
/// along the spine by `grow` (see [`cavity_gc`]).
fn inner_wall(gc: &Gc, s: &Sampled, grow: f64) -> Result<Option<Vec<Vec<DVec3>>>, GcError> {
    let rows = match gc.shape {
        ShapeType::Solid => return Ok(None),
        ShapeType::Shell { thickness } => {
            offset_rows(&s.rows, &s.vs, thickness - grow, &s.creases)?
        }
        ShapeType::Container {
            thickness,
            closed_end,
        } => container_wall(gc, s, thickness, closed_end, grow)?,
    };
    Ok(Some(if grow > 0.0 {
        open_ends_moved_out(gc, rows, grow)
    } else {
        rows
    }))
}

/// `rows` with the rings at the GC's open ends moved out along the spine
/// by `grow` (a container's floor stays).
fn open_ends_moved_out(gc: &Gc, mut rows: Vec<Vec<DVec3>>, grow: f64) -> Vec<Vec<DVec3>> {
    let (first_open, last_open) = match gc.shape {
        ShapeType::Container {
            closed_end: ClosedEnd::Start,
            ..
        } => (false, true),
        ShapeType::Container {
            closed_end: ClosedEnd::End,
            ..
        } => (true, false),
        _ => (true, true),
    };
    let (v0, v1) = (gc.sections[0].v, gc.sections[gc.sections.len() - 1].v);
    let n = rows.len();
    for (open, j, v, sign) in [(first_open, 0, v0, -1.0), (last_open, n - 1, v1, 1.0)] {
        if !open {
            continue;
        }
        if let Some(t) = gc.spine.curve.tangent(v).try_normalize() {
            for p in &mut rows[j] {
                *p += t * (sign * grow);
            }
        }
    }
    rows
}

/// A container's inner wall rings (see [`inner_wall`]), the wall and the
/// floor `thickness - grow` thick.
fn container_wall(
    gc: &Gc,
    s: &Sampled,
    thickness: f64,
    closed_end: ClosedEnd,
    grow: f64,
) -> Result<Vec<Vec<DVec3>>, GcError> {
    let vs = &s.vs;
    let nr = vs.len();
    let (v0, v1) = (vs[0], vs[nr - 1]);
    let eps = 1e-9 * (v1 - v0);
    let too_short = || GcError::ThicknessTooLarge {
        thickness,
        inscribed_radius: 0.0,
        v: if closed_end == ClosedEnd::Start {
            v0
        } else {
            v1
        },
    };
    let floor = thickness - grow;
    let vs_in: Vec<f64> = match closed_end {
        ClosedEnd::Start => {
            let vf = param_at_arc_length(gc, v0, v1, floor).ok_or_else(too_short)?;
            let mut v = vec![vf];
            v.extend(vs.iter().copied().filter(|x| *x > vf + eps));
            v
        }
        ClosedEnd::End => {
            let vf = param_at_arc_length(gc, v1, v0, floor).ok_or_else(too_short)?;
            let mut v: Vec<f64> = vs.iter().copied().filter(|x| *x < vf - eps).collect();
            v.push(vf);
            v
        }
    };
    if vs_in.len() < 2 {
        return Err(too_short());
    }
    let in_src = rows_at(&s.surf, &s.us, &vs_in)?;
    // Offset normals need v-neighbours: check the thickness on the full
    // outer rows too (inscribed radius of every ring).
    offset_rows(&s.rows, vs, thickness, &s.creases)?;
    offset_rows(&in_src, &vs_in, floor, &s.creases)
}

/// Meshes `gc` to a closed, oriented 2-manifold (see the module doc).
pub fn mesh_gc(gc: &Gc) -> Result<TriMesh, GcError> {
    let s = sample(gc)?;
    let inner = inner_wall(gc, &s, 0.0)?;
    let rows = &s.rows;
    let mut b = Builder {
        m: s.m,
        ..Default::default()
    };
    let nr = rows.len();
    let m = s.m;
    let outer = b.rows(rows);
    let row_base = |base: u32, j: usize| base + (j * m) as u32;
    b.side(outer, nr, false);
    match (gc.shape, inner) {
        (ShapeType::Container { closed_end, .. }, Some(inner_rows)) => {
            let ni = inner_rows.len();
            let inner = b.rows(&inner_rows);
            b.side(inner, ni, true);
            match closed_end {
                ClosedEnd::Start => {
                    b.cap(row_base(outer, 0), &rows[0], false);
                    b.cap(row_base(inner, 0), &inner_rows[0], true);
                    b.annulus(row_base(outer, nr - 1), row_base(inner, ni - 1), true);
                }
                ClosedEnd::End => {
                    b.cap(row_base(outer, nr - 1), &rows[nr - 1], true);
                    b.cap(row_base(inner, ni - 1), &inner_rows[ni - 1], false);
                    b.annulus(row_base(outer, 0), row_base(inner, 0), false);
                }
            }
        }
        (_, Some(inner_rows)) => {
            let inner = b.rows(&inner_rows);
            b.side(inner, nr, true);
            b.annulus(row_base(outer, 0), row_base(inner, 0), false);
            b.annulus(row_base(outer, nr - 1), row_base(inner, nr - 1), true);
        }
        (_, None) => {
            b.cap(row_base(outer, 0), &rows[0], false);
            b.cap(row_base(outer, nr - 1), &rows[nr - 1], true);
        }
    }
    let mut mesh = TriMesh::new(b.pos, b.tris);
    check_geometry(&mesh)?;
    mesh.compute_normals();
    Ok(mesh)
}

/// How much [`cavity_gc`] grows the hollow inside, relative to the GC's
/// size (the diagonal of its sampled side's box); at most a hundredth of
/// the wall.
pub const CAVITY_GROWTH: f64 = 1e-5;

/// The hollow inside of a shell or container as a closed solid (its inner
/// wall capped at both ends: the open ends' rims and a container's floor),
/// or `None` for a solid GC. An assembly keeps this space empty (see
/// [`crate::assembly::union_mesh`]).
///
/// The solid is the inside grown by `CAVITY_GROWTH` of the GC's size on
/// every side (3 µm on the teapot's body): a part cut by it keeps no face
/// on this GC's inner wall, and this GC cut by a hollow child's grown
/// inside keeps none on the child's, so the union never meets coincident
/// faces (where a handle's end was cut exactly at the body's inner wall,
/// the union left slivers and stray four-triangle pieces, depending on
/// rounding). The grown part lies inside the other part's wall.
pub fn cavity_gc(gc: &Gc) -> Result<Option<TriMesh>, GcError> {
    let s = sample(gc)?;
    let (lo, hi) = s
        .rows
        .iter()
        .flatten()
        .fold((DVec3::INFINITY, DVec3::NEG_INFINITY), |(lo, hi), p| {
            (lo.min(*p), hi.max(*p))
        });
    let thickness = match gc.shape {
        ShapeType::Solid => return Ok(None),
        ShapeType::Shell { thickness } | ShapeType::Container { thickness, .. } => thickness,
    };
    let grow = (CAVITY_GROWTH * (hi - lo).length()).min(0.01 * thickness);
    let Some(inner) = inner_wall(gc, &s, grow)? else {
        return Ok(None);
    };
    let mut b = Builder {
        m: s.m,
        ..Default::default()
    };
    let n = inner.len();
    let base = b.rows(&inner);
    b.side(base, n, false);
    b.cap(base, &inner[0], false);
    b.cap(base + ((n - 1) * s.m) as u32, &inner[n - 1], true);
    let mut mesh = TriMesh::new(b.pos, b.tris);
    check_geometry(&mesh)?;
    mesh.compute_normals();
    Ok(Some(mesh))
}

/// The geometric half of [`crate::mesh::validate`] (the topology is closed
/// and oriented by construction, and the tests run the full validation):
/// finite positions, no degenerate triangle (area at most 1e-14 times the
/// squared bounding-box diagonal, validate's default), positive volume.
/// O(n), a third of the cost of the full validation.
fn check_geometry(mesh: &TriMesh) -> Result<(), GcError> {
    if mesh.positions.iter().flatten().any(|x| !x.is_finite()) {
        return Err(GcError::InvalidMesh("non-finite vertices".into()));
    }
    let Some((lo, hi)) = mesh.bbox() else {
        return Err(GcError::InvalidMesh("no triangles".into()));
    };
    let tol = ValidationSettings::default().degenerate_area_rel * (hi - lo).length_squared();
    let degenerate = (0..mesh.triangles.len())
        .filter(|t| {
            let [a, b, c] = mesh.corners(*t);
            !(0.5 * (b - a).cross(c - a).length() > tol)
        })
        .count();
    if degenerate > 0 {
        return Err(GcError::InvalidMesh(format!(
            "{degenerate} degenerate triangles"
        )));
    }
    let v = mesh.signed_volume();
    if !(v > 0.0) {
        return Err(GcError::InvalidMesh(format!("non-positive volume {v}")));
    }
    Ok(())
}
