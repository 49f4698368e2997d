//! Components from any closed mesh, and the fused result moved, copied
//! and used as a component (paper 2 §3: "users are allowed to freely
//! augment the dataset"; Fig. 2: the result `M = B − A` is shrunk to `D`
//! and united with more components; §4.4: copy).
//!
//! - [`component_from_mesh`]: any closed oriented mesh (a document
//!   object's evaluated mesh, an imported file) becomes a user component:
//!   its SDF comes from the host's [`SdfCache`], and the placement
//!   returned puts the normalized component back exactly where the mesh
//!   was.
//! - **Reuse at full resolution.** The library's grid (40 cells across
//!   the longest side, §5.2) suits small parts placed at their natural
//!   size; a chair made a component that way lost a third of its volume
//!   and 2.7 cm of leg, a mug's walls fell apart into genus 11, a fused
//!   cup's copy was 93% of the cup. A component made from a document
//!   object is sampled instead with one cell the source volume's step or
//!   the target volume's, whichever is finer (the target's for objects
//!   that are not volumes), in the units it was made in
//!   ([`super::mesh_sdf::component_sdf_at`]).
//! - **A copy of the fused result is the fold of its operands**
//!   ([`super::fold::FoldField`]): its field is the CSG of the
//!   operands the result was fused from, evaluated exactly wherever the
//!   copy goes, so it is the result itself placed there, at any step,
//!   turn or scale. Made from the result's mesh, it had carried the
//!   result's chords and its sharp rim sampled on a grid twice: the cup's
//!   copy alone kept 98.3% of the cup at 1 cm and 95.1% at 12 mm; now
//!   99.7% to 100.2% at every step from 4 to 12 mm. The component keeps
//!   the result's mesh for drawing and budgets.
//! - **Checked, or refused.** A document object whose walls are thinner
//!   than two cells of the volume's step over more than
//!   [`THIN_AREA_TOL`] of its surface is refused, once its budget is
//!   checked ([`SdfError::ThinWalls`], [`check_walls`]: the thickness is
//!   measured from each face inward to the other side, by ray; the
//!   chair's 1.8 cm slats at 1 cm, 11.6% of its surface, and the mug's
//!   4 mm walls at 4 mm, 90.8%, had kept 97.6% and 91.4% of their volume
//!   and were accepted). Then a reused component is resampled where it
//!   goes and extracted on its own; if it does not come out with the
//!   source's number of pieces and genus, the op is refused with
//!   [`SdfError::TooThin`], naming both and the step. Its volume is not
//!   compared: what an object with walls of two cells or more loses is
//!   the grid's own chords (a 3 cm sphere at 1 cm keeps 93.7%, as any
//!   grid at that step would). A moved result is compared with itself at
//!   the old step, and a shrunk copy with the result, so there the volume
//!   is checked too ([`REUSE_VOLUME_TOL`]). A reused component placed
//!   anew (added again as an operand) or shrunk afterwards (two hands, a
//!   new placement, a copy of the operand) is checked again as it goes
//!   ([`SdfVolume::check_placed_reuse`]).
//! - **On the lattice.** A component made at the reuse step has its
//!   nodes at whole multiples of that step in the mesh's frame
//!   ([`super::mesh_sdf::component_sdf_at`]), so an object reused where it
//!   is resamples at nodes, exact distances: trilinear resampling of an
//!   unaligned grid at half the step had cost the chair 2.4% more of its
//!   volume and the mug 7%.
//! - [`SdfVolume::with_fused_moved`]: moving the fused result moves every
//!   fused operand (`T ∘ Tᵢ`) and the grid is rebuilt from the recipe:
//!   exact for a similarity (the fold of moved, uniformly scaled distance
//!   fields is the moved fold); a per-axis scale is refused with a typed
//!   error (it is not a similarity of the operands' frames): copy the
//!   result as a component and scale the copy instead. A shrink by `s`
//!   resamples at the step the result needs, `step · s` (not below the
//!   finest allowed step), so the result keeps as many cells across as
//!   it had; if it still loses a piece, a tunnel or more than 1% of its
//!   volume (at the finest step), the move is refused
//!   ([`SdfError::TooThin`]).
//! - [`SdfVolume::with_fused_copy`]: the fused result becomes a user
//!   component of the volume (the fold above) and is queued as a new
//!   operand where the result is, moved by a transform: the paper's copy,
//!   and a result used as a component.

use super::budget::Work;
use super::cache::SdfCache;
use super::csg::CsgOp;
use super::features::ExactField;
use super::mesh_sdf::COMPONENT_SIZE;
use super::volume::{stitch, Component, Operand, SdfVolume, UserMesh, STEP_RANGE};
use super::SdfError;
use crate::math::{DAffine3, DQuat, DVec3, Transform};
use crate::mesh::{validate, TriMesh, ValidationSettings};

/// A user component made from closed `mesh`: its stored mesh (with its
/// SDF now in `cache`) and the placement that puts the normalized
/// component where `mesh` is. `step`: one cell of its SDF in the mesh's
/// units (`None`: the library's normalized grid).
pub fn component_from_mesh(
    mesh: &TriMesh,
    step: Option<f64>,
    cache: &SdfCache,
) -> Result<(UserMesh, Transform), SdfError> {
    let r = validate(mesh, &Default::default());
    if !r.is_closed_manifold() {
        return Err(SdfError::BadMesh(r.problems()));
    }
    let (back, _) = normalized_frame(mesh)?;
    cache.component_field_at(mesh, step)?;
    Ok((UserMesh::from_mesh(mesh.clone(), step), back))
}

/// The placement that puts a component in the normalized frame (centred,
/// [`COMPONENT_SIZE`] across) where closed `mesh` is, and its inverse.
fn normalized_frame(mesh: &TriMesh) -> Result<(Transform, Transform), SdfError> {
    let (lo, hi) = mesh.bbox().ok_or(SdfError::EmptyResult)?;
    let s = (hi - lo).max_element() / COMPONENT_SIZE;
    let c = (lo + hi) * 0.5;
    let back = Transform {
        translate: c.to_array(),
        rotate: [0.0, 0.0, 0.0, 1.0],
        scale: [s; 3],
    };
    let to_local = Transform {
        translate: (-c / s).to_array(),
        rotate: [0.0, 0.0, 0.0, 1.0],
        scale: [1.0 / s; 3],
    };
    back.validate()?;
    to_local.validate()?;
    Ok((back, to_local))
}

/// `a ∘ b` (apply `b`, then `a`) as a transform, when `a` is a similarity.
pub fn compose(a: &Transform, b: &Transform) -> Result<Transform, SdfError> {
    a.validate()?;
    b.validate()?;
    let s = a.scale[0];
    if a.scale.iter().any(|x| (x - s).abs() > 1e-12 * s.abs()) {
        return Err(SdfError::NotSimilarity(a.scale));
    }
    let qa = DQuat::from_array(a.rotate).normalize();
    let qb = DQuat::from_array(b.rotate).normalize();
    let t = DVec3::from_array(a.translate) + qa * (DVec3::from_array(b.translate) * s);
    Ok(Transform {
        translate: t.to_array(),
        rotate: (qa * qb).normalize().to_array(),
        scale: b.scale.map(|x| x * s),
    })
}

/// Genus and number of pieces of a closed mesh (`None` when it is not a
/// closed 2-manifold).
pub fn topology(m: &TriMesh) -> Option<(i64, usize)> {
    shape(m).map(|s| s.topology)
}

/// What a reused surface must keep: its genus and pieces, and its volume
/// within [`REUSE_VOLUME_TOL`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Shape {
    /// Genus and number of pieces.
    pub topology: (i64, usize),
    /// Enclosed volume (in the units of the mesh it was measured on).
    pub volume: f64,
}

impl Shape {
    /// The same shape scaled by `s` (volume by `s³`).
    pub fn scaled(self, s: f64) -> Shape {
        Shape {
            volume: self.volume * (s * s * s).abs(),
            ..self
        }
    }
}

/// The [`Shape`] of a closed mesh (`None` when it is not a closed
/// 2-manifold).
pub fn shape(m: &TriMesh) -> Option<Shape> {
    // Its topology and volume: the self-intersection search (most of a
    // full check, 8 s on the result of a chain of 256 cups) is not needed.
    let r = validate(m, &ValidationSettings::topology_only());
    let g = r.is_closed_manifold().then_some(()).and(r.genus)?;
    Some(Shape {
        topology: (g, r.components),
        volume: r.signed_volume,
    })
}

/// A moved result may differ from its volume before the move by this
/// fraction (issue 33: within 1%); more, and its walls are below about two
/// grid cells: refused.
pub const REUSE_VOLUME_TOL: f64 = 0.01;

/// `Err` naming `what` and `step` unless `got` is `want`: its topology,
/// and its volume within `volume_tol` (relative; `None`: not checked).
fn check_shape(
    what: &str,
    step: f64,
    want: Shape,
    got: Option<Shape>,
    volume_tol: Option<f64>,
) -> Result<(), SdfError> {
    match got {
        Some(g)
            if g.topology == want.topology
                && volume_tol.is_none_or(|t| (g.volume / want.volume - 1.0).abs() <= t) =>
        {
            Ok(())
        }
        got => Err(too_thin(what, step, want, got)),
    }
}

/// The most of a reused object's surface (by area) that may lie on walls
/// thinner than [`MIN_WALL_CELLS`] grid cells; more, and it is refused
/// ([`SdfError::ThinWalls`]).
pub const THIN_AREA_TOL: f64 = 0.02;

/// A wall must be at least this many grid cells thick to come out of the
/// grid whole (a wall of one cell keeps its genus but not its volume: the
/// mug's 4 mm walls at 4 mm kept 91.4%).
pub const MIN_WALL_CELLS: f64 = 2.0;

/// At most this many triangles are measured (drawn by a fixed hash of
/// their index, so a mesh's regular ring order cannot line the samples up
/// with one angle), weighted by area: the share of thin walls is a
/// statistic, not a per-face answer.
const WALL_SAMPLES: usize = 20_000;

/// The `j`-th triangle measured of `n` (splitmix64 of `j`, modulo `n`).
fn sample_index(j: usize, n: usize) -> usize {
    let mut z = (j as u64).wrapping_add(0x9E37_79B9_7F4A_7C15);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    ((z ^ (z >> 31)) % n as u64) as usize
}

/// The share of `mesh`'s surface area (closed and oriented, checked by
/// the caller) lying on walls thinner than `below`: from each measured
/// triangle's centroid, the distance along the inward normal to the
/// surface on the other side (parry's BVH, in `f32`: the same bits on
/// every platform, IEEE arithmetic without fused operations).
pub fn thin_share(mesh: &TriMesh, below: f64) -> Result<f64, SdfError> {
    let (lo, hi) = mesh.bbox().ok_or(SdfError::EmptyResult)?;
    let dist = super::mesh_sdf::MeshDistance::of_checked(mesh, (lo + hi) * 0.5)?;
    // Off the surface by a hair, so the ray does not meet its own face.
    let eps = 1e-6 * (hi - lo).max_element();
    let n = mesh.triangles.len();
    let count = n.min(WALL_SAMPLES);
    let (mut thin, mut all) = (0.0, 0.0);
    for j in 0..count {
        let i = if n <= WALL_SAMPLES {
            j
        } else {
            sample_index(j, n)
        };
        let [a, b, c] = mesh.corners(i);
        let nrm = (b - a).cross(c - a);
        let area = 0.5 * nrm.length();
        let Some(nrm) = nrm.try_normalize() else {
            continue;
        };
        let o = (a + b + c) / 3.0 - nrm * eps;
        all += area;
        if dist.ray_hit(o, -nrm, below).is_some() {
            thin += area;
        }
    }
    Ok(if all > 0.0 { thin / all } else { 0.0 })
}

/// Refuses reusing `mesh` (named `what`, in a frame of `scale` model
/// units per unit, closed and oriented) in a volume of grid step `step`
/// (model units) when more than [`THIN_AREA_TOL`] of its surface lies on
/// walls thinner than [`MIN_WALL_CELLS`] cells. The refusal states the
/// step and the wall in model units, as `sdf_set_step` takes them.
pub fn check_walls(mesh: &TriMesh, step: f64, scale: f64, what: &str) -> Result<(), SdfError> {
    let wall = MIN_WALL_CELLS * step;
    let share = thin_share(mesh, wall / scale)?;
    if share > THIN_AREA_TOL {
        return Err(SdfError::ThinWalls {
            what: what.to_owned(),
            step,
            wall,
            percent: 100.0 * share,
        });
    }
    Ok(())
}

/// A reused component's grid is this fraction of the step it must keep:
/// resampled trilinearly onto the volume's lattice (not aligned with its
/// own), a grid at the same step shaved thin walls (a copy of the fused
/// cup was 96.5% of it, the chair 92%); at half the step the
/// interpolation error is a quarter.
pub const REUSE_REFINE: f64 = 0.5;

/// The step a reused component is sampled at: [`REUSE_REFINE`] of the
/// finer of the source's and the volume's.
pub fn reuse_step(source: Option<f64>, volume: f64) -> f64 {
    REUSE_REFINE * source.map_or(volume, |s| s.min(volume))
}

impl SdfVolume {
    /// Refuses a reused operand `o` whose surface, resampled on this
    /// volume's lattice alone, does not have `want`'s genus and pieces, or
    /// (when `volume_tol` is given) its volume within that fraction: its
    /// thinnest parts fall below the grid. `what` names it in the error.
    pub fn check_reuse(
        &self,
        o: &Operand,
        want: Shape,
        volume_tol: Option<f64>,
        what: &str,
        cache: &SdfCache,
    ) -> Result<(), SdfError> {
        let got = self.alone(o, cache)?;
        check_shape(what, self.step, want, got, volume_tol)
    }

    /// The shape of operand `o` resampled on this volume's lattice and
    /// extracted alone.
    fn alone(&self, o: &Operand, cache: &SdfCache) -> Result<Option<Shape>, SdfError> {
        let (field, sampled) = self.sampled_with(o, cache)?;
        let exact = ExactField::new(vec![(field, CsgOp::Union)], (sampled.band) as f64);
        Ok(shape(&stitch(&sampled.as_grid().extract_all(Some(&exact)))))
    }

    /// The volume with its fused result moved by `t` (a similarity): every
    /// fused operand placed at `t ∘ Tᵢ`, the grid rebuilt from the recipe
    /// (at `step · s` for a shrink by `s`, see the module doc). Pending
    /// operands stay where they are.
    pub fn with_fused_moved(&self, t: &Transform, cache: &SdfCache) -> Result<SdfVolume, SdfError> {
        if self.fused.is_empty() {
            return Err(SdfError::EmptyResult);
        }
        let want = shape(&self.evaluate_with(cache)?);
        let mut v = self.without_state();
        for o in &mut v.fused {
            o.transform = compose(t, &o.transform)?;
        }
        let s = t.scale[0].abs();
        if s < 1.0 {
            v.step = (self.step * s).clamp(STEP_RANGE[0], self.step);
        }
        if let Some(want) = want {
            let got = shape(&v.evaluate_with(cache)?);
            let tol = Some(REUSE_VOLUME_TOL);
            check_shape("the moved result", v.step, want.scaled(s), got, tol)?;
        }
        Ok(v)
    }

    /// Checks pending operand `o`, placed anew (`old`: `None`) or
    /// re-placed from `old` (a two-hand scale, a new placement, a copy of
    /// the operand), when it is a reused component (a copy of the fused
    /// result, or an object) placed anew or shrunk along any axis:
    /// sampled where it goes and extracted alone, it must keep its
    /// source's pieces and genus, and a copy of the result at least its
    /// volume less [`REUSE_VOLUME_TOL`], or the edit is refused with
    /// [`SdfError::TooThin`] naming the step. A copy made at full size and
    /// shrunk by half with two hands at 1 cm had fused into 58% of a cup.
    ///
    /// The volume is compared one way: the result's mesh it is compared
    /// with holds the result's own chords, and a copy as large or larger
    /// is resolved as well or better (grown by 1.3 at 12 mm, 1.4% more of
    /// the true cup), so a copy made grown and shrunk back toward its
    /// size must not be refused for having more of it.
    pub fn check_placed_reuse(
        &self,
        old: Option<&Transform>,
        o: &Operand,
        cache: &SdfCache,
    ) -> Result<(), SdfError> {
        let Component::User { name } = &o.component else {
            return Ok(());
        };
        let Some(user) = self.user_components.get(name) else {
            return Ok(());
        };
        let shrunk =
            old.is_none_or(|old| (0..3).any(|k| o.transform.scale[k].abs() < old.scale[k].abs()));
        if !shrunk || (user.fused.is_none() && user.step.is_none()) {
            return Ok(());
        }
        let (tol, what) = match user.fused {
            Some(_) => (Some(REUSE_VOLUME_TOL), "the placed copy of the result"),
            None => (None, "the placed component"),
        };
        // The check samples and extracts the copy alone: its work first.
        self.copy_work(o, cache)?.check(what)?;
        let mesh = TriMesh::new(user.positions.clone(), user.triangles.clone());
        let Some(want) = shape(&mesh) else {
            return Ok(());
        };
        // The component is placed from its normalized frame (an object's
        // mesh is stored where the object was; a copy's is already in it).
        let (back, _) = normalized_frame(&mesh)?;
        let b = back.scale[0];
        let [x, y, z] = o.transform.scale;
        let want = Shape {
            volume: want.volume * (x * y * z).abs() / (b * b * b),
            ..want
        };
        match self.alone(o, cache)? {
            Some(g)
                if g.topology == want.topology
                    && tol.is_none_or(|t| g.volume >= want.volume * (1.0 - t)) =>
            {
                Ok(())
            }
            got => Err(too_thin(what, self.step, want, got)),
        }
    }

    /// The work of queuing copy `o` of the fused result (its component
    /// already added): sampling it and extracting it alone for the check,
    /// and the memory the volume then holds.
    pub fn copy_work(&self, o: &Operand, cache: &SdfCache) -> Result<Work, SdfError> {
        let work = self.operand_work(&self.placed_unchecked(o, cache)?);
        Ok(Work {
            // Extracted alone, once (the update reuses the sample).
            surface_bricks: work.surface_bricks + work.held_bricks,
            held_bricks: self.held_bricks() + work.held_bricks,
            ..work
        })
    }

    /// The volume with the fused result added as user component `name`
    /// and queued as a new `csg` operand at `t ∘ (where the result is)`.
    /// The component is the fold of the operands the result was fused
    /// from (exact; its mesh, the result's surface, is kept for drawing
    /// and budgets). Refused when the copy, sampled where it goes, would
    /// not keep the result's pieces and genus and its volume within
    /// [`REUSE_VOLUME_TOL`] when it is shrunk (its walls below the grid).
    pub fn with_fused_copy(
        &self,
        name: &str,
        t: &Transform,
        csg: CsgOp,
        cache: &SdfCache,
    ) -> Result<SdfVolume, SdfError> {
        if name.is_empty() {
            return Err(SdfError::BadMesh("the component name is empty".into()));
        }
        if self.user_components.contains_key(name) {
            return Err(SdfError::DuplicateComponent(name.to_owned()));
        }
        let mesh = self.evaluate_with(cache)?;
        if mesh.triangles.is_empty() {
            return Err(SdfError::EmptyResult);
        }
        t.validate()?;
        // In the frame every component has (centred on the result, 0.4
        // across), so a two-hand scale of the copy afterwards scales it
        // about its own centre, and the component is placed by name like
        // any other.
        let (back, to_local) = normalized_frame(&mesh)?;
        let operands = self
            .fused
            .iter()
            .map(|o| {
                Ok(Operand {
                    transform: compose(&to_local, &o.transform)?,
                    ..o.clone()
                })
            })
            .collect::<Result<Vec<_>, SdfError>>()?;
        let a = to_local.to_affine()?;
        let local = TriMesh::new(
            mesh.positions
                .iter()
                .map(|p| a.transform_point3(DVec3::from_array(*p)).to_array())
                .collect(),
            mesh.triangles.clone(),
        );
        let mut v = self.clone();
        v.user_components
            .insert(name.to_owned(), UserMesh::from_fused(local, operands));
        let o = Operand::new(
            Component::User {
                name: name.to_owned(),
            },
            csg,
            // A similarity (a per-axis scale is for the copy's operand
            // afterwards, a two-hand scale).
            compose(t, &back)?,
        );
        // The copy's memory and the work of sampling it, before either.
        v.copy_work(&o, cache)?.check("the copy of the result")?;
        if let Some(want) = shape(&mesh) {
            // A shrunk copy must keep its volume too: its walls fall to
            // fewer cells than the result's. A copy as large or larger is
            // resolved as well or better than the result (grown at 12 mm,
            // the cup's copy has 1.4% more of the true cup than the
            // result's 1.25-cell walls kept), so its topology is checked.
            let s = t.scale[0].abs();
            let tol = (s < 1.0).then_some(REUSE_VOLUME_TOL);
            let want = want.scaled(s);
            v.check_reuse(&o, want, tol, "the copy of the result", cache)?;
        }
        v.pending.push(o);
        Ok(v)
    }
}

fn too_thin(what: &str, step: f64, want: Shape, got: Option<Shape>) -> SdfError {
    SdfError::TooThin {
        what: what.to_owned(),
        step,
        want_genus: want.topology.0,
        want_pieces: want.topology.1,
        got: match got {
            Some(g) => format!(
                "{} piece(s) of genus {} with {:.1}% of its volume",
                g.topology.1,
                g.topology.0,
                100.0 * g.volume / want.volume
            ),
            None => "no closed surface".into(),
        },
    }
}

/// The affine of a transform (for tests and hosts drawing a moved result
/// before the op lands).
pub fn affine(t: &Transform) -> Result<DAffine3, SdfError> {
    Ok(t.to_affine()?)
}

#[cfg(test)]
mod wall_tests {
    use super::*;
    use crate::solid::{tessellate, SolidShape};

    fn slab(thick: f64) -> TriMesh {
        tessellate(
            &SolidShape::Box {
                size: [0.2, 0.2, thick],
            },
            8,
        )
        .unwrap()
    }

    #[test]
    fn a_slab_is_thin_below_its_thickness_and_not_above() {
        // Top and bottom, 2 x 0.04 m², against sides of 4 x 0.2 x 0.01.
        let m = slab(0.01);
        assert_eq!(thin_share(&m, 0.008).unwrap(), 0.0);
        let share = thin_share(&m, 0.012).unwrap();
        assert!((share - 0.08 / 0.088).abs() < 1e-9, "{share}");
    }

    #[test]
    fn walls_are_refused_under_two_cells_naming_the_step_in_model_units() {
        let m = slab(0.01);
        assert!(check_walls(&m, 0.004, 1.0, "object #1").is_ok());
        let e = check_walls(&m, 0.006, 1.0, "object #1").unwrap_err();
        assert!(
            matches!(e, SdfError::ThinWalls { step, wall, .. } if step == 0.006 && wall == 0.012),
            "{e}"
        );
        // The slab in the frame of a volume placed at scale 2 (its frame's
        // unit is 2 model units): half as thick in the frame, as thick in
        // the model, and judged and named in the model's units.
        let half = TriMesh::new(
            m.positions.iter().map(|p| p.map(|x| x * 0.5)).collect(),
            m.triangles.clone(),
        );
        assert!(check_walls(&half, 0.004, 2.0, "object #1").is_ok());
        let e = check_walls(&half, 0.006, 2.0, "object #1").unwrap_err();
        assert!(
            e.to_string().contains("0.012 m") && e.to_string().contains("0.006 m"),
            "{e}"
        );
    }
}
