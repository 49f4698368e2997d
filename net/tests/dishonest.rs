//! Issue 35's "done when": a dishonest editor with a raw NATS client
//! (async-nats, their own password, the member rules the server runs)
//! tries to write as someone else, undo someone else's op, mislead a late
//! joiner with a forged snapshot, delete or purge the stream, publish on
//! another document; a member without a grant tries to read. Each is
//! refused by the server or ignored identically by every replica, and the
//! honest people and a late joiner end with the document they had before.

mod common;

use std::time::{Duration, Instant};

use async_nats::jetstream::{self, object_store, stream};
use common::*;
use shapewright::doc::shared::{Body, Entry, Replica};
use shapewright::doc::OpLog;
use shapewright_net::access::{server_config, Member};
use shapewright_net::{Link, LinkError, LinkOptions, SessionUrl, SnapshotState};

fn entry(author: &str, n: u64, body: Body) -> Vec<u8> {
    Entry::new(author, n, 0, body).to_bytes()
}

/// Publishes `bytes` on `subject` with the raw client's JetStream
/// context: the stream's sequence, or why not.
async fn publish(js: &jetstream::Context, subject: &str, bytes: Vec<u8>) -> Result<u64, String> {
    match js.publish(subject.to_string(), bytes.into()).await {
        Ok(ack) => ack.await.map(|a| a.sequence).map_err(|e| e.to_string()),
        Err(e) => Err(e.to_string()),
    }
}

async fn raw_js(url: &SessionUrl, options: &LinkOptions) -> jetstream::Context {
    let client = raw_client_with(url, options).await.unwrap();
    jetstream::ContextBuilder::new()
        .timeout(Duration::from_secs(1))
        .build(client)
}

#[test]
fn a_dishonest_editor_changes_nothing_anyone_sees() {
    let members = Member::parse_list(
        "ana pa doc:editor\nbob pb doc:editor\ncat pc doc:editor\neve pe other:editor\n",
    )
    .unwrap();
    let server = Server::with_config(&server_config(&members).unwrap());
    let url = server.url("doc");
    let (as_ana, as_bob, as_cat, as_eve) = (
        member("ana", "pa"),
        member("bob", "pb"),
        member("cat", "pc"),
        member("eve", "pe"),
    );
    let mut ana = Person::join_with(&url, "ana", as_ana.clone());
    let mut bob = Person::join_with(&url, "bob", as_bob.clone());
    settle(&mut [&mut ana, &mut bob], Duration::from_secs(30));
    let a = ana.log.apply(sphere(0.0)).unwrap().created.unwrap();
    for _ in 0..4 {
        ana.log.apply(nudge(a, 0.1)).unwrap();
    }
    let b = bob.log.apply(sphere(1.0)).unwrap().created.unwrap();
    settle(&mut [&mut ana, &mut bob], Duration::from_secs(30));
    let before = check_converged_with(&url, as_ana.clone(), &[&ana, &bob]);
    let last_before = last_sequence_with(&url, &as_ana);
    let ana_op = ana
        .log
        .confirmed()
        .op_states()
        .iter()
        .rev()
        .find(|(who, _, state)| who == "ana" && state.is_ok())
        .map(|(_, n, _)| *n)
        .unwrap();
    let bob_n = ana.log.confirmed().participant("bob").unwrap().last_n;
    assert!(ana_op > bob_n, "bob has no op {ana_op} of his own");

    let stored = block_on(async {
        let js = raw_js(&url, &as_bob).await;
        let mut refused = Vec::new();
        let mut stored = Vec::new();
        // 1. Writing on ana's subject: the server refuses.
        let undo = entry("ana", 90, Body::Undo(ana_op));
        refused.push((
            "publish on ana's subject",
            publish(&js, "sw.doc.log.ana", undo.clone()).await,
        ));
        // 2. Writing as ana on his own subject: stored, refused by replicas.
        stored.push(publish(&js, "sw.doc.log.bob", undo).await);
        let op = Body::Op {
            ids_from: None,
            op: delete(a),
        };
        stored.push(publish(&js, "sw.doc.log.bob", entry("ana", 91, op)).await);
        let rename = Body::Join {
            name: "Mallory".into(),
            colour: [1.0; 3],
        };
        stored.push(publish(&js, "sw.doc.log.bob", entry("ana", 92, rename)).await);
        // 3. Undoing ana's op as himself: names an op of his that is not.
        stored.push(
            publish(
                &js,
                "sw.doc.log.bob",
                entry("bob", bob_n + 1, Body::Undo(ana_op)),
            )
            .await,
        );
        // 4. Deleting, purging, emptying, re-configuring the stream.
        refused.push((
            "delete the stream",
            js.delete_stream("SW_doc")
                .await
                .map(|_| 0)
                .map_err(|e| e.to_string()),
        ));
        let mut s = js.get_stream("SW_doc").await.unwrap();
        refused.push((
            "purge the stream",
            s.purge().await.map(|_| 0).map_err(|e| e.to_string()),
        ));
        refused.push((
            "delete a message",
            s.delete_message(1)
                .await
                .map(|_| 0)
                .map_err(|e| e.to_string()),
        ));
        let mut config = s.info().await.unwrap().config.clone();
        config.deny_purge = false;
        config.subjects = vec!["sw.doc.>".into()];
        refused.push((
            "edit the stream",
            js.update_stream(config)
                .await
                .map(|_| 0)
                .map_err(|e| e.to_string()),
        ));
        let mut rollup = async_nats::HeaderMap::new();
        rollup.insert("Nats-Rollup", "all");
        let r = match js
            .publish_with_headers("sw.doc.log.bob", rollup, b"{}".to_vec().into())
            .await
        {
            Ok(ack) => ack.await.map(|a| a.sequence).map_err(|e| e.to_string()),
            Err(e) => Err(e.to_string()),
        };
        refused.push(("roll the stream up", r));
        // 5. Another document, where he has no grant.
        refused.push((
            "publish on another document",
            publish(&js, "sw.other.log.bob", b"{}".to_vec()).await,
        ));
        // 6. A forged snapshot: an empty document at the stream's last
        // sequence, under his name; under ana's, the server refuses.
        let mut empty = Replica::new();
        for (i, m) in [b"x".to_vec()]
            .iter()
            .cycle()
            .take(last_before as usize)
            .enumerate()
        {
            empty.integrate(i as u64 + 1, "nobody", m);
        }
        let forged = empty.snapshot();
        let store = match js.get_object_store("SW_doc_snapshots").await {
            Ok(s) => s,
            Err(_) => js
                .create_object_store(object_store::Config {
                    bucket: "SW_doc_snapshots".into(),
                    storage: stream::StorageType::File,
                    ..Default::default()
                })
                .await
                .unwrap(),
        };
        let put = |name: &str| object_store::ObjectMetadata {
            name: name.into(),
            description: Some(format!("seq={last_before}")),
            ..Default::default()
        };
        let as_ana = store.put(put("by.ana"), &mut forged.as_slice()).await;
        refused.push((
            "store a snapshot as ana",
            as_ana.map(|_| 0).map_err(|e| e.to_string()),
        ));
        store
            .put(put("by.bob"), &mut forged.as_slice())
            .await
            .expect("his own snapshot is his to store");
        for (what, r) in &refused {
            assert!(r.is_err(), "{what}: the server allowed it ({r:?})");
            eprintln!("refused: {what}: {}", r.as_ref().unwrap_err());
        }
        stored
    });
    assert!(stored.iter().all(Result::is_ok), "{stored:?}");

    // 7. Eve, without a grant for this document, reads nothing: not the
    // stream, not others' replies, not the log's subjects.
    let eve_saw = block_on(async {
        let client = raw_client_with(&url, &as_eve).await.unwrap();
        let js = jetstream::ContextBuilder::new()
            .timeout(Duration::from_secs(1))
            .build(client.clone());
        let lookup = js
            .get_stream("SW_doc")
            .await
            .map(|_| ())
            .map_err(|e| e.to_string());
        assert!(lookup.is_err(), "eve looked the stream up");
        let direct = client
            .request("$JS.API.DIRECT.GET.SW_doc", b"{\"seq\":1}".to_vec().into())
            .await;
        assert!(direct.is_err(), "eve read an entry: {direct:?}");
        let mut subs = Vec::new();
        for s in ["sw.doc.log.>", "_INBOX.>", "_INBOX_ana.>", "$JS.>"] {
            subs.push(client.subscribe(s.to_string()).await.unwrap());
        }
        client.flush().await.unwrap();
        subs
    });
    // ana undoes and redoes meanwhile (her deliveries go to her inbox).
    ana.log.undo().unwrap();
    settle(&mut [&mut ana, &mut bob], Duration::from_secs(30));
    ana.log.redo().unwrap();
    let after_edit = Instant::now();
    settle(&mut [&mut ana, &mut bob], Duration::from_secs(30));
    let mut eve_subs = eve_saw;
    let heard = block_on(async {
        let mut n = 0;
        for sub in eve_subs.iter_mut() {
            while let Ok(Some(_)) = tokio::time::timeout(
                Duration::from_millis(200),
                futures_util::StreamExt::next(sub),
            )
            .await
            {
                n += 1;
            }
        }
        n
    });
    assert_eq!(heard, 0, "eve heard {heard} messages");
    eprintln!("eve heard nothing for {:?}", after_edit.elapsed());

    // The honest people see the document as before (undo and redo give
    // the same bits), the forged entries skipped by both the same way.
    let now = check_converged_with(&url, as_ana.clone(), &[&ana, &bob]);
    assert_eq!(now, before);
    for p in [&ana, &bob] {
        let reasons = skipped_reasons(&p.log);
        assert_eq!(reasons.len(), 4, "{reasons:?}");
        assert!(
            reasons[..3]
                .iter()
                .all(|r| r.contains("claiming to be `ana`")),
            "{reasons:?}"
        );
        assert!(
            reasons[3].contains(&format!("`bob` has no op {ana_op} to undo")),
            "{reasons:?}"
        );
    }

    // 8. A late joiner starts from bob's forged snapshot, checks it, and
    // ends with the stream's document.
    let (mut cat_log, mut cat_link, messages) =
        shapewright_net::join::join(&url, "Cat", "cat", as_cat.clone(), &OpLog::new()).unwrap();
    eprintln!("cat joining: {messages:?}");
    assert!(
        messages.iter().any(|m| m.contains("`bob`'s snapshot")),
        "{messages:?}"
    );
    let t = Instant::now();
    let mut notices = Vec::new();
    while matches!(cat_link.snapshot_state(), SnapshotState::Checking { .. }) {
        let r = cat_link.pump_log(&mut cat_log).unwrap();
        notices.extend(r.notices);
        assert!(
            t.elapsed() < Duration::from_secs(30),
            "the check did not end"
        );
        std::thread::sleep(Duration::from_millis(2));
    }
    notices.extend(cat_link.pump_log(&mut cat_log).unwrap().notices);
    let cat_hash = cat_log.document().content_hash();
    assert_eq!(
        cat_hash, before,
        "the late joiner has the stream's document"
    );
    assert_eq!(
        cat_link.snapshot_state(),
        &SnapshotState::Replaced {
            writer: "bob".into()
        }
    );
    assert!(
        notices.iter().any(|n| n.contains("stored by `bob`")),
        "{notices:?}"
    );
    eprintln!("cat: bob's snapshot replaced after {:?}", t.elapsed());
    drop(cat_link);
    assert_eq!(
        read_stream_with(&url, as_ana).document().content_hash(),
        before
    );
    let _ = b;
}

#[test]
fn an_old_single_subject_stream_or_a_hand_made_one_is_refused_with_a_reason() {
    let server = Server::start();
    for (doc, subjects, deny_purge) in [
        ("old", vec!["sw.old.log".to_string()], true),
        ("loose", vec!["sw.loose.log.>".to_string()], false),
    ] {
        let url = server.url(doc);
        block_on(async {
            let js = jetstream::new(raw_client(&url).await.unwrap());
            js.create_stream(stream::Config {
                name: url.stream(),
                subjects,
                deny_delete: true,
                deny_purge,
                ..Default::default()
            })
            .await
            .unwrap();
        });
        let e = Link::connect(&url, "ana", 0, options())
            .err()
            .expect("refused");
        let text = e.to_string();
        eprintln!("{doc}: {text}");
        match doc {
            "old" => assert!(
                matches!(e, LinkError::OldStream { .. }) && text.contains("older Shapewright"),
                "{text}"
            ),
            _ => assert!(
                matches!(e, LinkError::Foreign { .. }) && text.contains("purging allowed"),
                "{text}"
            ),
        }
    }
}

#[test]
fn a_server_whose_certificate_the_team_ca_did_not_sign_is_refused() {
    let server = Server::start();
    let url = server.url("tls");
    let dir = std::env::temp_dir().join(format!("sw-other-ca-{}", std::process::id()));
    let out = std::process::Command::new("bash")
        .arg(concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../scripts/session_certs.sh"
        ))
        .arg(&dir)
        .arg("127.0.0.1")
        .output()
        .unwrap();
    assert!(out.status.success());
    let mut wrong = options();
    wrong.credentials.as_mut().unwrap().ca = Some(dir.join("ca.pem"));
    let e = Link::connect(&url, "ana", 0, wrong).err().expect("refused");
    assert!(matches!(e, LinkError::Tls { .. }), "{e}");
    // Without TLS at all, the TLS server does not take the client either.
    let plain = SessionUrl::parse(&format!("nats://127.0.0.1:{}/tls", server.port)).unwrap();
    assert!(Link::connect(&plain, "ana", 0, LinkOptions::default()).is_err());
    let _ = std::fs::remove_dir_all(&dir);
}
