//! Parametric data next to each object's mesh: `NurbsCurves` and
//! `NurbsPatch` prims (issue 7, ARCHITECTURE.md "USD mapping").
//!
//! - A generalized-cylinder assembly (paper 1 §3.1) gives, per part `i`:
//!   `Part<i>_Spine` (one curve), `Part<i>_Sections` (the key sections
//!   placed on the spine, one curve each) and `Part<i>_Surface`, the exact
//!   skin through them (`Gc::surface`). For shells and containers this is
//!   the outer side surface; the inner offset and the caps exist only as
//!   mesh.
//! - A curve network (paper 3 §5) gives `Curves` (its live curves, with
//!   `shapewright:curveIndices` naming each one's index in the network)
//!   and `Patch<k>` per patch, converted exactly to a bicubic NURBS surface
//!   ([`crate::coons`]); a patch of more sides as `Patch<k>`, a `Mesh` of
//!   its triangles, plus `Patch<k>_Boundary`, its pieces as curves.
//!
//! Authoring follows the UsdGeom schemas: `order = degree + 1`, `knots`
//! concatenated per curve (`count + order` each), `ranges` the curves'
//! domains, `points` Euclidean (not pre-weighted) as `point3f`, and
//! `pointWeights` only for rational data (any weight not 1). Patch points
//! are ordered with `u` varying fastest (RenderMan's `RiNuPatch` layout,
//! which the schema follows): `points[j * uVertexCount + i]` is `P_{i,j}`.
//! `extent` bounds the control points (the convex hull property, exact for
//! positive weights). Everything is in the stage space (Z-up, meters) of
//! the document.
//!
//! Loading cross-checks these prims against the document, like the meshes
//! ([`crate::check`]): a prim missing, of another type, or with an
//! attribute that differs (points beyond [`crate::check::POINT_ULPS`],
//! anything else exactly) is a [`crate::Mismatch::Parametric`]. The log stays
//! the truth; the prims are never read back into the document.
// Reads outside data: no indexing that can panic (issue 22).
#![deny(clippy::indexing_slicing)]

use std::collections::BTreeMap;

use openusd::gf;
use openusd::sdf::{self, AbstractData, Value};
use shapewright::doc::{Document, ObjectId, ObjectKind};
use shapewright::math::DVec3;
use shapewright::mesh::TriMesh;
use shapewright::nurbs::{euclidean, NurbsCurve, NurbsSurface};

use crate::check::{max_point_deviation, Mismatch};
use crate::load::attr_value;
use crate::prims::{AttrOut, PrimOut};

/// One parametric part of an object.
#[derive(Clone, Debug, PartialEq)]
pub enum Part {
    /// A `NurbsCurves` prim.
    Curves {
        /// Prim name.
        name: String,
        /// The curves.
        curves: Vec<NurbsCurve>,
        /// `shapewright:curveIndices` (network curve indices), if any.
        indices: Option<Vec<i32>>,
    },
    /// A `NurbsPatch` prim.
    Patch {
        /// Prim name.
        name: String,
        /// The surface.
        surface: NurbsSurface,
    },
    /// A `Mesh` prim: a patch that is not one NURBS surface (more than 4
    /// sides), stored as its evaluated triangles next to its boundary.
    Mesh {
        /// Prim name.
        name: String,
        /// The triangles.
        mesh: TriMesh,
    },
}

/// The parametric parts of an object, and the ones that could not be made.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Parts {
    /// The parts to write.
    pub parts: Vec<Part>,
    /// What could not be written, one line each (`part 2: ...`).
    pub problems: Vec<String>,
}

/// The parametric parts of `kind` (none for solids, SDF volumes and
/// sculpt meshes, whose data are the log's and the snapshot's only).
///
/// Never fails as a whole: a part that cannot be made is left out and
/// named in [`Parts::problems`], so the object's other parts (and its
/// mesh, and the other objects) are still written. A patch of more than 4
/// sides, or one whose exact bicubic form cannot be made, is written as
/// its mesh (`Patch<k>`, a `Mesh`) plus its boundary curves
/// (`Patch<k>_Boundary`), which does not depend on how the styling module
/// builds its inside.
pub fn parts(kind: &ObjectKind) -> Parts {
    let mut out = Parts::default();
    match kind {
        ObjectKind::Solid(_) | ObjectKind::SdfVolume(_) | ObjectKind::SculptMesh(_) => {}
        ObjectKind::GcAssembly(a) => {
            for (i, part) in a.parts.iter().enumerate() {
                let gc = &part.gc;
                let made = gc.placed_sections().and_then(|(sections, _)| {
                    Ok([
                        Part::Curves {
                            name: format!("Part{i}_Spine"),
                            curves: vec![gc.spine.curve.clone()],
                            indices: None,
                        },
                        Part::Curves {
                            name: format!("Part{i}_Sections"),
                            curves: sections,
                            indices: None,
                        },
                        Part::Patch {
                            name: format!("Part{i}_Surface"),
                            surface: gc.surface()?,
                        },
                    ])
                });
                match made {
                    Ok(p) => out.parts.extend(p),
                    Err(e) => out.problems.push(format!("part {i}: {e}")),
                }
            }
        }
        ObjectKind::CurveNetwork(net) => {
            let mut curves = Vec::new();
            let mut indices = Vec::new();
            for (i, c) in net.curves.iter().enumerate() {
                let Some(c) = c else { continue };
                match (c.to_nurbs(), i32::try_from(i)) {
                    (Ok(n), Ok(ix)) => {
                        curves.push(n);
                        indices.push(ix);
                    }
                    (Err(e), _) => out.problems.push(format!("curve {i}: {e}")),
                    (_, Err(_)) => out.problems.push(format!("curve index {i} exceeds int")),
                }
            }
            if !curves.is_empty() {
                out.parts.push(Part::Curves {
                    name: "Curves".to_owned(),
                    curves,
                    indices: Some(indices),
                });
            }
            for k in 0..net.patches.len() {
                if let Ok(surface) = crate::coons::patch_surface(net, k) {
                    out.parts.push(Part::Patch {
                        name: format!("Patch{k}"),
                        surface,
                    });
                    continue;
                }
                out.parts.push(Part::Mesh {
                    name: format!("Patch{k}"),
                    mesh: net.patch_mesh(k),
                });
                match crate::coons::patch_boundary(net, k) {
                    Ok(curves) => out.parts.push(Part::Curves {
                        name: format!("Patch{k}_Boundary"),
                        curves,
                        indices: None,
                    }),
                    Err(e) => out.problems.push(format!("patch {k} boundary: {e}")),
                }
            }
        }
    }
    out
}

impl Part {
    /// The prim name.
    pub fn name(&self) -> &str {
        match self {
            Self::Curves { name, .. } | Self::Patch { name, .. } | Self::Mesh { name, .. } => name,
        }
    }

    /// The prim authoring this part.
    pub fn prim(&self) -> PrimOut {
        match self {
            Self::Curves {
                name,
                curves,
                indices,
            } => curves_prim(name, curves, indices.as_deref()),
            Self::Patch { name, surface } => patch_prim(name, surface),
            Self::Mesh { name, mesh } => crate::kinds::mesh_prim(name, mesh),
        }
    }
}

fn f32_point(p: DVec3) -> gf::Vec3f {
    gf::vec3f(p.x as f32, p.y as f32, p.z as f32)
}

/// `extent` of `points` (zeros when empty).
pub fn extent(points: &[gf::Vec3f]) -> Value {
    let mut lo = [f32::INFINITY; 3];
    let mut hi = [f32::NEG_INFINITY; 3];
    for p in points {
        for ((l, h), v) in lo.iter_mut().zip(hi.iter_mut()).zip([p.x, p.y, p.z]) {
            *l = l.min(v);
            *h = h.max(v);
        }
    }
    if points.is_empty() {
        lo = [0.0; 3];
        hi = [0.0; 3];
    }
    Value::Vec3fVec(vec![lo.into(), hi.into()])
}

/// Appends `points` (and `pointWeights` when any weight is not 1) and
/// `extent` for homogeneous control points.
fn push_points<'a>(attrs: &mut Vec<AttrOut>, control: impl Iterator<Item = &'a glam::DVec4>) {
    let (points, weights): (Vec<gf::Vec3f>, Vec<f64>) =
        control.map(|h| (f32_point(euclidean(*h)), h.w)).unzip();
    attrs.push(AttrOut::schema("extent", "float3[]", extent(&points)));
    if weights.iter().any(|&w| w != 1.0) {
        attrs.push(AttrOut::schema(
            "pointWeights",
            "double[]",
            Value::DoubleVec(weights),
        ));
    }
    attrs.push(AttrOut::schema(
        "points",
        "point3f[]",
        Value::Vec3fVec(points),
    ));
}

fn int(n: usize) -> Value {
    Value::Int(i32::try_from(n).unwrap_or(i32::MAX))
}

/// A `NurbsCurves` prim holding `curves`.
pub fn curves_prim(name: &str, curves: &[NurbsCurve], indices: Option<&[i32]>) -> PrimOut {
    let mut p = PrimOut::new(name, "NurbsCurves");
    let count = |n: usize| i32::try_from(n).unwrap_or(i32::MAX);
    p.attrs.push(AttrOut::schema(
        "curveVertexCounts",
        "int[]",
        Value::IntVec(curves.iter().map(|c| count(c.control.len())).collect()),
    ));
    p.attrs.push(AttrOut::schema(
        "knots",
        "double[]",
        Value::DoubleVec(curves.iter().flat_map(|c| c.knots.clone()).collect()),
    ));
    p.attrs.push(AttrOut::schema(
        "order",
        "int[]",
        Value::IntVec(curves.iter().map(|c| count(c.degree + 1)).collect()),
    ));
    p.attrs.push(AttrOut::schema(
        "ranges",
        "double2[]",
        Value::Vec2dVec(
            curves
                .iter()
                .map(|c| {
                    let (a, b) = c.domain();
                    gf::vec2d(a, b)
                })
                .collect(),
        ),
    ));
    push_points(&mut p.attrs, curves.iter().flat_map(|c| c.control.iter()));
    if let Some(ix) = indices {
        p.attrs.push(AttrOut::custom(
            "shapewright:curveIndices",
            "int[]",
            Value::IntVec(ix.to_vec()),
        ));
    }
    p
}

/// A `NurbsPatch` prim holding `s` (`u` varying fastest in `points`).
pub fn patch_prim(name: &str, s: &NurbsSurface) -> PrimOut {
    let mut p = PrimOut::new(name, "NurbsPatch");
    let ((u0, u1), (v0, v1)) = s.domain();
    let dirs = [
        ("u", &s.knots_u, s.degree_u, (u0, u1), s.n_u),
        ("v", &s.knots_v, s.degree_v, (v0, v1), s.n_v),
    ];
    for (d, knots, degree, (a, b), count) in dirs {
        let open = Value::Token("open".into());
        p.attrs.extend([
            AttrOut::schema_uniform(&format!("{d}Form"), "token", open),
            AttrOut::schema(
                &format!("{d}Knots"),
                "double[]",
                Value::DoubleVec(knots.clone()),
            ),
            AttrOut::schema(&format!("{d}Order"), "int", int(degree + 1)),
            AttrOut::schema(
                &format!("{d}Range"),
                "double2",
                Value::Vec2d(gf::vec2d(a, b)),
            ),
            AttrOut::schema(&format!("{d}VertexCount"), "int", int(count)),
        ]);
    }
    let order = (0..s.n_v).flat_map(|j| (0..s.n_u).map(move |i| i * s.n_v + j));
    push_points(&mut p.attrs, order.filter_map(|k| s.control.get(k)));
    p
}

/// Compares the parametric prims stored under each object's prim (`prims`,
/// found by [`crate::layout::object_prims`]) with the ones the document
/// gives.
pub fn mismatches(
    data: &dyn AbstractData,
    doc: &Document,
    prims: &BTreeMap<ObjectId, sdf::Path>,
) -> Vec<Mismatch> {
    let mut out = Vec::new();
    for (id, obj) in doc.objects() {
        let Some(obj_path) = prims.get(&id) else {
            continue; // already a MissingMesh
        };
        let mut report = |prim: &str, detail: String| {
            out.push(Mismatch::Parametric {
                id,
                prim: prim.to_owned(),
                detail,
            })
        };
        // The same document gives the same parts (and leaves out the same
        // ones) as when it was saved.
        for part in parts(&obj.kind).parts {
            let want = part.prim();
            let Ok(path) = obj_path.append_path(want.name.as_str()) else {
                continue;
            };
            if !data.has_spec(&path) {
                report(&want.name, "missing".to_owned());
                continue;
            }
            let type_name = data.try_field(&path, "typeName").ok().flatten();
            if !matches!(type_name.as_deref(), Some(Value::Token(t)) if t.as_str() == want.type_name)
            {
                report(&want.name, format!("is not a {}", want.type_name));
                continue;
            }
            for a in &want.attrs {
                let got = attr_value(data, &path, &a.name);
                let same = match (&a.value, got.as_deref()) {
                    (Value::Vec3fVec(w), Some(Value::Vec3fVec(g))) if a.name == "points" => {
                        w.len() == g.len() && {
                            let (dev, tol) = max_point_deviation(w, g);
                            dev <= tol
                        }
                    }
                    (w, Some(g)) => w == g,
                    (_, None) => false,
                };
                if !same {
                    report(&want.name, format!("attribute `{}` differs", a.name));
                }
            }
        }
    }
    out
}
