//! Surfaces made solid: an open surface becomes a shell of a given wall
//! thickness, a closed one can be hollowed to a wall.
//!
//! Paper 3's patches are surfaces; printing one needs a wall. Each vertex
//! moves along its angle-weighted normal (the pseudo-normal: the average of
//! the incident faces' normals weighted by their corner angles), by the
//! thickness times a mitre factor `1 / min(n · n_f)` over the incident
//! faces `f` (capped at 2), so the wall measured along each face's normal
//! keeps the full thickness at creases up to 120 degrees. The two offset
//! sheets face away from each other and every boundary edge gets a wall
//! quad joining them, so a manifold, consistently oriented surface with
//! boundary gives a closed, consistently oriented 2-manifold. A surface
//! curved tighter than the offset folds; the caller finds that with the
//! self-intersection search and names the object.

use glam::DVec3;

use super::ShellOffset;
use crate::mesh::TriMesh;

/// Why a surface could not be thickened.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum ThickenError {
    /// The surface has no triangles.
    #[error("the surface has no triangles")]
    Empty,
    /// An edge is shared by more than two triangles: the surface branches,
    /// and a wall cannot follow both branches.
    #[error("{0} edges are shared by more than two triangles (the surface branches)")]
    NonManifold(usize),
    /// Neighbouring triangles disagree on which side is the front.
    #[error(
        "{0} edges join triangles facing opposite ways (the surface is not orientable as given)"
    )]
    Misoriented(usize),
    /// A vertex's normal is undefined (its faces cancel out or have no area).
    #[error("vertex {0} has no normal (its triangles fold back onto each other or have no area)")]
    NoNormal(usize),
}

/// The shell of wall `thickness` around the open surface `surface` (see the
/// module doc). Sources are kept: every shell triangle carries the source
/// of the surface triangle (or boundary edge's triangle) it came from.
pub fn thicken(
    surface: &TriMesh,
    thickness: f64,
    offset: ShellOffset,
) -> Result<(TriMesh, usize), ThickenError> {
    let mut s = surface.clone();
    s.weld_exact();
    if s.triangles.is_empty() {
        return Err(ThickenError::Empty);
    }
    let boundary = boundary_edges(&s)?;
    let normals = offset_normals(&s)?;
    let (front, back) = match offset {
        ShellOffset::Centered => (0.5 * thickness, -0.5 * thickness),
        ShellOffset::Inward => (0.0, -thickness),
        ShellOffset::Outward => (thickness, 0.0),
    };
    let n = s.positions.len() as u32;
    let mut out = TriMesh::default();
    for (p, m) in s.positions.iter().zip(&normals) {
        out.positions
            .push((DVec3::from_array(*p) + *m * front).to_array());
    }
    for (p, m) in s.positions.iter().zip(&normals) {
        out.positions
            .push((DVec3::from_array(*p) + *m * back).to_array());
    }
    let source = |t: usize| s.tri_source.get(t).copied().unwrap_or(0);
    for (t, tri) in s.triangles.iter().enumerate() {
        out.triangles.push(*tri);
        out.tri_source.push(source(t));
    }
    for (t, [a, b, c]) in s.triangles.iter().enumerate() {
        out.triangles.push([a + n, c + n, b + n]);
        out.tri_source.push(source(t));
    }
    for &(a, b, t) in &boundary {
        // The front sheet has a -> b; the wall runs b -> a on the front,
        // a -> b on the back (which has b -> a).
        out.triangles.push([b, a, a + n]);
        out.triangles.push([b, a + n, b + n]);
        out.tri_source.push(source(t));
        out.tri_source.push(source(t));
    }
    out.compute_normals();
    Ok((out, boundary.len()))
}

/// `closed` with a wall of `thickness` inside it: the surface plus its
/// inward offset, reversed, as a second (inner) sheet.
pub fn hollow(closed: &TriMesh, thickness: f64) -> Result<TriMesh, ThickenError> {
    let mut s = closed.clone();
    s.weld_exact();
    if s.triangles.is_empty() {
        return Err(ThickenError::Empty);
    }
    let normals = offset_normals(&s)?;
    let n = s.positions.len() as u32;
    let mut out = s.clone();
    out.normals.clear();
    for (p, m) in s.positions.iter().zip(&normals) {
        out.positions
            .push((DVec3::from_array(*p) - *m * thickness).to_array());
    }
    for [a, b, c] in &s.triangles {
        out.triangles.push([a + n, c + n, b + n]);
    }
    if out.tri_source.len() == s.triangles.len() {
        out.tri_source.extend_from_within(..);
    }
    out.compute_normals();
    Ok(out)
}

/// Per vertex: the angle-weighted normal times the mitre factor.
fn offset_normals(s: &TriMesh) -> Result<Vec<DVec3>, ThickenError> {
    let nv = s.positions.len();
    let mut acc = vec![DVec3::ZERO; nv];
    let face: Vec<Option<DVec3>> = s
        .triangles
        .iter()
        .map(|t| {
            let p = t.map(|i| DVec3::from_array(s.positions[i as usize]));
            (p[1] - p[0]).cross(p[2] - p[0]).try_normalize()
        })
        .collect();
    for (tri, n) in s.triangles.iter().zip(&face) {
        let Some(n) = n else { continue };
        let p = tri.map(|i| DVec3::from_array(s.positions[i as usize]));
        for k in 0..3 {
            let angle = (p[(k + 1) % 3] - p[k]).angle_between(p[(k + 2) % 3] - p[k]);
            if angle.is_finite() {
                acc[tri[k] as usize] += *n * angle;
            }
        }
    }
    let mut used = vec![false; nv];
    for t in &s.triangles {
        for &i in t {
            used[i as usize] = true;
        }
    }
    let mut unit = Vec::with_capacity(nv);
    for (v, a) in acc.iter().enumerate() {
        match a.try_normalize() {
            Some(n) => unit.push(n),
            None if !used[v] => unit.push(DVec3::ZERO),
            None => return Err(ThickenError::NoNormal(v)),
        }
    }
    let mut min_cos = vec![1.0f64; nv];
    for (tri, n) in s.triangles.iter().zip(&face) {
        let Some(n) = n else { continue };
        for &i in tri {
            let c = unit[i as usize].dot(*n);
            min_cos[i as usize] = min_cos[i as usize].min(c);
        }
    }
    Ok(unit
        .into_iter()
        .zip(min_cos)
        .map(|(n, c)| n / c.clamp(0.5, 1.0))
        .collect())
}

/// Directed boundary edges `(a, b, triangle)` in the order their triangles
/// give them; errors for branching or misoriented edges.
fn boundary_edges(s: &TriMesh) -> Result<Vec<(u32, u32, usize)>, ThickenError> {
    let mut edges: Vec<(u32, u32, bool, usize)> = Vec::with_capacity(3 * s.triangles.len());
    for (t, tri) in s.triangles.iter().enumerate() {
        for k in 0..3 {
            let (a, b) = (tri[k], tri[(k + 1) % 3]);
            if a != b {
                edges.push((a.min(b), a.max(b), a < b, t));
            }
        }
    }
    edges.sort_unstable();
    let (mut out, mut branching, mut misoriented) = (Vec::new(), 0, 0);
    let mut i = 0;
    while i < edges.len() {
        let mut j = i;
        while j < edges.len() && edges[j].0 == edges[i].0 && edges[j].1 == edges[i].1 {
            j += 1;
        }
        match j - i {
            1 => {
                let (lo, hi, fwd, t) = edges[i];
                out.push(if fwd { (lo, hi, t) } else { (hi, lo, t) });
            }
            2 if edges[i].2 == edges[i + 1].2 => misoriented += 1,
            2 => {}
            _ => branching += 1,
        }
        i = j;
    }
    if branching > 0 {
        return Err(ThickenError::NonManifold(branching));
    }
    if misoriented > 0 {
        return Err(ThickenError::Misoriented(misoriented));
    }
    out.sort_by_key(|e| e.2);
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::fm::DetMath as _;
    use crate::mesh::{validate, ValidationSettings};

    /// A flat n x n grid of unit squares in the xy plane, facing +z.
    fn grid(n: u32, size: f64) -> TriMesh {
        let mut m = TriMesh::default();
        for j in 0..=n {
            for i in 0..=n {
                m.positions
                    .push([size * i as f64 / n as f64, size * j as f64 / n as f64, 0.0]);
            }
        }
        let id = |i: u32, j: u32| j * (n + 1) + i;
        for j in 0..n {
            for i in 0..n {
                m.triangles.push([id(i, j), id(i + 1, j), id(i + 1, j + 1)]);
                m.triangles.push([id(i, j), id(i + 1, j + 1), id(i, j + 1)]);
            }
        }
        m
    }

    #[test]
    fn a_flat_sheet_becomes_a_slab_of_the_right_volume() {
        for offset in [
            ShellOffset::Centered,
            ShellOffset::Inward,
            ShellOffset::Outward,
        ] {
            let (shell, walls) = thicken(&grid(6, 0.1), 0.002, offset).unwrap();
            assert_eq!(walls, 24);
            let r = validate(&shell, &ValidationSettings::default());
            assert!(r.is_printable(), "{offset:?}: {}", r.problems());
            assert!((r.signed_volume - 0.1 * 0.1 * 0.002).abs() < 1e-12);
            let [lo, hi] = r.bbox.unwrap();
            let (z0, z1) = match offset {
                ShellOffset::Centered => (-0.001, 0.001),
                ShellOffset::Inward => (-0.002, 0.0),
                ShellOffset::Outward => (0.0, 0.002),
            };
            assert!((lo[2] - z0).abs() < 1e-15 && (hi[2] - z1).abs() < 1e-15);
        }
    }

    #[test]
    fn a_crease_keeps_its_wall_thickness() {
        // Fold the grid 90 degrees along x = 0.05: the mitre factor keeps
        // the wall 2 mm thick on both legs, so the volume stays area * t
        // up to the corner's small excess.
        let mut g = grid(10, 0.1);
        for p in &mut g.positions {
            if p[0] > 0.05 {
                let d = p[0] - 0.05;
                p[0] = 0.05;
                p[2] = d;
            }
        }
        let (shell, _) = thicken(&g, 0.002, ShellOffset::Centered).unwrap();
        let r = validate(&shell, &ValidationSettings::default());
        assert!(r.is_printable(), "{}", r.problems());
        let want = 0.1 * 0.1 * 0.002;
        assert!(
            (r.signed_volume - want).abs() / want < 0.02,
            "{}",
            r.signed_volume
        );
    }

    #[test]
    fn hollow_sphere_has_the_shell_volume() {
        let s = crate::solid::tessellate(&crate::solid::SolidShape::Sphere { radius: 0.05 }, 64)
            .unwrap();
        let h = hollow(&s, 0.002).unwrap();
        let r = validate(&h, &ValidationSettings::default());
        assert!(r.is_printable(), "{}", r.problems());
        assert_eq!(r.components, 2);
        let shell = 4.0 / 3.0 * std::f64::consts::PI * (0.05f64.fpowi(3) - 0.048f64.fpowi(3));
        assert!(
            (r.signed_volume - shell).abs() / shell < 0.01,
            "{}",
            r.signed_volume
        );
    }

    #[test]
    fn branching_and_misoriented_surfaces_are_refused() {
        let mut g = grid(2, 1.0);
        g.triangles[1].swap(1, 2);
        assert!(matches!(
            thicken(&g, 0.1, ShellOffset::Centered),
            Err(ThickenError::Misoriented(_))
        ));
        let mut fin = grid(2, 1.0);
        fin.positions.push([0.5, 0.5, 1.0]);
        fin.triangles.push([0, 1, 9]);
        fin.triangles.push([1, 0, 9]);
        assert!(thicken(&fin, 0.1, ShellOffset::Centered).is_err());
        assert_eq!(
            thicken(&TriMesh::default(), 0.1, ShellOffset::Centered),
            Err(ThickenError::Empty)
        );
    }
}
