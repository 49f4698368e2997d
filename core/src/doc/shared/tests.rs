//! Shared-session semantics against an in-process sequencer that behaves
//! as JetStream does for us (one total order, appends conditional on the
//! last sequence, de-duplication by message id). The real server is
//! exercised by `shapewright-net`'s tests; these pin the rules.

use std::collections::BTreeMap;

use proptest::prelude::*;

use super::*;
use crate::doc::{ObjectId, Op, OpLog};

mod trust;

/// The stream: messages in order with their subject's last token (the
/// sender), message ids seen.
#[derive(Default)]
struct Server {
    msgs: Vec<(String, Vec<u8>)>,
    ids: BTreeMap<String, u64>,
}

impl Server {
    /// `p`, appended on `from`'s subject.
    fn append(&mut self, from: &str, p: &Publish) -> client::Published {
        if let Some(&seq) = self.ids.get(&p.msg_id) {
            return client::Published::Stored(seq);
        }
        if p.expected_last_seq != self.msgs.len() as u64 {
            return client::Published::Conflict;
        }
        self.msgs
            .push((subject_token(from).unwrap(), p.bytes.clone()));
        let seq = self.msgs.len() as u64;
        self.ids.insert(p.msg_id.clone(), seq);
        client::Published::Stored(seq)
    }

    /// A raw message nobody checked (a hostile or broken client), sent on
    /// the subject of the author it names (`someone` when it names none).
    fn inject(&mut self, bytes: &[u8]) {
        let author = serde_json::from_slice::<serde_json::Value>(bytes)
            .ok()
            .and_then(|v| v["author"].as_str().and_then(subject_token))
            .unwrap_or_else(|| "someone".into());
        self.inject_as(&author, bytes);
    }

    /// A raw message on the subject whose last token is `from`.
    fn inject_as(&mut self, from: &str, bytes: &[u8]) {
        self.msgs.push((from.to_string(), bytes.to_vec()));
    }
}

struct Sim {
    server: Server,
    clients: Vec<(SharedLog, u64)>,
}

impl Sim {
    fn new(n: usize) -> Self {
        let clients = (0..n)
            .map(|i| {
                let me = format!("p{i}");
                let log = SharedLog::new(&me, &format!("Person {i}"), [0.2, 0.5, 0.9]).unwrap();
                (log, 0)
            })
            .collect();
        Self {
            server: Server::default(),
            clients,
        }
    }

    /// Client `i` receives the stream up to `upto` (or all).
    fn deliver(&mut self, i: usize, upto: Option<u64>) {
        let end = upto.unwrap_or(u64::MAX).min(self.server.msgs.len() as u64);
        let (c, seen) = &mut self.clients[i];
        while *seen < end {
            *seen += 1;
            let (from, bytes) = &self.server.msgs[*seen as usize - 1];
            c.integrate(*seen, from, bytes);
        }
    }

    /// Client `i` appends what it may (one conflict ends the round).
    fn publish(&mut self, i: usize) {
        let (c, _) = &mut self.clients[i];
        while let Some(p) = c.next_publish() {
            let r = self.server.append(c.me(), &p);
            c.published(p.n, r);
            if r == client::Published::Conflict {
                break;
            }
        }
    }

    fn quiesce(&mut self) {
        for _ in 0..10_000 {
            for i in 0..self.clients.len() {
                self.deliver(i, None);
                self.publish(i);
            }
            let busy = self.clients.iter().any(|(c, _)| c.pending_count() > 0);
            if !busy {
                for i in 0..self.clients.len() {
                    self.deliver(i, None);
                }
                return;
            }
        }
        panic!("the session did not quiesce");
    }

    fn log(&mut self, i: usize) -> &mut SharedLog {
        &mut self.clients[i].0
    }

    /// Every replica equals a single replay of the stream; returns its hash.
    fn check_converged(&self) -> u64 {
        let mut solo = Replica::new();
        for (i, (from, m)) in self.server.msgs.iter().enumerate() {
            solo.integrate(i as u64 + 1, from, m);
        }
        let want = solo.document().content_hash();
        for (c, _) in &self.clients {
            assert_eq!(c.pending_count(), 0);
            assert_eq!(c.confirmed().document().content_hash(), want, "{}", c.me());
            assert_eq!(c.document().content_hash(), want, "{}'s view", c.me());
            assert_eq!(c.confirmed().op_states(), solo.op_states());
        }
        // Saved as single-user history, it replays to the same bits.
        let linear = self.clients[0].0.linear_log().unwrap();
        let replayed = OpLog::replay(linear.ops().to_vec(), linear.len()).unwrap();
        assert_eq!(replayed.document().content_hash(), want);
        // Every object's id lies in the range of the one who made it.
        for (id, _) in solo.document().objects() {
            let slot = id.0 >> ID_RANGE_BITS;
            let seeded = slot == 0
                && solo
                    .linear_ops()
                    .first()
                    .is_some_and(|o| o.name() != "reserve_ids");
            assert!(
                seeded || (slot >= 1 && slot <= solo.participants().len() as u32),
                "{id}"
            );
        }
        want
    }
}

fn op(json: &str) -> Op {
    serde_json::from_str(json).unwrap()
}

fn sphere(x: f64) -> Op {
    op(&format!(
        r#"{{"op":"add_solid","shape":{{"kind":"sphere","radius":0.1}},"segments":8,"transform":{{"translate":[{x},0,0]}}}}"#
    ))
}

fn nudge(id: ObjectId, dy: f64) -> Op {
    op(&format!(
        r#"{{"op":"transform_by","id":{},"transform":{{"translate":[0,{dy},0]}}}}"#,
        id.0
    ))
}

fn delete(id: ObjectId) -> Op {
    op(&format!(r#"{{"op":"delete","id":{}}}"#, id.0))
}

/// The bytes of a version-[`ENTRY_VERSION`] entry on base 0 (also used
/// by the `trust` tests).
fn entry(author: &str, n: u64, body: Body) -> Vec<u8> {
    Entry::new(author, n, 0, body).to_bytes()
}

/// A session where everyone has joined.
fn joined(n: usize) -> Sim {
    let mut sim = Sim::new(n);
    sim.quiesce();
    for (c, _) in &sim.clients {
        assert!(c.is_joined());
    }
    sim
}

#[test]
fn each_person_undoes_only_their_own_ops() {
    let mut sim = joined(2);
    let a = sim.log(0).apply(sphere(0.0)).unwrap().created.unwrap();
    let b = sim.log(1).apply(sphere(1.0)).unwrap().created.unwrap();
    sim.quiesce();
    assert_ne!(a, b);
    assert_eq!(a.0 >> ID_RANGE_BITS, 1);
    assert_eq!(b.0 >> ID_RANGE_BITS, 2);
    // B's edit is the latest in the stream; A's undo still takes back A's.
    sim.log(1).apply(nudge(b, 0.5)).unwrap();
    sim.quiesce();
    sim.log(0).undo().unwrap();
    sim.quiesce();
    let doc = sim.clients[1].0.document().clone();
    assert!(doc.get(a).is_err(), "A's sphere is undone");
    assert_eq!(doc.get(b).unwrap().transform().translate, [1.0, 0.5, 0.0]);
    // B's undo takes back B's nudge, not A's undo.
    sim.log(1).undo().unwrap();
    sim.quiesce();
    let doc = sim.clients[0].0.document().clone();
    assert_eq!(doc.get(b).unwrap().transform().translate, [1.0, 0.0, 0.0]);
    // A's redo brings the sphere back with its id.
    sim.log(0).redo().unwrap();
    sim.quiesce();
    assert!(sim.clients[1].0.document().get(a).is_ok());
    assert_eq!(sim.log(0).redo(), Err(SharedError::NothingToRedo));
    sim.check_converged();
}

#[test]
fn an_op_that_needed_an_undone_op_is_skipped_and_restored_with_notices() {
    let mut sim = joined(2);
    let a = sim.log(0).apply(sphere(0.0)).unwrap().created.unwrap();
    sim.quiesce();
    sim.log(1).apply(nudge(a, 0.25)).unwrap();
    sim.quiesce();
    let _ = sim.log(1).take_notices();
    sim.log(0).undo().unwrap();
    sim.quiesce();
    let notices = sim.log(1).take_notices();
    assert_eq!(notices.len(), 1, "{notices:?}");
    assert_eq!(notices[0].kind, NoticeKind::Skipped);
    assert!(
        notices[0].message.contains("does not exist"),
        "{}",
        notices[0].message
    );
    assert!(
        sim.log(0).take_notices().is_empty(),
        "notices go to their author only"
    );
    // B has nothing in effect to undo now: its nudge is skipped.
    assert!(!sim.clients[1].0.can_undo());
    sim.log(0).redo().unwrap();
    sim.quiesce();
    let notices = sim.log(1).take_notices();
    assert_eq!(notices[0].kind, NoticeKind::Restored);
    let doc = sim.clients[0].0.document();
    assert_eq!(doc.get(a).unwrap().transform().translate, [0.0, 0.25, 0.0]);
    sim.check_converged();
}

#[test]
fn concurrent_creations_keep_their_ids_through_a_rebase() {
    let mut sim = joined(2);
    // Both create before seeing each other; B then names its own object.
    let a = sim.log(0).apply(sphere(0.0)).unwrap().created.unwrap();
    let b = sim.log(1).apply(sphere(1.0)).unwrap().created.unwrap();
    sim.log(1).apply(nudge(b, 0.5)).unwrap();
    sim.publish(0);
    sim.publish(1); // conflicts: A's landed first
    assert_eq!(sim.clients[1].0.pending_count(), 2);
    sim.quiesce();
    let doc = sim.clients[0].0.document();
    assert_eq!(doc.len(), 2);
    assert!(doc.get(a).is_ok());
    assert_eq!(doc.get(b).unwrap().transform().translate, [1.0, 0.5, 0.0]);
    sim.check_converged();
}

#[test]
fn a_pending_op_that_no_longer_applies_is_refused_for_its_author() {
    let mut sim = joined(2);
    let a = sim.log(0).apply(sphere(0.0)).unwrap().created.unwrap();
    sim.quiesce();
    // A deletes the sphere while B, not having seen that, moves it.
    sim.log(0).apply(delete(a)).unwrap();
    sim.log(1).apply(nudge(a, 0.5)).unwrap();
    sim.publish(0);
    sim.quiesce();
    let notices = sim.log(1).take_notices();
    assert_eq!(notices.len(), 1, "{notices:?}");
    assert_eq!(notices[0].kind, NoticeKind::Refused);
    assert!(
        notices[0].message.contains("no longer applies"),
        "{}",
        notices[0].message
    );
    // It never reached the stream: join, join, create, delete.
    assert_eq!(sim.server.msgs.len(), 4);
    sim.check_converged();
}

#[test]
fn an_offline_participant_keeps_working_and_rebases_on_reconnect() {
    let mut sim = joined(2);
    let a = sim.log(0).apply(sphere(0.0)).unwrap().created.unwrap();
    sim.quiesce();
    // B is cut off: it edits, undoes, creates, names its creation.
    let mut made = Vec::new();
    for k in 0..5 {
        let id = sim
            .log(1)
            .apply(sphere(1.0 + k as f64))
            .unwrap()
            .created
            .unwrap();
        sim.log(1).apply(nudge(id, 0.1)).unwrap();
        made.push(id);
    }
    sim.log(1).undo().unwrap();
    sim.log(1).apply(nudge(a, 0.3)).unwrap();
    // Meanwhile A goes on.
    for _ in 0..3 {
        sim.log(0).apply(nudge(a, 0.01)).unwrap();
        sim.publish(0);
    }
    assert_eq!(sim.clients[1].0.pending_count(), 12);
    sim.quiesce();
    let doc = sim.clients[0].0.document();
    assert_eq!(doc.len(), 6);
    for &id in &made[..4] {
        assert_eq!(doc.get(id).unwrap().transform().translate[1], 0.1);
    }
    assert_eq!(
        doc.get(made[4]).unwrap().transform().translate[1],
        0.0,
        "undone nudge"
    );
    let y = doc.get(a).unwrap().transform().translate[1];
    assert!((y - 0.33).abs() < 1e-12, "{y}");
    sim.check_converged();
}

#[test]
fn hostile_and_broken_messages_are_skipped_identically_everywhere() {
    let mut sim = joined(2);
    let a = sim.log(0).apply(sphere(0.0)).unwrap().created.unwrap();
    sim.quiesce();
    let before = sim.clients[0].0.document().content_hash();
    let nan = String::from_utf8(entry(
        "p0",
        90,
        Body::Op {
            ids_from: None,
            op: nudge(a, 0.1),
        },
    ))
    .unwrap()
    .replace("0.1", "1e300");
    assert!(nan.contains("1e300"), "{nan}");
    let huge = vec![b' '; MAX_ENTRY_BYTES + 1];
    let bad: Vec<(Vec<u8>, &str)> = vec![
        (b"{not json".to_vec(), "not an entry"),
        (huge, "larger than"),
        (
            entry(
                "mallory",
                1,
                Body::Op {
                    ids_from: None,
                    op: delete(a),
                },
            ),
            "has not joined",
        ),
        (entry("p1", 50, Body::Undo(2)), "no op 2"),
        (
            entry(
                "p1",
                51,
                Body::Op {
                    ids_from: Some(5),
                    op: sphere(3.0),
                },
            ),
            "outside the id range",
        ),
        (
            entry(
                "p1",
                52,
                Body::Op {
                    ids_from: None,
                    op: sphere(3.0),
                },
            ),
            "outside the id range",
        ),
        (
            entry(
                "p1",
                53,
                Body::Op {
                    ids_from: Some(id_range(1).0),
                    op: sphere(3.0),
                },
            ),
            "outside the id range",
        ),
        (
            entry(
                "p0",
                1,
                Body::Op {
                    ids_from: None,
                    op: delete(a),
                },
            ),
            "duplicate",
        ),
        (nan.into_bytes(), "field"),
        (
            entry("p1", 54, Body::Seed(vec![sphere(0.0)])),
            "first op entry",
        ),
        (
            entry(
                "p1",
                55,
                Body::Join {
                    name: "x\u{7}".into(),
                    colour: [0.0; 3],
                },
            ),
            "control",
        ),
    ];
    for (bytes, _) in &bad {
        sim.server.inject(bytes);
    }
    sim.quiesce();
    for (c, _) in &sim.clients {
        assert_eq!(c.document().content_hash(), before);
        let skipped = c.confirmed().skipped();
        assert_eq!(skipped.len(), bad.len());
        for (s, (_, why)) in skipped.iter().zip(&bad) {
            assert!(s.reason.contains(why), "{} lacks `{why}`", s.reason);
        }
    }
    // The session goes on.
    sim.log(1).apply(nudge(a, 0.5)).unwrap();
    sim.quiesce();
    sim.check_converged();
}

#[test]
fn a_participant_the_server_refuses_only_views_and_changes_nothing() {
    let mut sim = joined(2);
    let a = sim.log(0).apply(sphere(0.0)).unwrap().created.unwrap();
    sim.quiesce();
    let before = sim.clients[0].0.document().content_hash();
    // B edits, and the server refuses B's append (B may only view).
    let b = sim.log(1).apply(sphere(1.0)).unwrap().created.unwrap();
    assert!(sim.clients[1].0.document().get(b).is_ok());
    sim.log(1)
        .deny("permissions violation for publish to sw.doc.log");
    let viewer = &mut sim.clients[1].0;
    assert_eq!(viewer.pending_count(), 0);
    assert_eq!(viewer.document().content_hash(), before, "B's edit is gone");
    let notices = viewer.take_notices();
    assert_eq!(notices.len(), 1, "{notices:?}");
    assert_eq!(notices[0].kind, NoticeKind::Refused);
    assert!(notices[0].message.contains("only view"));
    assert!(viewer.view_only().is_some());
    for refused in [
        viewer.apply(nudge(a, 1.0)).map(|_| ()),
        viewer.undo(),
        viewer.redo(),
        viewer.seed(vec![sphere(2.0)]),
    ] {
        assert!(
            matches!(refused, Err(SharedError::ViewOnly(_))),
            "{refused:?}"
        );
    }
    assert!(viewer.next_publish().is_none());
    // A's later edits still reach B.
    sim.log(0).apply(nudge(a, 0.5)).unwrap();
    sim.quiesce();
    let doc = sim.clients[1].0.document().clone();
    assert_eq!(doc.get(a).unwrap().transform().translate, [0.0, 0.5, 0.0]);
    assert!(doc.get(b).is_err());
    sim.check_converged();
}

#[test]
fn duplicate_publishes_land_once() {
    let mut sim = joined(2);
    sim.log(0).apply(sphere(0.0)).unwrap();
    let p = sim.log(0).next_publish().unwrap();
    let first = sim.server.append("p0", &p);
    // The ack was lost: the same message goes again, twice.
    assert_eq!(sim.server.append("p0", &p), first);
    sim.log(0).published(p.n, client::Published::Failed);
    sim.log(0).connection_lost();
    sim.quiesce();
    assert_eq!(sim.server.msgs.len(), 3);
    // A message landing twice anyway (outside the server's window) is
    // skipped as a duplicate by every replica.
    let (from, again) = sim.server.msgs[2].clone();
    sim.server.inject_as(&from, &again);
    sim.quiesce();
    assert!(sim.clients[1].0.confirmed().skipped()[0]
        .reason
        .contains("duplicate"));
    assert_eq!(sim.clients[1].0.document().len(), 1);
    sim.check_converged();
}

#[test]
fn two_writers_racing_on_one_object_converge() {
    let mut sim = joined(2);
    let a = sim.log(0).apply(sphere(0.0)).unwrap().created.unwrap();
    sim.quiesce();
    for k in 0..1000 {
        sim.log(0).apply(nudge(a, 0.001)).unwrap();
        sim.log(1).apply(nudge(a, -0.0005)).unwrap();
        if k % 7 == 0 {
            sim.log(1).undo().unwrap();
        }
        let first = k % 2;
        sim.publish(first);
        sim.publish(1 - first);
        sim.deliver(0, None);
        sim.deliver(1, None);
    }
    sim.quiesce();
    sim.check_converged();
    let y = sim.clients[0]
        .0
        .document()
        .get(a)
        .unwrap()
        .transform()
        .translate[1];
    let undone = (0..1000).filter(|k| k % 7 == 0).count() as f64;
    let want = 1000.0 * 0.001 - (1000.0 - undone) * 0.0005;
    assert!((y - want).abs() < 1e-9, "{y} vs {want}");
}

#[test]
fn an_undo_near_the_head_replays_from_a_nearby_checkpoint() {
    let mut sim = joined(2);
    let a = sim.log(0).apply(sphere(0.0)).unwrap().created.unwrap();
    sim.quiesce();
    for _ in 0..600 {
        sim.log(0).apply(nudge(a, 0.001)).unwrap();
        sim.publish(0);
        sim.deliver(0, None);
    }
    sim.log(1).apply(nudge(a, 1.0)).unwrap();
    sim.quiesce();
    let r = sim.clients[0].0.confirmed();
    assert!(
        r.checkpoint_count() <= 20,
        "{} checkpoints",
        r.checkpoint_count()
    );
    let before = sim.clients[0].0.confirmed().ops_replayed();
    sim.log(0).undo().unwrap();
    sim.quiesce();
    let replayed = sim.clients[0].0.confirmed().ops_replayed() - before;
    let every = crate::doc::CheckpointPolicy::default().every_ops as u64;
    assert!(
        replayed <= every + 2,
        "{replayed} ops replayed for an undo near the head"
    );
    sim.check_converged();
}

#[test]
fn a_seeded_session_keeps_the_files_ids_and_history() {
    let mut solo = OpLog::new();
    solo.apply(sphere(0.0)).unwrap();
    solo.apply(sphere(1.0)).unwrap();
    let mut sim = Sim::new(2);
    sim.quiesce();
    sim.log(0).seed(solo.ops().to_vec()).unwrap();
    sim.quiesce();
    let doc = sim.clients[1].0.document();
    assert_eq!(doc.content_hash(), solo.document().content_hash());
    let c = sim.log(1).apply(sphere(2.0)).unwrap().created.unwrap();
    sim.log(1).apply(nudge(ObjectId(1), 0.5)).unwrap();
    sim.quiesce();
    assert_eq!(c.0, id_range(2).0);
    // The seed is nobody's to undo.
    sim.log(0).undo().unwrap_err();
    sim.check_converged();
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 48, ..ProptestConfig::default() })]

    /// Random edits, undos, redos, partial deliveries and publishes by 2
    /// to 16 people: after quiescence every replica equals one replay of
    /// the stream, bit for bit.
    #[test]
    fn random_sessions_converge(seed in any::<u64>(), people in 2usize..=16) {
        let mut rng = seed | 1;
        let mut next = move |n: u64| {
            rng ^= rng << 13;
            rng ^= rng >> 7;
            rng ^= rng << 17;
            rng % n
        };
        let mut sim = Sim::new(people);
        for _ in 0..(12 * people) {
            let i = next(people as u64) as usize;
            let ids: Vec<ObjectId> = sim.clients[i].0.document().objects().map(|(id, _)| id).collect();
            let pick = |k: u64| ids.get(k as usize % ids.len().max(1)).copied();
            let _ = match next(9) {
                0 | 1 => sim.log(i).apply(sphere(next(100) as f64 / 10.0)).map(|_| ()),
                2 | 3 => match pick(next(64)) {
                    Some(id) => sim.log(i).apply(nudge(id, 0.01)).map(|_| ()),
                    None => Ok(()),
                },
                4 => match pick(next(64)) {
                    Some(id) => sim.log(i).apply(delete(id)).map(|_| ()),
                    None => Ok(()),
                },
                5 => sim.log(i).undo(),
                6 => sim.log(i).redo(),
                7 => {
                    let upto = sim.clients[i].1 + next(4);
                    sim.deliver(i, Some(upto));
                    Ok(())
                }
                _ => {
                    sim.publish(i);
                    Ok(())
                }
            };
        }
        sim.quiesce();
        sim.check_converged();
    }
}

#[test]
fn an_oplog_can_be_one_persons_side_of_a_session() {
    let mut sim = joined(2);
    let a = sim.log(0).apply(sphere(0.0)).unwrap().created.unwrap();
    sim.quiesce();
    // B's host holds an ordinary OpLog backed by its shared log.
    let (b, seen) = sim.clients.remove(1);
    let mut log = OpLog::from_shared(b);
    log.apply(nudge(a, 0.5)).unwrap();
    let b_ball = log.apply(sphere(1.0)).unwrap().created.unwrap();
    assert_eq!(b_ball.0 >> ID_RANGE_BITS, 2);
    assert_eq!(log.document().get(a).unwrap().transform().translate[1], 0.5);
    // Its history is the session's document as single-user ops.
    let names: Vec<&str> = log.ops().iter().map(Op::name).collect();
    assert_eq!(
        names,
        [
            "reserve_ids",
            "add_solid",
            "transform_by",
            "reserve_ids",
            "add_solid"
        ]
    );
    assert_eq!(log.cursor(), log.len());
    assert!(matches!(log.seek(1), Err(crate::doc::LogError::Shared(_))));
    log.undo().unwrap();
    assert!(log.document().get(b_ball).is_err());
    assert!(log.can_redo());
    let mut back = log.shared().unwrap().clone();
    let replayed = OpLog::replay(log.ops().to_vec(), log.len()).unwrap();
    assert_eq!(
        replayed.document().content_hash(),
        log.document().content_hash()
    );
    // Its entries reach the others.
    log.with_shared(|s| std::mem::swap(s, &mut back)).unwrap();
    sim.clients.insert(1, (back, seen));
    sim.quiesce();
    assert_eq!(
        sim.clients[0]
            .0
            .document()
            .get(a)
            .unwrap()
            .transform()
            .translate[1],
        0.5
    );
    sim.check_converged();
}

/// Issue 33: a build from before the fused copy's fold ignores
/// `UserMesh::fused` and computes another copy from the same op, so two
/// builds in one session would silently hold different models. The
/// entry version says what the ops compute: history written by an older
/// build replays here, but once a newer build has written to the session
/// an older build's entries are refused, with a notice that says why,
/// and a late joiner from a snapshot refuses the same ones.
#[test]
fn an_older_builds_entries_are_refused_once_a_newer_build_has_written() {
    let mut r = Replica::new();
    let mut seq = 0;
    let mut feed = |r: &mut Replica, v: u32, author: &str, n: u64, body: Body| {
        let mut e = Entry::new(author, n, 0, body);
        e.v = v;
        seq += 1;
        let from = subject_token(author).unwrap();
        r.integrate(seq, &from, &e.to_bytes()).result.map(|_| ())
    };
    let join = |name: &str| Body::Join {
        name: name.into(),
        colour: [0.5; 3],
    };
    let add = |r: &Replica, author: &str, x: f64| Body::Op {
        ids_from: r.next_free_id(author),
        op: sphere(x),
    };
    // A session an older build wrote replays here.
    feed(&mut r, 1, "old", 1, join("Old")).unwrap();
    let body = add(&r, "old", 0.0);
    feed(&mut r, 1, "old", 2, body).unwrap();
    assert_eq!(r.document().len(), 1);
    // A newer build's entry that is itself refused (its author never
    // joined) does not shut the older build out.
    let body = add(&r, "old", 0.5);
    let ghost = Body::Op {
        ids_from: None,
        op: delete(ObjectId(1)),
    };
    let err = feed(&mut r, ENTRY_VERSION, "ghost", 1, ghost).unwrap_err();
    assert!(err.to_string().contains("has not joined"), "{err}");
    feed(&mut r, 1, "old", 3, body).unwrap();
    assert_eq!(r.document().len(), 2);
    // A newer build joins and edits; the older build's next edit is
    // refused, and its author is told why.
    feed(&mut r, ENTRY_VERSION, "new", 1, join("New")).unwrap();
    let body = add(&r, "new", 1.0);
    feed(&mut r, ENTRY_VERSION, "new", 2, body).unwrap();
    r.take_notices();
    let body = add(&r, "old", 2.0);
    let err = feed(&mut r, 1, "old", 4, body.clone()).unwrap_err();
    assert!(err.to_string().contains("older Shapewright"), "{err}");
    assert_eq!(r.document().len(), 3);
    let notices = r.take_notices();
    assert_eq!(notices.len(), 1);
    assert_eq!(notices[0].author, "old");
    assert!(notices[0].message.contains("update Shapewright"));
    // A version this build does not know is refused too.
    let body3 = add(&r, "new", 3.0);
    let err = feed(&mut r, ENTRY_VERSION + 1, "new", 3, body3).unwrap_err();
    assert!(err.to_string().contains("entry format version"), "{err}");
    // A late joiner starts from the snapshot and refuses what the others
    // refuse.
    let mut late = Replica::from_snapshot(&r.snapshot()).unwrap();
    let err = feed(&mut late, 1, "old", 5, body).unwrap_err();
    assert!(err.to_string().contains("older Shapewright"), "{err}");
    let body = add(&late, "new", 4.0);
    feed(&mut late, ENTRY_VERSION, "new", 4, body).unwrap();
    assert_eq!(late.document().len(), 4);
}
