//! The assembly union cache (issue 21, "Unions"): a GC edit re-meshes,
//! re-trims and re-unites only what changed, and the document's mesh is
//! bit for bit the one a fresh full recompute gives, through edits of one
//! part of a multi-part assembly, undo and redo.

use crate::common;

use shapewright::assembly::{
    union_mesh, union_mesh_cached, CacheStats, GcEditPart, PartEdit, UnionCache,
};
use shapewright::doc::{parse_script, run_script, Edit, ObjectId, ObjectKind, Op, OpLog};
use shapewright::gc::{GcAssembly, PartId, SectionIndex};
use shapewright::mesh::{validate, TriMesh};

fn assembly(log: &OpLog) -> GcAssembly {
    match &log.document().get(ObjectId(1)).expect("object 1").kind {
        ObjectKind::GcAssembly(a) => a.clone(),
        #[allow(unreachable_patterns)]
        _ => panic!("object 1 is not an assembly"),
    }
}

fn edit(part: usize, edit: PartEdit) -> Op {
    Op::GcEditPart(Edit::new(
        ObjectId(1),
        GcEditPart {
            part: PartId(part),
            edit,
        },
    ))
}

fn resize(part: usize, section: usize, factor: f64) -> Op {
    edit(
        part,
        PartEdit::Resize {
            section: SectionIndex(section),
            factor,
        },
    )
}

/// The object's mesh is the fresh full recompute of its assembly, bit for
/// bit, and a closed oriented 2-manifold; the document's hash is the one
/// a fresh replay of its ops gives.
fn assert_fresh(log: &OpLog, what: &str) {
    assert_fresh_mesh(log, what);
    let replayed = OpLog::replay(log.ops().to_vec(), log.cursor()).expect("replay");
    assert_eq!(
        replayed.document().content_hash(),
        log.document().content_hash(),
        "{what}: document hash"
    );
}

/// The object's mesh is the fresh full recompute of its assembly, bit for
/// bit, and a closed oriented 2-manifold.
fn assert_fresh_mesh(log: &OpLog, what: &str) {
    let obj = log.document().get(ObjectId(1)).expect("object 1");
    let mut fresh: TriMesh = union_mesh(&assembly(log)).expect("fresh union");
    fresh.set_source(1);
    assert_eq!(
        obj.local_mesh.positions, fresh.positions,
        "{what}: positions"
    );
    assert_eq!(
        obj.local_mesh.triangles, fresh.triangles,
        "{what}: triangles"
    );
    assert_eq!(*obj.local_mesh, fresh, "{what}: mesh");
    let r = validate(&fresh, &Default::default());
    assert!(
        r.is_closed() && r.non_manifold_vertices == 0 && r.signed_volume > 0.0,
        "{what}: {}",
        r.problems()
    );
}

fn delta(a: CacheStats, b: CacheStats) -> CacheStats {
    CacheStats {
        mesh_hits: b.mesh_hits - a.mesh_hits,
        mesh_misses: b.mesh_misses - a.mesh_misses,
        cavity_hits: b.cavity_hits - a.cavity_hits,
        cavity_misses: b.cavity_misses - a.cavity_misses,
        trim_hits: b.trim_hits - a.trim_hits,
        trim_misses: b.trim_misses - a.trim_misses,
        parts_reused: b.parts_reused - a.parts_reused,
        union_steps: b.union_steps - a.union_steps,
        result_hits: b.result_hits - a.result_hits,
    }
}

fn stats(log: &OpLog) -> CacheStats {
    log.document()
        .get(ObjectId(1))
        .expect("object 1")
        .cache
        .stats()
}

#[test]
fn cached_union_is_the_fresh_union_through_edits_undo_and_redo() {
    // The teapot: a hollow body, a shell spout opening through its wall, a
    // handle; every trim path (cavities cut out of other parts) is used.
    let mut log = common::run(&common::data("teapot.jsonl"));
    assert_eq!(assembly(&log).parts.len(), 3);
    assert_fresh(&log, "script");
    let steps: Vec<(&str, Op)> = vec![
        ("resize the handle", resize(2, 0, 1.1)),
        ("resize the spout", resize(1, 1, 1.15)),
        ("resize the handle again", resize(2, 0, 0.95)),
        ("resize the body", resize(0, 1, 1.05)),
    ];
    for (what, op) in steps {
        log.apply(op).unwrap_or_else(|e| panic!("{what}: {e}"));
        assert_fresh(&log, what);
    }
    for k in 0..3 {
        log.undo().expect("undo");
        assert_fresh(&log, &format!("undo {k}"));
    }
    log.redo().expect("redo");
    assert_fresh(&log, "redo");
    // A new branch after undo: the same part edited differently.
    log.apply(resize(1, 0, 0.9)).expect("branch");
    assert_fresh(&log, "branch");
    log.undo().expect("undo");
    log.undo().expect("undo");
    log.redo().expect("redo");
    assert_fresh(&log, "undo twice, redo");
}

#[test]
fn an_edit_of_one_part_reuses_the_other_parts() {
    let mut log = common::run(&common::data("teapot.jsonl"));
    // The handle (part 2, last) changes; body and spout do not.
    let before = stats(&log);
    log.apply(resize(2, 0, 1.1)).expect("resize the handle");
    let d = delta(before, stats(&log));
    assert_eq!((d.mesh_hits, d.mesh_misses), (2, 1), "{d:?}");
    assert_eq!((d.cavity_hits, d.cavity_misses), (2, 1), "{d:?}");
    // The body is found whole; spout and handle, one group (their boxes
    // are disjoint), are imported together again, the spout from its
    // kept trim: one union step.
    assert_eq!(d.parts_reused, 1, "{d:?}");
    assert_eq!((d.trim_hits, d.trim_misses), (1, 1), "{d:?}");
    assert_eq!(d.union_steps, 1, "{d:?}");
    // Undo and redo re-mesh, re-trim and re-unite nothing (the log keeps
    // the states it passed through; what it replays is found whole).
    let before = stats(&log);
    log.undo().expect("undo");
    log.redo().expect("redo");
    let d = delta(before, stats(&log));
    assert_eq!(
        (d.mesh_misses, d.cavity_misses, d.trim_misses),
        (0, 0, 0),
        "{d:?}"
    );
    assert_eq!(d.union_steps, 0, "{d:?}");
    // The chair: adding a part unites only the new part with the cached
    // union of the others.
    let chair = common::data("chair.jsonl");
    let lines: Vec<&str> = chair.lines().filter(|l| !l.trim().is_empty()).collect();
    let (head, last) = lines.split_at(lines.len() - 1);
    let mut log = common::run(&head.join("\n"));
    let n = assembly(&log).parts.len();
    let before = stats(&log);
    let script = parse_script(last[0]).expect("parses");
    run_script(&mut log, &script).expect("runs");
    let d = delta(before, stats(&log));
    let added = assembly(&log).parts.len() - n;
    assert!(added >= 1);
    assert_eq!(d.mesh_hits, n as u64, "{d:?}");
    assert_eq!(d.mesh_misses, added as u64, "{d:?}");
    // Every other part is found in a kept node or imported again from its
    // kept trim (the added part joins a group); only the new one is
    // trimmed.
    assert_eq!(d.parts_reused + d.trim_hits, n as u64, "{d:?}");
    assert_eq!(d.trim_misses, added as u64, "{d:?}");
    assert_eq!(d.union_steps, added as u64, "{d:?}");
    assert_fresh(&log, "chair");
}

#[test]
fn a_cache_that_keeps_nothing_gives_the_same_bits() {
    // Budget 0: every entry of the evaluations before the last is dropped
    // as soon as the next one stores anything; the meshes must not change.
    let mut log = common::run(&common::data("teapot.jsonl"));
    let tiny = UnionCache::with_budget(0);
    let big = UnionCache::new();
    for op in [resize(2, 0, 1.1), resize(1, 1, 1.1), resize(2, 0, 0.9)] {
        log.apply(op).expect("edit");
        let asm = assembly(&log);
        let a = union_mesh_cached(&asm, &tiny).expect("tiny");
        let b = union_mesh_cached(&asm, &big).expect("big");
        let c = union_mesh(&asm).expect("fresh");
        assert_eq!(a, c);
        assert_eq!(b, c);
        // Evaluating again hits the whole result.
        let hits = big.stats().result_hits;
        assert_eq!(union_mesh_cached(&asm, &big).expect("again"), c);
        assert_eq!(big.stats().result_hits, hits + 1);
    }
    assert!(big.bytes() > 0 && big.bytes() <= UnionCache::DEFAULT_BUDGET);
}

#[test]
fn the_union_has_the_same_bits_on_one_and_two_threads() {
    // manifold-rust's `parallel` option is on: its parallel sites must give
    // the sequential bits, and so must the assembly's parallel meshing,
    // trimming and importing, cached or not.
    let log = common::run(&common::data("teapot.jsonl"));
    let asm = assembly(&log);
    let on = |threads: usize, cache: &UnionCache| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .expect("pool")
            .install(|| union_mesh_cached(&asm, cache).expect("union"))
    };
    let one = on(1, &UnionCache::new());
    let two = on(2, &UnionCache::new());
    assert_eq!(one, two);
    assert_eq!(one, union_mesh(&asm).expect("fresh"));
    // An edit re-united on two threads from a cache filled on one.
    let shared = UnionCache::new();
    on(1, &shared);
    let mut log = log;
    log.apply(resize(0, 1, 1.05)).expect("resize the body");
    let asm = assembly(&log);
    let cached = rayon::ThreadPoolBuilder::new()
        .num_threads(2)
        .build()
        .expect("pool")
        .install(|| union_mesh_cached(&asm, &shared).expect("union"));
    assert_eq!(cached, union_mesh(&asm).expect("fresh"));
}

#[test]
fn adding_parts_then_undo_and_redo_never_gives_a_stale_union() {
    // The chair: each op adds a part, so each commit unites the new part
    // with the cached union of the others; after undo the cache still
    // holds the longer fold, after redo the shorter one.
    let chair = common::data("chair.jsonl");
    let lines: Vec<&str> = chair.lines().filter(|l| !l.trim().is_empty()).collect();
    // Its first seven ops (seat, four legs, two back posts), kept short.
    let (head, tail) = lines[..7].split_at(4);
    let mut log = common::run(&head.join("\n"));
    assert_fresh_mesh(&log, "chair head");
    for (k, line) in tail.iter().enumerate() {
        run_script(&mut log, &parse_script(line).expect("parses")).expect("runs");
        assert_fresh_mesh(&log, &format!("chair part {k}"));
    }
    for k in 0..2 {
        log.undo().expect("undo");
        assert_fresh_mesh(&log, &format!("chair undo {k}"));
    }
    log.redo().expect("redo");
    assert_fresh_mesh(&log, "chair redo");
    // A different part where the undone ones were: its own union, not the
    // undone ones'.
    log.apply(resize(1, 0, 1.2)).expect("resize a leg");
    assert_fresh_mesh(&log, "chair branch");
    log.undo().expect("undo");
    assert_fresh(&log, "chair branch undone");
}

/// The last evaluation is kept whatever the budget: an edit of the
/// teapot's handle with a cache that keeps nothing else still reuses the
/// union of body and spout (one union step). The GC time budget estimates
/// an edit on that. (Before, a fold prefix over the budget was dropped as
/// soon as the edit meshed its changed part, and every part was united
/// again: a handle edit on a 2 M-triangle body took the full union's
/// time.)
#[test]
fn an_edit_reuses_the_last_evaluation_whatever_the_budget() {
    let log = common::run(&common::data("teapot.jsonl"));
    let tiny = UnionCache::with_budget(0);
    union_mesh_cached(&assembly(&log), &tiny).expect("first");
    let mut log = log;
    for (k, op) in [resize(2, 0, 1.1), resize(2, 0, 0.9)]
        .into_iter()
        .enumerate()
    {
        log.apply(op).expect("edit");
        let before = tiny.stats();
        let m = union_mesh_cached(&assembly(&log), &tiny).expect("edit");
        let d = delta(before, tiny.stats());
        assert_eq!(d.parts_reused, 1, "edit {k}: {d:?}");
        assert_eq!(d.union_steps, 1, "edit {k}: {d:?}");
        assert_eq!(m, union_mesh(&assembly(&log)).expect("fresh"));
    }
    // An undo finds its result whole and keeps its nodes and its parts'
    // trims: the edit after it unites one step too.
    let undone = {
        log.undo().expect("undo");
        assembly(&log)
    };
    union_mesh_cached(&undone, &tiny).expect("undo");
    log.apply(resize(2, 0, 1.2)).expect("branch");
    let before = tiny.stats();
    union_mesh_cached(&assembly(&log), &tiny).expect("branch");
    let d = delta(before, tiny.stats());
    assert_eq!(d.union_steps, 1, "after undo: {d:?}");
    // Only the edited handle is trimmed again: the spout, imported again
    // with it (one group), comes from its kept trim.
    assert_eq!((d.trim_hits, d.trim_misses), (1, 1), "after undo: {d:?}");
}

/// The chair's nine parts are united in the union tree (issue 37): its
/// leaves are groups of parts whose boxes are pairwise disjoint, each
/// imported as one mesh without a boolean (C++ Manifold's batch union
/// groups the same way), so the chair takes one boolean: the seat with the
/// back's two rails, and the four legs with the two back posts. The bits
/// are the same on one and two threads, and an edit of a leg (which its
/// copy follows) imports the legs' group again, the other parts from
/// their kept trims, and re-unites the root, reusing the seat's group
/// whole.
#[test]
fn the_chair_unites_in_a_tree_with_the_same_bits_on_one_and_two_threads() {
    let log = common::run(&common::data("chair.jsonl"));
    let asm = assembly(&log);
    let boxes: Vec<_> = asm
        .parts
        .iter()
        .map(|p| shapewright::gc::mesh_gc(&p.gc).expect("part").bbox())
        .collect();
    let groups = shapewright::mesh::disjoint_groups(&boxes);
    assert_eq!(groups, vec![vec![0, 7, 8], vec![1, 2, 3, 4, 5, 6]]);
    let on = |threads: usize, asm: &GcAssembly, cache: &UnionCache| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .expect("pool")
            .install(|| union_mesh_cached(asm, cache).expect("union"))
    };
    let one = on(1, &asm, &UnionCache::new());
    let shared = UnionCache::new();
    let two = on(2, &asm, &shared);
    assert_eq!(one, two);
    assert_eq!(shared.stats().union_steps, 1);
    let mut log = log;
    log.apply(resize(3, 0, 1.2)).expect("resize a leg");
    let edited = assembly(&log);
    let changed: Vec<usize> = (0..9)
        .filter(|&i| asm.parts[i].gc != edited.parts[i].gc)
        .collect();
    assert_eq!(changed, vec![3, 4]);
    let before = shared.stats();
    let cached = on(2, &edited, &shared);
    let d = delta(before, shared.stats());
    assert_eq!(d.union_steps, 1, "{d:?}");
    // The seat's group whole (3); the legs' group imported again, parts
    // 1, 2, 5 and 6 from their kept trims.
    assert_eq!(d.parts_reused, 3, "{d:?}");
    assert_eq!((d.trim_hits, d.trim_misses), (4, 2), "{d:?}");
    assert_eq!(cached, on(1, &edited, &UnionCache::new()));
    assert_eq!(
        *log.document().get(ObjectId(1)).expect("chair").local_mesh,
        {
            let mut m = cached.clone();
            m.set_source(1);
            m
        }
    );
}
