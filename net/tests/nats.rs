//! Shared sessions against a real `nats-server -js` on 127.0.0.1 (issue
//! 23's tests): many people editing one document converge to one replay
//! of the stream; a server killed mid-session loses nothing committed; a
//! participant cut off for 10 s keeps editing and rebases; duplicates
//! land once; two writers race on one object; hostile messages are
//! skipped identically everywhere.

mod common;

use std::time::{Duration, Instant};

use common::*;
use shapewright::doc::shared::{
    Body, Entry, NoticeKind, Replica, SharedError, SharedLog, MAX_ENTRY_BYTES,
};
use shapewright::doc::ObjectId;
use shapewright_net::access::{server_config, Member};
use shapewright_net::{Link, LinkError, LinkOptions, SnapshotState};

/// A tiny deterministic generator (the tests' randomness).
struct Rng(u64);

impl Rng {
    fn below(&mut self, n: u64) -> u64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        self.0 % n
    }
}

/// Person `i` does something random: create, nudge, delete, undo, redo.
fn random_edit(p: &mut Person, rng: &mut Rng) {
    let ids: Vec<ObjectId> = p.log.document().objects().map(|(id, _)| id).collect();
    let pick = |k: u64| ids.get(k as usize % ids.len().max(1)).copied();
    let _ = match rng.below(8) {
        0 | 1 => p
            .log
            .apply(sphere(rng.below(100) as f64 / 10.0))
            .map(|_| ()),
        2..=4 => match pick(rng.below(64)) {
            Some(id) => p.log.apply(nudge(id, 0.01)).map(|_| ()),
            None => Ok(()),
        },
        5 => match pick(rng.below(64)) {
            Some(id) => p.log.apply(delete(id)).map(|_| ()),
            None => Ok(()),
        },
        6 => p.log.undo(),
        _ => p.log.redo(),
    };
}

fn session(people: usize, edits_each: usize, seed: u64) {
    let server = Server::start();
    let url = server.url("converge");
    let mut ps: Vec<Person> = (0..people)
        .map(|i| Person::join(&url, &format!("p{i}")))
        .collect();
    settle(
        &mut ps.iter_mut().collect::<Vec<_>>(),
        Duration::from_secs(60),
    );
    let mut rng = Rng(seed);
    for _ in 0..edits_each {
        for p in ps.iter_mut() {
            random_edit(p, &mut rng);
            p.pump();
        }
        std::thread::sleep(Duration::from_millis(1));
    }
    settle(
        &mut ps.iter_mut().collect::<Vec<_>>(),
        Duration::from_secs(120),
    );
    let hash = check_converged(&url, &ps.iter().collect::<Vec<_>>());
    let doc = ps[0].log.document();
    eprintln!(
        "{people} people, {edits_each} edits each: {} entries, {} objects, hash {hash:016x}",
        ps[0].log.confirmed().last_seq(),
        doc.len()
    );
    assert!(
        ps[0].log.confirmed().op_count() > edits_each,
        "the edits reached the stream"
    );
}

#[test]
fn two_people_converge() {
    session(2, 60, 7);
}

#[test]
fn sixteen_people_converge() {
    session(16, 12, 11);
}

#[test]
fn a_server_killed_mid_session_loses_nothing_committed() {
    let mut server = Server::start();
    let url = server.url("restart");
    let mut a = Person::join(&url, "a");
    let mut b = Person::join(&url, "b");
    settle(&mut [&mut a, &mut b], Duration::from_secs(30));
    let x = a.log.apply(sphere(0.0)).unwrap().created.unwrap();
    for _ in 0..20 {
        a.log.apply(nudge(x, 0.01)).unwrap();
        settle(&mut [&mut a, &mut b], Duration::from_secs(30));
    }
    let committed = last_sequence(&url);
    let before = b.log.document().content_hash();
    server.kill();
    // Both go on editing while the server is down.
    let y = b.log.apply(sphere(1.0)).unwrap().created.unwrap();
    for _ in 0..5 {
        a.log.apply(nudge(x, 0.01)).unwrap();
        b.log.apply(nudge(y, 0.02)).unwrap();
        a.pump();
        b.pump();
        std::thread::sleep(Duration::from_millis(50));
    }
    assert!(a.log.pending_count() > 0 && b.log.pending_count() > 0);
    server.restart();
    settle(&mut [&mut a, &mut b], Duration::from_secs(60));
    // Everything committed before the crash is still there, then the rest.
    let after = read_stream(&url);
    assert!(
        after.last_seq() >= committed + 11,
        "{} < {committed} + 11",
        after.last_seq()
    );
    let hash = check_converged(&url, &[&a, &b]);
    assert_ne!(hash, before);
    let doc = a.log.document();
    let ya = doc.get(x).unwrap().transform().translate[1];
    let yb = doc.get(y).unwrap().transform().translate[1];
    assert!(
        (ya - 0.25).abs() < 1e-9 && (yb - 0.10).abs() < 1e-9,
        "{ya} {yb}"
    );
}

#[test]
fn a_participant_cut_off_for_ten_seconds_keeps_editing_and_rebases() {
    let server = Server::start();
    let url = server.url("cutoff");
    let relay = Relay::new(server.port);
    let via_relay =
        shapewright_net::SessionUrl::parse(&format!("tls://127.0.0.1:{}/cutoff", relay.port))
            .unwrap();
    let mut a = Person::join(&url, "a");
    let mut b = Person::join(&via_relay, "b");
    settle(&mut [&mut a, &mut b], Duration::from_secs(30));
    let x = a.log.apply(sphere(0.0)).unwrap().created.unwrap();
    settle(&mut [&mut a, &mut b], Duration::from_secs(30));

    relay.cut(true);
    let t = Instant::now();
    let mut made = Vec::new();
    let mut offline_seen = false;
    while t.elapsed() < Duration::from_secs(10) {
        // B keeps creating and editing its own objects, and moves A's.
        let id = b
            .log
            .apply(sphere(2.0 + made.len() as f64))
            .unwrap()
            .created
            .unwrap();
        b.log.apply(nudge(id, 0.1)).unwrap();
        b.log.apply(nudge(x, 0.001)).unwrap();
        made.push(id);
        a.log.apply(nudge(x, 0.01)).unwrap();
        for _ in 0..50 {
            a.pump();
            b.pump();
            offline_seen |= !b.link.is_online();
            std::thread::sleep(Duration::from_millis(10));
        }
    }
    assert!(offline_seen, "B noticed it was offline");
    assert_eq!(b.log.pending_count(), 3 * made.len());
    relay.cut(false);
    settle(&mut [&mut a, &mut b], Duration::from_secs(60));
    check_converged(&url, &[&a, &b]);
    let doc = a.log.document();
    for id in &made {
        assert_eq!(doc.get(*id).unwrap().transform().translate[1], 0.1);
    }
    let y = doc.get(x).unwrap().transform().translate[1];
    let want = made.len() as f64 * 0.011;
    assert!((y - want).abs() < 1e-9, "{y} vs {want}");
    assert!(b.link.is_online());
}

#[test]
fn duplicate_publishes_land_once() {
    let server = Server::start();
    let url = server.url("dupes");
    let mut a = Person::join(&url, "a");
    settle(&mut [&mut a], Duration::from_secs(30));
    let entry = Entry::new(
        "a",
        2,
        1,
        Body::Op {
            ids_from: Some(a.log.confirmed().next_free_id("a").unwrap()),
            op: sphere(0.0),
        },
    );
    let bytes = entry.to_bytes();
    let id = entry.msg_id();
    // The same append three times (a retry after a lost ack): one lands.
    let r = inject(
        &url,
        "a",
        &[
            (Some(&id), bytes.clone()),
            (Some(&id), bytes.clone()),
            (Some(&id), bytes),
        ],
    );
    assert_eq!(r[0], r[1]);
    assert_eq!(r[1], r[2]);
    assert_eq!(last_sequence(&url), 2);
    // The author's own log takes it as its own and goes on from there.
    let t = Instant::now();
    while a.log.confirmed().last_seq() < 2 {
        a.pump();
        assert!(t.elapsed() < Duration::from_secs(10));
    }
    a.log.apply(sphere(1.0)).unwrap();
    settle(&mut [&mut a], Duration::from_secs(30));
    assert_eq!(a.log.document().len(), 2);
    check_converged(&url, &[&a]);
}

#[test]
fn two_writers_racing_on_one_object_a_thousand_times_converge() {
    let server = Server::start();
    let url = server.url("race");
    let mut a = Person::join(&url, "a");
    let mut b = Person::join(&url, "b");
    settle(&mut [&mut a, &mut b], Duration::from_secs(30));
    let x = a.log.apply(sphere(0.0)).unwrap().created.unwrap();
    settle(&mut [&mut a, &mut b], Duration::from_secs(30));
    for k in 0..500 {
        a.log.apply(nudge(x, 0.001)).unwrap();
        b.log.apply(nudge(x, -0.0005)).unwrap();
        if k % 2 == 0 {
            a.pump();
            b.pump();
        } else {
            b.pump();
            a.pump();
        }
    }
    settle(&mut [&mut a, &mut b], Duration::from_secs(120));
    check_converged(&url, &[&a, &b]);
    let y = a.log.document().get(x).unwrap().transform().translate[1];
    assert!((y - 0.25).abs() < 1e-9, "{y}");
    // Both raced: each had appends refused and rebased, none was lost.
    assert_eq!(a.log.confirmed().op_count(), 1001);
}

#[test]
fn hostile_messages_are_skipped_identically_by_every_replica() {
    let server = Server::start();
    let url = server.url("hostile");
    let mut a = Person::join(&url, "a");
    let mut b = Person::join(&url, "b");
    settle(&mut [&mut a, &mut b], Duration::from_secs(30));
    let x = a.log.apply(sphere(0.0)).unwrap().created.unwrap();
    settle(&mut [&mut a, &mut b], Duration::from_secs(30));
    let before = a.log.document().content_hash();
    let fake = |n: u64, body: Body| Entry::new("b", n, 0, body).to_bytes();
    let msgs = vec![
        (None, b"\xff\xfe not json".to_vec()),
        (None, vec![b'['; MAX_ENTRY_BYTES + 10]),
        (
            None,
            fake(
                90,
                Body::Op {
                    ids_from: None,
                    op: op(r#"{"op":"delete","id":999}"#),
                },
            ),
        ),
        (None, fake(91, Body::Undo(1))),
        (
            None,
            fake(
                92,
                Body::Op {
                    ids_from: Some(1),
                    op: sphere(5.0),
                },
            ),
        ),
    ];
    let r = inject(&url, "b", &msgs);
    assert!(r.iter().all(Result::is_ok), "{r:?}");
    settle(&mut [&mut a, &mut b], Duration::from_secs(30));
    for p in [&a, &b] {
        assert_eq!(p.log.document().content_hash(), before);
        let reasons = skipped_reasons(&p.log);
        assert_eq!(reasons.len(), 5, "{reasons:?}");
        assert!(reasons[0].contains("not an entry"));
        assert!(reasons[1].contains("larger than"));
        assert!(reasons[2].contains("does not exist"));
        assert!(reasons[3].contains("no op 1"));
        assert!(reasons[4].contains("outside the id range"));
    }
    // B is told about the entries made in its name; the session goes on.
    let notices = b.log.take_notices();
    assert!(
        notices.iter().all(|n| n.kind == NoticeKind::Refused) && notices.len() == 3,
        "{notices:?}"
    );
    b.log.apply(nudge(x, 0.5)).unwrap();
    settle(&mut [&mut a, &mut b], Duration::from_secs(30));
    check_converged(&url, &[&a, &b]);
}

#[test]
fn an_unreachable_server_is_a_clear_error() {
    let url =
        shapewright_net::SessionUrl::parse(&format!("nats://127.0.0.1:{}/nobody", free_port()))
            .unwrap();
    let opts = shapewright_net::LinkOptions {
        connect_timeout: Duration::from_millis(500),
        ..options()
    };
    let e = shapewright_net::Link::connect(&url, "a", 0, opts)
        .err()
        .expect("no server there");
    let text = e.to_string();
    assert!(
        text.contains("cannot reach the session server nats://127.0.0.1:"),
        "{text}"
    );
}

#[test]
fn a_late_joiner_loads_the_latest_snapshot_and_replays_only_the_tail() {
    let server = Server::start();
    let url = server.url("late");
    let mut a = Person::join(&url, "a");
    let mut b = Person::join(&url, "b");
    a.log.set_snapshot_every(100);
    b.log.set_snapshot_every(100);
    settle(&mut [&mut a, &mut b], Duration::from_secs(30));
    let x = a.log.apply(sphere(0.0)).unwrap().created.unwrap();
    let y = b.log.apply(sphere(1.0)).unwrap().created.unwrap();
    settle(&mut [&mut a, &mut b], Duration::from_secs(30));
    for k in 0..170 {
        a.log.apply(nudge(x, 0.001)).unwrap();
        if k % 2 == 0 {
            b.log.apply(nudge(y, 0.002)).unwrap();
        }
        a.pump();
        b.pump();
    }
    settle(&mut [&mut a, &mut b], Duration::from_secs(60));
    let last = last_sequence(&url);
    let stored = shapewright_net::fetch_snapshot(&url, &options())
        .unwrap()
        .expect("a snapshot was written");
    let (seq, bytes) = (stored.seq, stored.bytes);
    // The latest boundary's writer snapshots what it has applied when it
    // sees its entry past the boundary (entries arrive in batches, so a
    // few more may be in): at or after the boundary, before the next.
    let boundary = last / 100 * 100;
    assert!(
        (boundary..(boundary + 100).min(last + 1)).contains(&seq),
        "the latest boundary's snapshot: {seq} of {last} entries"
    );
    let replica = Replica::from_snapshot(&bytes).unwrap();
    assert_eq!(replica.last_seq(), seq);
    assert!(
        ["a", "b"].contains(&stored.writer.as_str()),
        "{}",
        stored.writer
    );
    // The joiner starts from it, reads only the tail, and checks it
    // against the stream in the background: an honest snapshot is the
    // stream's replay byte for byte.
    let mut c = Person {
        log: SharedLog::resume("c", "Person c", [0.1, 0.8, 0.3], replica, 1).unwrap(),
        link: Link::connect(&url, "c", seq, options()).unwrap(),
    };
    c.link.check_snapshot(seq, bytes.clone(), &stored.writer);
    settle(&mut [&mut a, &mut b, &mut c], Duration::from_secs(30));
    let t = Instant::now();
    while matches!(c.link.snapshot_state(), SnapshotState::Checking { .. }) {
        settle(&mut [&mut a, &mut b, &mut c], Duration::from_secs(30));
        assert!(
            t.elapsed() < Duration::from_secs(30),
            "the check did not end"
        );
    }
    assert_eq!(c.link.snapshot_state(), &SnapshotState::Confirmed);
    assert!(c.log.confirmed().op_count() > 0);
    check_converged(&url, &[&a, &b, &c]);
    // Undo of ops made before the snapshot works for everyone, the joiner
    // included (it replays from the snapshot's base).
    for _ in 0..3 {
        b.log.undo().unwrap();
    }
    let z = c.log.apply(sphere(2.0)).unwrap().created.unwrap();
    settle(&mut [&mut a, &mut b, &mut c], Duration::from_secs(30));
    check_converged(&url, &[&a, &b, &c]);
    assert_eq!(z.0 >> 24, 3, "the joiner's own id range");
    let yb = c.log.document().get(y).unwrap().transform().translate[1];
    assert!((yb - 82.0 * 0.002).abs() < 1e-9, "{yb}");
    // A broken snapshot is a clear error (the joiner then replays all).
    assert!(Replica::from_snapshot(b"{}")
        .unwrap_err()
        .contains("not a replica snapshot"));
}

#[test]
fn a_three_node_cluster_keeps_an_r3_stream_through_a_node_loss() {
    let mut cluster = Cluster::start(3);
    let url = cluster.url("cluster");
    let options = LinkOptions {
        replicas: 3,
        ..options()
    };
    // The cluster elects its JetStream leader in a few seconds; until then
    // the stream cannot be made.
    let t = Instant::now();
    let mut a = loop {
        match Link::connect(&url, "a", 0, options.clone()) {
            Ok(link) => {
                let log = SharedLog::new("a", "Person a", [0.9, 0.4, 0.1]).unwrap();
                break Person { log, link };
            }
            Err(e) => {
                assert!(t.elapsed() < Duration::from_secs(30), "no cluster: {e}");
                std::thread::sleep(Duration::from_millis(250));
            }
        }
    };
    let formed = t.elapsed();
    let mut b = Person::join_with(&url, "b", options);
    settle(&mut [&mut a, &mut b], Duration::from_secs(30));
    let x = a.log.apply(sphere(0.0)).unwrap().created.unwrap();
    let y = b.log.apply(sphere(1.0)).unwrap().created.unwrap();
    for _ in 0..20 {
        a.log.apply(nudge(x, 0.01)).unwrap();
        b.log.apply(nudge(y, 0.01)).unwrap();
        a.pump();
        b.pump();
    }
    settle(&mut [&mut a, &mut b], Duration::from_secs(30));
    let committed = a.log.confirmed().last_seq();
    // The first listed server (the one both clients reach first) dies.
    cluster.nodes[0].kill();
    let killed = Instant::now();
    for _ in 0..20 {
        a.log.apply(nudge(x, 0.01)).unwrap();
        b.log.apply(nudge(y, 0.01)).unwrap();
        a.pump();
        b.pump();
        std::thread::sleep(Duration::from_millis(20));
    }
    settle(&mut [&mut a, &mut b], Duration::from_secs(60));
    eprintln!(
        "cluster: stream made after {formed:?}; all 40 edits made during a node's loss landed {:?} after it",
        killed.elapsed()
    );
    assert_eq!(
        a.log.confirmed().last_seq(),
        committed + 40,
        "nothing lost, everything after the loss landed"
    );
    let doc = a.log.document();
    for id in [x, y] {
        let v = doc.get(id).unwrap().transform().translate[1];
        assert!((v - 0.4).abs() < 1e-9, "{v}");
    }
    assert_eq!(doc.content_hash(), b.log.document().content_hash());
}

#[test]
fn people_opening_a_new_document_at_the_same_moment_all_get_in() {
    let server = Server::start();
    let url = server.url("same-moment");
    let people: Vec<Person> = std::thread::scope(|s| {
        let joins: Vec<_> = (0..6)
            .map(|i| {
                let url = url.clone();
                s.spawn(move || Person::join(&url, &format!("p{i}")))
            })
            .collect();
        joins.into_iter().map(|j| j.join().unwrap()).collect()
    });
    let mut people = people;
    settle(
        &mut people.iter_mut().collect::<Vec<_>>(),
        Duration::from_secs(30),
    );
    assert!(people.iter().all(|p| p.log.is_joined()));
}

#[test]
fn a_viewer_reads_but_its_edits_are_refused_and_change_nothing() {
    let members =
        Member::parse_list("ana pa doc:editor\nvic pv doc:viewer\neve pe other:editor\n").unwrap();
    let server = Server::with_config(&server_config(&members).unwrap());
    let url = server.url("doc");
    let (as_ana, as_vic) = (member("ana", "pa"), member("vic", "pv"));
    let mut ana = Person::join_with(&url, "ana", as_ana.clone());
    settle(&mut [&mut ana], Duration::from_secs(30));
    let a = ana.log.apply(sphere(0.0)).unwrap().created.unwrap();
    settle(&mut [&mut ana], Duration::from_secs(30));

    // Vic may only view: the server refuses his join, and his log knows.
    let mut vic = Person::join_with(&url, "vic", as_vic.clone());
    let t = Instant::now();
    while !vic.link.is_view_only() {
        vic.pump();
        ana.pump();
        assert!(
            t.elapsed() < Duration::from_secs(10),
            "no refusal: {:?}",
            vic.link.take_errors()
        );
        std::thread::sleep(Duration::from_millis(2));
    }
    assert!(vic.log.view_only().is_some());
    let refused = vic.log.apply(nudge(a, 1.0));
    assert!(
        matches!(refused, Err(SharedError::ViewOnly(_))),
        "{refused:?}"
    );
    // He still sees Ana's edits.
    ana.log.apply(nudge(a, 0.5)).unwrap();
    settle(&mut [&mut ana, &mut vic], Duration::from_secs(30));
    let seen = vic.log.document().get(a).unwrap().transform().translate;
    assert_eq!(seen, [0.0, 0.5, 0.0]);

    // A raw publish with his password, past our client: refused, and the
    // stream does not change.
    let before = last_sequence_with(&url, &as_ana);
    let raw = block_on(async {
        let client = raw_client_with(&url, &as_vic).await.unwrap();
        let js = async_nats::jetstream::ContextBuilder::new()
            .timeout(Duration::from_secs(1))
            .build(client);
        match js.publish("sw.doc.log.vic", b"{}".to_vec().into()).await {
            Ok(ack) => ack.await.map(|a| a.sequence).map_err(|e| e.to_string()),
            Err(e) => Err(e.to_string()),
        }
    });
    assert!(raw.is_err(), "a viewer's raw publish was stored at {raw:?}");
    assert_eq!(last_sequence_with(&url, &as_ana), before);
    let hash = check_converged_with(&url, as_ana.clone(), &[&ana, &vic]);
    let solo = read_stream_with(&url, as_ana);
    let authors: Vec<&str> = solo.participants().iter().map(|p| p.id.as_str()).collect();
    assert_eq!(authors, ["ana"]);
    eprintln!("viewer: refused in {:?}, document {hash:016x}", t.elapsed());

    // Eve has no grant for this document, and a wrong password is no
    // better: both are told they are not allowed in.
    for (user, password) in [("eve", "pe"), ("ana", "wrong")] {
        match Link::connect(&url, user, 0, member(user, password)) {
            Err(LinkError::NotAllowed { why, .. }) => eprintln!("{user}: {why}"),
            Err(e) => panic!("{user}: {e}"),
            Ok(_) => panic!("{user} got in"),
        }
    }
}

#[test]
fn presence_reaches_the_others_and_bad_presence_is_dropped() {
    use shapewright::doc::shared::{Presence, PresencePose};
    let server = Server::start();
    let url = server.url("presence");
    let a = Link::connect(&url, "ana", 0, options()).unwrap();
    let b = Link::connect(&url, "ben", 0, options()).unwrap();
    let (pa, pb) = (a.presence(), b.presence());
    let good = Presence {
        head: Some(PresencePose {
            p: [0.1, 0.2, 0.3],
            q: [0.0, 0.0, 0.0, 1.0],
        }),
        selected: Some(7),
        ..Presence::empty()
    };
    let wait_for = |what: &dyn Fn() -> bool| {
        let t = Instant::now();
        while !what() {
            assert!(
                t.elapsed() < Duration::from_secs(10),
                "presence did not arrive"
            );
            std::thread::sleep(Duration::from_millis(5));
        }
    };
    // Sent until heard (a subscription may still be starting).
    wait_for(&|| {
        pa.send(&good);
        pb.others(Duration::from_secs(2)) == vec![("ana".to_string(), good.clone())]
    });
    // Nobody hears themselves.
    assert!(pa.others(Duration::from_secs(2)).is_empty());
    // A NaN pose, a message from the future and garbage are dropped; the
    // last good presence stays. Then a good one replaces it.
    let subject = url.presence_subject("ana").unwrap();
    block_on(async {
        let client = raw_client(&url).await.unwrap();
        for bad in [
            &br#"{"v":1,"head":{"p":[1e999,0,0],"q":[0,0,0,1]}}"#[..],
            &br#"{"v":9}"#[..],
            &b"\xff\xfe"[..],
            &vec![b' '; 4096][..],
        ] {
            client
                .publish(subject.clone(), bad.to_vec().into())
                .await
                .unwrap();
        }
        client.flush().await.unwrap();
    });
    std::thread::sleep(Duration::from_millis(200));
    assert_eq!(
        pb.others(Duration::from_secs(2)),
        vec![("ana".to_string(), good.clone())]
    );
    let moved = Presence {
        selected: None,
        ..good.clone()
    };
    wait_for(&|| {
        pa.send(&moved);
        pb.others(Duration::from_secs(2)) == vec![("ana".to_string(), moved.clone())]
    });
    // Stale presence is not listed.
    std::thread::sleep(Duration::from_millis(300));
    assert!(pb.others(Duration::from_millis(100)).is_empty());
}
