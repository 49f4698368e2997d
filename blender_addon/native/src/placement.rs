//! Placements across the border as values: [`Placement`] (a core
//! `Transform`: translation in metres, rotation, scale per axis, the
//! order scale, rotate, translate) and [`Pose`] (a tracked position and
//! orientation). A host builds them from its own matrices and reads them
//! back as matrices; the units are stated where they change (a scene whose
//! unit is not the metre passes its metres per unit).

use pyo3::prelude::*;
use shapewright::interact::{Pose as CorePose, STAGE_FROM_Z_UP};
use shapewright::math::{DMat4, DQuat, DVec3, Transform};

use crate::error::ParseError;

/// A placement: translation (metres), rotation quaternion `(x, y, z, w)`,
/// scale per axis.
#[pyclass(module = "shapewright._native", frozen, eq, from_py_object)]
#[derive(Clone, Copy, Debug, PartialEq)]
#[repr(transparent)]
pub struct Placement(pub(crate) Transform);

fn bad(e: impl std::fmt::Display) -> PyErr {
    ParseError::new_err(format!("placement: {e}"))
}

impl Placement {
    /// A checked placement.
    pub(crate) fn checked(t: Transform) -> PyResult<Self> {
        crate::convert::check_finite("translate", &t.translate)?;
        crate::convert::check_finite("scale", &t.scale)?;
        t.validate().map_err(bad)?;
        Ok(Self(t))
    }
}

#[pymethods]
impl Placement {
    /// A placement; refuses non-finite parts, a zero rotation or a zero
    /// scale with the reason.
    #[new]
    #[pyo3(signature = (translate=[0.0; 3], rotate=[0.0, 0.0, 0.0, 1.0], scale=[1.0; 3]))]
    fn new(translate: [f64; 3], rotate: [f64; 4], scale: [f64; 3]) -> PyResult<Self> {
        let q = DQuat::from_array(rotate);
        let rotate = if q.is_finite() && q.length_squared() > 1e-24 {
            q.normalize().to_array()
        } else {
            rotate
        };
        Self::checked(Transform {
            translate,
            rotate,
            scale,
        })
    }

    /// A Z-up model where the Z-up world is, in the Y-up stage: the
    /// stage's origin, [`STAGE_FROM_Z_UP`], scale 1 (Blender's VR session,
    /// whose world is the model's).
    #[staticmethod]
    fn z_up_in_stage() -> Self {
        Self(Transform {
            translate: [0.0; 3],
            rotate: STAGE_FROM_Z_UP.to_array(),
            scale: [1.0; 3],
        })
    }

    /// The placement of a 4x4 matrix given as rows (Blender's
    /// `Matrix`), whose translation is in units of `metres_per_unit`
    /// metres. Refuses a matrix that shears (it has no scale-rotate-
    /// translate form) or flattens.
    #[staticmethod]
    #[pyo3(signature = (rows, metres_per_unit=1.0))]
    fn from_matrix(rows: [[f64; 4]; 4], metres_per_unit: f64) -> PyResult<Self> {
        if !(metres_per_unit.is_finite() && metres_per_unit > 0.0) {
            return Err(bad(format!(
                "metres per unit must be positive, got {metres_per_unit}"
            )));
        }
        let m = DMat4::from_cols_array_2d(&rows).transpose();
        if !m.is_finite() {
            return Err(bad("the matrix has a non-finite entry"));
        }
        let (scale, rotation, translation) = m.to_scale_rotation_translation();
        let back = DMat4::from_scale_rotation_translation(scale, rotation, translation);
        // A host's matrices are float32 (Blender's): its own rounding is
        // not a shear. Compared on the linear part, relative to its size.
        let linear = |x: DMat4| shapewright::math::DMat3::from_mat4(x);
        let size = linear(m)
            .to_cols_array()
            .iter()
            .fold(0.0f64, |a, x| a.max(x.abs()));
        let projective = rows[3]
            .iter()
            .zip([0.0, 0.0, 0.0, 1.0])
            .any(|(a, b)| (a - b).abs() > 1e-12);
        if projective || !linear(back).abs_diff_eq(linear(m), 1e-5 * size) {
            return Err(bad(
                "the matrix shears or projects; a placement is a scale along the object's \
                 own axes, a rotation and a translation",
            ));
        }
        Self::checked(Transform {
            translate: (translation * metres_per_unit).to_array(),
            rotate: rotation.normalize().to_array(),
            scale: scale.to_array(),
        })
    }

    /// The placement as a 4x4 matrix of rows, its translation in units of
    /// `1 / units_per_metre` metres.
    #[pyo3(signature = (units_per_metre=1.0))]
    fn matrix(&self, units_per_metre: f64) -> [[f64; 4]; 4] {
        let t = self.0;
        let m = DMat4::from_scale_rotation_translation(
            DVec3::from_array(t.scale),
            DQuat::from_array(t.rotate).normalize(),
            DVec3::from_array(t.translate) * units_per_metre,
        );
        m.transpose().to_cols_array_2d()
    }

    /// Translation (metres).
    #[getter]
    fn translate(&self) -> [f64; 3] {
        self.0.translate
    }

    /// Rotation quaternion `(x, y, z, w)`.
    #[getter]
    fn rotate(&self) -> [f64; 4] {
        self.0.rotate
    }

    /// Scale per axis.
    #[getter]
    fn scale(&self) -> [f64; 3] {
        self.0.scale
    }

    /// Whether `other` is this placement within `tolerance` (metres for
    /// the translation, relative for rotation and scale): a host's float32
    /// copy of a placement still counts as it.
    #[pyo3(signature = (other, tolerance=1e-6))]
    pub(crate) fn close_to(&self, other: &Placement, tolerance: f64) -> bool {
        let (a, b) = (self.0, other.0);
        let qa = DQuat::from_array(a.rotate).normalize();
        let qb = DQuat::from_array(b.rotate).normalize();
        let near = |x: &[f64], y: &[f64], tol: f64| {
            x.iter()
                .zip(y)
                .all(|(p, q)| (p - q).abs() <= tol * (1.0 + p.abs().max(q.abs())))
        };
        near(&a.translate, &b.translate, tolerance)
            && near(&a.scale, &b.scale, tolerance)
            && qa.dot(qb).abs() >= 1.0 - tolerance
    }

    fn __repr__(&self) -> String {
        let t = self.0;
        format!(
            "Placement(translate={:?}, rotate={:?}, scale={:?})",
            t.translate, t.rotate, t.scale
        )
    }
}

/// A tracked pose: position `p` (metres) and orientation `q` `(x, y, z,
/// w)`. Not checked here: lost tracking (NaN) is the sanitizer's to see.
#[pyclass(module = "shapewright._native", frozen, eq, from_py_object)]
#[derive(Clone, Copy, Debug, PartialEq)]
#[repr(transparent)]
pub struct Pose(pub(crate) CorePose);

#[pymethods]
impl Pose {
    /// A pose.
    #[new]
    #[pyo3(signature = (p=[0.0; 3], q=[0.0, 0.0, 0.0, 1.0]))]
    fn new(p: [f64; 3], q: [f64; 4]) -> Self {
        Self(CorePose {
            position: DVec3::from_array(p),
            orientation: DQuat::from_array(q),
        })
    }

    /// Position (metres).
    #[getter]
    fn p(&self) -> [f64; 3] {
        self.0.position.to_array()
    }

    /// Orientation `(x, y, z, w)`.
    #[getter]
    fn q(&self) -> [f64; 4] {
        self.0.orientation.to_array()
    }

    /// The stage pose of a pose in a Z-up world (Blender's), position in
    /// metres, orientation `(x, y, z, w)`.
    #[staticmethod]
    fn from_z_up(p: [f64; 3], q: [f64; 4]) -> Self {
        Self(CorePose::from_z_up(
            DVec3::from_array(p),
            DQuat::from_array(q),
        ))
    }

    /// This stage pose in a Z-up world: `(position, (x, y, z, w))`.
    #[pyo3(name = "to_z_up")]
    fn z_up(&self) -> ([f64; 3], [f64; 4]) {
        let (p, q) = self.0.to_z_up();
        (p.to_array(), q.to_array())
    }

    /// A point given in this pose's frame, in the frame the pose is in.
    fn apply(&self, point: [f64; 3]) -> [f64; 3] {
        (self.0.position + self.0.orientation * DVec3::from_array(point)).to_array()
    }

    fn __repr__(&self) -> String {
        format!("Pose(p={:?}, q={:?})", self.p(), self.q())
    }
}
