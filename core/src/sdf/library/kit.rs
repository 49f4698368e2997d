//! The shape kit the component library is built with: every builder
//! returns a closed, consistently oriented 2-manifold by construction.
//!
//! - [`rings`]: the one mesher behind lathes and sweeps. A solid is a
//!   stack of rings of `n` points each, every ring counter-clockwise seen
//!   from the side the stack grows towards, closed by a pole (a single
//!   vertex), a flat cap (a fan around the ring's centroid, for star-shaped
//!   rings), or by joining the last ring to the first (a ring-shaped
//!   solid, genus 1).
//! - [`lathe`] / [`lathe_ring`]: surfaces of revolution of a meridian
//!   profile `(r, z)` around +Z (pole to pole, or a closed loop off the
//!   axis: shells, tyres, lamp shades), optionally with the radius
//!   modulated by the angle (flutes, pleats).
//! - [`sweep`]: a cross-section carried along a 3D path on rotation-
//!   minimizing frames (handles, spouts, bent legs), open with flat caps or
//!   closed into a loop (planar loops only, so the frames close up).
//! - [`extrude`]: a simple polygon (any shape, ear-clipped caps) pulled
//!   along Z (brackets, slats, plates).
//! - [`implicit`]: a signed distance function meshed by our own
//!   marching cubes (blends, rounded boxes).
//! - [`union`] / [`difference`]: several parts joined or cut through
//!   Manifold (`crate::mesh::boolean`), which keeps the result closed.
//!
//! [`Detail`] says how finely to mesh: the full component, or the
//! low-poly preview the headset palette shows as its thumbnail.

use crate::math::fm::DetMath as _;
use std::f64::consts::TAU;

use crate::math::frames::{double_reflection, Frame};
use crate::math::DVec3;
use crate::mesh::TriMesh;

use super::super::analytic::solid_distance;
use super::super::mc::extract_dense;
use crate::solid::SolidShape;

/// How finely a component is meshed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Detail {
    /// The component itself (its SDF is computed from this mesh).
    Full,
    /// The palette thumbnail: a few hundred triangles.
    Preview,
}

impl Detail {
    /// Points around a circle.
    pub fn segments(self) -> usize {
        match self {
            Detail::Full => 48,
            Detail::Preview => 10,
        }
    }

    /// Stations along a curved path or profile arc of `full` stations.
    pub fn stations(self, full: usize) -> usize {
        match self {
            Detail::Full => full,
            Detail::Preview => (full / 4).max(3),
        }
    }

    /// Marching-cubes cells across the longest side of an implicit shape.
    pub fn cells(self) -> f64 {
        match self {
            Detail::Full => 90.0,
            Detail::Preview => 14.0,
        }
    }
}

/// How one end of a ring stack is closed.
#[derive(Clone, Copy, Debug)]
pub enum End {
    /// A single vertex (where a profile meets the axis).
    Pole(DVec3),
    /// A fan around the ring's centroid (rings must be star-shaped around
    /// it, as circles and convex sections are).
    Flat,
}

/// The stack of `rings` (each of the same length, counter-clockwise seen
/// from the side the stack grows towards) closed by `start` and `end`, or,
/// with `ends = None`, joined last to first.
pub fn rings(rings: &[Vec<DVec3>], ends: Option<(End, End)>) -> TriMesh {
    let n = rings[0].len();
    let mut positions: Vec<[f64; 3]> = Vec::with_capacity(rings.len() * n + 2);
    let mut triangles = Vec::with_capacity(2 * n * (rings.len() + 1));
    for r in rings {
        assert_eq!(r.len(), n, "rings of equal length");
        positions.extend(r.iter().map(|p| p.to_array()));
    }
    let at = |i: usize, j: usize| (i * n + j % n) as u32;
    let bands = if ends.is_some() {
        rings.len() - 1
    } else {
        rings.len()
    };
    for i in 0..bands {
        let i1 = (i + 1) % rings.len();
        for j in 0..n {
            let (a0, a1, b0, b1) = (at(i, j), at(i, j + 1), at(i1, j), at(i1, j + 1));
            triangles.push([a0, a1, b1]);
            triangles.push([a0, b1, b0]);
        }
    }
    if let Some((start, end)) = ends {
        let centre = |r: &[DVec3]| r.iter().copied().sum::<DVec3>() / r.len() as f64;
        let s = match start {
            End::Pole(p) => p,
            End::Flat => centre(&rings[0]),
        };
        let e = match end {
            End::Pole(p) => p,
            End::Flat => centre(&rings[rings.len() - 1]),
        };
        let si = positions.len() as u32;
        positions.push(s.to_array());
        let ei = positions.len() as u32;
        positions.push(e.to_array());
        let last = rings.len() - 1;
        for j in 0..n {
            triangles.push([si, at(0, j + 1), at(0, j)]);
            triangles.push([at(last, j), at(last, j + 1), ei]);
        }
    }
    TriMesh::new(positions, triangles)
}

fn circle(n: usize) -> impl Iterator<Item = (f64, f64)> {
    (0..n).map(move |j| {
        let a = TAU * j as f64 / n as f64;
        (a.fcos(), a.fsin())
    })
}

/// One ring of `n` points per `(r, z)` profile point, the radius scaled
/// by `modulation(angle)`: what both lathes sweep.
fn mod_rings(profile: &[[f64; 2]], n: usize, modulation: &impl Fn(f64) -> f64) -> Vec<Vec<DVec3>> {
    profile
        .iter()
        .map(|&[r, z]| {
            (0..n)
                .map(|j| {
                    let a = TAU * j as f64 / n as f64;
                    let r = r * modulation(a);
                    DVec3::new(r * a.fcos(), r * a.fsin(), z)
                })
                .collect()
        })
        .collect()
}

/// The solid of revolution of `profile` (`(r, z)` points from a point on
/// the axis up the outside to another point on the axis; the first and
/// last have `r = 0`, the others `r > 0`), with `n` points per ring and
/// the radius scaled by `modulation(angle)`.
pub fn lathe_mod(profile: &[[f64; 2]], n: usize, modulation: impl Fn(f64) -> f64) -> TriMesh {
    let rs = mod_rings(&profile[1..profile.len() - 1], n, &modulation);
    let (z0, z1) = (profile[0][1], profile[profile.len() - 1][1]);
    rings(
        &rs,
        Some((
            End::Pole(DVec3::new(0.0, 0.0, z0)),
            End::Pole(DVec3::new(0.0, 0.0, z1)),
        )),
    )
}

/// [`lathe_mod`] without modulation.
pub fn lathe(profile: &[[f64; 2]], n: usize) -> TriMesh {
    lathe_mod(profile, n, |_| 1.0)
}

/// The ring-shaped solid of revolution of a closed `profile` loop
/// (counter-clockwise in the `(r, z)` half plane, every `r > 0`): tyres,
/// tubes, open shells (a lamp shade, a bowl without a bottom).
pub fn lathe_ring_mod(profile: &[[f64; 2]], n: usize, modulation: impl Fn(f64) -> f64) -> TriMesh {
    let rs = mod_rings(profile, n, &modulation);
    rings(&rs, None)
}

/// [`lathe_ring_mod`] without modulation.
pub fn lathe_ring(profile: &[[f64; 2]], n: usize) -> TriMesh {
    lathe_ring_mod(profile, n, |_| 1.0)
}

/// A profile arc: `count` points from angle `a0` to `a1` (radians, in the
/// `(r, z)` plane) on the circle of radius `radius` around `centre`,
/// both ends included.
pub fn arc(centre: [f64; 2], radius: f64, a0: f64, a1: f64, count: usize) -> Vec<[f64; 2]> {
    (0..count)
        .map(|i| {
            let a = a0 + (a1 - a0) * i as f64 / (count - 1) as f64;
            [centre[0] + radius * a.fcos(), centre[1] + radius * a.fsin()]
        })
        .collect()
}

/// A closed cross-section: the circle of `n` points.
pub fn round_section(n: usize) -> Vec<[f64; 2]> {
    circle(n).map(|(c, s)| [c, s]).collect()
}

/// Unit tangents of a polyline (central differences; one-sided at open
/// ends).
fn tangents(path: &[DVec3], closed: bool) -> Vec<DVec3> {
    let m = path.len();
    (0..m)
        .map(|i| {
            let (a, b) = if closed {
                (path[(i + m - 1) % m], path[(i + 1) % m])
            } else {
                (path[i.saturating_sub(1)], path[(i + 1).min(m - 1)])
            };
            (b - a).normalize()
        })
        .collect()
}

/// The `section` (a closed polygon, counter-clockwise, star-shaped around
/// the origin) carried along `path`, scaled by `radii` at each point, on
/// rotation-minimizing frames that start with `r` along `r_hint`. Open
/// paths get flat caps; `closed` paths (planar loops) join up.
pub fn sweep(
    section: &[[f64; 2]],
    path: &[DVec3],
    radii: &[f64],
    r_hint: DVec3,
    closed: bool,
) -> TriMesh {
    let ts = tangents(path, closed);
    let first = Frame::new(path[0], ts[0], r_hint).expect("hint not along the path");
    let frames = double_reflection(first, path, &ts);
    let rs: Vec<Vec<DVec3>> = frames
        .iter()
        .zip(radii)
        .map(|(f, &rad)| {
            section
                .iter()
                .map(|&[x, y]| f.origin + f.r * (x * rad) + f.s * (y * rad))
                .collect()
        })
        .collect();
    rings(&rs, (!closed).then_some((End::Flat, End::Flat)))
}

/// A round tube of radius `radius` along an open `path`, with flat caps.
pub fn tube(path: &[DVec3], radius: f64, n: usize, r_hint: DVec3) -> TriMesh {
    sweep(
        &round_section(n),
        path,
        &vec![radius; path.len()],
        r_hint,
        false,
    )
}

/// Points along a planar arc in the XZ plane: centre `c`, radius `r`, from
/// angle `a0` to `a1` (measured from +X towards +Z), `count` points.
pub fn arc_xz(c: [f64; 2], r: f64, a0: f64, a1: f64, count: usize) -> Vec<DVec3> {
    arc(c, r, a0, a1, count)
        .into_iter()
        .map(|[x, z]| DVec3::new(x, 0.0, z))
        .collect()
}

/// Twice the signed area of a 2D polygon (positive: counter-clockwise).
fn area2(poly: &[[f64; 2]]) -> f64 {
    (0..poly.len())
        .map(|i| {
            let (a, b) = (poly[i], poly[(i + 1) % poly.len()]);
            a[0] * b[1] - b[0] * a[1]
        })
        .sum()
}

/// Triangles (indices, counter-clockwise) of a simple counter-clockwise
/// polygon by ear clipping.
pub fn ear_clip(poly: &[[f64; 2]]) -> Vec<[u32; 3]> {
    let cross = |o: [f64; 2], a: [f64; 2], b: [f64; 2]| {
        (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0])
    };
    let mut idx: Vec<usize> = (0..poly.len()).collect();
    let mut out = Vec::with_capacity(poly.len().saturating_sub(2));
    while idx.len() > 3 {
        let m = idx.len();
        let ear = (0..m).find(|&i| {
            let (a, b, c) = (idx[(i + m - 1) % m], idx[i], idx[(i + 1) % m]);
            if cross(poly[a], poly[b], poly[c]) <= 1e-15 {
                return false;
            }
            idx.iter().all(|&p| {
                p == a
                    || p == b
                    || p == c
                    || !(cross(poly[a], poly[b], poly[p]) >= 0.0
                        && cross(poly[b], poly[c], poly[p]) >= 0.0
                        && cross(poly[c], poly[a], poly[p]) >= 0.0)
            })
        });
        let i = ear.expect("a simple polygon always has an ear");
        let (a, b, c) = (idx[(i + m - 1) % m], idx[i], idx[(i + 1) % m]);
        out.push([a as u32, b as u32, c as u32]);
        idx.remove(i);
    }
    out.push([idx[0] as u32, idx[1] as u32, idx[2] as u32]);
    out
}

/// The prism of a simple polygon (either orientation) from `z0` to `z1`.
pub fn extrude(poly: &[[f64; 2]], z0: f64, z1: f64) -> TriMesh {
    let mut poly = poly.to_vec();
    if area2(&poly) < 0.0 {
        poly.reverse();
    }
    let n = poly.len() as u32;
    let mut positions = Vec::with_capacity(2 * poly.len());
    positions.extend(poly.iter().map(|p| [p[0], p[1], z0]));
    positions.extend(poly.iter().map(|p| [p[0], p[1], z1]));
    let mut triangles = Vec::new();
    for t in ear_clip(&poly) {
        triangles.push([t[0] + n, t[1] + n, t[2] + n]);
        triangles.push([t[0], t[2], t[1]]);
    }
    for i in 0..n {
        let j = (i + 1) % n;
        triangles.push([i, j, j + n]);
        triangles.push([i, j + n, i + n]);
    }
    TriMesh::new(positions, triangles)
}

/// A rounded rectangle polygon (`w` × `h`, corner radius `r`, `k` points
/// per corner), centred, counter-clockwise.
pub fn rounded_rect(w: f64, h: f64, r: f64, k: usize) -> Vec<[f64; 2]> {
    let (hx, hy) = (w / 2.0 - r, h / 2.0 - r);
    let mut out = Vec::with_capacity(4 * k);
    for (q, (cx, cy)) in [(hx, hy), (-hx, hy), (-hx, -hy), (hx, -hy)]
        .into_iter()
        .enumerate()
    {
        for i in 0..k {
            let a = TAU / 4.0 * (q as f64 + i as f64 / (k - 1).max(1) as f64);
            out.push([cx + r * a.fcos(), cy + r * a.fsin()]);
        }
    }
    out
}

/// The regular polygon of `n` sides and circumradius `r`, counter-clockwise.
pub fn regular(n: usize, r: f64, phase: f64) -> Vec<[f64; 2]> {
    (0..n)
        .map(|i| {
            let a = phase + TAU * i as f64 / n as f64;
            [r * a.fcos(), r * a.fsin()]
        })
        .collect()
}

/// A star (or gear) polygon: `n` points alternating between radii `r0`
/// and `r1`, counter-clockwise.
pub fn star(n: usize, r0: f64, r1: f64) -> Vec<[f64; 2]> {
    (0..2 * n)
        .map(|i| {
            let a = TAU * i as f64 / (2 * n) as f64;
            let r = if i % 2 == 0 { r0 } else { r1 };
            [r * a.fcos(), r * a.fsin()]
        })
        .collect()
}

/// A solid's mesh, placed: the shape tessellated at `detail`, rotated by
/// `rot` (a unit quaternion `[x, y, z, w]`) and moved to `at`.
pub fn solid_at(shape: SolidShape, detail: Detail, at: [f64; 3], rot: [f64; 4]) -> TriMesh {
    let mut m = crate::solid::tessellate(&shape, detail.segments() as u32)
        .expect("library shapes are valid");
    let q = crate::math::DQuat::from_array(rot);
    let a = crate::math::DAffine3::from_rotation_translation(q, DVec3::from_array(at));
    m.transform(&a);
    m.normals.clear();
    m
}

/// No rotation.
pub const NO_ROT: [f64; 4] = [0.0, 0.0, 0.0, 1.0];

/// The quaternion of a rotation by `angle` about unit `axis`.
pub fn rot(axis: [f64; 3], angle: f64) -> [f64; 4] {
    crate::math::DQuat::from_axis_angle(DVec3::from_array(axis), angle).to_array()
}

/// `m` moved by `d`.
pub fn moved(mut m: TriMesh, d: [f64; 3]) -> TriMesh {
    for p in &mut m.positions {
        for k in 0..3 {
            p[k] += d[k];
        }
    }
    m
}

/// `m` rotated by `q` about the origin.
pub fn rotated(mut m: TriMesh, q: [f64; 4]) -> TriMesh {
    m.transform(&crate::math::DAffine3::from_quat(
        crate::math::DQuat::from_array(q),
    ));
    m.normals.clear();
    m
}

/// The union of closed parts (Manifold), as one closed mesh.
pub fn union(parts: &[TriMesh]) -> TriMesh {
    let refs: Vec<&TriMesh> = parts.iter().collect();
    let mut m = crate::mesh::union(&refs).expect("library parts are closed");
    m.tri_source.clear();
    m
}

/// `a` minus the union of `cutters` (Manifold), as one closed mesh.
pub fn difference(a: &TriMesh, cutters: &[TriMesh]) -> TriMesh {
    let refs: Vec<&TriMesh> = cutters.iter().collect();
    let mut m = crate::mesh::difference(a, &refs).expect("library parts are closed");
    m.tri_source.clear();
    m
}

/// The zero set of `f` within the box `lo..hi` (`f` must be positive on
/// and beyond the box's faces), meshed by our marching cubes with about
/// `detail.cells()` cells across the longest side.
pub fn implicit(f: impl Fn(DVec3) -> f64, lo: DVec3, hi: DVec3, detail: Detail) -> TriMesh {
    let step = (hi - lo).max_element() / detail.cells();
    implicit_at_step(f, lo - DVec3::splat(step), hi + DVec3::splat(step), step)
}

/// The zero set of `f` sampled on the grid from `lo` at spacing `step`
/// covering `hi` (samples beyond the grid count as outside).
pub fn implicit_at_step(f: impl Fn(DVec3) -> f64, lo: DVec3, hi: DVec3, step: f64) -> TriMesh {
    let n = ((hi - lo) / step).ceil();
    let dims = [n.x as usize + 1, n.y as usize + 1, n.z as usize + 1];
    let mut v = Vec::with_capacity(dims[0] * dims[1] * dims[2]);
    for z in 0..dims[2] {
        for y in 0..dims[1] {
            for x in 0..dims[0] {
                v.push(f(lo + DVec3::new(x as f64, y as f64, z as f64) * step) as f32);
            }
        }
    }
    let (p, t) = extract_dense(&v, dims, lo.to_array(), step);
    TriMesh::new(p, t)
}

/// Polynomial smooth minimum of `a` and `b` with blend radius `k`.
pub fn smin(a: f64, b: f64, k: f64) -> f64 {
    let h = (0.5 + 0.5 * (b - a) / k).clamp(0.0, 1.0);
    b + (a - b) * h - k * h * (1.0 - h)
}

/// The exact distance of `shape` at `p - at`.
pub fn dist(shape: &SolidShape, p: DVec3, at: [f64; 3]) -> f64 {
    solid_distance(shape, p - DVec3::from_array(at))
}

/// Signed distance to a box of half sizes `h` with rounded edges of
/// radius `r` (centred at the origin).
pub fn rounded_box(p: DVec3, h: DVec3, r: f64) -> f64 {
    let q = p.abs() - h + DVec3::splat(r);
    q.max(DVec3::ZERO).length() + q.max_element().min(0.0) - r
}
