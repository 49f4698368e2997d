//! Importing `UsdGeom.Mesh` prims authored elsewhere (Blender, Pixar tools,
//! any DCC) as [`TriMesh`]es: library components, brushes or sculpt bases.
//!
//! The file (usda, usdc or usdz) is opened as a composed `openusd` stage, so
//! references, payloads and instances resolve. For every active mesh:
//! - polygons are triangulated: quads along 0-2 as Pixar and Blender do
//!   (a warped quad's volume depends on the diagonal), convex polygons as
//!   fans, concave ones by ear clipping in the polygon's plane so they do
//!   not fold over; `holeIndices` faces are skipped;
//!   `orientation = "leftHanded"` flips the winding;
//! - the world transform of its xformOp stack and its ancestors' is applied
//!   ([`crate::xform`]);
//! - units are converted from the stage's `metersPerUnit` to
//!   [`ImportOptions::meters_per_unit`], and a Y-up stage is turned Z-up
//!   (+90° about X, as Blender's importer does).
//!
//! Bad data (indices out of range, counts that do not add up, non-finite
//! points, unknown xformOps) is an [`ImportError`] naming the prim. The
//! module takes outside data: no indexing that can panic (checked by
//! `clippy::indexing_slicing`, with one documented exception).
#![deny(clippy::indexing_slicing)]

use std::path::Path;

use openusd::sdf::{self, AbstractData, Value};
use openusd::usd::Stage;
use shapewright::math::{DMat4, DVec2, DVec3};
use shapewright::mesh::TriMesh;

use crate::xform::{local_transform, Attrs, FlatLayer};
use crate::ImportError;

/// How to import.
#[derive(Clone, Debug, PartialEq)]
pub struct ImportOptions {
    /// The units the meshes are wanted in (1: meters, Shapewright's unit).
    pub meters_per_unit: f64,
    /// Only meshes whose path starts with this prefix (e.g. `/root/Cube`).
    pub prefix: Option<String>,
}

impl Default for ImportOptions {
    fn default() -> Self {
        Self {
            meters_per_unit: 1.0,
            prefix: None,
        }
    }
}

/// One imported mesh.
#[derive(Clone, Debug, PartialEq)]
pub struct ImportedMesh {
    /// The mesh prim's path.
    pub path: String,
    /// Its triangles in world space, Z-up, in the requested units, with
    /// per-vertex normals computed.
    pub mesh: TriMesh,
    /// Polygons in the source (before triangulation, without holes).
    pub polygons: usize,
}

/// Stage-level conversion: source units and up axis.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StageUnits {
    /// `metersPerUnit` (0.01 when not authored, as USD specifies).
    pub meters_per_unit: f64,
    /// True for `upAxis = "Y"` (the USD fallback when not authored).
    pub y_up: bool,
}

/// Imports every mesh of the USD file at `path`.
///
/// Runs on a thread with a large stack ([`crate::limits`]); usda text is
/// checked for its nesting first, and the prim walk refuses prims deeper
/// than [`crate::limits::MAX_PRIM_DEPTH`].
pub fn import_file(path: &Path, options: &ImportOptions) -> Result<Vec<ImportedMesh>, ImportError> {
    crate::limits::with_parser_stack(|| import_file_here(path, options))
}

fn import_file_here(
    path: &Path,
    options: &ImportOptions,
) -> Result<Vec<ImportedMesh>, ImportError> {
    let name = path.display().to_string();
    let open_err = |message: String| ImportError::Open {
        path: name.clone(),
        message,
    };
    if !path.is_file() {
        return Err(open_err("no such file".to_owned()));
    }
    if !(options.meters_per_unit.is_finite() && options.meters_per_unit > 0.0) {
        return Err(ImportError::BadStageMetadata {
            key: "metersPerUnit (requested)",
            value: options.meters_per_unit.to_string(),
        });
    }
    // usda text: refuse deep nesting before the recursive parser sees it.
    let bytes = std::fs::read(path).map_err(|e| open_err(e.to_string()))?;
    if !(bytes.starts_with(b"PXR-USDC") || bytes.starts_with(b"PK\x03\x04")) {
        if let Ok(text) = std::str::from_utf8(&bytes) {
            crate::limits::check_usda_nesting(text)?;
        }
    }
    // A layer without composition arcs is its own stage: read it directly
    // (linear in the file). Only files with arcs are composed by openusd.
    if let Ok(layer) = crate::read_layer(&bytes) {
        if let Some(meshes) = import_flat(layer.as_ref(), options, &name)? {
            return Ok(meshes);
        }
    }
    drop(bytes);
    let stage = Stage::open(&name).map_err(|e| open_err(format!("{e:#}")))?;
    let root_fix = root_fix(&stage_units(&stage)?, options);
    read_meshes(&stage, walk(&stage)?, root_fix, options, &name)
}

/// From the file's units and up axis to the caller's units, Z up.
fn root_fix(units: &StageUnits, options: &ImportOptions) -> DMat4 {
    let scale = DMat4::from_scale(DVec3::splat(
        units.meters_per_unit / options.meters_per_unit,
    ));
    if units.y_up {
        scale * DMat4::from_rotation_x(std::f64::consts::FRAC_PI_2)
    } else {
        scale
    }
}

/// The meshes `found` (in traversal order) under the options' prefix,
/// read from `src` and carried by their world transform and `root_fix`;
/// [`ImportError::NoMesh`] when there are none.
fn read_meshes(
    src: &impl Attrs,
    found: Vec<MeshVisit>,
    root_fix: DMat4,
    options: &ImportOptions,
    name: &str,
) -> Result<Vec<ImportedMesh>, ImportError> {
    let mut out = Vec::new();
    for visit in found {
        let p = visit.path;
        if let Some(prefix) = &options.prefix {
            if !p.as_str().starts_with(prefix.as_str()) {
                continue;
            }
        }
        let (mut mesh, polygons) = read_mesh(src, &p)?;
        let world = root_fix * visit.world?;
        mesh.transform(&shapewright::math::DAffine3::from_mat4(world));
        mesh.compute_normals();
        out.push(ImportedMesh {
            path: p.as_str().to_owned(),
            mesh,
            polygons,
        });
    }
    if out.is_empty() {
        return Err(ImportError::NoMesh(name.to_owned()));
    }
    Ok(out)
}

/// Fields that make a layer more than itself (composition arcs).
const ARC_FIELDS: [&str; 7] = [
    "references",
    "payload",
    "inheritPaths",
    "specializes",
    "variantSetNames",
    "variantSelection",
    "relocates",
];

/// The meshes of a layer read without composition, or `None` when the
/// layer has a composition arc anywhere (then the stage must compose it).
///
/// Same region and rules as [`walk`] (defined, active, not abstract;
/// transforms carried down), reading each prim's own fields: a fixed
/// amount of work per prim, so deep nesting costs what its bytes cost.
fn import_flat(
    data: &dyn AbstractData,
    options: &ImportOptions,
    name: &str,
) -> Result<Option<Vec<ImportedMesh>>, ImportError> {
    let root = sdf::Path::abs_root();
    let field = |p: &sdf::Path, key: &str| data.try_field(p, key).ok().flatten();
    if field(&root, "subLayers").is_some() {
        return Ok(None);
    }
    let meta = |key: &'static str| Ok(field(&root, key).map(std::borrow::Cow::into_owned));
    let root_fix = root_fix(&units_from(meta)?, options);
    let layer = FlatLayer(data);
    let names = |p: &sdf::Path| -> Vec<String> {
        match field(p, "primChildren").as_deref() {
            Some(Value::TokenVec(v)) => v.iter().map(|t| t.as_str().to_owned()).collect(),
            Some(Value::StringVec(v)) => v.clone(),
            _ => Vec::new(),
        }
    };
    let mut stack: Vec<(sdf::Path, Result<DMat4, ImportError>, usize)> = Vec::new();
    let push =
        |stack: &mut Vec<_>, parent: &sdf::Path, world: &Result<DMat4, ImportError>, depth| {
            for n in names(parent).iter().rev() {
                if let Ok(child) = parent.append_path(n.as_str()) {
                    stack.push((child, world.clone(), depth + 1));
                }
            }
        };
    push(&mut stack, &root, &Ok(DMat4::IDENTITY), 0);
    let mut found = Vec::new();
    while let Some((path, parent_world, depth)) = stack.pop() {
        crate::limits::check_prim_depth(
            "prim hierarchy",
            path.as_str(),
            depth,
            crate::limits::MAX_PRIM_DEPTH,
        )?;
        if ARC_FIELDS.iter().any(|k| field(&path, k).is_some()) {
            return Ok(None);
        }
        let defined = matches!(
            field(&path, "specifier").as_deref(),
            Some(Value::Specifier(sdf::Specifier::Def))
        );
        let active = !matches!(field(&path, "active").as_deref(), Some(Value::Bool(false)));
        if !(defined && active) {
            continue;
        }
        let world = parent_world.and_then(|parent| {
            let (local, reset) = local_transform(&layer, &path)?;
            Ok(if reset { local } else { parent * local })
        });
        push(&mut stack, &path, &world, depth);
        let is_mesh = matches!(
            field(&path, "typeName").as_deref(),
            Some(Value::Token(t)) if t.as_str() == "Mesh"
        );
        if is_mesh {
            found.push(MeshVisit { path, world });
        }
    }
    read_meshes(&layer, found, root_fix, options, name).map(Some)
}

/// A mesh prim found by [`walk`], with its local-to-world transform (an
/// error when its own or an ancestor's xformOp stack is unreadable).
struct MeshVisit {
    path: sdf::Path,
    world: Result<DMat4, ImportError>,
}

/// The `Mesh` prims of the stage in traversal order (depth first, children
/// in order), in USD's default traversal region with instance proxies:
/// defined (`def`), active, not abstract (`class`) prims and everything
/// below instances.
///
/// Own walk rather than `Stage::traverse`, which re-walks every prim's
/// ancestor chain for its status (and `world_transform` per mesh walked it
/// again): cubic in the nesting depth (1,000 nested prims took 10.5 s).
/// Here each prim's status and world transform come from its parent's, so
/// the walk does a fixed amount of work per prim.
fn walk(stage: &Stage) -> Result<Vec<MeshVisit>, ImportError> {
    let read_err = |p: &sdf::Path, message: String| ImportError::Read {
        path: p.as_str().to_owned(),
        message,
    };
    let root = sdf::Path::abs_root();
    let children = |p: &sdf::Path| {
        stage
            .prim(p.clone())
            .child_names()
            .map_err(|e| read_err(p, format!("{e:#}")))
    };
    let mut stack: Vec<(sdf::Path, Result<DMat4, ImportError>, usize)> = Vec::new();
    let push_children = |stack: &mut Vec<_>,
                         parent: &sdf::Path,
                         world: &Result<DMat4, ImportError>,
                         depth: usize|
     -> Result<(), ImportError> {
        for name in children(parent)?.iter().rev() {
            let child = parent
                .append_path(name.as_str())
                .map_err(|e| read_err(parent, format!("child `{}`: {e}", name.as_str())))?;
            stack.push((child, world.clone(), depth + 1));
        }
        Ok(())
    };
    push_children(&mut stack, &root, &Ok(DMat4::IDENTITY), 0)?;
    let mut out = Vec::new();
    while let Some((path, parent_world, depth)) = stack.pop() {
        crate::limits::check_prim_depth(
            "prim hierarchy of a file with composition arcs",
            path.as_str(),
            depth,
            crate::limits::MAX_COMPOSED_DEPTH,
        )?;
        let prim = stage.prim(path.clone());
        // `over` and unspecified prims are not defined, `class` prims are
        // abstract: neither they nor anything below them is in the region.
        let specifier = prim
            .specifier()
            .map_err(|e| read_err(&path, format!("specifier: {e:#}")))?;
        if specifier != Some(sdf::Specifier::Def) || !locally_active(stage, &prim)? {
            continue;
        }
        let world = parent_world.and_then(|parent| {
            let (local, reset) = local_transform(stage, &path)?;
            Ok(if reset { local } else { parent * local })
        });
        let type_name = prim
            .type_name()
            .map_err(|e| read_err(&path, format!("{e:#}")))?;
        push_children(&mut stack, &path, &world, depth)?;
        if type_name.as_ref().map(|t| t.as_str()) == Some("Mesh") {
            out.push(MeshVisit { path, world });
        }
    }
    Ok(out)
}

/// The prim's own `active` opinion (the strongest one in its prim stack;
/// unauthored is active). Its ancestors are known active by the walk.
fn locally_active(stage: &Stage, prim: &openusd::usd::Prim) -> Result<bool, ImportError> {
    let sites = prim.prim_stack().map_err(|e| ImportError::Read {
        path: prim.path().as_str().to_owned(),
        message: format!("prim stack: {e:#}"),
    })?;
    for (layer, spec) in sites {
        let Some(layer) = stage.layer(&layer) else {
            continue;
        };
        if let Ok(Some(v)) = layer.data().try_field(&spec, "active") {
            if let Value::Bool(b) = v.as_ref() {
                return Ok(*b);
            }
        }
    }
    Ok(true)
}

/// All imported meshes appended into one.
pub fn combined(meshes: &[ImportedMesh]) -> TriMesh {
    let mut out = TriMesh::default();
    for m in meshes {
        out.append(&m.mesh);
    }
    out
}

/// Reads `upAxis` and `metersPerUnit`, with USD's fallbacks (Y, 0.01).
pub fn stage_units(stage: &Stage) -> Result<StageUnits, ImportError> {
    units_from(|key| {
        stage.stage_metadata(key).map_err(|e| ImportError::Read {
            path: "/".to_owned(),
            message: format!("{key}: {e:#}"),
        })
    })
}

/// [`stage_units`] from a metadata getter.
fn units_from(
    meta: impl Fn(&'static str) -> Result<Option<Value>, ImportError>,
) -> Result<StageUnits, ImportError> {
    let y_up = match meta("upAxis")? {
        None => true,
        Some(Value::Token(t)) if t.as_str() == "Y" => true,
        Some(Value::Token(t)) if t.as_str() == "Z" => false,
        Some(Value::String(t)) if t == "Y" => true,
        Some(Value::String(t)) if t == "Z" => false,
        Some(other) => {
            return Err(ImportError::BadStageMetadata {
                key: "upAxis",
                value: format!("{other:?}"),
            })
        }
    };
    let mpu = match meta("metersPerUnit")? {
        None => 0.01,
        Some(Value::Double(d)) => d,
        Some(Value::Float(f)) => f.into(),
        Some(Value::Int(i)) => i.into(),
        Some(Value::Int64(i)) => i as f64,
        Some(other) => {
            return Err(ImportError::BadStageMetadata {
                key: "metersPerUnit",
                value: format!("{other:?}"),
            })
        }
    };
    if !(mpu.is_finite() && mpu > 0.0) {
        return Err(ImportError::BadStageMetadata {
            key: "metersPerUnit",
            value: mpu.to_string(),
        });
    }
    Ok(StageUnits {
        meters_per_unit: mpu,
        y_up,
    })
}

fn ints(v: Option<Value>) -> Option<Vec<i64>> {
    Some(match v? {
        Value::IntVec(v) => v.into_iter().map(i64::from).collect(),
        Value::Int64Vec(v) => v,
        Value::UintVec(v) => v.into_iter().map(i64::from).collect(),
        _ => return None,
    })
}

/// Reads one mesh prim as triangles in its local space.
fn read_mesh(stage: &impl Attrs, p: &sdf::Path) -> Result<(TriMesh, usize), ImportError> {
    let bad = |message: String| ImportError::BadMesh {
        path: p.as_str().to_owned(),
        message,
    };
    let get = |name: &str| {
        stage.attr(p, name).map_err(|message| ImportError::Read {
            path: p.as_str().to_owned(),
            message,
        })
    };
    let points: Vec<[f64; 3]> = match get("points")? {
        Some(Value::Vec3fVec(v)) => v.iter().map(|a| [a.x, a.y, a.z].map(f64::from)).collect(),
        Some(Value::Vec3dVec(v)) => v.iter().map(|a| [a.x, a.y, a.z]).collect(),
        Some(Value::Vec3hVec(v)) => v
            .iter()
            .map(|a| [a.x, a.y, a.z].map(|h| h.to_f64()))
            .collect(),
        None => Vec::new(),
        Some(other) => return Err(bad(format!("points are not 3-vectors: {}", short(&other)))),
    };
    if let Some(i) = points.iter().position(|q| !q.iter().all(|x| x.is_finite())) {
        return Err(bad(format!("point {i} is not finite")));
    }
    let counts = ints(get("faceVertexCounts")?).unwrap_or_default();
    let indices = ints(get("faceVertexIndices")?).unwrap_or_default();
    let holes: std::collections::BTreeSet<i64> = ints(get("holeIndices")?)
        .unwrap_or_default()
        .into_iter()
        .collect();
    let left_handed = matches!(
        get("orientation")?,
        Some(Value::Token(t)) if t.as_str() == "leftHanded"
    );
    if u32::try_from(points.len()).is_err() {
        return Err(bad(format!(
            "{} points exceed 32-bit indices",
            points.len()
        )));
    }
    let total = counts.iter().try_fold(0i64, |acc, &c| acc.checked_add(c));
    if counts.iter().any(|&c| c < 0) || total != Some(indices.len() as i64) {
        let total = total.map_or("more than 2^63".to_owned(), |t| t.to_string());
        return Err(bad(format!(
            "faceVertexCounts add up to {total} but there are {} faceVertexIndices",
            indices.len()
        )));
    }
    if let Some(i) = indices
        .iter()
        .position(|&i| i < 0 || i as usize >= points.len())
    {
        return Err(bad(format!(
            "faceVertexIndices[{i}] = {} is out of range for {} points",
            indices.get(i).copied().unwrap_or_default(),
            points.len()
        )));
    }
    let mut triangles = Vec::new();
    let mut polygons = 0;
    let mut start = 0usize;
    for (face, &c) in counts.iter().enumerate() {
        let c = c as usize;
        let poly: Vec<u32> = indices
            .get(start..start + c)
            .ok_or_else(|| bad(format!("face {face} runs past faceVertexIndices")))?
            .iter()
            .map(|&i| i as u32)
            .collect();
        start += c;
        if holes.contains(&(face as i64)) {
            continue;
        }
        if c < 3 {
            return Err(bad(format!("face {face} has {c} vertices (fewer than 3)")));
        }
        polygons += 1;
        let before = triangles.len();
        triangulate_checked(&points, &poly, &mut triangles)
            .map_err(|e| bad(format!("face {face} {e}")))?;
        if left_handed {
            for t in triangles.iter_mut().skip(before) {
                t.swap(1, 2);
            }
        }
    }
    let mut mesh = TriMesh::new(points, triangles);
    mesh.compute_normals();
    Ok((mesh, polygons))
}

fn short(v: &Value) -> String {
    let s = format!("{v:?}");
    s.chars().take(60).collect()
}

/// The most vertices of a concave polygon that ear clipping (cubic in the
/// vertex count at worst) triangulates; a larger concave polygon is an
/// error from `read_mesh` (and fanned by `triangulate`), so a hostile
/// file cannot make the importer run for hours.
pub const MAX_EAR_CLIP: usize = 1024;

/// Appends the triangles of polygon `poly` (n-2 of them, winding kept).
/// An index outside `points` counts as a point at NaN (the polygon is then
/// fanned); the caller checks indices first. A concave polygon of more
/// than [`MAX_EAR_CLIP`] vertices is fanned.
pub fn triangulate(points: &[[f64; 3]], poly: &[u32], out: &mut Vec<[u32; 3]>) {
    if triangulate_checked(points, poly, out).is_err() {
        fan(poly, out);
    }
}

// Indices into `poly`, `flat` and `rest` are taken modulo their lengths or
// come from `rest`, whose entries are below `n`: in range by construction.
#[allow(clippy::indexing_slicing)]
fn triangulate_checked(
    points: &[[f64; 3]],
    poly: &[u32],
    out: &mut Vec<[u32; 3]>,
) -> Result<(), String> {
    let n = poly.len();
    if n < 3 {
        return Ok(());
    }
    let pos = |i: u32| DVec3::from_array(points.get(i as usize).copied().unwrap_or([f64::NAN; 3]));
    if n == 3 {
        out.push([poly[0], poly[1], poly[2]]);
        return Ok(());
    }
    // Newell normal: robust plane normal of a (possibly non-planar) polygon.
    let mut normal = DVec3::ZERO;
    for k in 0..n {
        let a = pos(poly[k]);
        let b = pos(poly[(k + 1) % n]);
        normal += DVec3::new(
            (a.y - b.y) * (a.z + b.z),
            (a.z - b.z) * (a.x + b.x),
            (a.x - b.x) * (a.y + b.y),
        );
    }
    let Some(normal) = normal.try_normalize() else {
        fan(poly, out);
        return Ok(());
    };
    let u = normal.any_orthonormal_vector();
    let v = normal.cross(u);
    let flat: Vec<DVec2> = poly
        .iter()
        .map(|&i| {
            let p = pos(i);
            DVec2::new(p.dot(u), p.dot(v))
        })
        .collect();
    let cross = |a: DVec2, b: DVec2, c: DVec2| (b - a).perp_dot(c - a);
    // Turns this far below zero (relative to the polygon's size) are
    // reflex; smaller ones are noise of a flat or slightly warped polygon.
    let size = flat
        .iter()
        .map(|p| (*p - flat[0]).length_squared())
        .fold(0.0, f64::max);
    let eps = 1e-12 * size;
    let reflex = |k: usize| cross(flat[(k + n - 1) % n], flat[k], flat[(k + 1) % n]) < -eps;
    if n == 4 {
        // Always along 0-2, as Pixar's (HdMeshUtil) and Blender's fixed
        // triangulation split quads: a warped quad's volume depends on the
        // diagonal, and imports must measure what the source tools measure.
        // (A concave quad folds along 0-2, but its signed area and volume
        // stay right.)
        fan(poly, out);
        return Ok(());
    }
    if !(0..n).any(reflex) {
        fan(poly, out);
        return Ok(());
    }
    if n > MAX_EAR_CLIP {
        return Err(format!(
            "has {n} vertices and is concave; the importer ear-clips concave polygons of up to {MAX_EAR_CLIP} (triangulate it in the tool that wrote the file)"
        ));
    }
    // Ear clipping (counter-clockwise in the (u, v) frame by construction).
    let mut rest: Vec<usize> = (0..n).collect();
    let mut guard = 0;
    while rest.len() > 3 && guard < n * n {
        guard += 1;
        let m = rest.len();
        let mut clipped = false;
        for k in 0..m {
            let (a, b, c) = (rest[(k + m - 1) % m], rest[k], rest[(k + 1) % m]);
            if cross(flat[a], flat[b], flat[c]) <= 0.0 {
                continue;
            }
            let inside = rest.iter().any(|&q| {
                q != a && q != b && q != c && {
                    let p = flat[q];
                    cross(flat[a], flat[b], p) >= 0.0
                        && cross(flat[b], flat[c], p) >= 0.0
                        && cross(flat[c], flat[a], p) >= 0.0
                }
            });
            if inside {
                continue;
            }
            out.push([poly[a], poly[b], poly[c]]);
            rest.remove(k);
            clipped = true;
            break;
        }
        if !clipped {
            break;
        }
    }
    // Whatever is left (3 vertices, or a degenerate remainder) as a fan.
    let left: Vec<u32> = rest.iter().map(|&k| poly[k]).collect();
    fan(&left, out);
    Ok(())
}

fn fan(poly: &[u32], out: &mut Vec<[u32; 3]>) {
    if let Some((&first, rest)) = poly.split_first() {
        for pair in rest.windows(2) {
            if let [b, c] = pair {
                out.push([first, *b, *c]);
            }
        }
    }
}
