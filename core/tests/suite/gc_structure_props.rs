//! Structure-aware editing (issues 18 and 33, paper 1 §3.3) under random
//! edit sequences on the example assemblies (mug, teapot, chair, rack).
//!
//! Every GC edit (bend, resize by 0.5 to 2, shift, twist, replace section
//! by any profile kind, delete, insert, set shape, replace spine), slides
//! and turns (`gc_transform_part`: along the parent's surface, spun about
//! the normal, turned about the parent's axis) and copies (`gc_copy`:
//! slid, turned or mirrored) go through the same functions the document
//! calls ([`gc_props::edits`]). After every op:
//! - each child is still where it sat on its parent: its spine start (and
//!   a handle's end) has the same coordinates in its anchor frame as
//!   before, to 1e-9 of the scene size, unless the op edited that part's
//!   own spine, an open end was sunk in along the normal (the junction
//!   keeps a spout's rim in its parent), or it was kept in a coplanar
//!   partner's plane across a change of profile kind;
//! - each recorded twin pair is mirrored about the parent's spine plane,
//!   each coplanar pair coplanar, each concentric pair on one line, and
//!   no recorded relation was dropped;
//! - the op did what it says (resize multiplies the scale by the factor,
//!   a turn about a body of revolution's axis is the turned part, ...).
//!
//! The `*_keep_topology` tests also take the union after every op (at a
//! lower resolution, for time): it stays a closed 2-manifold without a
//! degenerate triangle, with the genus and component count of the
//! unedited model (a copy adds what its source adds), as long as no edit
//! made parts meet or part that are not parent and child
//! ([`gc_props::topology::Contacts`]; counted and printed). The union is
//! also evaluated through one cache kept across the sequence, as the
//! document keeps it, and must be the fresh union bit for bit (issue 37's
//! incremental union: only the union tree's nodes over changed parts are
//! united again). A core that does not sink an open end back into its
//! parent (the teapot's spout root opening, issue 33) fails the teapot's
//! within 80 cases: its genus changes after a bend of the body (shown).
//!
//! Refused ops must be typed errors (a relation refusal names the
//! relation and two parts); the refusal rate is printed and bounded.
//! `PROPTEST_CASES` (default 100) sets the number of cases per example of
//! the relation tests, `GC_TOPOLOGY_CASES` (default 80: 240 sequences, a
//! minute in CI) those of the topology tests; `GC_TOPOLOGY_FULL=1` meshes
//! those at the examples' own resolution (slower).

use crate::gc_props;

use std::collections::BTreeMap;
use std::sync::OnceLock;

use gc_props::checks::{
    all_local, check_effect, check_relations, local_ends, moved_by_op, own_spine_edited, twins,
};
use gc_props::edits::{apply, make, seed, Made, Motion, Seed};
use gc_props::topology::{
    contacts, evaluate, folded_part, topology, Contacts, Evaluated, Topology,
};
use glam::DQuat;
use proptest::prelude::*;
use proptest::test_runner::{Config, RngAlgorithm, TestCaseError, TestRng, TestRunner};
use shapewright::assembly::{descendants_bfs, AssemblyError, UnionCache};
use shapewright::doc::{parse_script, run_script, ObjectId, ObjectKind, OpLog};
use shapewright::gc::*;

const EXAMPLES: [&str; 4] = ["mug", "teapot", "chair", "rack"];

/// The resolution the topology tests mesh at.
const TOPOLOGY_RESOLUTION: Resolution = Resolution { u: 32, v: 24 };

fn examples() -> &'static Vec<GcAssembly> {
    static CELL: OnceLock<Vec<GcAssembly>> = OnceLock::new();
    CELL.get_or_init(|| {
        EXAMPLES
            .iter()
            .map(|name| {
                let path = format!("{}/../tests/data/{name}.jsonl", env!("CARGO_MANIFEST_DIR"));
                let text = std::fs::read_to_string(&path).expect("example script");
                let mut log = OpLog::new();
                run_script(&mut log, &parse_script(&text).expect("parses")).expect("runs");
                match &log.document().get(ObjectId(1)).expect("object 1").kind {
                    ObjectKind::GcAssembly(a) => a.clone(),
                    _ => panic!("{name}: not an assembly"),
                }
            })
            .collect()
    })
}

/// The parts `keep` of `asm` alone (parents renumbered, a part whose
/// parent is left out becomes a root; no relations: only its union is
/// wanted).
fn only(asm: &GcAssembly, keep: &[usize]) -> GcAssembly {
    let index = |i: usize| keep.iter().position(|&k| k == i);
    GcAssembly {
        parts: keep
            .iter()
            .map(|&i| {
                let mut p = asm.parts[i].clone();
                p.parent = p.parent.and_then(index);
                if p.parent.is_none() {
                    p.attach = None;
                }
                p
            })
            .collect(),
        relations: None,
    }
}

/// What a copy of child `src` that touches nothing but its parent adds to
/// the union's genus: what `src` with its descendants adds to its parent
/// alone (a handle's loop, a spout's channel; not a loop it closes
/// through another part it touches).
fn adds(asm: &GcAssembly, src: usize) -> Result<i64, String> {
    let parent = asm.parts[src].parent.ok_or("a copied root")?;
    let mut keep = vec![parent, src];
    keep.extend(descendants_bfs(asm, &[src]));
    Ok(topology(&only(asm, &keep))?.genus - topology(&only(asm, &[parent]))?.genus)
}

#[derive(Default)]
struct Stats {
    ops: usize,
    refused: usize,
    reasons: BTreeMap<String, usize>,
    /// Accepted ops whose union was compared with the expected topology.
    compared: usize,
    /// Accepted ops after which parts met or parted (not compared).
    contact_changed: usize,
}

/// What the topology tests track through a sequence: the union's
/// expected topology and the contacts it holds under.
struct Expect {
    topology: Topology,
    contacts: Contacts,
}

/// Refuses with a message unless `e` is a typed refusal: a relation
/// refusal naming its relation and two parts of `asm`, a pick off the
/// parent's surface, or a GC error (a fold, a section order, ...).
fn typed(e: &AssemblyError, asm: &GcAssembly) -> Result<(), TestCaseError> {
    match e {
        AssemblyError::RelationBroken { parts, .. } => {
            let n = asm.parts.len();
            prop_assert!(
                parts.0 != parts.1 && parts.0 < n && parts.1 < n,
                "a refusal names parts {parts:?} of {n}"
            );
        }
        AssemblyError::OffSurface { .. } | AssemblyError::Gc(_) => {}
        other => prop_assert!(false, "untyped refusal {other:?}"),
    }
    Ok(())
}

fn reason(m: &Made, e: &AssemblyError) -> String {
    match e {
        AssemblyError::RelationBroken { relation, .. } => {
            format!("{}: broken {relation}", m.name())
        }
        AssemblyError::Gc(g) => format!(
            "{}: {}",
            m.name(),
            format!("{g:?}").split(['{', '(', ' ']).next().unwrap_or("")
        ),
        _ => format!(
            "{}: {}",
            m.name(),
            format!("{e:?}").split(['{', '(']).next().unwrap_or("")
        ),
    }
}

/// The union's checks after an accepted op (topology tests): no
/// degenerate triangle, and, while the contacts are the unedited
/// model's, its genus and component count.
fn check_topology(
    before: &GcAssembly,
    next: &GcAssembly,
    ev: &Evaluated,
    m: &Made,
    expect: &mut Option<Expect>,
    stats: &mut Stats,
) -> Result<(), TestCaseError> {
    let fail = |e: String| TestCaseError::fail(format!("after {m:?}: {e}"));
    let t = ev.topology;
    prop_assert_eq!(t.degenerate, 0, "degenerate triangles after {:?}", m);
    let Some(want) = expect.as_mut() else {
        return Ok(());
    };
    let now = contacts(next, &ev.parts).map_err(fail)?;
    if now != want.contacts {
        stats.contact_changed += 1;
        *expect = None;
        return Ok(());
    }
    if let Made::Copy(_, src, ..) = m {
        want.topology.genus += adds(before, *src).map_err(fail)?;
    }
    stats.compared += 1;
    prop_assert_eq!(
        (t.genus, t.components),
        (want.topology.genus, want.topology.components),
        "the union's topology changed after {:?}",
        m
    );
    Ok(())
}

/// `next` evaluated (topology tests), or `None` (counted as a refusal)
/// when the document would not keep it: a part cannot be meshed (the
/// document evaluates the assembly after each op and refuses it with
/// that typed GC error: a section replaced by a loop too narrow for the
/// wall, ...), or a part passes through itself (a bend much tighter than
/// its sections: the document flags or refuses the fold,
/// `set_self_intersection_policy`, and the union is not the model's).
fn evaluated(
    next: &GcAssembly,
    m: &Made,
    stats: &mut Stats,
    cache: &UnionCache,
) -> Result<Option<Evaluated>, TestCaseError> {
    let why = match evaluate(next, Some(cache)).map_err(TestCaseError::fail)? {
        Err(g) => format!("{g:?}")
            .split(['{', '(', ' '])
            .next()
            .unwrap_or("")
            .to_string(),
        Ok(ev) => match folded_part(&ev) {
            None => return Ok(Some(ev)),
            Some(p) => format!("part {p} folds"),
        },
    };
    stats.refused += 1;
    *stats
        .reasons
        .entry(format!("{}: (mesh) {why}", m.name()))
        .or_default() += 1;
    Ok(None)
}

fn run_case(ex: usize, seeds: &[Seed], topo: bool, stats: &mut Stats) -> Result<(), TestCaseError> {
    let mut asm = examples()[ex].clone();
    if topo && std::env::var_os("GC_TOPOLOGY_FULL").is_none() {
        for p in &mut asm.parts {
            p.gc.resolution = TOPOLOGY_RESOLUTION;
        }
    }
    let mut expected = all_local(&asm);
    let mut recorded = asm.relations.clone().expect("examples record relations");
    let cache = UnionCache::new();
    let mut expect = if topo {
        let ev = evaluate(&asm, Some(&cache))
            .map_err(TestCaseError::fail)?
            .map_err(|e| TestCaseError::fail(e.to_string()))?;
        let contacts = contacts(&asm, &ev.parts).map_err(TestCaseError::fail)?;
        Some(Expect {
            topology: ev.topology,
            contacts,
        })
    } else {
        None
    };
    for s in seeds {
        let m = make(&asm, s);
        let mut next = asm.clone();
        stats.ops += 1;
        match apply(&mut next, &m) {
            Err(e) => {
                stats.refused += 1;
                *stats.reasons.entry(reason(&m, &e)).or_default() += 1;
                typed(&e, &asm)?;
            }
            Ok(()) => {
                let ev = if topo {
                    match evaluated(&next, &m, stats, &cache)? {
                        Some(ev) => Some(ev),
                        None => continue,
                    }
                } else {
                    None
                };
                check_effect(&asm, &next, &m)
                    .map_err(|e| TestCaseError::fail(format!("{m:?}: {e}")))?;
                for p in own_spine_edited(&asm, &m) {
                    expected[p] = local_ends(&next, p);
                }
                expected.resize(next.parts.len(), None);
                for (c, e) in expected.iter_mut().enumerate() {
                    if e.is_none() {
                        *e = local_ends(&next, c);
                    }
                }
                if let Made::Slide(e, Motion::Slide { spin }, _) = &m {
                    // A spin turns the part about its normal (the anchor
                    // frame's x axis); a handle's end keeps its coordinates
                    // at its own slid anchor (the handle is turned and
                    // scaled about its start to land there: found by a
                    // slide around the mug, GC_PROPS_SEED=12); a twin's
                    // mirrored spin is re-read.
                    if *spin != 0.0 {
                        let q = DQuat::from_rotation_x(*spin);
                        if let Some((s0, e0)) = expected[e.part.0] {
                            expected[e.part.0] = Some((q * s0, e0));
                        }
                        for t in twins(&asm, e.part.0) {
                            expected[t] = local_ends(&next, t);
                        }
                    }
                }
                let moved = moved_by_op(&asm, &next, &m);
                check_relations(&next, &asm, &moved, &mut expected)
                    .map_err(|e| TestCaseError::fail(format!("after {m:?}: {e}")))?;
                let rec = next.relations.clone().expect("recorded");
                for (old, new) in [
                    (&recorded.symmetric, &rec.symmetric),
                    (&recorded.coplanar, &rec.coplanar),
                    (&recorded.concentric, &rec.concentric),
                ] {
                    prop_assert!(
                        old.iter().all(|p| new.contains(p)),
                        "a relation was dropped by {m:?}"
                    );
                }
                if let Some(ev) = &ev {
                    check_topology(&asm, &next, ev, &m, &mut expect, stats)?;
                }
                recorded = rec;
                asm = next;
            }
        }
    }
    Ok(())
}

fn cases(var: &str, default: u32) -> u32 {
    std::env::var(var)
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(default)
}

/// Runs the random sequences on example `ex`: the relation checks
/// (`topo` false: `PROPTEST_CASES` cases of 1 to 6 ops), or those and the
/// union's topology (`GC_TOPOLOGY_CASES` cases of 1 to 4 ops).
fn run_example(ex: usize, topo: bool) {
    let n = if topo {
        cases("GC_TOPOLOGY_CASES", 80)
    } else {
        cases("PROPTEST_CASES", 100)
    };
    // A fixed seed, so CI runs the same cases every time (a random seed
    // made CI fail on whatever it happened to find); GC_PROPS_SEED=<u64>
    // explores other cases in longer runs.
    let rng = match std::env::var("GC_PROPS_SEED")
        .ok()
        .and_then(|s| s.parse::<u64>().ok())
    {
        Some(seed) => TestRng::from_seed(RngAlgorithm::ChaCha, &[seed.to_le_bytes(); 4].concat()),
        None => TestRng::deterministic_rng(RngAlgorithm::ChaCha),
    };
    let mut runner = TestRunner::new_with_rng(
        Config {
            cases: n,
            failure_persistence: None,
            ..Config::default()
        },
        rng,
    );
    let stats = std::cell::RefCell::new(Stats::default());
    let len = if topo { 1..5 } else { 1..7 };
    let result = runner.run(&prop::collection::vec(seed(), len), |seeds| {
        run_case(ex, &seeds, topo, &mut stats.borrow_mut())
    });
    if let Err(e) = result {
        panic!("{}: {e}", EXAMPLES[ex]);
    }
    let s = stats.borrow();
    let rate = s.refused as f64 / s.ops.max(1) as f64;
    eprintln!(
        "{}{}: {n} cases, {} ops, {} refused ({:.1}%), {} unions compared, {} after a contact \
         changed; 0 broken relations, 0 degenerate triangles; refusals: {:?}",
        EXAMPLES[ex],
        if topo { " (topology)" } else { "" },
        s.ops,
        s.refused,
        100.0 * rate,
        s.compared,
        s.contact_changed,
        s.reasons
    );
    assert!(
        rate < 0.25,
        "{}: {:.1}% of ops refused",
        EXAMPLES[ex],
        100.0 * rate
    );
}

/// Runs one case of the relation tests from its seeds, each `(kind,
/// [part, section, x, y, z, w])`, on example `ex` (a case a random run
/// found, kept as a test).
fn regression(ex: usize, seeds: &[(u8, [f64; 6])]) {
    let seeds: Vec<Seed> = seeds
        .iter()
        .map(|&(kind, [part, section, x, y, z, w])| Seed {
            kind,
            part,
            section,
            x,
            y,
            z,
            w,
        })
        .collect();
    run_case(ex, &seeds, false, &mut Stats::default()).unwrap();
}

#[test]
fn the_examples_record_their_relations() {
    let ex = examples();
    let rec = |i: usize| ex[i].relations.clone().expect("recorded");
    // mug: the handle is in the body's spine plane
    assert!(rec(0).coplanar.contains(&(0, 1)), "{:?}", rec(0));
    // teapot: spout and handle coplanar (for pouring), with the body
    for p in [(0, 1), (0, 2), (1, 2)] {
        assert!(rec(1).coplanar.contains(&p), "{:?}", rec(1));
    }
    // chair: three mirrored pairs (front legs, back legs, back posts)
    for p in [(1, 2), (3, 4), (5, 6)] {
        assert!(rec(2).symmetric.contains(&p), "{:?}", rec(2));
    }
    // rack: the mirrored feet
    assert!(rec(3).symmetric.contains(&(3, 4)), "{:?}", rec(3));
    assert!(rec(3).symmetric.contains(&(5, 6)), "{:?}", rec(3));
}

#[test]
fn mug_random_edits_keep_relations() {
    run_example(0, false);
}

#[test]
fn teapot_random_edits_keep_relations() {
    run_example(1, false);
}

#[test]
fn chair_random_edits_keep_relations() {
    run_example(2, false);
}

#[test]
fn rack_random_edits_keep_relations() {
    run_example(3, false);
}

#[test]
fn mug_random_edits_keep_topology() {
    run_example(0, true);
}

#[test]
fn teapot_random_edits_keep_topology() {
    run_example(1, true);
}

#[test]
fn chair_random_edits_keep_topology() {
    run_example(2, true);
}

/// Found by a random seed in a CI-like run (2026-11-28): after the mug
/// body's section was replaced by a sketched loop, an unturned copy of the
/// handle, dropped 9e-6 m off the body's plane, looked 0.4 mm off its
/// source ("copy: start 0.000415 off the source's anchor coordinates").
/// The core was right and the check was not: the source, coplanar with
/// the body, was read in the frame kept in the body's plane and the copy,
/// off the plane, in the plain anchor frame, which the new profile tilts
/// against the first. Both are now read in the copy's kind of frame
/// (`gc_props::checks`, issue 33).
#[test]
fn mug_handle_copied_after_a_body_edit_sits_where_its_source_sits() {
    regression(
        0,
        &[
            (
                4,
                [0.0, 0.6192683192484946, 0.0, 0.0, 0.0, 0.6686199948530956],
            ),
            (
                10,
                [
                    0.7385887906169473,
                    0.0,
                    -0.1843922702988571,
                    0.0,
                    0.7796427786804366,
                    0.5706112155144293,
                ],
            ),
        ],
    );
}

/// Found by a random seed in the same run: a slid and spun copy on the
/// teapot landed 2.3e-7 m from where its source's anchor coordinates,
/// spun, put it (issue 33). The core read a slide's turn as the least
/// rotation back onto the new normal, the twist of `f_newᵀ m f_old`,
/// which differs from following the anchor frames by the frames' own
/// turn about the normal between the two anchors; with no rotation at all
/// it followed the frames, so the smallest spin jumped the part by that
/// turn. Slid in any direction of the tangent plane (not only along the
/// spine) the jump is first order in the slide: a spun copy 3 mm around
/// the teapot's body landed 3e-5 m off, and the random tests found it on
/// the mug and the teapot in 200 cases. The turn is now read as the part's
/// bearing to the parent's spine (`own_turn` in `assembly/edits.rs`).
#[test]
fn teapot_spun_copy_sits_where_its_source_sits() {
    regression(
        1,
        &[
            (4, [0.0, 0.0, 0.0, 0.0, 0.0, 0.4862623956248063]),
            (
                10,
                [
                    0.978270517226612,
                    0.0,
                    0.41669863651552874,
                    0.14201845397955284,
                    0.0,
                    0.7951101524335711,
                ],
            ),
        ],
    );
}

/// Found by a 2,000-case run (2026-11-30): the chair's seat section
/// replaced by a circle, then bent. A leg recorded coplanar with a post
/// (not with the seat) is kept in the post's plane by the frame kept
/// there, which the new profile turns against the plain anchor frame; the
/// check read the leg in the plain frame only and saw it 1.4e-6 m off.
/// The core was right: the leg keeps its coordinates in the frame it is
/// placed by. The check now accepts either frame
/// (`kept_in_a_siblings_plane`).
#[test]
fn chair_leg_kept_in_a_posts_plane_after_the_seat_is_bent() {
    regression(
        2,
        &[
            (4, [0.0, 0.0, 0.0, 0.0, 0.0, 0.0]),
            (0, [0.0, 0.0, 0.0, -0.49388340631091404, 0.0, 0.0]),
        ],
    );
}

/// Found by a 2,000-case run (GC_PROPS_SEED=14): after the teapot body's
/// section became a sketched loop, a spun copy of the spout was sunk
/// 0.9 mm deeper by the junction, along the body's inward normal
/// projected into the copy's spine plane, which the new profile had
/// turned off the anchor frame's `-x`. The core was right; the check
/// allowed sinking along `-x` only (`gc_props::checks::sink`).
#[test]
fn teapot_spun_spout_copy_sinks_in_its_own_plane() {
    regression(
        1,
        &[
            (
                4,
                [
                    0.0,
                    0.47613959775093617,
                    0.0,
                    0.0,
                    0.618677661477631,
                    0.8137548640804837,
                ],
            ),
            (
                10,
                [
                    0.3758116101295561,
                    0.0,
                    0.0,
                    -0.45931396114366924,
                    0.0,
                    0.8801736350783702,
                ],
            ),
        ],
    );
}
