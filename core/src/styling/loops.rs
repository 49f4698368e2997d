//! Pieces and loops of a curve network (paper §5.2).
//!
//! Pieces are the spans between consecutive nodes of a curve. Automatic
//! loops are the chordless cycles of 3 to [`MAX_SIDES`] pieces (a
//! topological criterion; the paper's geometric search is not specified
//! further); explicit loops are checked to close. Filling them all goes by
//! size (3- and 4-sided first, then 5, 6, ...) and skips a loop with a
//! piece that already borders two patches, so on a closed net only the
//! faces are filled (a cube's chordless hexagons are not).

use serde::{Deserialize, Serialize};

use super::budget::Budget;
use super::network::CurveNetwork;
use super::ngon::MAX_SIDES;
use super::patch::Patch;
use super::StylingError;

/// A span of one curve between two of its consecutive nodes, directed.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct Piece {
    /// Curve index.
    pub curve: usize,
    /// Start node.
    pub from: usize,
    /// End node.
    pub to: usize,
}

impl Piece {
    fn reversed(self) -> Self {
        Self {
            curve: self.curve,
            from: self.to,
            to: self.from,
        }
    }

    fn same_span(&self, o: &Piece) -> bool {
        self.curve == o.curve
            && ((self.from == o.from && self.to == o.to)
                || (self.from == o.to && self.to == o.from))
    }
}

impl CurveNetwork {
    /// Every piece: consecutive nodes along each live curve.
    pub fn pieces(&self) -> Vec<Piece> {
        let mut out = Vec::new();
        for (ci, c) in self.curves.iter().enumerate() {
            if c.is_none() {
                continue;
            }
            let mut on: Vec<(f64, usize)> = self
                .nodes
                .iter()
                .enumerate()
                .filter_map(|(k, n)| {
                    n.members
                        .iter()
                        .find(|(c, _)| *c == ci)
                        .map(|(_, t)| (*t, k))
                })
                .collect();
            on.sort_by(|a, b| a.0.total_cmp(&b.0));
            for w in on.windows(2) {
                out.push(Piece {
                    curve: ci,
                    from: w[0].1,
                    to: w[1].1,
                });
            }
        }
        out
    }

    /// Chordless loops of 3 to [`MAX_SIDES`] pieces not yet filled, each
    /// as pieces head to tail, in a deterministic order; none when the
    /// search would exceed the default [`Budget`] (see
    /// [`CurveNetwork::try_find_loops`]).
    pub fn find_loops(&self) -> Vec<Vec<Piece>> {
        self.try_find_loops(&Budget::default()).unwrap_or_default()
    }

    /// [`CurveNetwork::find_loops`], refusing a search that would extend
    /// more than `budget.max_loop_search` partial loops. Partial loops with
    /// a chord are not extended (a chordless cycle has no chord in any of
    /// its sub-paths), which keeps the search small on real nets.
    pub fn try_find_loops(&self, budget: &Budget) -> Result<Vec<Vec<Piece>>, StylingError> {
        let pieces = self.pieces();
        let mut edges: Vec<(usize, usize)> = pieces
            .iter()
            .map(|p| (p.from.min(p.to), p.from.max(p.to)))
            .collect();
        edges.sort_unstable();
        edges.dedup();
        let connected = |a: usize, b: usize| edges.binary_search(&(a.min(b), a.max(b))).is_ok();
        let mut work: u64 = 0;
        let step = |p: &Piece, at: usize| -> Option<Piece> {
            if p.from == at {
                Some(*p)
            } else if p.to == at {
                Some(p.reversed())
            } else {
                None
            }
        };
        let mut found: Vec<(Vec<usize>, Vec<Piece>)> = Vec::new();
        for (e0, p0) in pieces.iter().enumerate() {
            let mut stack: Vec<(Vec<usize>, Vec<Piece>)> = vec![(vec![e0], vec![*p0])];
            while let Some((ids, path)) = stack.pop() {
                let last = path[path.len() - 1];
                let start = path[0].from;
                if path.len() >= 3 && last.to == start {
                    let nodes: Vec<usize> = path.iter().map(|p| p.from).collect();
                    let n = nodes.len();
                    let chord = (0..n).any(|i| {
                        (i + 2..n).any(|j| (j + 1) % n != i && connected(nodes[i], nodes[j]))
                    });
                    let mut key = ids.clone();
                    key.sort_unstable();
                    if !chord && !found.iter().any(|(k, _)| *k == key) {
                        found.push((key, path));
                    }
                    continue;
                }
                if path.len() == MAX_SIDES {
                    continue;
                }
                for (e, p) in pieces.iter().enumerate() {
                    if ids.contains(&e) || e < e0 {
                        continue;
                    }
                    let Some(next) = step(p, last.to) else {
                        continue;
                    };
                    let revisit = path.iter().any(|q| q.from == next.to) && next.to != start;
                    if revisit {
                        continue;
                    }
                    if next.to != start && path[1..].iter().any(|q| connected(q.from, next.to)) {
                        continue;
                    }
                    work += 1;
                    if work > budget.max_loop_search {
                        return Err(StylingError::OverBudget(crate::budget::OverBudget::new(
                            "curve network",
                            "partial loops searched",
                            work as f64,
                            budget.max_loop_search as f64,
                        )));
                    }
                    let mut ids2 = ids.clone();
                    ids2.push(e);
                    let mut path2 = path.clone();
                    path2.push(next);
                    stack.push((ids2, path2));
                }
            }
        }
        Ok(found
            .into_iter()
            .map(|(_, p)| p)
            .filter(|l| self.filled_by(l).is_none())
            .collect())
    }

    fn filled_by(&self, lp: &[Piece]) -> Option<usize> {
        self.patches.iter().position(|p| {
            p.pieces.len() == lp.len() && lp.iter().all(|a| p.pieces.iter().any(|b| a.same_span(b)))
        })
    }

    /// Checks that `lp` is a closed loop of 3 to [`MAX_SIDES`] pieces of
    /// live curves, each between consecutive nodes of its curve.
    pub fn check_loop(&self, lp: &[Piece]) -> Result<(), StylingError> {
        if lp.len() < 3 || lp.len() > MAX_SIDES {
            return Err(StylingError::LoopSize(lp.len()));
        }
        self.check_ngon(lp.len())?;
        let all = self.pieces();
        for (k, p) in lp.iter().enumerate() {
            self.curve(p.curve)?;
            if !all.iter().any(|q| q.same_span(p)) {
                return Err(StylingError::LoopNotClosed(format!(
                    "piece {k} (curve {}, nodes {} -> {}) is not a span between consecutive nodes of its curve",
                    p.curve, p.from, p.to
                )));
            }
            let next = lp[(k + 1) % lp.len()];
            if p.to != next.from {
                return Err(StylingError::LoopNotClosed(format!(
                    "piece {k} ends at node {} but piece {} starts at node {}",
                    p.to,
                    (k + 1) % lp.len(),
                    next.from
                )));
            }
        }
        let mut nodes: Vec<usize> = lp.iter().map(|p| p.from).collect();
        nodes.sort_unstable();
        nodes.dedup();
        if nodes.len() != lp.len() {
            return Err(StylingError::LoopNotClosed(
                "the loop visits a node twice".into(),
            ));
        }
        Ok(())
    }

    /// Fills a loop with a patch, oriented against the patches it borders.
    /// Returns the patch index.
    pub fn fill(&mut self, lp: &[Piece]) -> Result<usize, StylingError> {
        self.check_loop(lp)?;
        if let Some(k) = self.filled_by(lp) {
            return Err(StylingError::AlreadyFilled(k));
        }
        let mut pieces = lp.to_vec();
        let same_dir = self.patches.iter().flat_map(|p| &p.pieces).any(|q| {
            pieces
                .iter()
                .any(|p| p.curve == q.curve && p.from == q.from && p.to == q.to)
        });
        if same_dir {
            pieces = pieces.iter().rev().map(|p| p.reversed()).collect();
        }
        let n = self.surface_n as usize;
        self.patches.push(Patch {
            pieces,
            disp: vec![[0.0; 3]; n * n],
        });
        Ok(self.patches.len() - 1)
    }

    /// Patches bordering the span of `p`.
    fn borders(&self, p: &Piece) -> usize {
        self.patches
            .iter()
            .flat_map(|q| &q.pieces)
            .filter(|q| q.same_span(p))
            .count()
    }

    /// Fills every automatically found loop by size tiers (3 and 4 sides,
    /// then 5, 6, ...), neighbours first within a tier (each next loop
    /// shares a piece with a filled one when possible), so that the
    /// orientation propagates consistently over a closed net. A loop with
    /// a piece that already borders two patches is skipped.
    pub fn fill_all(&mut self) -> Result<Vec<usize>, StylingError> {
        let tier = |l: &Vec<Piece>| l.len().max(4);
        let mut loops = self.try_find_loops(&Budget::default())?;
        loops.sort_by_key(tier);
        let mut out = Vec::new();
        while !loops.is_empty() {
            let now = tier(&loops[0]);
            let next = loops
                .iter()
                .position(|l| tier(l) == now && l.iter().any(|p| self.borders(p) > 0))
                .unwrap_or(0);
            let lp = loops.remove(next);
            if lp.iter().any(|p| self.borders(p) >= 2) {
                continue;
            }
            out.push(self.fill(&lp)?);
        }
        Ok(out)
    }
}
