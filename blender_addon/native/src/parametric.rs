//! The parametric data next to each object's mesh (`shapewright-usd`'s
//! `parametric::parts`: GC spines, sections and skins, curve-network
//! curves and patches), in the forms Blender can show exactly:
//! - a NURBS curve as Blender `Curves` take it with the
//!   `ENDPOINT_BEZIER` knot mode: the curve's Bézier segments (core
//!   `NurbsCurve::bezier_segments`, exact knot insertion) joined, with
//!   their weights. Blender's knot modes cannot hold arbitrary knots, but
//!   a clamped piecewise-Bézier knot vector can hold any clamped curve
//!   exactly (same shape; its parameter speed differs between segments);
//! - a NURBS patch as a triangle grid at knot-aligned samples (the grid's
//!   index pattern is built here; the points are the core's evaluation).

use pyo3::prelude::*;
use pyo3::types::{PyBytes, PyDict, PyList};
use shapewright::doc::ObjectId;
use shapewright::mesh::{f64_le_bytes, u32_le_bytes};
use shapewright::nurbs::{euclidean, knot_aligned_samples, NurbsCurve, NurbsSurface};
use shapewright_usd::parametric::{parts, Part};

use crate::doc::Session;
use crate::error::OpRejected;

/// Samples per unit domain of a patch grid (knot spans are kept).
const PATCH_SAMPLES: usize = 48;

fn curve_dict<'py>(py: Python<'py>, c: &NurbsCurve) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    let segs = c.bezier_segments();
    let mut points = Vec::new();
    let mut weights = Vec::new();
    for (s, (_, ctrl)) in segs.iter().enumerate() {
        for h in ctrl.iter().skip(usize::from(s > 0)) {
            points.push(euclidean(*h).to_array());
            weights.push(h.w);
        }
    }
    d.set_item("order", c.degree + 1)?;
    d.set_item("bezier_points", points)?;
    d.set_item("bezier_weights", weights)?;
    d.set_item("segments", segs.len())?;
    d.set_item("knots", c.knots.clone())?;
    d.set_item(
        "points",
        c.control
            .iter()
            .map(|h| euclidean(*h).to_array())
            .collect::<Vec<_>>(),
    )?;
    d.set_item("weights", c.control.iter().map(|h| h.w).collect::<Vec<_>>())?;
    Ok(d)
}

fn patch_grid(s: &NurbsSurface) -> (Vec<[f64; 3]>, Vec<[u32; 3]>) {
    let us = knot_aligned_samples(&s.knots_u, s.degree_u, PATCH_SAMPLES);
    let vs = knot_aligned_samples(&s.knots_v, s.degree_v, PATCH_SAMPLES);
    let pts: Vec<[f64; 3]> = s.grid(&us, &vs).iter().map(|p| p.to_array()).collect();
    let nu = us.len() as u32;
    let mut tris = Vec::with_capacity(2 * us.len() * vs.len());
    for j in 0..vs.len().saturating_sub(1) as u32 {
        for i in 0..nu - 1 {
            let a = j * nu + i;
            let (b, c, d) = (a + 1, a + nu, a + nu + 1);
            tris.push([a, b, d]);
            tris.push([a, d, c]);
        }
    }
    (pts, tris)
}

/// The parametric parts of object `id`: a list of `{"name", "kind":
/// "curves", "curves": [...], "indices"}` and `{"name", "kind": "patch",
/// "positions" (f64 bytes), "triangles" (u32 bytes)}` (empty for solids,
/// SDF volumes and sculpts).
#[pyfunction]
pub(crate) fn parametric_parts<'py>(
    py: Python<'py>,
    doc: &Session,
    id: u32,
) -> PyResult<Bound<'py, PyList>> {
    let obj = doc
        .log()
        .document()
        .get(ObjectId(id))
        .map_err(|e| OpRejected::new_err(e.to_string()))?;
    // Display helpers: a part that cannot be made (named in
    // `problems`) is left out; the object's mesh still shows it.
    let found = py.detach(|| parts(&obj.kind));
    let out = PyList::empty(py);
    for p in &found.parts {
        let d = PyDict::new(py);
        d.set_item("name", p.name())?;
        let mesh_item = |pts: &[[f64; 3]], tris: &[[u32; 3]]| -> PyResult<()> {
            d.set_item("kind", "patch")?;
            let pos = f64_le_bytes(pts.iter().flatten(), 1.0);
            d.set_item("positions", PyBytes::new(py, &pos))?;
            let tri = u32_le_bytes(tris.iter().flatten());
            d.set_item("triangles", PyBytes::new(py, &tri))
        };
        match p {
            Part::Curves {
                curves, indices, ..
            } => {
                d.set_item("kind", "curves")?;
                let list = PyList::empty(py);
                for c in curves {
                    list.append(curve_dict(py, c)?)?;
                }
                d.set_item("curves", list)?;
                d.set_item("indices", indices.clone())?;
            }
            Part::Patch { surface, .. } => {
                let (pts, tris) = py.detach(|| patch_grid(surface));
                mesh_item(&pts, &tris)?;
            }
            // A patch of more than 4 sides: its evaluated triangles.
            Part::Mesh { mesh, .. } => mesh_item(&mesh.positions, &mesh.triangles)?,
        }
        out.append(d)?;
    }
    Ok(out)
}
