//! What each object kind contributes to the stage.
//!
//! Every object becomes an `Xform` prim `Object_<id>` (custom attributes
//! `shapewright:objectId`, `shapewright:kind`) holding a `Mesh` child named
//! `Mesh` with its evaluated triangles, so any USD tool sees the model.
//! Kinds with parametric parts add more children next to the mesh through
//! [`crate::parametric::parts`]: generalized cylinders their spine and sections as
//! `NurbsCurves` and their surface as a `NurbsPatch`, curve networks their
//! curves and patches ([`crate::parametric`]). The match there is exhaustive on purpose: a new
//! `ObjectKind` variant does not compile until it decides what it adds.

use openusd::gf;
use openusd::sdf::Value;
use shapewright::doc::{Object, ObjectId};
use shapewright::mesh::TriMesh;

use crate::prims::{AttrOut, PrimOut};

/// Name of the object prim for `id`.
pub fn object_prim_name(id: ObjectId) -> String {
    format!("Object_{}", id.0)
}

/// Name of the mesh child of every object prim.
pub const MESH_PRIM: &str = "Mesh";

/// The prim of object `id`: an Xform with the mesh and the kind's extras,
/// and what of the extras could not be made (the prim is written without
/// them and lists them in `shapewright:unwritten`).
pub fn object_prim(id: ObjectId, obj: &Object) -> (PrimOut, Vec<String>) {
    let mut p = PrimOut::new(object_prim_name(id), "Xform");
    p.attrs.push(AttrOut::custom(
        "shapewright:objectId",
        "int",
        Value::Int(i32::try_from(id.0).unwrap_or(i32::MAX)),
    ));
    p.attrs.push(AttrOut::custom(
        "shapewright:kind",
        "token",
        Value::Token(obj.kind.name().into()),
    ));
    p.children.push(mesh_prim(MESH_PRIM, &obj.mesh));
    let extras = crate::parametric::parts(&obj.kind);
    p.children
        .extend(extras.parts.iter().map(crate::parametric::Part::prim));
    if !extras.problems.is_empty() {
        p.attrs.push(AttrOut::custom(
            "shapewright:unwritten",
            "string[]",
            Value::StringVec(extras.problems.iter().map(|s| plain_text(s)).collect()),
        ));
    }
    (p, extras.problems)
}

/// `text` with no character that usda readers disagree on or that needs a
/// triple-quoted string (backslashes, double quotes, line breaks).
pub fn plain_text(text: &str) -> String {
    text.chars()
        .map(|c| match c {
            '\\' => '/',
            '"' => '\'',
            c if c.is_control() => ' ',
            c => c,
        })
        .collect()
}

/// Positions as USD stores them (`point3f`): each coordinate rounded to
/// the nearest f32.
pub fn points_f32(mesh: &TriMesh) -> Vec<gf::Vec3f> {
    mesh.positions
        .iter()
        .map(|p| gf::vec3f(p[0] as f32, p[1] as f32, p[2] as f32))
        .collect()
}

/// A `UsdGeom.Mesh` prim for `mesh`: points, triangle counts and indices,
/// per-vertex normals (computed when the mesh has none), extent, and
/// `subdivisionScheme = "none"` so that viewers show the triangles as they
/// are instead of subdividing them.
pub fn mesh_prim(name: &str, mesh: &TriMesh) -> PrimOut {
    let points = points_f32(mesh);
    let normals: Vec<gf::Vec3f> = mesh
        .normals_or_computed()
        .iter()
        .map(|n| gf::vec3f(n[0] as f32, n[1] as f32, n[2] as f32))
        .collect();
    let indices: Vec<i32> = mesh
        .triangles
        .iter()
        .flat_map(|t| t.map(|i| i as i32))
        .collect();
    let mut p = PrimOut::new(name, "Mesh");
    p.attrs = vec![
        AttrOut::schema("extent", "float3[]", crate::parametric::extent(&points)),
        AttrOut::schema(
            "faceVertexCounts",
            "int[]",
            Value::IntVec(vec![3; mesh.triangles.len()]),
        ),
        AttrOut::schema("faceVertexIndices", "int[]", Value::IntVec(indices)),
        AttrOut {
            interpolation: Some("vertex"),
            ..AttrOut::schema("normals", "normal3f[]", Value::Vec3fVec(normals))
        },
        AttrOut::schema("points", "point3f[]", Value::Vec3fVec(points)),
        AttrOut::schema_uniform("subdivisionScheme", "token", Value::Token("none".into())),
    ];
    p
}
