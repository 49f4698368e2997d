//! A real `nats-server -js` on 127.0.0.1 for the tests (installed by
//! scripts/setup.sh), participants driven through real links, and a TCP
//! relay that can cut one participant off.

#![allow(dead_code, unused_imports)]

use std::io::{Read, Write};
use std::net::{Shutdown, TcpListener, TcpStream};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

use shapewright::doc::shared::SharedLog;
use shapewright::doc::{ObjectId, Op};
pub use shapewright_net::testkit::{
    free_port, member, options, read_stream, read_stream_with, Cluster, Server,
};
use shapewright_net::{Link, LinkOptions, SessionUrl};

/// One participant: a shared log and its link.
pub struct Person {
    pub log: SharedLog,
    pub link: Link,
}

impl Person {
    pub fn join(url: &SessionUrl, me: &str) -> Self {
        Self::join_with(url, me, options())
    }

    pub fn join_with(url: &SessionUrl, me: &str, options: LinkOptions) -> Self {
        let log = SharedLog::new(me, &format!("Person {me}"), [0.9, 0.4, 0.1]).unwrap();
        let link = Link::connect(url, me, 0, options).unwrap();
        Self { log, link }
    }

    pub fn pump(&mut self) {
        self.link.pump(&mut self.log);
    }
}

/// Pumps everyone until nobody has anything pending and all have the
/// same last sequence for 150 ms.
pub fn settle(people: &mut [&mut Person], limit: Duration) {
    let t = Instant::now();
    let mut stable_since: Option<Instant> = None;
    let mut last = (u64::MAX, 0);
    loop {
        for p in people.iter_mut() {
            p.pump();
        }
        let seqs: Vec<u64> = people
            .iter()
            .map(|p| p.log.confirmed().last_seq())
            .collect();
        let pending: usize = people.iter().map(|p| p.log.pending_count()).sum();
        let same = seqs.iter().all(|&s| s == seqs[0]);
        let state = (seqs[0], pending);
        if pending == 0 && same {
            if state != last || stable_since.is_none() {
                stable_since = Some(Instant::now());
            }
            if stable_since.is_some_and(|s| s.elapsed() > Duration::from_millis(150)) {
                return;
            }
        } else {
            stable_since = None;
        }
        last = state;
        assert!(
            t.elapsed() < limit,
            "no quiescence in {limit:?}: last sequences {seqs:?}, {pending} pending, errors {:?}",
            people
                .iter_mut()
                .map(|p| p.link.take_errors())
                .collect::<Vec<_>>()
        );
        std::thread::sleep(Duration::from_millis(2));
    }
}

/// Every replica has the same document, equal to one replay of the whole
/// stream by a fresh reader; returns its hash.
pub fn check_converged(url: &SessionUrl, people: &[&Person]) -> u64 {
    check_converged_with(url, options(), people)
}

/// [`check_converged`], the reader with `options` (a member's).
pub fn check_converged_with(url: &SessionUrl, options: LinkOptions, people: &[&Person]) -> u64 {
    let solo = read_stream_with(url, options);
    let want = solo.document().content_hash();
    for p in people {
        assert_eq!(p.log.document().content_hash(), want, "{}", p.log.me());
        assert_eq!(
            p.log.confirmed().op_states(),
            solo.op_states(),
            "{}",
            p.log.me()
        );
    }
    want
}

/// Runs `f` to completion on a runtime of its own (the tests' raw NATS
/// calls, beside the links).
pub fn block_on<F: std::future::Future>(f: F) -> F::Output {
    tokio::runtime::Builder::new_current_thread()
        .enable_all()
        .build()
        .unwrap()
        .block_on(f)
}

/// A plain NATS client for `url` with `options`' credentials (TLS
/// verified, the user's own inbox prefix): what a dishonest member could
/// write with their own password.
pub async fn raw_client_with(
    url: &SessionUrl,
    options: &LinkOptions,
) -> Result<async_nats::Client, async_nats::ConnectError> {
    let creds = options.credentials.clone().unwrap_or_default();
    let mut c = async_nats::ConnectOptions::new().require_tls(true);
    if let Some(ca) = &creds.ca {
        c = c.add_root_certificates(ca.clone());
    }
    if let (Some(u), Some(p)) = (&creds.user, &creds.password) {
        c = c
            .user_and_password(u.clone(), p.clone())
            .custom_inbox_prefix(shapewright_net::access::inbox_prefix(u));
    }
    c.connect(url.server_urls()).await
}

/// [`raw_client_with`] the test CA and no user.
pub async fn raw_client(url: &SessionUrl) -> Result<async_nats::Client, async_nats::ConnectError> {
    raw_client_with(url, &options()).await
}

/// The stream's last sequence, asked of the server.
pub fn last_sequence(url: &SessionUrl) -> u64 {
    last_sequence_with(url, &options())
}

/// [`last_sequence`] with a member's options.
pub fn last_sequence_with(url: &SessionUrl, options: &LinkOptions) -> u64 {
    block_on(async {
        let client = raw_client_with(url, options).await.unwrap();
        let js = async_nats::jetstream::new(client);
        let mut s = js.get_stream(url.stream()).await.unwrap();
        s.info().await.unwrap().state.last_sequence
    })
}

/// Raw messages appended on `from`'s subject without any check (a
/// hostile or broken client), with optional message ids.
pub fn inject(
    url: &SessionUrl,
    from: &str,
    msgs: &[(Option<&str>, Vec<u8>)],
) -> Vec<Result<u64, String>> {
    let subject = url.log_subject(from).unwrap();
    block_on(async {
        let client = raw_client(url).await.unwrap();
        let js = async_nats::jetstream::new(client);
        let mut out = Vec::new();
        for (id, bytes) in msgs {
            let mut m = async_nats::jetstream::message::PublishMessage::build()
                .payload(bytes.clone().into());
            if let Some(id) = id {
                m = m.message_id(id);
            }
            let r = match js.send_publish(subject.clone(), m).await {
                Ok(ack) => ack.await.map(|a| a.sequence).map_err(|e| e.to_string()),
                Err(e) => Err(e.to_string()),
            };
            out.push(r);
        }
        out
    })
}

pub fn op(json: &str) -> Op {
    serde_json::from_str(json).unwrap()
}

pub fn sphere(x: f64) -> Op {
    op(&format!(
        r#"{{"op":"add_solid","shape":{{"kind":"sphere","radius":0.1}},"segments":8,"transform":{{"translate":[{x},0,0]}}}}"#
    ))
}

pub fn nudge(id: ObjectId, dy: f64) -> Op {
    op(&format!(
        r#"{{"op":"transform_by","id":{},"transform":{{"translate":[0,{dy},0]}}}}"#,
        id.0
    ))
}

pub fn delete(id: ObjectId) -> Op {
    op(&format!(r#"{{"op":"delete","id":{}}}"#, id.0))
}

/// A TCP relay to the server that can cut its clients off: while cut,
/// open connections are closed and new ones refused at once.
pub struct Relay {
    pub port: u16,
    cut: Arc<AtomicBool>,
    conns: Arc<Mutex<Vec<TcpStream>>>,
}

impl Relay {
    pub fn new(to: u16) -> Self {
        let listener = TcpListener::bind("127.0.0.1:0").unwrap();
        let port = listener.local_addr().unwrap().port();
        let cut = Arc::new(AtomicBool::new(false));
        let conns = Arc::new(Mutex::new(Vec::new()));
        let (c, k) = (cut.clone(), conns.clone());
        std::thread::spawn(move || {
            for inbound in listener.incoming() {
                let Ok(inbound) = inbound else { continue };
                if c.load(Ordering::SeqCst) {
                    let _ = inbound.shutdown(Shutdown::Both);
                    continue;
                }
                let Ok(outbound) = TcpStream::connect(("127.0.0.1", to)) else {
                    continue;
                };
                k.lock().unwrap().push(inbound.try_clone().unwrap());
                k.lock().unwrap().push(outbound.try_clone().unwrap());
                pipe(inbound.try_clone().unwrap(), outbound.try_clone().unwrap());
                pipe(outbound, inbound);
            }
        });
        Self { port, cut, conns }
    }

    pub fn cut(&self, on: bool) {
        self.cut.store(on, Ordering::SeqCst);
        if on {
            for s in self.conns.lock().unwrap().drain(..) {
                let _ = s.shutdown(Shutdown::Both);
            }
        }
    }
}

fn pipe(mut from: TcpStream, mut to: TcpStream) {
    std::thread::spawn(move || {
        let mut buf = [0u8; 16384];
        loop {
            match from.read(&mut buf) {
                Ok(0) | Err(_) => break,
                Ok(n) => {
                    if to.write_all(&buf[..n]).is_err() {
                        break;
                    }
                }
            }
        }
        let _ = to.shutdown(Shutdown::Both);
    });
}

/// Why each entry `log`'s confirmed replica skipped was skipped, in the
/// order of [`shapewright::doc::shared::Replica::skipped`].
pub fn skipped_reasons(log: &SharedLog) -> Vec<&str> {
    log.confirmed()
        .skipped()
        .iter()
        .map(|s| s.reason.as_str())
        .collect()
}
