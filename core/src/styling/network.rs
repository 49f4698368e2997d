//! Curve networks (paper §5): the `CurveNetwork` object kind.
//!
//! A [`CurveNetwork`] holds curves (indices are never reused; a deleted
//! curve leaves `None`), nodes (junctions: the `(curve, t)` pairs that meet
//! there) and patches filling loops of curve pieces. The network is split
//! by idea:
//!
//! - [`super::junction`]: weaving a new curve into the net (intersections,
//!   the least-change re-approximation that interpolates them) and keeping
//!   it connected when a curve changes (§5.1);
//! - [`super::loops`]: pieces, loop search and explicit loops (§5.2);
//! - [`super::patch`]: patches filling loops, their evaluation and meshing
//!   (§5.3), with [`super::ngon`] for loops of more than 4 pieces.
//!
//! This file keeps the data and the accessors every part shares.

use serde::{Deserialize, Serialize};

use crate::math::DVec3;

use super::curve::SplineCurve;
use super::StylingError;

pub use super::junction::{closest_approaches, constrain, Hit};
pub use super::loops::Piece;
pub use super::patch::Patch;

/// A junction: the curve parameters that meet at one point.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Node {
    /// `(curve index, parameter)` of each curve through this node.
    pub members: Vec<(usize, f64)>,
}

/// A network of styled curves with patches: the `CurveNetwork` object kind.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct CurveNetwork {
    /// Curves; `None` where a curve was deleted.
    pub curves: Vec<Option<SplineCurve>>,
    /// Junctions.
    pub nodes: Vec<Node>,
    /// Patches.
    pub patches: Vec<Patch>,
    /// Mesh samples per patch side.
    pub resolution: u32,
    /// Displacement control points per patch side.
    pub surface_n: u32,
}

impl CurveNetwork {
    /// An empty network.
    pub fn new(resolution: u32, surface_n: u32) -> Result<Self, StylingError> {
        if !(2..=256).contains(&resolution) {
            return Err(StylingError::BadParameter("resolution must be 2..=256"));
        }
        if !(4..=64).contains(&surface_n) {
            return Err(StylingError::BadParameter("surface_n must be 4..=64"));
        }
        Ok(Self {
            curves: Vec::new(),
            nodes: Vec::new(),
            patches: Vec::new(),
            resolution,
            surface_n,
        })
    }

    /// The live curve `i`.
    pub fn curve(&self, i: usize) -> Result<&SplineCurve, StylingError> {
        self.curves
            .get(i)
            .and_then(|c| c.as_ref())
            .ok_or(StylingError::NoCurve(i))
    }

    /// The point of node `k` (its first member's evaluation).
    pub fn node_point(&self, k: usize) -> DVec3 {
        let (c, t) = self.nodes[k].members[0];
        self.curves[c]
            .as_ref()
            .map(|cv| cv.point(t))
            .unwrap_or(DVec3::NAN)
    }

    /// Parameter of node `k` on curve `c`.
    pub fn param(&self, k: usize, c: usize) -> Option<f64> {
        self.nodes
            .get(k)?
            .members
            .iter()
            .find(|(ci, _)| *ci == c)
            .map(|(_, t)| *t)
    }

    /// Largest distance between the members of any node.
    pub fn junction_gap(&self) -> f64 {
        let mut worst: f64 = 0.0;
        for n in &self.nodes {
            let pts: Vec<DVec3> = n
                .members
                .iter()
                .filter_map(|(c, t)| self.curves[*c].as_ref().map(|cv| cv.point(*t)))
                .collect();
            for p in &pts {
                worst = worst.max(p.distance(pts[0]));
            }
        }
        worst
    }
}
