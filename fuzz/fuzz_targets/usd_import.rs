//! Mesh import from a USD file (composed stage, own prim walk, xformOps,
//! polygons) on any bytes: meshes or a typed error.
#![no_main]

use libfuzzer_sys::fuzz_target;
use shapewright_usd::{import_file, ImportOptions};

fuzz_target!(|data: &[u8]| {
    // The importer opens a stage by path: one scratch file per process.
    let path = std::env::temp_dir().join(format!("sw-fuzz-import-{}.usd", std::process::id()));
    if std::fs::write(&path, data).is_ok() {
        if let Ok(meshes) = import_file(&path, &ImportOptions::default()) {
            for m in meshes {
                let n = m.mesh.positions.len();
                assert!(m.mesh.triangles.iter().flatten().all(|&i| (i as usize) < n));
            }
        }
    }
});
