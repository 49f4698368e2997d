//! [`printable_with`]: the same bits as [`printable`], progress that moves
//! through the union, and a cancel that stops the job within a boolean.

use std::time::{Duration, Instant};

use glam::{DAffine3, DVec3};

use crate::mesh::TriMesh;
use crate::print::{
    printable, printable_with, PrintControl, PrintError, PrintPart, PrintSettings, PrintStage,
};
use crate::solid::{tessellate, SolidShape};

/// `n` overlapping spheres in a row, `segments` around each.
fn spheres(n: usize, segments: u32) -> Vec<TriMesh> {
    (0..n)
        .map(|i| {
            let mut m = tessellate(&SolidShape::Sphere { radius: 0.05 }, segments).unwrap();
            m.transform(&DAffine3::from_translation(DVec3::new(
                0.07 * i as f64,
                0.0,
                0.0,
            )));
            m
        })
        .collect()
}

fn parts(meshes: &[TriMesh]) -> Vec<PrintPart<'_>> {
    meshes
        .iter()
        .enumerate()
        .map(|(i, m)| PrintPart {
            id: i as u32 + 1,
            kind: "solid",
            surface: false,
            mesh: m,
        })
        .collect()
}

#[test]
fn a_controlled_job_gives_the_same_bits_and_reports_every_step() {
    let meshes = spheres(4, 48);
    let settings = PrintSettings::default();
    let plain = printable(&parts(&meshes), &settings).unwrap();
    let control = PrintControl::new();
    let seen = std::sync::Mutex::new(Vec::new());
    let watcher = control.clone();
    let done = std::sync::atomic::AtomicBool::new(false);
    let controlled = std::thread::scope(|s| {
        s.spawn(|| {
            while !done.load(std::sync::atomic::Ordering::Relaxed) {
                seen.lock().unwrap().push(watcher.progress());
                std::thread::sleep(Duration::from_micros(200));
            }
        });
        let out = printable_with(&parts(&meshes), &settings, &control).unwrap();
        done.store(true, std::sync::atomic::Ordering::Relaxed);
        out
    });
    assert_eq!(controlled.mesh.positions, plain.mesh.positions);
    assert_eq!(controlled.mesh.triangles, plain.mesh.triangles);
    assert_eq!(controlled.mesh.tri_source, plain.mesh.tri_source);
    let seen = seen.into_inner().unwrap();
    let fractions: Vec<f64> = seen.iter().map(|p| p.fraction()).collect();
    assert!(
        fractions.windows(2).all(|w| w[1] >= w[0]),
        "progress went back: {fractions:?}"
    );
    // The job ends in its checks, past every union step.
    let last = control.progress();
    assert_eq!(last.stage, PrintStage::Checking, "{last:?}");
    assert!(last.fraction() >= 0.85, "{last:?}");
}

#[test]
fn a_cancelled_job_stops_within_a_boolean_and_returns_no_mesh() {
    let settings = PrintSettings::default();
    // Cancelled before it starts: refused at once.
    let meshes = spheres(2, 16);
    let control = PrintControl::new();
    control.cancel();
    let out = printable_with(&parts(&meshes), &settings, &control);
    assert!(matches!(out, Err(PrintError::Cancelled)), "{out:?}");

    // Cancelled while uniting big parts: stops long before the union ends.
    let meshes = spheres(6, 400);
    let control = PrintControl::new();
    let start = Instant::now();
    let full = printable(&parts(&meshes), &settings).map(|_| start.elapsed());
    let full = full.unwrap();
    let canceller = control.clone();
    let (out, latency) = std::thread::scope(|s| {
        let job = s.spawn(|| printable_with(&parts(&meshes), &settings, &control));
        while canceller.progress().stage != PrintStage::Uniting || canceller.progress().done < 7 {
            std::thread::sleep(Duration::from_micros(100));
        }
        let asked = Instant::now();
        canceller.cancel();
        let out = job.join().unwrap();
        (out, asked.elapsed())
    });
    assert!(matches!(out, Err(PrintError::Cancelled)), "{out:?}");
    assert!(
        latency < full / 2 && latency < Duration::from_secs(1),
        "stopped {latency:?} after the cancel; the whole job takes {full:?}"
    );
}
