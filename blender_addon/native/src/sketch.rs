//! The core's sketch pipeline for mouse strokes (`core::sketch`): the same
//! RDP, template matching and spine fitting the headset's GC tool runs,
//! and the section placement that makes a sketched tube follow its stroke.
//! Plain values in and out (lists and dicts, profiles as ops hold them);
//! the add-on builds op dicts from them.

use pyo3::prelude::*;
use pyo3::types::PyDict;
use shapewright::doc::{ObjectId, ObjectKind};
use shapewright::gc::{GcAssembly, Profile};
use shapewright::math::DVec3;
use shapewright::sketch::{
    child_from_stroke as core_child, match_section_stroke, profile_radius as core_radius,
    replace_spine_from_stroke as core_replace, sketch_spine as core_spine, ChildSettings,
    EndChoice, SectionPlan, SectionSettings, SketchError, SketchPlane,
};

use crate::convert::{from_py, into_py};
use crate::doc::Session;
use crate::error::{OpRejected, ParseError};

fn sketch_err(e: SketchError) -> PyErr {
    OpRejected::new_err(e.to_string())
}

fn vecs(points: &[[f64; 3]]) -> Vec<DVec3> {
    points.iter().map(|p| DVec3::from_array(*p)).collect()
}

fn settings(tolerance: Option<f64>) -> SectionSettings {
    let mut s = SectionSettings::default();
    if let Some(t) = tolerance {
        s.tolerance = t;
    }
    s
}

fn plan_items(d: &Bound<'_, PyDict>, plan: &SectionPlan) -> PyResult<()> {
    d.set_item("params", plan.params.clone())?;
    d.set_item("max_error", plan.max_error)?;
    d.set_item("min_bend_radius", plan.min_bend_radius)?;
    Ok(())
}

fn assembly(doc: &Session, id: u32) -> PyResult<&GcAssembly> {
    let obj = doc
        .log()
        .document()
        .get(ObjectId(id))
        .map_err(|e| OpRejected::new_err(e.to_string()))?;
    match &obj.kind {
        ObjectKind::GcAssembly(a) => Ok(a),
        other => Err(OpRejected::new_err(format!(
            "object {id} is a {}, not a generalized-cylinder assembly",
            other.name()
        ))),
    }
}

/// The spine a stroke sketched in a plane makes and where its key
/// sections go, for sections reaching `radius` from it: `{"points",
/// "plane_normal", "params", "max_error", "min_bend_radius"}`.
#[pyfunction]
#[pyo3(signature = (points, plane_origin, plane_normal, x_hint, radius, tolerance=None))]
pub(crate) fn sketch_spine<'py>(
    py: Python<'py>,
    points: Vec<[f64; 3]>,
    plane_origin: [f64; 3],
    plane_normal: [f64; 3],
    x_hint: [f64; 3],
    radius: f64,
    tolerance: Option<f64>,
) -> PyResult<Bound<'py, PyDict>> {
    let plane = SketchPlane::new(
        DVec3::from_array(plane_origin),
        DVec3::from_array(plane_normal),
        DVec3::from_array(x_hint),
    )
    .map_err(sketch_err)?;
    let stroke = vecs(&points);
    let s = settings(tolerance);
    let out = py
        .detach(|| core_spine(&stroke, &plane, radius, &s))
        .map_err(sketch_err)?;
    let d = PyDict::new(py);
    d.set_item(
        "points",
        out.points.iter().map(|p| p.to_array()).collect::<Vec<_>>(),
    )?;
    d.set_item("plane_normal", out.plane_normal.to_array())?;
    plan_items(&d, &out.plan)?;
    Ok(d)
}

/// The child part a stroke makes on assembly `id` (it must start on a
/// part's side surface): `{"parent", "at", "spine", "end", "end_tolerance",
/// "params", ...}`, the values of a `gc_add_child` op. `end` is `auto`,
/// `free` or `parent`.
#[pyfunction]
#[pyo3(signature = (doc, id, points, radius, end="auto"))]
pub(crate) fn child_from_stroke<'py>(
    py: Python<'py>,
    doc: &Session,
    id: u32,
    points: Vec<[f64; 3]>,
    radius: f64,
    end: &str,
) -> PyResult<Bound<'py, PyDict>> {
    let end = match end {
        "auto" => EndChoice::Auto,
        "free" => EndChoice::Free,
        "parent" => EndChoice::Parent,
        other => {
            return Err(ParseError::new_err(format!(
                "end must be auto, free or parent, got `{other}`"
            )))
        }
    };
    let asm = assembly(doc, id)?;
    let stroke = vecs(&points);
    let s = ChildSettings::default();
    let c = py
        .detach(|| core_child(asm, &stroke, radius, end, &s))
        .map_err(sketch_err)?;
    let d = PyDict::new(py);
    d.set_item("parent", c.parent)?;
    d.set_item("at", c.at.to_array())?;
    d.set_item("spine", c.spine.clone())?;
    d.set_item("end", if c.lands { "parent" } else { "free" })?;
    d.set_item("end_tolerance", c.end_tolerance)?;
    plan_items(&d, &c.plan)?;
    Ok(d)
}

/// How part `part` of assembly `id` gets the spine a stroke describes:
/// `{"points", "plane_normal", "insert_at", "params", ...}` (insert key
/// sections at `insert_at` first, then replace the spine).
#[pyfunction]
pub(crate) fn replace_spine_from_stroke<'py>(
    py: Python<'py>,
    doc: &Session,
    id: u32,
    part: usize,
    points: Vec<[f64; 3]>,
) -> PyResult<Bound<'py, PyDict>> {
    let asm = assembly(doc, id)?;
    let stroke = vecs(&points);
    let s = SectionSettings::default();
    let r = py
        .detach(|| core_replace(asm, part, &stroke, &s))
        .map_err(sketch_err)?;
    let d = PyDict::new(py);
    d.set_item(
        "points",
        r.points.iter().map(|p| p.to_array()).collect::<Vec<_>>(),
    )?;
    d.set_item("plane_normal", r.plane_normal.to_array())?;
    d.set_item("insert_at", r.insert_at.clone())?;
    plan_items(&d, &r.plan)?;
    Ok(d)
}

/// Matches a closed stroke in a plane against the section templates (the
/// headset's matcher): `{"profile" (a dict, as an op holds it), "score",
/// "center" (3D), "rotation", "candidates", "sketch" (the loop itself as
/// a profile dict)}`.
#[pyfunction]
pub(crate) fn match_section<'py>(
    py: Python<'py>,
    points: Vec<[f64; 3]>,
    plane_origin: [f64; 3],
    plane_normal: [f64; 3],
    x_hint: [f64; 3],
) -> PyResult<Bound<'py, PyDict>> {
    let plane = SketchPlane::new(
        DVec3::from_array(plane_origin),
        DVec3::from_array(plane_normal),
        DVec3::from_array(x_hint),
    )
    .map_err(sketch_err)?;
    let m = match_section_stroke(&vecs(&points), &plane).map_err(sketch_err)?;
    let d = PyDict::new(py);
    d.set_item("profile", into_py(py, &m.profile)?)?;
    d.set_item("sketch", into_py(py, &m.sketch)?)?;
    d.set_item("score", m.score)?;
    d.set_item("center", plane.lift(m.center).to_array())?;
    d.set_item("rotation", m.rotation)?;
    d.set_item("candidates", m.candidates.clone())?;
    Ok(d)
}

/// Largest distance of a section profile (a dict, as an op holds it)
/// from its centre.
#[pyfunction]
pub(crate) fn profile_radius(profile: &Bound<'_, PyAny>) -> PyResult<f64> {
    let p: Profile = from_py(profile, "profile")?;
    p.curve().map_err(|e| OpRejected::new_err(e.to_string()))?;
    Ok(core_radius(&p))
}
