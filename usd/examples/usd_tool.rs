//! Helper for the pytest suite (tests/usd): writes and reads USD with this
//! crate and prints what it saw as JSON, so Python can compare it with
//! Pixar's `pxr` and Blender's `bpy`.
//!
//! ```text
//! usd_tool save SCRIPT.jsonl OUT.usda     run a script, save document + log
//! usd_tool dump FILE.usda                 our loader's view: ops, cursor, meshes
//! usd_tool import FILE [MPU]              import every mesh (Z-up, MPU meters/unit)
//! usd_tool import-into FILE DOC.usda component|base [PREFIX]
//!                                         import as an op into DOC (created when
//!                                         missing), save; the op's object mesh
//! usd_tool nurbs FILE.usda                our NURBS evaluated at a few parameters
//!                                         (per NurbsCurves/NurbsPatch prim)
//! ```

use std::path::Path;
use std::process::ExitCode;

use serde_json::{json, Value};
use shapewright::doc::{parse_script, run_script, ObjectKind, Op, OpLog};
use shapewright::math::Transform;
use shapewright::mesh::TriMesh;
use shapewright::nurbs::uniform_samples as params;
use shapewright_usd::import::combined;
use shapewright_usd::parametric::{parts, Part};
use shapewright_usd::{
    import_file, import_into, load_file, save_file, ImportOptions, ImportTarget, LoadOptions,
    SaveOptions,
};

fn run(args: &[String]) -> Result<Value, String> {
    match args {
        [cmd, script, out] if cmd == "save" => {
            let text = std::fs::read_to_string(script).map_err(|e| e.to_string())?;
            let lines = parse_script(&text).map_err(|e| e.to_string())?;
            let mut log = OpLog::new();
            run_script(&mut log, &lines).map_err(|e| e.to_string())?;
            save_file(Path::new(out), &log, &SaveOptions::default()).map_err(|e| e.to_string())?;
            Ok(json!({"ops": log.len(), "cursor": log.cursor(), "objects": log.document().len()}))
        }
        [cmd, file] if cmd == "dump" => {
            let loaded = load_file(
                Path::new(file),
                LoadOptions {
                    verify_history: true,
                    strict: false,
                },
            )
            .map_err(|e| e.to_string())?;
            let log = &loaded.log;
            let meshes: Vec<Value> = log
                .document()
                .objects()
                .map(|(id, o)| {
                    let points: Vec<[f64; 3]> = o
                        .mesh
                        .positions
                        .iter()
                        .map(|p| p.map(|x| f64::from(x as f32)))
                        .collect();
                    let indices: Vec<u32> = o.mesh.triangles.iter().flatten().copied().collect();
                    json!({"id": id.0, "prim": format!("/World/Object_{}/Mesh", id.0),
                           "points": points, "indices": indices,
                           "volume": o.mesh.signed_volume()})
                })
                .collect();
            let ops: Vec<Value> = log
                .ops()
                .iter()
                .map(|op| serde_json::to_value(op).unwrap_or(Value::Null))
                .collect();
            Ok(json!({"ops": ops, "cursor": log.cursor(), "meshes": meshes,
                      "consistent": loaded.report.is_consistent(),
                      "report": loaded.report.to_string()}))
        }
        [cmd, file, rest @ ..] if cmd == "import" && rest.len() <= 1 => {
            let mpu = match rest.first() {
                Some(s) => s.parse::<f64>().map_err(|e| e.to_string())?,
                None => 1.0,
            };
            let meshes = import_file(
                Path::new(file),
                &ImportOptions {
                    meters_per_unit: mpu,
                    prefix: None,
                },
            )
            .map_err(|e| e.to_string())?;
            let all = combined(&meshes);
            let list: Vec<Value> = meshes
                .iter()
                .map(|m| {
                    json!({"path": m.path, "triangles": m.mesh.triangle_count(),
                           "polygons": m.polygons, "volume": m.mesh.signed_volume(),
                           "points": m.mesh.positions})
                })
                .collect();
            Ok(
                json!({"triangles": all.triangle_count(), "volume": all.signed_volume(), "meshes": list}),
            )
        }
        [cmd, file, doc, what, prefix @ ..] if cmd == "import-into" && prefix.len() <= 1 => {
            import_into_doc(Path::new(file), Path::new(doc), what, prefix.first())
        }
        [cmd, file] if cmd == "nurbs" => nurbs_samples(Path::new(file)),
        _ => Err(
            "usage: usd_tool save SCRIPT OUT.usda | dump FILE | import FILE [MPU] | nurbs FILE"
                .to_owned(),
        ),
    }
}

/// `import-into`: the shapewright-xr `import` command's path, printing the
/// imported mesh as the document now stores it.
fn import_into_doc(
    file: &Path,
    doc: &Path,
    what: &str,
    prefix: Option<&String>,
) -> Result<Value, String> {
    let mut log = if doc.exists() {
        load_file(doc, LoadOptions::default())
            .map_err(|e| e.to_string())?
            .log
    } else {
        OpLog::new()
    };
    let name = "imported".to_owned();
    let target = match what {
        "component" => ImportTarget::Component {
            volume: None,
            name: name.clone(),
        },
        "base" => ImportTarget::SculptBase {
            transform: Transform::default(),
        },
        other => return Err(format!("import as `{other}`: use component or base")),
    };
    let options = ImportOptions {
        meters_per_unit: 1.0,
        prefix: prefix.cloned(),
    };
    let imported = import_into(&mut log, file, &options, target).map_err(|e| e.to_string())?;
    for note in &imported.flipped {
        eprintln!("note: {note}");
    }
    let outcome = imported.outcome;
    save_file(doc, &log, &SaveOptions::default()).map_err(|e| e.to_string())?;
    let last = log.ops().last().ok_or("no op")?;
    // The mesh as the document holds it: the volume's component, or the
    // sculpt object's evaluated surface.
    let component = log.document().objects().find_map(|(_, o)| match &o.kind {
        ObjectKind::SdfVolume(v) => v.user_components.get(&name),
        _ => None,
    });
    let mesh = match (last, component) {
        (Op::SdfImportComponent(_), Some(u)) => {
            TriMesh::new(u.positions.clone(), u.triangles.clone())
        }
        _ => {
            let id = outcome.created.ok_or("no object created")?;
            let obj = log.document().get(id).map_err(|e| e.to_string())?;
            (*obj.mesh).clone()
        }
    };
    Ok(
        json!({"op": last.name(), "ops": log.len(), "objects": log.document().len(),
              "triangles": mesh.triangle_count(), "volume": mesh.signed_volume()}),
    )
}

/// Every parametric part of the loaded document, evaluated by core's NURBS
/// code (f64) at 9 parameters per curve and a 7×7 grid per patch.
fn nurbs_samples(file: &Path) -> Result<Value, String> {
    let loaded = load_file(file, LoadOptions::default()).map_err(|e| e.to_string())?;
    let mut prims = Vec::new();
    for (id, obj) in loaded.log.document().objects() {
        for part in parts(&obj.kind).parts {
            let prim = format!("/World/Object_{}/{}", id.0, part.name());
            prims.push(match &part {
                Part::Curves { curves, .. } => {
                    let samples: Vec<Vec<[f64; 4]>> = curves
                        .iter()
                        .map(|c| {
                            let (a, b) = c.domain();
                            params(a, b, 8)
                                .into_iter()
                                .map(|t| {
                                    let p = c.point(t);
                                    [t, p.x, p.y, p.z]
                                })
                                .collect()
                        })
                        .collect();
                    json!({"prim": prim, "type": "NurbsCurves", "curves": samples})
                }
                Part::Patch { surface, .. } => {
                    let ((u0, u1), (v0, v1)) = surface.domain();
                    let mut samples = Vec::new();
                    for u in params(u0, u1, 6) {
                        for v in params(v0, v1, 6) {
                            let p = surface.point(u, v);
                            samples.push([u, v, p.x, p.y, p.z]);
                        }
                    }
                    json!({"prim": prim, "type": "NurbsPatch", "samples": samples})
                }
                // n-sided patches are stored as meshes, checked as meshes.
                Part::Mesh { .. } => continue,
            });
        }
    }
    Ok(
        json!({"prims": prims, "consistent": loaded.report.is_consistent(),
              "report": loaded.report.to_string()}),
    )
}

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    match run(&args) {
        Ok(v) => {
            println!("{v}");
            ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}
