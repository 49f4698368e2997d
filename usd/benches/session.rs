//! Save and load of a 10k-op session: 100 solids, then 9 900 incremental
//! moves (what a VR session's grabs record), saved as one usda.

// criterion_group! generates an undocumented public function.
#![allow(missing_docs)]

use criterion::{criterion_group, criterion_main, Criterion};
use shapewright::doc::{Op, OpLog};
use shapewright_usd::{load_from_str, save_file, save_to_string, LoadOptions, SaveOptions};

fn session() -> OpLog {
    let mut log = OpLog::new();
    for i in 0..10_000u32 {
        let text = if i < 100 {
            format!(
                r#"{{"op":"add_solid","shape":{{"kind":"sphere","radius":0.05}},"segments":16,"transform":{{"translate":[{},{},0]}}}}"#,
                f64::from(i % 10) * 0.2,
                f64::from(i / 10) * 0.2
            )
        } else {
            format!(
                r#"{{"op":"transform_by","id":{},"transform":{{"translate":[0.001,0,{}]}}}}"#,
                i % 100 + 1,
                f64::from(i) * 1e-6
            )
        };
        let op: Op = serde_json::from_str(&text).expect("op parses");
        log.apply(op).expect("op applies");
    }
    log
}

fn bench(c: &mut Criterion) {
    let log = session();
    let text = save_to_string(&log, &SaveOptions::default()).expect("save");
    eprintln!(
        "10k-op session: {} objects, {} bytes of usda",
        log.document().len(),
        text.len()
    );
    let mut g = c.benchmark_group("usd_10k_ops");
    g.sample_size(10);
    g.bench_function("save_to_string", |b| {
        b.iter(|| save_to_string(&log, &SaveOptions::default()).expect("save"))
    });
    let dir = std::env::temp_dir().join(format!("sw-usd-bench-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("dir");
    let path = dir.join("session.usda");
    g.bench_function("save_file_fsync", |b| {
        b.iter(|| save_file(&path, &log, &SaveOptions::default()).expect("save"))
    });
    g.bench_function("load_from_str", |b| {
        b.iter(|| load_from_str(&text, LoadOptions::default()).expect("load"))
    });
    g.bench_function("load_verify_history", |b| {
        b.iter(|| {
            load_from_str(
                &text,
                LoadOptions {
                    verify_history: true,
                    strict: false,
                },
            )
            .expect("load")
        })
    });
    g.finish();
    let _ = std::fs::remove_dir_all(&dir);
}

criterion_group!(benches, bench);
criterion_main!(benches);
