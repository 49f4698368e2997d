//! Helper for the pytest suite (tests/usd): writes and reads USD with this
//! crate and prints what it saw as JSON, so Python can compare it with
//! Pixar's `pxr` and Blender's `bpy`.
//!
//! ```text
//! usd_tool save SCRIPT.jsonl OUT.usda     run a script, save document + log
//! usd_tool dump FILE.usda                 our loader's view: ops, cursor, meshes
//! usd_tool import FILE [MPU]              import every mesh (Z-up, MPU meters/unit)
//! ```

use std::path::Path;
use std::process::ExitCode;

use serde_json::{json, Value};
use shapewright::doc::{parse_script, run_script, OpLog};
use shapewright_usd::import::combined;
use shapewright_usd::{import_file, load_file, save_file, ImportOptions, LoadOptions, SaveOptions};

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
        _ => Err("usage: usd_tool save SCRIPT OUT.usda | dump FILE | import FILE [MPU]".to_owned()),
    }
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
