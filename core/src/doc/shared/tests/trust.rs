//! Issue 35: authorship bound to the sender's subject, and snapshots
//! checked against the stream.

use super::*;

#[test]
fn subject_tokens_are_one_token_and_never_shared() {
    assert_eq!(subject_token("ana").as_deref(), Some("ana"));
    assert_eq!(subject_token("ana.b").as_deref(), Some("ana%2Eb"));
    assert_eq!(subject_token("ana_b-2").as_deref(), Some("ana_b-2"));
    for bad in ["", "a b", "a*", "a>", "a%2E", "é"] {
        assert_eq!(subject_token(bad), None, "{bad}");
    }
    for id in ["ana", "ana.b", "a.b.c", "x_y"] {
        let t = subject_token(id).unwrap();
        assert!(!t.contains('.'), "{t}");
        assert_eq!(id_from_token(&t).as_deref(), Some(id));
    }
    // `a_2Eb` and `a.b` stay apart; a bare `%` or a `.` is no token.
    assert_ne!(subject_token("a_2Eb"), subject_token("a.b"));
    for bad in ["a%2", "a%", "a.b", "a%2e", ""] {
        assert_eq!(id_from_token(bad), None, "{bad}");
    }
}

#[test]
fn an_entry_sent_on_another_persons_subject_is_refused_by_every_replica() {
    let mut sim = joined(3);
    let a = sim.log(0).apply(sphere(0.0)).unwrap().created.unwrap();
    sim.log(0).apply(nudge(a, 0.5)).unwrap();
    sim.quiesce();
    let before = sim.clients[0].0.document().content_hash();
    let p0_n = sim.clients[0]
        .0
        .confirmed()
        .participant("p0")
        .unwrap()
        .last_n;
    // p1 writes as p0 on its own subject: an undo of p0's nudge, an op,
    // a rejoin under p0's name; and as a newcomer.
    for bytes in [
        entry("p0", p0_n + 1, Body::Undo(p0_n)),
        entry(
            "p0",
            p0_n + 2,
            Body::Op {
                ids_from: None,
                op: delete(a),
            },
        ),
        entry(
            "p0",
            p0_n + 3,
            Body::Join {
                name: "Mallory".into(),
                colour: [1.0; 3],
            },
        ),
        entry(
            "p9",
            1,
            Body::Join {
                name: "p9".into(),
                colour: [1.0; 3],
            },
        ),
    ] {
        sim.server.inject_as("p1", &bytes);
    }
    sim.quiesce();
    for (c, _) in &sim.clients {
        assert_eq!(c.document().content_hash(), before, "{}", c.me());
        let skipped = c.confirmed().skipped();
        assert_eq!(skipped.len(), 4, "{skipped:?}");
        assert!(skipped
            .iter()
            .all(|s| s.reason.contains("was sent on the subject of `p1`")));
        assert_eq!(c.confirmed().participants().len(), 3);
        assert_eq!(c.confirmed().participant("p0").unwrap().name, "Person 0");
    }
    // Both the sender and the one it claimed to be are told.
    let told = |sim: &mut Sim, i: usize| {
        sim.log(i)
            .take_notices()
            .iter()
            .filter(|n| n.message.contains("claiming to be"))
            .count()
    };
    assert_eq!(told(&mut sim, 0), 3);
    assert_eq!(told(&mut sim, 1), 4);
    assert_eq!(told(&mut sim, 2), 0);
    // p0's own undo still works: the forged one took nothing.
    sim.log(0).undo().unwrap();
    sim.quiesce();
    let y = sim.clients[2]
        .0
        .document()
        .get(a)
        .unwrap()
        .transform()
        .translate[1];
    assert_eq!(y, 0.0);
    sim.check_converged();
}

/// A session of three with some history, and the stream's snapshot.
fn session_with_history() -> (Sim, ObjectId) {
    let mut sim = joined(3);
    let a = sim.log(0).apply(sphere(0.0)).unwrap().created.unwrap();
    let b = sim.log(1).apply(sphere(1.0)).unwrap().created.unwrap();
    sim.quiesce();
    for k in 0..6 {
        sim.log(k % 2)
            .apply(nudge(if k % 2 == 0 { a } else { b }, 0.1))
            .unwrap();
        sim.quiesce();
    }
    sim.log(1).undo().unwrap();
    sim.quiesce();
    (sim, a)
}

fn replay(sim: &Sim, upto: usize) -> Replica {
    let mut r = Replica::new();
    for (i, (from, m)) in sim.server.msgs[..upto].iter().enumerate() {
        r.integrate(i as u64 + 1, from, m);
    }
    r
}

fn check(sim: &Sim, seq: u64, claimed: Vec<u8>) -> Verdict {
    let mut check = SnapshotCheck::new(seq, claimed);
    for (i, (from, m)) in sim.server.msgs.iter().enumerate() {
        if let Some(v) = check.feed(i as u64 + 1, from, m) {
            return v;
        }
    }
    check.verdict()
}

#[test]
fn an_honest_snapshot_is_the_streams_byte_for_byte() {
    let (sim, _) = session_with_history();
    let seq = sim.server.msgs.len() as u64;
    // Written by a participant who replayed, and by one who itself joined
    // from a snapshot: both are the replay's.
    let written = sim.clients[2].0.confirmed().snapshot();
    assert!(matches!(check(&sim, seq, written.clone()), Verdict::Same));
    let restored = Replica::from_snapshot(&written).unwrap();
    assert!(matches!(
        check(&sim, seq, restored.snapshot()),
        Verdict::Same
    ));
    let mid = replay(&sim, 5);
    assert!(matches!(check(&sim, 5, mid.snapshot()), Verdict::Same));
}

#[test]
fn a_forged_snapshot_is_replaced_by_the_streams_document() {
    let (mut sim, a) = session_with_history();
    let seq = sim.server.msgs.len() as u64;
    // Forgeries: an empty replica at the stream's sequence; the true one
    // with one op flipped to undone.
    let mut empty = Replica::new();
    empty.skip_to(seq);
    let honest = String::from_utf8(sim.clients[0].0.confirmed().snapshot()).unwrap();
    let flipped = honest.replacen("\"undone\":false", "\"undone\":true", 1);
    assert_ne!(flipped, honest);
    for (k, forged) in [empty.snapshot(), flipped.into_bytes()]
        .into_iter()
        .enumerate()
    {
        let me = format!("late{k}");
        let restored = Replica::from_snapshot(&forged).unwrap();
        assert_eq!(restored.last_seq(), seq);
        // The joiner starts from it: its join goes out, it creates
        // something on what it sees, and others go on meanwhile.
        let mut joiner = SharedLog::resume(&me, "Late", [0.3; 3], restored, 1).unwrap();
        let mut live = Vec::new();
        let deliver = |joiner: &mut SharedLog, sim: &Sim, live: &mut Vec<_>| {
            for s in joiner.confirmed().last_seq() + 1..=sim.server.msgs.len() as u64 {
                let (from, m) = sim.server.msgs[s as usize - 1].clone();
                joiner.integrate(s, &from, &m);
                live.push((s, from, m));
            }
        };
        deliver(&mut joiner, &sim, &mut live);
        let p = joiner.next_publish().unwrap();
        let r = sim.server.append(&me, &p);
        assert!(matches!(r, client::Published::Stored(_)), "{r:?}");
        joiner.published(p.n, r);
        sim.log(0).apply(nudge(a, 0.25)).unwrap();
        sim.quiesce();
        deliver(&mut joiner, &sim, &mut live);
        joiner.apply(sphere(5.0 + k as f64)).unwrap();
        let streams = sim.clients[0].0.document().content_hash();
        // The empty one shows at once; the flipped flag lies in wait for
        // the next replay (an undo near it) to show.
        if k == 0 {
            let shown = joiner.confirmed().document().content_hash();
            assert_ne!(shown, streams, "{me}: the forgery shows");
        }
        let verdict = check(&sim, seq, forged.clone());
        assert!(matches!(verdict, Verdict::Differs(_)), "{me}");
        assert!(verdict.settle(&mut joiner, &live, "forged"));
        assert_eq!(
            joiner.confirmed().document().content_hash(),
            streams,
            "{me}"
        );
        assert_eq!(
            joiner.confirmed().op_states(),
            sim.clients[0].0.confirmed().op_states()
        );
        let notices = joiner.take_notices();
        assert!(
            notices.iter().any(|n| n.kind == NoticeKind::Replaced),
            "{notices:?}"
        );
        // The joiner goes on as anyone else: its own id range, its undo.
        let mine = joiner.apply(sphere(7.0)).unwrap().created.unwrap();
        assert_eq!(mine.0 >> ID_RANGE_BITS, 4 + k as u32);
        sim.clients.push((joiner, sim.server.msgs.len() as u64));
        sim.quiesce();
        sim.check_converged();
        sim.log(3).undo().unwrap();
        sim.quiesce();
        sim.check_converged();
        sim.clients.pop();
    }
}

#[test]
fn a_snapshot_past_the_streams_end_or_short_of_it_differs() {
    let (sim, _) = session_with_history();
    let seq = sim.server.msgs.len() as u64;
    let mut ahead = replay(&sim, seq as usize);
    ahead.skip_to(seq + 5);
    assert!(matches!(
        check(&sim, seq + 5, ahead.snapshot()),
        Verdict::Differs(_)
    ));
    let early = replay(&sim, 4);
    assert!(matches!(
        check(&sim, 5, early.snapshot()),
        Verdict::Differs(_)
    ));
}
