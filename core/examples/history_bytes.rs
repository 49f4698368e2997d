//! History memory of the 20-object session (issue 21, "lean history"), for
//! the honest bench (`scripts/bench/run_all.py`); prints one JSON line.
//!
//! `history_bytes [OPS] [SEGMENTS]` (defaults 20000 and 16): 20 spheres
//! (radius 0.1, SEGMENTS segments; 16 is the `oplog` bench's session and
//! the one issue 21 measured at +8 MiB per 1,000 ops), then small moves
//! (`transform_by`) round-robin over them, OPS ops in all, through
//! `OpLog::apply` with the default checkpoint policy.
//!
//! Measured with a counting global allocator (live bytes requested, not
//! the allocator's own overhead): the log's heap after 1,000 ops and after
//! OPS ops, minus the heap of its current document alone (the log is
//! dropped with a clone of its document kept, so the objects the document
//! shares with the checkpoints are counted once, as the document's). The
//! history is everything else: ops, checkpoints, the undo window. Reports
//! history bytes per 1,000 ops at OPS (the goal's number: under 1 MiB), the
//! slope between 1,000 and OPS ops, and undo+redo time at the end of both
//! logs (undo must stay flat). Bytes are deterministic: no spread.

use std::alloc::{GlobalAlloc, Layout, System};
use std::sync::atomic::{AtomicIsize, Ordering};
use std::time::Instant;

use shapewright::doc::{AddSolid, ObjectId, Op, OpLog, TransformBy};
use shapewright::math::Transform;
use shapewright::solid::SolidShape;

/// System allocation, counting the live bytes requested.
struct Counting;

static LIVE: AtomicIsize = AtomicIsize::new(0);

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, l: Layout) -> *mut u8 {
        LIVE.fetch_add(l.size() as isize, Ordering::Relaxed);
        // SAFETY: forwarded unchanged to the system allocator.
        unsafe { System.alloc(l) }
    }
    unsafe fn dealloc(&self, p: *mut u8, l: Layout) {
        LIVE.fetch_sub(l.size() as isize, Ordering::Relaxed);
        // SAFETY: `p` came from `alloc`/`realloc` above with layout `l`.
        unsafe { System.dealloc(p, l) }
    }
    unsafe fn alloc_zeroed(&self, l: Layout) -> *mut u8 {
        LIVE.fetch_add(l.size() as isize, Ordering::Relaxed);
        // SAFETY: forwarded unchanged to the system allocator.
        unsafe { System.alloc_zeroed(l) }
    }
    unsafe fn realloc(&self, p: *mut u8, l: Layout, new: usize) -> *mut u8 {
        LIVE.fetch_add(new as isize - l.size() as isize, Ordering::Relaxed);
        // SAFETY: `p` came from this allocator with layout `l`.
        unsafe { System.realloc(p, l, new) }
    }
}

#[global_allocator]
static ALLOC: Counting = Counting;

fn live() -> isize {
    LIVE.load(Ordering::Relaxed)
}

const OBJECTS: usize = 20;

fn op(i: usize, segments: u32) -> Op {
    if i < OBJECTS {
        Op::AddSolid(AddSolid {
            shape: SolidShape::Sphere { radius: 0.1 },
            segments,
            transform: Transform::translation([i as f64 * 0.3, 0.0, 0.0]),
        })
    } else {
        Op::TransformBy(TransformBy {
            id: ObjectId((i % OBJECTS) as u32 + 1),
            transform: Transform::translation([0.001, 0.0, 0.0005]),
        })
    }
}

/// (history bytes, document bytes, undo+redo µs median) after `len` ops.
fn measure(len: usize, segments: u32) -> Result<(isize, isize, f64), Box<dyn std::error::Error>> {
    let base = live();
    let mut log = OpLog::new();
    for i in 0..len {
        log.apply(op(i, segments))?;
    }
    let total = live() - base;
    // Undo + redo at the end of the log (median of 21).
    let mut t = Vec::new();
    for _ in 0..21 {
        let s = Instant::now();
        log.undo()?;
        log.redo()?;
        t.push(s.elapsed().as_secs_f64() * 1e6);
    }
    t.sort_by(f64::total_cmp);
    let undo_us = t[t.len() / 2];
    drop(t);
    // The document alone (`total` was taken before the undo window and `t`
    // existed, so they are not counted on either side).
    let before_clone = live();
    let doc = log.document().clone();
    let clone_overhead = live() - before_clone;
    drop(log);
    let doc_only = live() - base - clone_overhead;
    drop(doc);
    Ok((total - doc_only, doc_only, undo_us))
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let a: Vec<String> = std::env::args().collect();
    let ops: usize = a.get(1).and_then(|s| s.parse().ok()).unwrap_or(20_000);
    let segments: u32 = a.get(2).and_then(|s| s.parse().ok()).unwrap_or(16);
    let first = 1_000.min(ops);
    // Warm-up: statics initialised on first use (rayon's pool, caches)
    // stay allocated and would otherwise count as the first document's.
    measure(OBJECTS + 10, segments)?;
    let (h1, d1, u1) = measure(first, segments)?;
    let (hn, dn, un) = measure(ops, segments)?;
    let per_k = hn as f64 / (ops as f64 / 1000.0);
    let slope = if ops > first {
        (hn - h1) as f64 / ((ops - first) as f64 / 1000.0)
    } else {
        per_k
    };
    println!(
        "{{\"kind\":\"history\",\"objects\":{OBJECTS},\"segments\":{segments},\"ops\":{ops},\"history_bytes\":{hn},\"document_bytes\":{dn},\"bytes_per_1000_ops\":{per_k:.0},\"slope_bytes_per_1000_ops\":{slope:.0},\"history_bytes_at_{first}\":{h1},\"document_bytes_at_{first}\":{d1},\"undo_redo_us_at_{first}\":{u1:.2},\"undo_redo_us\":{un:.2}}}"
    );
    Ok(())
}
