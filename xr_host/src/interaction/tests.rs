//! Tests of the interaction step: stepping a trace matches the core's
//! replay bit for bit, commits apply in order off the frame, autosave and
//! its failures, a frame never waiting for a commit, and message wrapping.

use std::sync::mpsc;
use std::sync::Arc;
use std::time::{Duration, Instant};

use shapewright::doc::OpLog;
use shapewright::interact::{Similarity, TraceError};
use shapewright_usd::Autosaver;

use super::commit::*;
use super::frame::*;
use super::sink::*;
use crate::xr::frame_loop::note_input_stats;
use crate::xr::{FrameSink, LifecycleEvent, RunReport};
use shapewright::interact::{replay, Trace};
use shapewright_usd::{load_file, AutosaveSettings, LoadOptions, SaveOptions};

fn fixture() -> Trace {
    let p = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../tests/data/primitives_session.trace.jsonl"
    );
    Trace::from_jsonl(&std::fs::read_to_string(p).unwrap()).unwrap()
}

#[test]
fn stepping_a_trace_matches_the_core_replay_bit_for_bit() {
    let trace = fixture();
    let model = trace.header.model.similarity().unwrap();
    let mut it = Interaction::new(&trace.header.tool, model, OpLog::new(), None).unwrap();
    let mut rays = 0;
    for f in &trace.frames {
        it.step(f);
        it.flush();
        rays += usize::from(!it.scene().lines.is_empty());
    }
    let core = replay(&trace).unwrap();
    assert_eq!(it.stats().commands as usize, core.commands.len());
    assert_eq!(it.stats().rejected.len(), core.rejected.len());
    assert_eq!(it.log().len(), core.log.len());
    assert_eq!(
        it.log().document().content_hash(),
        core.log.document().content_hash()
    );
    // The scene follows: the document mesh has every object, and the
    // controllers' rays were drawn on most frames.
    let doc = it.scene().document.as_ref().unwrap();
    assert_eq!(
        doc.triangle_count(),
        core.log.document().combined_mesh().triangle_count()
    );
    assert!(rays * 2 >= trace.frames.len(), "{rays}");
    assert!(it.scene().version as usize > core.log.cursor());
}

/// Commits run off the frame, and the tool never acts on a document
/// older than the commands it made, however slow the commits: with no
/// flush per frame, and commits taking no extra time or 30 ms each (the
/// frames coming far faster), the tool makes the commands the core's
/// replay of the same input makes, every one is applied in order, and the
/// scene catches up. Before (2026-11-30) the tool stepped frames against
/// the last committed document: with 30 ms commits it made 6 commands
/// where the replay makes 9, and a loaded machine's host dragged the
/// original where the replay of its own recording dragged the duplicate
/// on top of it (`testrt` failed 3 tests when it ran beside another test
/// binary). The head, hands and controllers never wait: they are drawn
/// from the newest frame.
#[test]
fn slow_background_commits_do_not_change_what_the_tool_does() {
    let trace = fixture();
    let model = trace.header.model.similarity().unwrap();
    let core = replay(&trace).unwrap();
    // The scene a flush per frame leaves (what `replay` draws last).
    let mut each = Interaction::new(&trace.header.tool, model, OpLog::new(), None).unwrap();
    for f in &trace.frames {
        each.step(f);
        each.flush();
    }
    for slow in [0, 30] {
        let mut it = Interaction::new(&trace.header.tool, model, OpLog::new(), None).unwrap();
        it.send(Job::Slow(Duration::from_millis(slow)));
        let (mut returned, mut lagged, mut moved) = (0, 0, 0);
        for f in &trace.frames {
            returned += usize::from(it.step(f).is_some());
            // The head, hands and controllers are drawn from the newest
            // frame, while the tool's frames wait for a commit, and the
            // others see them there too.
            let drawn = it.drawn.clone().unwrap();
            assert_eq!(drawn.time, f.time);
            let (time, sent) = it.presence_now().unwrap();
            assert_eq!(time, f.time);
            assert_eq!(sent, it.session().presence_at(&drawn, sent.selected));
            lagged += usize::from(it.session().last_frame().map(|l| l.time) != Some(f.time));
            // Where the tool's last frame would have shown them.
            moved += usize::from(it.session().presence(sent.selected) != Some(sent));
        }
        if slow > 0 {
            assert!(lagged > 0, "no frame was held for a commit");
            assert!(moved > 0, "the held frames never moved the head or hands");
        }
        // The frames held for the last commits are stepped by the flush,
        // and the scene shows where they left the tool.
        it.flush();
        assert_eq!(it.scene().lines, each.scene().lines, "{slow} ms commits");
        assert_eq!(it.scene().ui, each.scene().ui, "{slow} ms commits");
        let what = format!("{slow} ms commits: {returned} commands made while stepping");
        assert_eq!(it.stats().commands as usize, core.commands.len(), "{what}");
        assert_eq!(it.stats().rejected.len(), core.rejected.len(), "{what}");
        assert_eq!(it.stats().commit_ms.len(), core.commands.len(), "{what}");
        let hash = it.log().document().content_hash();
        assert_eq!(hash, core.log.document().content_hash(), "{what}");
        assert_eq!(it.document().content_hash(), hash);
        let doc = it.scene().document.as_ref().unwrap();
        assert_eq!(
            doc.triangle_count(),
            core.log.document().combined_mesh().triangle_count()
        );
    }
}

/// A run's report counts the poses of every frame it received, also
/// those still held for a slow commit when the run ended: the counts are
/// read after the held frames are stepped. Shown to fail when they are
/// read first (20 lost heads in the last frames, 0 counted; `testrt`'s
/// NaN-pose test failed so on a loaded machine, 2026-12-01).
#[test]
fn a_run_that_ends_during_a_commit_counts_the_held_frames_poses() {
    let mut trace = fixture();
    let n = trace.frames.len();
    for f in &mut trace.frames[n - 20..] {
        f.head = None;
    }
    let model = trace.header.model.similarity().unwrap();
    let mut each = Interaction::new(&trace.header.tool, model, OpLog::new(), None).unwrap();
    for f in &trace.frames {
        each.step(f);
        each.flush();
    }
    let want = each.input_stats().unwrap();
    assert!(want.poses_untracked >= 20, "{want:?}");
    let mut it = Interaction::new(&trace.header.tool, model, OpLog::new(), None).unwrap();
    it.send(Job::Slow(Duration::from_millis(200)));
    for f in &trace.frames {
        it.step(f);
    }
    assert!(!it.held.is_empty(), "no frame was held at the end");
    let mut report = RunReport::default();
    note_input_stats(&mut report, &mut it);
    assert_eq!(report.input, Some(want));
    assert_eq!(
        report.poses_dropped,
        want.poses_untracked + want.poses_rejected
    );
}

#[test]
fn unknown_tools_are_typed_errors() {
    let e = Interaction::new("nope", Similarity::IDENTITY, OpLog::new(), None).err();
    assert!(matches!(e, Some(InteractionError::Tool(TraceError::UnknownTool(t))) if t.0 == "nope"));
}

#[test]
fn session_loss_saves_every_op_and_reopening_continues_the_history() {
    let dir = std::env::temp_dir().join(format!("sw_xr_interaction_{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("s.usda");
    let trace = fixture();
    let model = trace.header.model.similarity().unwrap();
    // Only the loss triggers a save: no op or time trigger fires.
    let settings = AutosaveSettings {
        every_ops: usize::MAX,
        every: std::time::Duration::from_secs(3600),
    };
    let saver = Autosaver::new(&path, settings, SaveOptions::default());
    let mut it = Interaction::new("object", model, OpLog::new(), Some(saver)).unwrap();
    let half = trace.frames.len() / 2;
    for f in &trace.frames[..half] {
        it.step(f);
    }
    assert!(!path.exists(), "nothing saved before the loss");
    let acknowledged = it.log().len();
    assert!(acknowledged >= 2, "{acknowledged}");
    it.lifecycle(&LifecycleEvent::SessionLost);
    let loaded = load_file(&path, LoadOptions::default()).unwrap();
    assert_eq!(loaded.log.len(), acknowledged);
    assert_eq!(
        loaded.log.document().content_hash(),
        it.log().document().content_hash()
    );
    // Continue from the file: the history is kept, new ops append to
    // it, the exit save has them all, and undo reaches back into the
    // saved history.
    let saver = Autosaver::new(&path, AutosaveSettings::default(), SaveOptions::default());
    let mut cont = Interaction::new("object", model, loaded.log, Some(saver)).unwrap();
    for f in &trace.frames[half..] {
        cont.step(f);
    }
    let kept = it.log().cursor();
    assert!(cont.log().len() > kept);
    assert_eq!(cont.log().ops()[..kept], it.log().ops()[..kept]);
    cont.save_now();
    let reopened = load_file(&path, LoadOptions::default()).unwrap();
    assert_eq!(reopened.log.ops(), cont.log().ops());
    assert_eq!(reopened.log.cursor(), cont.log().cursor());
    let mut log = reopened.log;
    while log.cursor() > 0 {
        log.undo().unwrap();
    }
    assert!(log.document().is_empty());
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn commits_pulse_the_hands_that_made_them() {
    let trace = fixture();
    let model = trace.header.model.similarity().unwrap();
    let mut it = Interaction::new(&trace.header.tool, model, OpLog::new(), None).unwrap();
    let mut pulses = Vec::new();
    for f in &trace.frames {
        it.step(f);
        it.flush();
        pulses.extend(it.take_haptics());
    }
    let commits = it.stats().commands as usize - it.stats().rejected.len();
    let strong: Vec<_> = pulses.iter().filter(|p| p.amplitude > 0.5).collect();
    assert!(commits >= 3, "{commits}");
    // At least one pulse per landed commit, on a real hand.
    assert!(strong.len() >= commits, "{} < {commits}", strong.len());
    assert!(strong.iter().all(|p| p.hand < 2 && p.millis > 0));
    // Ticks when a ray starts pointing at something.
    assert!(pulses.iter().any(|p| p.amplitude < 0.5));
    assert_eq!(it.stats().haptics as usize, pulses.len());
}

#[test]
fn a_failing_save_shows_in_the_headset_until_a_save_succeeds() {
    let dir = std::env::temp_dir().join(format!("sw_xr_notice_{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("s.usda");
    // A directory where the file should be: the atomic save's final
    // rename fails (whatever its temporary file is called).
    let blocker = path.clone();
    std::fs::create_dir(&blocker).unwrap();
    let trace = fixture();
    let model = trace.header.model.similarity().unwrap();
    let saver = Autosaver::new(&path, AutosaveSettings::default(), SaveOptions::default());
    let mut it = Interaction::new("object", model, OpLog::new(), Some(saver)).unwrap();
    let mut k = 0;
    while it.log().is_empty() {
        it.step(&trace.frames[k]);
        k += 1;
    }
    assert!(!it.save_now());
    let notes = it.notices();
    assert_eq!(notes.len(), 1);
    assert!(notes[0].warning && notes[0].text.starts_with("AUTOSAVE FAILED"));
    assert!(!it.stats().save_errors.is_empty());
    std::fs::remove_dir(&blocker).unwrap();
    assert!(it.save_now());
    assert!(it.notices().is_empty());
    let loaded = load_file(&path, LoadOptions::default()).unwrap();
    assert_eq!(loaded.log.len(), it.log().len());
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_frame_reads_its_notices_while_a_commit_holds_the_log() {
    // The commit thread holds the log while an op applies (a quarter
    // second for a GC edit); the frame's notices must not wait for it.
    let trace = fixture();
    let model = trace.header.model.similarity().unwrap();
    let it = Interaction::new("object", model, OpLog::new(), None).unwrap();
    let held = Arc::clone(&it.shared);
    let (locked_tx, locked) = mpsc::channel();
    let (release, release_rx) = mpsc::channel::<()>();
    let holder = std::thread::spawn(move || {
        let _guard = lock(&held);
        locked_tx.send(()).unwrap();
        let _ = release_rx.recv_timeout(Duration::from_secs(10));
    });
    locked.recv().unwrap();
    let t0 = Instant::now();
    let notes = it.notices();
    let waited = t0.elapsed();
    release.send(()).unwrap();
    holder.join().unwrap();
    assert!(notes.is_empty());
    assert!(
        waited < Duration::from_secs(5),
        "notices() waited {waited:?} for the log"
    );
}

#[test]
fn wrapped_messages_fit_the_width() {
    let w = wrap(
        "cannot author the USD layer: object #1: patch 4 has 6 sides and more words",
        20,
    );
    assert!(w.lines().all(|l| l.chars().count() <= 20), "{w}");
    assert!(w.starts_with("cannot author the"));
    assert_eq!(wrap(&"x".repeat(50), 20).lines().count(), 3);
    assert!(wrap(&"word ".repeat(100), 10).ends_with("..."));
}

/// The drawn document carries each object's own normals where its mesh
/// has them, and computed ones, bit for bit those of its part of the
/// combined mesh, where it has none (a GC assembly's union); only the
/// objects an edit changed have theirs computed again (kept normals are
/// reused exactly while an object's mesh is the same one).
#[test]
fn drawn_normals_are_each_objects_computed_once_per_changed_mesh() {
    use shapewright::doc::{parse_script, run_script_with, Document};
    let p = concat!(env!("CARGO_MANIFEST_DIR"), "/../tests/data/chair.jsonl");
    let mut text = std::fs::read_to_string(p).unwrap();
    // Two solids beside the chair (their meshes carry normals).
    text.push_str(concat!(
        "\n{\"op\":\"add_solid\",\"shape\":{\"kind\":\"box\",\"size\":[0.3,0.3,0.3]},",
        "\"transform\":{\"translate\":[1.0,0.0,0.15]}}\n",
        "{\"op\":\"add_solid\",\"shape\":{\"kind\":\"sphere\",\"radius\":0.17},",
        "\"transform\":{\"translate\":[1.5,0.0,0.17]}}\n",
    ));
    let mut log = OpLog::new();
    run_script_with(&mut log, &parse_script(&text).unwrap(), |_, _| {}).unwrap();
    // Each object's own normals, or those of the whole combined mesh
    // (what the host drew before) for the ones without.
    let expected = |doc: &Document| -> Vec<u64> {
        let mut out = Vec::new();
        for (_, o) in doc.objects() {
            let n = o.mesh.normals_or_computed();
            out.extend(n.iter().flatten().map(|x| x.to_bits()));
        }
        out
    };
    let same = |drawn: &DrawnDocument, doc: &Document| {
        let d = drawn.mesh.as_ref().unwrap();
        let bits: Vec<u64> = d.normals.iter().flatten().map(|x| x.to_bits()).collect();
        assert_eq!(d.normals.len(), d.positions.len());
        assert!(
            bits == expected(doc),
            "drawn normals differ from each object's"
        );
    };
    let bare = |doc: &Document| {
        doc.objects()
            .filter(|(_, o)| !o.mesh.has_vertex_normals())
            .count()
    };
    let doc = log.document();
    assert!(
        bare(doc) >= 1 && bare(doc) < doc.len(),
        "a union without normals and solids with"
    );
    let mut kept = DrawnNormals::default();
    same(&document_mesh(doc, &mut kept), doc);
    let first = kept.computed;
    assert_eq!(first, bare(doc));
    let turn = |log: &mut OpLog, id: u32| {
        let edit = format!(
            "{{\"op\":\"transform_by\",\"id\":{id},\"transform\":{{\"rotate\":[0.0,0.0,0.3826834323650898,0.9238795325112867]}}}}"
        );
        log.apply_command(&parse_script(&edit).unwrap()[0].command)
            .unwrap();
    };
    // Turning a solid computes nothing: the chair's normals are kept.
    let solid = log.document().objects().last().map(|(id, _)| id.0).unwrap();
    turn(&mut log, solid);
    same(&document_mesh(log.document(), &mut kept), log.document());
    assert_eq!(
        kept.computed, first,
        "an unchanged union's normals are kept"
    );
    // Turning the chair computes its normals again (and only its).
    turn(&mut log, 1);
    same(&document_mesh(log.document(), &mut kept), log.document());
    assert_eq!(kept.computed, first + 1);
    // Unchanged: nothing computed.
    same(&document_mesh(log.document(), &mut kept), log.document());
    assert_eq!(kept.computed, first + 1);
}
