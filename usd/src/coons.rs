//! A curve network's patches for their USD prims: the mapping from the
//! network's pieces to curves. The geometry (segments, knot unions, the
//! Coons patch as one bicubic NURBS surface) is
//! [`shapewright::nurbs::coons_bicubic`]'s.
//!
//! A 3- or 4-sided patch of a curve network (paper 3 §5,
//! `core::styling::network`) is a bilinearly blended Coons patch of its
//! boundary pieces plus a clamped uniform bicubic displacement: its pieces,
//! cut out of their curves and reparameterized onto `[0, 1]`, are the
//! sides (a 3-sided patch has a constant left side, its collapsed node).
//! Patches of more sides are not written as one surface at all: the writer
//! stores their mesh and their boundary curves ([`patch_boundary`]), which
//! does not depend on how the styling module builds them inside.

use shapewright::math::DVec3;
use shapewright::nurbs::{coons_bicubic, segment, CoonsSides, NurbsCurve, NurbsError};
use shapewright::styling::{CurveNetwork, Piece, StylingError};

/// Why a patch could not be converted.
#[derive(Debug, thiserror::Error)]
pub enum PatchError {
    /// The network has no patch with this index.
    #[error("no patch {0}")]
    NoPatch(usize),
    /// The patch has more than 4 sides (no single Coons surface): write its
    /// mesh and boundary instead.
    #[error("patch {patch} has {sides} sides (only 3 and 4 are one Coons surface)")]
    NotCoons {
        /// The patch.
        patch: usize,
        /// Its sides.
        sides: usize,
    },
    /// A node of a piece is not on the piece's curve.
    #[error("node {node} is not on curve {curve}")]
    NodeOffCurve {
        /// The node.
        node: usize,
        /// The curve.
        curve: usize,
    },
    /// A piece starts and ends at the same parameter.
    #[error("piece of curve {0} has zero length")]
    ZeroLength(usize),
    /// A curve of the network is missing or invalid.
    #[error(transparent)]
    Styling(#[from] StylingError),
    /// The NURBS construction failed.
    #[error(transparent)]
    Nurbs(#[from] NurbsError),
}

/// The piece as a curve on `[0, 1]`, from its `from` node to its `to` node.
pub fn piece_curve(net: &CurveNetwork, piece: &Piece) -> Result<NurbsCurve, PatchError> {
    let curve = net.curve(piece.curve)?.to_nurbs()?;
    let param = |node: usize| {
        net.param(node, piece.curve)
            .ok_or(PatchError::NodeOffCurve {
                node,
                curve: piece.curve,
            })
    };
    let (ta, tb) = (param(piece.from)?, param(piece.to)?);
    if ta == tb {
        return Err(PatchError::ZeroLength(piece.curve));
    }
    Ok(if ta < tb {
        segment(&curve, ta, tb)?.with_domain(0.0, 1.0)
    } else {
        segment(&curve, tb, ta)?.with_domain(0.0, 1.0).reversed()
    })
}

/// The boundary of patch `k`: one curve per piece, in loop order, each on
/// `[0, 1]` from the piece's first node to its last.
pub fn patch_boundary(net: &CurveNetwork, k: usize) -> Result<Vec<NurbsCurve>, PatchError> {
    let patch = net.patches.get(k).ok_or(PatchError::NoPatch(k))?;
    patch.pieces.iter().map(|p| piece_curve(net, p)).collect()
}

/// Patch `k` of `net` (3 or 4 sides) as one polynomial bicubic NURBS
/// surface on `[0, 1]²` (`S(u, v) = net.patch_point(k, u, v)` up to
/// rounding).
pub fn patch_surface(
    net: &CurveNetwork,
    k: usize,
) -> Result<shapewright::nurbs::NurbsSurface, PatchError> {
    let patch = net.patches.get(k).ok_or(PatchError::NoPatch(k))?;
    let (bottom_p, right_p, top_p, left_p) = match patch.pieces.as_slice() {
        [a, b, c] => (a, b, c, None),
        [a, b, c, d] => (a, b, c, Some(d)),
        other => {
            return Err(PatchError::NotCoons {
                patch: k,
                sides: other.len(),
            })
        }
    };
    let p00 = net.node_point(bottom_p.from);
    let p10 = net.node_point(right_p.from);
    let p11 = net.node_point(top_p.from);
    let (left, p01) = match left_p {
        Some(l) => (piece_curve(net, l)?.reversed(), net.node_point(l.from)),
        None => (
            NurbsCurve::from_points(3, vec![0.0, 0.0, 0.0, 0.0, 1.0, 1.0, 1.0, 1.0], &[p00; 4])?,
            p00,
        ),
    };
    let sides = CoonsSides {
        bottom: piece_curve(net, bottom_p)?,
        right: piece_curve(net, right_p)?,
        top: piece_curve(net, top_p)?.reversed(),
        left,
        corners: [p00, p10, p01, p11],
    };
    let disp: Vec<DVec3> = patch.disp.iter().map(|d| DVec3::from_array(*d)).collect();
    Ok(coons_bicubic(&sides, &disp, net.surface_n as usize)?)
}
