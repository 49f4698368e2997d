//! Validation of the invariants a printable mesh must hold: every edge
//! shared by exactly two triangles with opposite orientation, every vertex a
//! single fan, finite coordinates within a printable range, no degenerate
//! triangles, no self-intersection (exact, see [`super::self_intersections`]);
//! plus topology (components, Euler characteristic, genus) and measures
//! (volume, box).
//!
//! Edges are found by sorting, not hashing, so the cost is O(n log n) with
//! good locality and the report is deterministic.
//!
//! [`ValidationReport::is_closed_manifold`] is the topological verdict
//! (what Manifold's import accepts, plus finite, non-degenerate, positive
//! volume); [`ValidationReport::is_printable`] adds the geometric ones (no
//! self-intersection, coordinates in range): what a slicer prints without
//! repair. Validate a mesh at the precision of its file with
//! [`super::at_precision`] first.

use glam::DVec3;
use rayon::prelude::*;
use serde::Serialize;

use super::{self_intersections, TriMesh};

/// Tolerances for [`validate`].
#[derive(Clone, Copy, Debug)]
pub struct ValidationSettings {
    /// A triangle whose area is at most this times the squared bounding-box
    /// diagonal counts as degenerate.
    pub degenerate_area_rel: f64,
    /// Look for self-intersections (a BVH and exact predicates; the whole
    /// check took 0.76 µs per triangle on two threads on the README
    /// bench's 1M-triangle sphere, 2026-11-29). Off, the report's
    /// `self_intersecting_pairs` is `None` and `is_printable` is false.
    pub self_intersections: bool,
    /// Coordinates beyond this magnitude are out of range: no printer
    /// builds a part a thousand kilometres wide, and float32 files hold
    /// such a part with steps of metres. In file units.
    pub max_abs_coordinate: f64,
}

impl Default for ValidationSettings {
    fn default() -> Self {
        Self {
            degenerate_area_rel: 1e-14,
            self_intersections: true,
            max_abs_coordinate: 1e6,
        }
    }
}

impl ValidationSettings {
    /// Topology and measures only (no self-intersection search).
    pub fn topology_only() -> Self {
        Self {
            self_intersections: false,
            ..Self::default()
        }
    }
}

/// How many intersecting pairs a report lists by index.
pub const LISTED_PAIRS: usize = 8;

/// What [`validate`] found. `is_closed_manifold` sums it up.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct ValidationReport {
    /// Vertices in the buffer.
    pub vertex_count: usize,
    /// Vertices referenced by at least one triangle.
    pub referenced_vertices: usize,
    /// Triangles in the buffer.
    pub triangle_count: usize,
    /// Distinct undirected edges.
    pub edge_count: usize,
    /// Vertices with a NaN or infinite coordinate.
    pub non_finite_vertices: usize,
    /// Finite vertices with a coordinate beyond
    /// [`ValidationSettings::max_abs_coordinate`].
    pub out_of_range_vertices: usize,
    /// Triangles with an index past the end of the positions.
    pub out_of_range_triangles: usize,
    /// Triangles with a repeated index or (near) zero area.
    pub degenerate_triangles: usize,
    /// Edges used by one triangle only (holes).
    pub boundary_edges: usize,
    /// Edges used by more than two triangles.
    pub non_manifold_edges: usize,
    /// Edges used twice in the same direction (neighbours disagree on
    /// which side is out).
    pub misoriented_edges: usize,
    /// Vertices whose triangles form more than one fan (pinch points).
    pub non_manifold_vertices: usize,
    /// Pairs of triangles meeting outside what they share, or `None` when
    /// not searched (turned off, or coordinates that cannot be judged).
    pub self_intersecting_pairs: Option<usize>,
    /// The first [`LISTED_PAIRS`] intersecting pairs (triangle indices).
    pub intersecting_examples: Vec<(u32, u32)>,
    /// Connected components (through shared vertices).
    pub components: usize,
    /// V - E + F over referenced vertices.
    pub euler_characteristic: i64,
    /// Total genus when the mesh is a closed oriented 2-manifold.
    pub genus: Option<i64>,
    /// Signed enclosed volume (positive when triangles face outward).
    pub signed_volume: f64,
    /// Surface area.
    pub area: f64,
    /// Bounding box `[min, max]`, or `None` for an empty mesh.
    pub bbox: Option<[[f64; 3]; 2]>,
}

impl ValidationReport {
    /// Every edge has exactly two triangles, in opposite directions.
    pub fn is_closed(&self) -> bool {
        self.boundary_edges == 0 && self.non_manifold_edges == 0 && self.misoriented_edges == 0
    }

    /// A closed, consistently oriented 2-manifold with finite coordinates,
    /// no degenerate triangles, at least one triangle and positive volume:
    /// what a slicer accepts without repair.
    pub fn is_closed_manifold(&self) -> bool {
        self.triangle_count > 0
            && self.is_closed()
            && self.non_manifold_vertices == 0
            && self.non_finite_vertices == 0
            && self.out_of_range_triangles == 0
            && self.degenerate_triangles == 0
            && self.signed_volume > 0.0
    }

    /// What a slicer prints without repair: a closed manifold
    /// ([`Self::is_closed_manifold`]) that was searched for
    /// self-intersections and has none, with every coordinate in range.
    pub fn is_printable(&self) -> bool {
        self.is_closed_manifold()
            && self.self_intersecting_pairs == Some(0)
            && self.out_of_range_vertices == 0
    }

    /// Each check with its verdict, in the order `info` prints them.
    pub fn checks(&self) -> Vec<(&'static str, bool)> {
        vec![
            ("non-empty", self.triangle_count > 0),
            ("finite coordinates", self.non_finite_vertices == 0),
            ("coordinates in range", self.out_of_range_vertices == 0),
            ("indices in range", self.out_of_range_triangles == 0),
            ("no degenerate triangles", self.degenerate_triangles == 0),
            ("closed (no boundary edges)", self.boundary_edges == 0),
            ("manifold edges", self.non_manifold_edges == 0),
            ("consistently oriented", self.misoriented_edges == 0),
            ("no pinched vertices", self.non_manifold_vertices == 0),
            ("positive volume", self.signed_volume > 0.0),
            (
                "no self-intersections",
                self.self_intersecting_pairs == Some(0),
            ),
        ]
    }

    /// A one-line list of what is wrong, or `"ok"`.
    pub fn problems(&self) -> String {
        let mut p = Vec::new();
        let mut add = |n: usize, what: &str| {
            if n > 0 {
                p.push(format!("{n} {what}"));
            }
        };
        add(self.non_finite_vertices, "non-finite vertices");
        add(
            self.out_of_range_vertices,
            "vertices with a coordinate out of range",
        );
        add(
            self.out_of_range_triangles,
            "triangles with out-of-range indices",
        );
        add(self.degenerate_triangles, "degenerate triangles");
        add(self.boundary_edges, "boundary edges");
        add(self.non_manifold_edges, "non-manifold edges");
        add(self.misoriented_edges, "misoriented edges");
        add(self.non_manifold_vertices, "non-manifold vertices");
        match self.self_intersecting_pairs {
            Some(n) => add(n, "self-intersecting triangle pairs"),
            None => p.push("self-intersections not checked".into()),
        }
        if self.triangle_count == 0 {
            p.push("no triangles".into());
        } else if self.signed_volume <= 0.0 {
            p.push(format!("non-positive volume {}", self.signed_volume));
        }
        if p.is_empty() {
            "ok".into()
        } else {
            p.join(", ")
        }
    }
}

/// Checks `mesh` and measures it. Never panics, whatever the buffer holds.
pub fn validate(mesh: &TriMesh, settings: &ValidationSettings) -> ValidationReport {
    // The self-intersection search needs nothing the topology finds:
    // the two run side by side (the topology is one thread's sorting and
    // walking, a fifth of the whole check on the teapot; issue 37).
    let (mut r, found) = rayon::join(
        || topology(mesh, settings),
        || {
            settings
                .self_intersections
                .then(|| self_intersections(mesh))
        },
    );
    if let Some(s) = found.filter(|s| s.checked) {
        r.self_intersecting_pairs = Some(s.pairs.len());
        r.intersecting_examples = s.pairs.iter().take(LISTED_PAIRS).copied().collect();
    }
    r
}

/// Everything [`validate`] reports but the self-intersections.
fn topology(mesh: &TriMesh, settings: &ValidationSettings) -> ValidationReport {
    let n = mesh.positions.len();
    let mut r = ValidationReport {
        vertex_count: n,
        triangle_count: mesh.triangles.len(),
        ..Default::default()
    };
    r.non_finite_vertices = mesh
        .positions
        .iter()
        .filter(|p| !p.iter().all(|x| x.is_finite()))
        .count();
    r.out_of_range_vertices = mesh
        .positions
        .iter()
        .filter(|p| {
            p.iter().all(|x| x.is_finite())
                && p.iter().any(|x| x.abs() > settings.max_abs_coordinate)
        })
        .count();
    let finite_box = mesh
        .positions
        .iter()
        .filter(|p| p.iter().all(|x| x.is_finite()))
        .map(|p| DVec3::from_array(*p))
        .fold(None, |acc: Option<(DVec3, DVec3)>, p| {
            Some(acc.map_or((p, p), |(lo, hi)| (lo.min(p), hi.max(p))))
        });
    r.bbox = finite_box.map(|(lo, hi)| [lo.to_array(), hi.to_array()]);
    let diag2 = finite_box.map_or(0.0, |(lo, hi)| (hi - lo).length_squared());
    let area_tol = settings.degenerate_area_rel * diag2;

    // Only in-range triangles take part in the topology below.
    let tris: Vec<[u32; 3]> = mesh
        .triangles
        .iter()
        .copied()
        .filter(|t| t.iter().all(|&i| (i as usize) < n))
        .collect();
    r.out_of_range_triangles = mesh.triangles.len() - tris.len();

    let mut referenced = vec![false; n];
    let (mut volume, mut area) = (0.0, 0.0);
    let origin = finite_box.map_or(DVec3::ZERO, |(lo, hi)| (lo + hi) * 0.5);
    for t in &tris {
        for &i in t {
            referenced[i as usize] = true;
        }
        let [a, b, c] = t.map(|i| DVec3::from_array(mesh.positions[i as usize]) - origin);
        let twice_area = (b - a).cross(c - a).length();
        if t[0] == t[1]
            || t[1] == t[2]
            || t[0] == t[2]
            || (0.5 * twice_area).partial_cmp(&area_tol) != Some(std::cmp::Ordering::Greater)
        {
            r.degenerate_triangles += 1;
        }
        area += 0.5 * twice_area;
        volume += a.dot(b.cross(c));
    }
    r.signed_volume = volume / 6.0;
    r.area = area;
    r.referenced_vertices = referenced.iter().filter(|&&x| x).count();

    // Edges: (lo, hi, forward?) sorted, then grouped.
    let mut edges: Vec<(u32, u32, bool)> = Vec::with_capacity(tris.len() * 3);
    for t in &tris {
        for k in 0..3 {
            let (a, b) = (t[k], t[(k + 1) % 3]);
            if a != b {
                edges.push((a.min(b), a.max(b), a < b));
            }
        }
    }
    edges.par_sort_unstable();
    for (run, fwd) in edge_runs(&edges, |e| *e) {
        r.edge_count += 1;
        match run.len() {
            1 => r.boundary_edges += 1,
            2 if fwd != 1 => r.misoriented_edges += 1,
            2 => {}
            _ => r.non_manifold_edges += 1,
        }
    }

    r.non_manifold_vertices = count_pinched_vertices(n, &tris);
    r.components = count_components(n, &tris, &referenced);
    r.euler_characteristic = r.referenced_vertices as i64 - r.edge_count as i64 + tris.len() as i64;
    if r.is_closed() && r.non_manifold_vertices == 0 && !tris.is_empty() {
        r.genus = Some((2 * r.components as i64 - r.euler_characteristic) / 2);
    }
    r
}

/// The runs of one undirected edge in `edges` sorted by its `(min, max)`
/// vertices (`key`: min, max, and whether the half-edge goes from min to
/// max): each run's range and how many of its half-edges go forward. The
/// report and [`problem_triangles`] group edges through it alike (over
/// the triangles each keeps).
fn edge_runs<'a, T>(
    edges: &'a [T],
    key: impl Fn(&T) -> (u32, u32, bool) + 'a,
) -> impl Iterator<Item = (std::ops::Range<usize>, usize)> + 'a {
    let mut i = 0;
    std::iter::from_fn(move || {
        let (a, b, _) = key(edges.get(i)?);
        let (mut j, mut fwd) = (i, 0);
        while let Some((x, y, f)) = edges.get(j).map(&key) {
            if (x, y) != (a, b) {
                break;
            }
            fwd += usize::from(f);
            j += 1;
        }
        let run = i..j;
        i = j;
        Some((run, fwd))
    })
}

/// Indices of the triangles that make `report` fail: non-finite or out of
/// range corners, degenerate, on a boundary, non-manifold or misoriented
/// edge, at a pinched vertex, or in an intersecting pair. Sorted. For
/// naming the objects at fault (through `tri_source`); not a fast path.
pub fn problem_triangles(mesh: &TriMesh, report: &ValidationReport) -> Vec<u32> {
    let n = mesh.positions.len();
    let mut bad = vec![false; mesh.triangles.len()];
    let diag2 = report.bbox.map_or(0.0, |[lo, hi]| {
        (DVec3::from_array(hi) - DVec3::from_array(lo)).length_squared()
    });
    let area_tol = ValidationSettings::default().degenerate_area_rel * diag2;
    let mut vertex_bad = vec![false; n];
    for (v, p) in mesh.positions.iter().enumerate() {
        vertex_bad[v] = p.iter().any(|x| !x.is_finite());
    }
    let mut edges: Vec<(u32, u32, bool, usize)> = Vec::new();
    let mut tris = Vec::new();
    for (t, tri) in mesh.triangles.iter().enumerate() {
        if tri
            .iter()
            .any(|&i| i as usize >= n || vertex_bad[i as usize])
        {
            bad[t] = true;
            continue;
        }
        tris.push(*tri);
        let [a, b, c] = tri.map(|i| DVec3::from_array(mesh.positions[i as usize]));
        if tri[0] == tri[1]
            || tri[1] == tri[2]
            || tri[0] == tri[2]
            || 0.5 * (b - a).cross(c - a).length() <= area_tol
        {
            bad[t] = true;
        }
        for k in 0..3 {
            let (x, y) = (tri[k], tri[(k + 1) % 3]);
            if x != y {
                edges.push((x.min(y), x.max(y), x < y, t));
            }
        }
    }
    edges.par_sort_unstable();
    for (run, fwd) in edge_runs(&edges, |e| (e.0, e.1, e.2)) {
        if run.len() != 2 || fwd != 1 {
            for e in &edges[run] {
                bad[e.3] = true;
            }
        }
    }
    if report.non_manifold_vertices > 0 {
        let pinched = pinched_vertices(n, &tris);
        for (t, tri) in mesh.triangles.iter().enumerate() {
            if tri.iter().any(|&v| (v as usize) < n && pinched[v as usize]) {
                bad[t] = true;
            }
        }
    }
    if report.self_intersecting_pairs.unwrap_or(0) > 0 {
        for (a, b) in self_intersections(mesh).pairs {
            bad[a as usize] = true;
            bad[b as usize] = true;
        }
    }
    (0..bad.len() as u32).filter(|&t| bad[t as usize]).collect()
}

/// Counts vertices whose incident triangles do not form one connected fan.
fn count_pinched_vertices(n: usize, tris: &[[u32; 3]]) -> usize {
    pinched_vertices(n, tris).iter().filter(|&&p| p).count()
}

/// The corners of `tris` grouped by vertex, as (next, prev) around it:
/// vertex `v`'s corners are `link[start[v]..start[v + 1]]` (CSR), in
/// triangle order. Indices must be below `n`.
pub(crate) fn corners_by_vertex(n: usize, tris: &[[u32; 3]]) -> (Vec<u32>, Vec<(u32, u32)>) {
    let mut start = vec![0u32; n + 1];
    for t in tris {
        for &v in t {
            start[v as usize + 1] += 1;
        }
    }
    for v in 0..n {
        start[v + 1] += start[v];
    }
    let mut fill = start.clone();
    let mut link = vec![(0u32, 0u32); tris.len() * 3];
    for t in tris {
        for k in 0..3 {
            let v = t[k] as usize;
            link[fill[v] as usize] = (t[(k + 1) % 3], t[(k + 2) % 3]);
            fill[v] += 1;
        }
    }
    (start, link)
}

/// Per vertex: its incident triangles form more than one fan.
fn pinched_vertices(n: usize, tris: &[[u32; 3]]) -> Vec<bool> {
    let (start, link) = corners_by_vertex(n, tris);
    let mut pinched = vec![false; n];
    let mut nodes: Vec<u32> = Vec::new();
    let mut parent: Vec<usize> = Vec::new();
    for v in 0..n {
        let fan = &link[start[v] as usize..start[v + 1] as usize];
        if fan.len() < 2 {
            continue;
        }
        nodes.clear();
        parent.clear();
        let index_of = |x: u32, nodes: &mut Vec<u32>, parent: &mut Vec<usize>| -> usize {
            match nodes.iter().position(|&y| y == x) {
                Some(i) => i,
                None => {
                    nodes.push(x);
                    parent.push(parent.len());
                    nodes.len() - 1
                }
            }
        };
        for &(a, b) in fan {
            let ia = index_of(a, &mut nodes, &mut parent);
            let ib = index_of(b, &mut nodes, &mut parent);
            let (ra, rb) = (find(&mut parent, ia), find(&mut parent, ib));
            if ra != rb {
                parent[ra] = rb;
            }
        }
        let roots = (0..parent.len())
            .filter(|&i| find(&mut parent, i) == i)
            .count();
        if roots > 1 {
            pinched[v] = true;
        }
    }
    pinched
}

fn count_components(n: usize, tris: &[[u32; 3]], referenced: &[bool]) -> usize {
    let mut parent: Vec<usize> = (0..n).collect();
    for t in tris {
        for k in 1..3 {
            let (a, b) = (
                find(&mut parent, t[0] as usize),
                find(&mut parent, t[k] as usize),
            );
            if a != b {
                parent[a.max(b)] = a.min(b);
            }
        }
    }
    (0..n)
        .filter(|&v| referenced[v] && find(&mut parent, v) == v)
        .count()
}

fn find(parent: &mut [usize], mut i: usize) -> usize {
    while parent[i] != i {
        parent[i] = parent[parent[i]];
        i = parent[i];
    }
    i
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::test_meshes::tetra;

    #[test]
    fn tetrahedron_is_closed_genus_zero() {
        let r = validate(&tetra(), &Default::default());
        assert!(r.is_closed_manifold(), "{}", r.problems());
        assert!(r.is_printable(), "{}", r.problems());
        assert_eq!(r.self_intersecting_pairs, Some(0));
        assert!(r.checks().iter().all(|c| c.1));
        assert_eq!(r.genus, Some(0));
        assert_eq!(r.euler_characteristic, 2);
        assert!((r.signed_volume - 1.0 / 6.0).abs() < 1e-15);
    }

    #[test]
    fn flipped_face_is_misoriented() {
        let mut m = tetra();
        m.triangles[0].swap(1, 2);
        let r = validate(&m, &Default::default());
        assert_eq!(r.misoriented_edges, 3);
        assert!(!r.is_closed_manifold());
    }

    #[test]
    fn missing_face_leaves_boundary() {
        let mut m = tetra();
        m.triangles.pop();
        let r = validate(&m, &Default::default());
        assert_eq!(r.boundary_edges, 3);
        assert_eq!(r.genus, None);
    }

    #[test]
    fn two_tetrahedra_sharing_a_vertex_are_pinched() {
        let mut m = tetra();
        let mut other = tetra();
        other.transform(&glam::DAffine3::from_translation(DVec3::new(
            -1.0, -1.0, -1.0,
        )));
        // Glue other's vertex 3 (at 0,0,0 after translation) onto m's vertex 0.
        let base = m.positions.len() as u32;
        m.append(&other);
        for t in &mut m.triangles[4..] {
            for i in t.iter_mut() {
                if *i == base + 3 {
                    *i = 0;
                }
            }
        }
        let r = validate(&m, &Default::default());
        assert!(r.is_closed());
        assert_eq!(r.non_manifold_vertices, 1);
        assert!(!r.is_closed_manifold());
    }

    #[test]
    fn a_closed_mesh_through_itself_is_not_printable() {
        let mut m = tetra();
        let mut other = tetra();
        other.transform(&glam::DAffine3::from_translation(DVec3::splat(0.1)));
        m.append(&other);
        let r = validate(&m, &Default::default());
        assert!(r.is_closed_manifold(), "{}", r.problems());
        assert!(!r.is_printable());
        assert!(r.self_intersecting_pairs.unwrap() > 0);
        assert!(r.problems().contains("self-intersecting"));
        let t = validate(&m, &ValidationSettings::topology_only());
        assert_eq!(t.self_intersecting_pairs, None);
        assert!(!t.is_printable());
    }

    #[test]
    fn absurd_coordinates_are_out_of_range() {
        let mut m = tetra();
        m.transform(&glam::DAffine3::from_scale(DVec3::splat(3.4e38)));
        let r = validate(&m, &Default::default());
        assert_eq!(r.out_of_range_vertices, 3);
        assert!(r.is_closed_manifold() && !r.is_printable());
    }

    #[test]
    fn garbage_never_panics() {
        let m = TriMesh::new(
            vec![[f64::NAN, 0.0, 0.0], [1.0, 1.0, 1.0]],
            vec![[0, 1, 7], [0, 0, 1], [1, 1, 1]],
        );
        let r = validate(&m, &Default::default());
        assert_eq!(r.non_finite_vertices, 1);
        assert_eq!(r.out_of_range_triangles, 1);
        assert_eq!(r.degenerate_triangles, 2);
        assert!(!r.is_closed_manifold());
    }
}
