//! Components from any closed mesh, and the fused result moved, copied
//! and used as a component (paper 2 §3: "users are allowed to freely
//! augment the dataset"; Fig. 2: the result `M = B − A` is shrunk to `D`
//! and united with more components; §4.4: copy).
//!
//! - [`component_from_mesh`]: any closed oriented mesh (a document
//!   object's evaluated mesh, an imported file) becomes a user component:
//!   its normalized SDF (§5.2) comes from the host's [`SdfCache`], and the
//!   placement returned puts the normalized component back exactly where
//!   the mesh was.
//! - [`SdfVolume::with_fused_moved`]: moving the fused result moves every
//!   fused operand (`T ∘ Tᵢ`) and the grid is rebuilt from the recipe:
//!   exact for a similarity (the fold of moved, uniformly scaled distance
//!   fields is the moved fold); a per-axis scale is refused with a typed
//!   error (it is not a similarity of the operands' frames): copy the
//!   result as a component and scale the copy instead.
//! - [`SdfVolume::with_fused_copy`]: the fused surface becomes a user
//!   component of the volume and is queued as a new operand where the
//!   result is, moved by a transform: the paper's copy, and a result used
//!   as a component.

use std::collections::BTreeMap;

use super::cache::SdfCache;
use super::csg::CsgOp;
use super::mesh_sdf::COMPONENT_SIZE;
use super::volume::{Component, Operand, SdfVolume, UserMesh};
use super::SdfError;
use crate::math::{DAffine3, DQuat, DVec3, Transform};
use crate::mesh::{validate, TriMesh};

/// A user component made from closed `mesh`: its stored mesh (with the
/// normalized SDF now in `cache`) and the placement that puts the
/// normalized component where `mesh` is.
pub fn component_from_mesh(
    mesh: &TriMesh,
    cache: &SdfCache,
) -> Result<(UserMesh, Transform), SdfError> {
    let r = validate(mesh, &Default::default());
    if !r.is_closed_manifold() {
        return Err(SdfError::BadMesh(r.problems()));
    }
    let (lo, hi) = mesh.bbox().ok_or(SdfError::EmptyResult)?;
    cache.component_sdf(mesh)?;
    let s = (hi - lo).max_element() / COMPONENT_SIZE;
    let back = Transform {
        translate: ((lo + hi) * 0.5).to_array(),
        rotate: [0.0, 0.0, 0.0, 1.0],
        scale: [s; 3],
    };
    Ok((
        UserMesh {
            positions: mesh.positions.clone(),
            triangles: mesh.triangles.clone(),
        },
        back,
    ))
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

impl SdfVolume {
    /// The volume with its fused result moved by `t` (a similarity): every
    /// fused operand placed at `t ∘ Tᵢ`, the grid rebuilt from the recipe.
    /// Pending operands stay where they are.
    pub fn with_fused_moved(&self, t: &Transform, cache: &SdfCache) -> Result<SdfVolume, SdfError> {
        if self.fused.is_empty() {
            return Err(SdfError::EmptyResult);
        }
        let mut v = self.without_state();
        for o in &mut v.fused {
            o.transform = compose(t, &o.transform)?;
        }
        v.state_with(cache)?;
        Ok(v)
    }

    /// The volume with its fused surface added as user component `name`
    /// and queued as a new `csg` operand at `t ∘ (where the result is)`.
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
        let (user, back) = component_from_mesh(&mesh, cache)?;
        let mut v = self.clone();
        let mut comps: BTreeMap<String, UserMesh> = v.user_components.clone();
        comps.insert(name.to_owned(), user);
        v.user_components = comps;
        let o = Operand::new(
            Component::User {
                name: name.to_owned(),
            },
            csg,
            compose(t, &back)?,
        );
        v.placed_with(&o, cache)?;
        v.pending.push(o);
        Ok(v)
    }
}

/// The affine of a transform (for tests and hosts drawing a moved result
/// before the op lands).
pub fn affine(t: &Transform) -> Result<DAffine3, SdfError> {
    Ok(t.to_affine()?)
}
