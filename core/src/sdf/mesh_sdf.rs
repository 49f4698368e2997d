//! Closed mesh → discrete SDF (paper 2 §5.2 steps 1–5).
//!
//! - **Distance:** the closest point on the mesh by parry3d's BVH
//!   (`TriMesh::project_local_point`); parry works in `f32`, which is ample
//!   for components normalized to 0.4 (error ~1e-8 against a 0.01 step).
//! - **Sign:** parry's angle-weighted pseudo-normals
//!   (`TriMeshFlags::ORIENTED`, Bærentzen & Aanæs 2005): the sign of
//!   `(p − closest) · n` with `n` the pseudo-normal of the closest feature
//!   (face, edge or vertex) is correct for every point of a closed,
//!   consistently oriented mesh, including points on or near edges and
//!   vertices, where ray casting (what `mesh_to_sdf` 0.4 does) fails.
//!   We therefore refuse meshes that are not closed oriented 2-manifolds.
//! - **Normalization** ([`normalize_component`]): centred on its box,
//!   scaled so the longest side is 0.4, padded by 0.1, step 0.01.
//! - **Components at a chosen step** ([`component_sdf_at`]): a document
//!   object or a fused result reused as a component keeps its detail: its
//!   SDF is sampled at the step it had (its volume's, or the target
//!   volume's if finer), not at the library's 40 cells across (which took
//!   a third of a chair's volume and 2.7 cm of its legs). At fine steps
//!   most samples lie far from the surface, so [`mesh_to_sdf_banded`]
//!   asks parry only near it: a block of 4³ samples whose centre is
//!   farther from the surface than the block's radius plus the band gets
//!   `±(|d(centre)| − |p − centre|)`, a value of the right sign that never
//!   exceeds the true distance (so the field stays 1-Lipschitz where it
//!   matters), beyond the band wherever it is used.

use rayon::prelude::*;

use super::dense::DenseSdf;
use super::SdfError;
use crate::math::DVec3;
use crate::mesh::{validate, TriMesh};

/// Longest side of a normalized component (§5.2 step 3).
pub const COMPONENT_SIZE: f64 = 0.4;
/// Padding around a normalized component's box (§5.2 step 3).
pub const COMPONENT_PADDING: f64 = 0.1;
/// Grid step of a component's SDF (§5.2 step 4).
pub const COMPONENT_STEP: f64 = 0.01;

/// Most samples a [`mesh_to_sdf`] grid may have (64 Mi, 256 MiB).
pub const MAX_SAMPLES: usize = 1 << 26;

fn check_mesh(mesh: &TriMesh) -> Result<(), SdfError> {
    let r = validate(mesh, &Default::default());
    if !r.is_closed_manifold() {
        return Err(SdfError::BadMesh(r.problems()));
    }
    Ok(())
}

/// The signed distance field of a closed, oriented mesh, sampled on the
/// grid covering the mesh's box plus `padding`, at spacing `step`, in the
/// mesh's own frame. Public so that the sculpt system can build grid
/// brushes from any mesh (sample it with [`DenseSdf::sample`] and
/// [`DenseSdf::gradient`]).
pub fn mesh_to_sdf(mesh: &TriMesh, step: f64, padding: f64) -> Result<DenseSdf, SdfError> {
    let (dims, origin) = sdf_grid(mesh, step, padding)?;
    let total = dims[0] * dims[1] * dims[2];
    let centre = origin + DVec3::from_array(dims.map(|d| (d - 1) as f64)) * step * 0.5;
    let query = MeshDistance::new(mesh, centre)?;
    let slab = dims[0] * dims[1];
    let mut values = vec![0f32; total];
    values
        .par_chunks_mut(slab)
        .enumerate()
        .for_each(|(k, out)| {
            for j in 0..dims[1] {
                for i in 0..dims[0] {
                    let p = origin + DVec3::new(i as f64, j as f64, k as f64) * step;
                    out[i + dims[0] * j] = query.signed_distance(p) as f32;
                }
            }
        });
    Ok(DenseSdf {
        dims,
        origin: origin.to_array(),
        step,
        values,
    })
}

/// Samples per edge of the blocks [`mesh_to_sdf_banded`] proves far.
const FAR_BLOCK: usize = 4;

/// The grid [`mesh_to_sdf`] and [`mesh_to_sdf_banded`] sample: dims and
/// origin (centred on the padded box), or the budget error.
fn sdf_grid(mesh: &TriMesh, step: f64, padding: f64) -> Result<([usize; 3], DVec3), SdfError> {
    check_mesh(mesh)?;
    if !(step.is_finite() && step > 0.0 && padding.is_finite() && padding >= 0.0) {
        return Err(SdfError::BadMesh(format!(
            "step {step} must be > 0 and padding {padding} >= 0"
        )));
    }
    let (lo, hi) = mesh
        .bbox()
        .ok_or_else(|| SdfError::BadMesh("empty".into()))?;
    let lo = lo - DVec3::splat(padding);
    let hi = hi + DVec3::splat(padding);
    let n = ((hi - lo) / step).ceil();
    let dims = [n.x as usize + 1, n.y as usize + 1, n.z as usize + 1];
    let total = dims[0].saturating_mul(dims[1]).saturating_mul(dims[2]);
    if total > MAX_SAMPLES {
        return Err(SdfError::OverBudget(super::budget::grid_memory(
            super::budget::mib_ceil(total as f64 * 4.0),
            ((MAX_SAMPLES * 4) >> 20) as u64,
        )));
    }
    // Centre the grid on the box so both sides get the same padding.
    let extra = (n * step - (hi - lo)) * 0.5;
    Ok((dims, lo - extra))
}

/// [`mesh_to_sdf`], exact only within `band` of the surface: farther, each
/// sample holds a value of the right sign whose magnitude is at least
/// `band` and at most the true distance (see the module doc). The same
/// grid as [`mesh_to_sdf`] with the same arguments, and the same values
/// wherever either is within `band`.
pub fn mesh_to_sdf_banded(
    mesh: &TriMesh,
    step: f64,
    padding: f64,
    band: f64,
) -> Result<DenseSdf, SdfError> {
    let (dims, origin) = sdf_grid(mesh, step, padding)?;
    banded_on(mesh, dims, origin, step, band)
}

/// [`mesh_to_sdf_banded`] on the grid of `dims` samples from `origin`.
fn banded_on(
    mesh: &TriMesh,
    dims: [usize; 3],
    origin: DVec3,
    step: f64,
    band: f64,
) -> Result<DenseSdf, SdfError> {
    let centre = origin + DVec3::from_array(dims.map(|d| (d - 1) as f64)) * step * 0.5;
    let query = MeshDistance::new(mesh, centre)?;
    let at =
        |i: usize, j: usize, k: usize| origin + DVec3::new(i as f64, j as f64, k as f64) * step;
    let b = FAR_BLOCK;
    let slab = dims[0] * dims[1] * b;
    let mut values = vec![0f32; dims[0] * dims[1] * dims[2]];
    // One task per layer of blocks: each writes its own samples.
    values
        .par_chunks_mut(slab)
        .enumerate()
        .for_each(|(bz, out)| {
            let k0 = bz * b;
            let nk = out.len() / (dims[0] * dims[1]);
            for bj in (0..dims[1]).step_by(b) {
                for bi in (0..dims[0]).step_by(b) {
                    let c = at(bi, bj, k0) + DVec3::splat((b - 1) as f64 * 0.5 * step);
                    let r = (b - 1) as f64 * 0.5 * 3f64.sqrt() * step;
                    let dc = query.signed_distance(c);
                    let far = dc.abs() - r > band;
                    for k in 0..nk {
                        for j in bj..(bj + b).min(dims[1]) {
                            for i in bi..(bi + b).min(dims[0]) {
                                let p = at(i, j, k0 + k);
                                let v = if far {
                                    dc.signum() * (dc.abs() - (p - c).length())
                                } else {
                                    query.signed_distance(p)
                                };
                                out[i + dims[0] * (j + dims[1] * k)] = v as f32;
                            }
                        }
                    }
                }
            }
        });
    Ok(DenseSdf {
        dims,
        origin: origin.to_array(),
        step,
        values,
    })
}

/// Signed distance queries against a closed, oriented mesh (parry3d BVH
/// closest point, pseudo-normal sign).
pub struct MeshDistance {
    tri: parry3d::shape::TriMesh,
    centre: DVec3,
}

impl MeshDistance {
    /// Builds the BVH and pseudo-normals. `centre` is subtracted from every
    /// point before going to parry's `f32` (keeps digits near the mesh).
    pub fn new(mesh: &TriMesh, centre: DVec3) -> Result<Self, SdfError> {
        check_mesh(mesh)?;
        Self::of_checked(mesh, centre)
    }

    /// [`MeshDistance::new`] for a mesh the caller has already checked
    /// closed and oriented (no second validation of a large mesh).
    pub(crate) fn of_checked(mesh: &TriMesh, centre: DVec3) -> Result<Self, SdfError> {
        let verts: Vec<parry3d::math::Vector> = mesh
            .positions
            .iter()
            .map(|p| {
                let q = DVec3::from_array(*p) - centre;
                parry3d::math::Vector::new(q.x as f32, q.y as f32, q.z as f32)
            })
            .collect();
        let tri = parry3d::shape::TriMesh::with_flags(
            verts,
            mesh.triangles.clone(),
            parry3d::shape::TriMeshFlags::ORIENTED,
        )
        .map_err(|e| SdfError::BadMesh(format!("{e:?}")))?;
        Ok(Self { tri, centre })
    }

    /// How far the ray from `origin` along unit `dir` goes before it
    /// meets the surface (within `max`), or `None`.
    pub fn ray_hit(&self, origin: DVec3, dir: DVec3, max: f64) -> Option<f64> {
        use parry3d::query::{Ray, RayCast};
        let o = origin - self.centre;
        let ray = Ray::new(
            parry3d::math::Vector::new(o.x as f32, o.y as f32, o.z as f32),
            parry3d::math::Vector::new(dir.x as f32, dir.y as f32, dir.z as f32),
        );
        self.tri
            .cast_local_ray(&ray, max as f32, false)
            .map(f64::from)
    }

    /// The signed distance at `p` (negative inside).
    pub fn signed_distance(&self, p: DVec3) -> f64 {
        use parry3d::query::PointQuery;
        let p = p - self.centre;
        let q = parry3d::math::Vector::new(p.x as f32, p.y as f32, p.z as f32);
        let proj = self.tri.project_local_point(q, false);
        let d = (proj.point - q).length() as f64;
        if proj.is_inside {
            -d
        } else {
            d
        }
    }
}

/// `mesh` centred on its box and scaled so its longest side is
/// [`COMPONENT_SIZE`] (§5.2 steps 1–3).
pub fn normalize_component(mesh: &TriMesh) -> Result<TriMesh, SdfError> {
    check_mesh(mesh)?;
    let (lo, hi) = mesh
        .bbox()
        .ok_or_else(|| SdfError::BadMesh("empty".into()))?;
    let c = (lo + hi) * 0.5;
    let s = COMPONENT_SIZE / (hi - lo).max_element();
    let mut out = mesh.clone();
    for p in &mut out.positions {
        *p = ((DVec3::from_array(*p) - c) * s).to_array();
    }
    out.normals.clear();
    Ok(out)
}

/// The area of `mesh` once normalized ([`normalize_component`]).
pub fn normalized_area(mesh: &TriMesh) -> f64 {
    let size = mesh.bbox().map_or(0.0, |(lo, hi)| (hi - lo).max_element());
    let k = COMPONENT_SIZE / size;
    mesh.area() * k * k
}

/// A library component's SDF: normalized, padded, step 0.01 (§5.2).
pub fn component_sdf(mesh: &TriMesh) -> Result<DenseSdf, SdfError> {
    let m = normalize_component(mesh)?;
    mesh_to_sdf(&m, COMPONENT_STEP, COMPONENT_PADDING)
}

/// Grid cells of padding around a component sampled at its own step
/// ([`component_sdf_at`]): its surface stays inside the box with room for
/// a crossing cell on each side even when the operand is shrunk to 0.4.
pub const REUSE_PADDING_CELLS: f64 = 3.0;
/// Cells within which [`component_sdf_at`] computes exact distances: the
/// volume's band (3 cells) and two more for the interpolation around it.
pub const REUSE_BAND_CELLS: f64 = 5.0;

/// A reused component's SDF: normalized as [`component_sdf`], but sampled
/// so that one grid cell is `step` in the mesh's own units (narrow band,
/// [`REUSE_PADDING_CELLS`] of padding; see the module doc).
pub fn component_sdf_at(mesh: &TriMesh, step: f64) -> Result<DenseSdf, SdfError> {
    let (lo, hi) = mesh
        .bbox()
        .ok_or_else(|| SdfError::BadMesh("empty".into()))?;
    let size = (hi - lo).max_element();
    let local = step * COMPONENT_SIZE / size;
    if !(local.is_finite() && local > 0.0) {
        return Err(SdfError::BadMesh(format!(
            "step {step} on a mesh {size} across gives no grid"
        )));
    }
    // The work, counted before it is done (see `super::budget`).
    let grown =
        (hi - lo) * (COMPONENT_SIZE / size) + DVec3::splat(2.0 * REUSE_PADDING_CELLS * local);
    let samples = ((grown / local) + DVec3::ONE)
        .to_array()
        .iter()
        .product::<f64>();
    let work = super::budget::Work {
        mesh_queries: super::budget::banded_queries(
            samples,
            normalized_area(mesh),
            local,
            REUSE_BAND_CELLS * local,
        ),
        mesh_triangles: mesh.triangles.len() as f64,
        ..Default::default()
    };
    work.check("the component's SDF")?;
    if samples > MAX_SAMPLES as f64 {
        return Err(SdfError::OverBudget(super::budget::grid_memory(
            super::budget::mib_ceil(samples * 4.0),
            ((MAX_SAMPLES * 4) >> 20) as u64,
        )));
    }
    let m = normalize_component(mesh)?;
    // On the lattice: the nodes sit at whole multiples of `step` in the
    // mesh's own frame (normalized: `(p - c) / s`), so a volume whose
    // lattice is a multiple of `step` in that frame (the object's own
    // volume, or the target one at twice the reuse step) resamples it at
    // nodes: exact distances, no trilinear blur of thin walls.
    let c = (lo + hi) * 0.5;
    let s = size / COMPONENT_SIZE;
    let pad = REUSE_PADDING_CELLS * step;
    let first = ((lo - DVec3::splat(pad)) / step).floor();
    let last = ((hi + DVec3::splat(pad)) / step).ceil();
    let n = last - first;
    let dims = [n.x as usize + 1, n.y as usize + 1, n.z as usize + 1];
    let origin = (first * step - c) / s;
    banded_on(&m, dims, origin, local, REUSE_BAND_CELLS * local)
}
