//! Does the geometry stored in a file agree with its log?
//!
//! The log (through the snapshot it restores) is the truth; the stored
//! meshes are what other tools see. They disagree when a file was edited
//! outside Shapewright, corrupted, or written by a build that evaluates
//! differently. Points are stored as f32, so they are compared with the
//! evaluated f64 positions rounded to f32, allowing [`POINT_ULPS`] f32 ulps
//! of the mesh's largest coordinate (a different libm may move a rounding);
//! counts and indices must match exactly.
// Reads outside data: no indexing that can panic (issue 22).
#![deny(clippy::indexing_slicing)]

use std::fmt;

use openusd::gf;
use shapewright::doc::{Document, ObjectId};

use crate::kinds::points_f32;

/// Allowed point deviation, in f32 ulps of the mesh's largest coordinate.
pub const POINT_ULPS: f32 = 4.0;
/// How many times [`POINT_ULPS`] placed points may deviate: the host's
/// float32 copy of the placement rounds once more.
pub const PLACED_FACTOR: f64 = 4.0;

/// One disagreement between the file's geometry and its log.
#[derive(Clone, Debug, PartialEq)]
pub enum Mismatch {
    /// The log has an object the file has no mesh for.
    MissingMesh {
        /// The object.
        id: ObjectId,
    },
    /// The file has an object prim the log does not know.
    ExtraPrim {
        /// The prim path.
        path: String,
    },
    /// The stored topology (vertex count, face counts or indices) differs.
    Topology {
        /// The object.
        id: ObjectId,
        /// What differs.
        detail: String,
    },
    /// Stored points are further from the evaluated ones than rounding
    /// explains.
    Points {
        /// The object.
        id: ObjectId,
        /// Largest deviation of a coordinate.
        max_deviation: f64,
        /// The tolerance used.
        tolerance: f64,
    },
    /// A `NurbsCurves`/`NurbsPatch` prim next to the mesh disagrees with the
    /// object's parametric data ([`crate::parametric`]).
    Parametric {
        /// The object.
        id: ObjectId,
        /// The prim's name under the object prim.
        prim: String,
        /// What differs.
        detail: String,
    },
    /// Replaying the history does not give the snapshot.
    History {
        /// What differs.
        detail: String,
    },
}

impl fmt::Display for Mismatch {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::MissingMesh { id } => write!(f, "object {id}: no mesh in the file"),
            Self::ExtraPrim { path } => write!(f, "{path}: object prim not in the log"),
            Self::Topology { id, detail } => write!(f, "object {id}: topology differs: {detail}"),
            Self::Points {
                id,
                max_deviation,
                tolerance,
            } => write!(
                f,
                "object {id}: points differ by up to {max_deviation:e} (tolerance {tolerance:e})"
            ),
            Self::Parametric { id, prim, detail } => {
                write!(f, "object {id}: parametric prim {prim}: {detail}")
            }
            Self::History { detail } => write!(f, "history: {detail}"),
        }
    }
}

/// All disagreements found. Empty means consistent.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ConsistencyReport {
    /// Objects checked.
    pub objects_checked: usize,
    /// Whether the history was replayed and compared with the snapshot.
    pub history_checked: bool,
    /// The disagreements.
    pub mismatches: Vec<Mismatch>,
}

impl ConsistencyReport {
    /// True when nothing disagrees.
    pub fn is_consistent(&self) -> bool {
        self.mismatches.is_empty()
    }
}

impl fmt::Display for ConsistencyReport {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.mismatches.is_empty() {
            return write!(
                f,
                "consistent: {} object mesh(es) match the log{}",
                self.objects_checked,
                if self.history_checked {
                    "; replaying the history gives the snapshot"
                } else {
                    ""
                }
            );
        }
        for (i, m) in self.mismatches.iter().enumerate() {
            if i > 0 {
                writeln!(f)?;
            }
            write!(f, "- {m}")?;
        }
        Ok(())
    }
}

/// A mesh as the file stores it.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct StoredMesh {
    /// `points`.
    pub points: Vec<gf::Vec3f>,
    /// `faceVertexCounts`.
    pub counts: Vec<i32>,
    /// `faceVertexIndices`.
    pub indices: Vec<i32>,
    /// The points were placed by the prims' transforms to compare them
    /// (a host that writes each object at its origin, as Blender does):
    /// the transform's own float32 rounding is allowed for as well.
    pub placed: bool,
}

/// Compares the stored meshes (by object id; `extra` lists object prims
/// whose id the document lacks) with the document's evaluated meshes.
pub fn compare(
    doc: &Document,
    stored: &std::collections::BTreeMap<ObjectId, StoredMesh>,
    extra: Vec<String>,
) -> ConsistencyReport {
    let mut r = ConsistencyReport::default();
    for path in extra {
        r.mismatches.push(Mismatch::ExtraPrim { path });
    }
    for id in stored.keys().filter(|id| doc.get(**id).is_err()) {
        r.mismatches.push(Mismatch::ExtraPrim {
            path: format!("/World/{}", crate::kinds::object_prim_name(*id)),
        });
    }
    for (id, obj) in doc.objects() {
        r.objects_checked += 1;
        let Some(s) = stored.get(&id) else {
            r.mismatches.push(Mismatch::MissingMesh { id });
            continue;
        };
        let m = &obj.mesh;
        if s.points.len() != m.positions.len() {
            r.mismatches.push(Mismatch::Topology {
                id,
                detail: format!(
                    "{} stored points, {} evaluated",
                    s.points.len(),
                    m.positions.len()
                ),
            });
            continue;
        }
        if s.counts.len() != m.triangles.len() || s.counts.iter().any(|&c| c != 3) {
            r.mismatches.push(Mismatch::Topology {
                id,
                detail: format!(
                    "{} stored faces (all triangles: {}), {} evaluated triangles",
                    s.counts.len(),
                    s.counts.iter().all(|&c| c == 3),
                    m.triangles.len()
                ),
            });
            continue;
        }
        let same_indices = s.indices.len() == m.triangles.len() * 3
            && m.triangles
                .iter()
                .flatten()
                .zip(&s.indices)
                .all(|(&a, &b)| i64::from(a) == i64::from(b));
        if !same_indices {
            r.mismatches.push(Mismatch::Topology {
                id,
                detail: "faceVertexIndices differ".to_owned(),
            });
            continue;
        }
        let (max_dev, mut tolerance) = max_point_deviation(&points_f32(m), &s.points);
        if s.placed {
            tolerance *= PLACED_FACTOR;
        }
        if max_dev > tolerance {
            r.mismatches.push(Mismatch::Points {
                id,
                max_deviation: max_dev,
                tolerance,
            });
        }
    }
    r
}

/// The largest coordinate deviation between `expect` and `stored` (paired
/// in order) and the tolerance for it: [`POINT_ULPS`] f32 ulps of the
/// largest expected coordinate. NaN in `stored` is an infinite deviation.
pub fn max_point_deviation(expect: &[gf::Vec3f], stored: &[gf::Vec3f]) -> (f64, f64) {
    let scale = expect
        .iter()
        .flat_map(|p| [p.x.abs(), p.y.abs(), p.z.abs()])
        .fold(f32::MIN_POSITIVE, f32::max);
    let tolerance = f64::from(POINT_ULPS * scale * f32::EPSILON);
    let mut max_dev = 0.0f64;
    for (a, b) in expect.iter().zip(stored) {
        for (x, y) in [(a.x, b.x), (a.y, b.y), (a.z, b.z)] {
            let d = (f64::from(x) - f64::from(y)).abs();
            max_dev = if d.is_nan() {
                f64::INFINITY
            } else {
                max_dev.max(d)
            };
        }
    }
    (max_dev, tolerance)
}
