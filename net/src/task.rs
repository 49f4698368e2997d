//! The network side of a [`crate::Link`]: its thread's async task, which
//! connects, makes or checks the document's stream, reads it, appends,
//! sends presence, stores snapshots and runs snapshot checks.

use std::collections::BTreeMap;
use std::sync::mpsc as std_mpsc;
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

use async_nats::jetstream::{self, context::PublishErrorKind};
use futures_util::StreamExt;
use shapewright::doc::shared::{id_from_token, Presence, Publish, Published, SnapshotCheck};
use tokio::sync::mpsc;

use crate::connect::{check_stream, client_options, connect, stream_config};
use crate::consume::{consume, Read};
use crate::link::{Cmd, Event};
use crate::{LinkError, LinkOptions, SessionUrl};

pub(crate) struct Task {
    pub(crate) url: SessionUrl,
    pub(crate) me: String,
    pub(crate) after: u64,
    pub(crate) options: LinkOptions,
    pub(crate) seen: Arc<Mutex<BTreeMap<String, (Instant, Presence)>>>,
    /// This link's part of its message ids (random).
    pub(crate) nonce: String,
}

/// 64 random bits as hex (the message ids' nonce), from the system's
/// random source (the clock should it fail).
pub(crate) fn nonce() -> String {
    let mut b = [0u8; 8];
    if getrandom::getrandom(&mut b).is_err() {
        let t = std::time::SystemTime::now()
            .duration_since(std::time::UNIX_EPOCH)
            .map(|d| d.as_nanos() as u64)
            .unwrap_or_default();
        b = (t ^ u64::from(std::process::id())).to_le_bytes();
    }
    b.iter().map(|x| format!("{x:02x}")).collect()
}

impl Task {
    pub(crate) async fn run(
        self,
        mut cmds: mpsc::UnboundedReceiver<Cmd>,
        events: std_mpsc::Sender<Event>,
        ready: std_mpsc::SyncSender<Result<u64, LinkError>>,
    ) {
        let ev = events.clone();
        // A permissions violation while connecting makes the connect's
        // error a clear "not allowed".
        let denied = Arc::new(Mutex::new(None::<String>));
        let denied_cb = Arc::clone(&denied);
        let options = client_options(&self.url, &self.me, &self.options)
            .reconnect_delay_callback(|attempts| {
                Duration::from_millis((100 * attempts as u64).min(1000))
            })
            .event_callback(move |e| {
                let ev = ev.clone();
                let denied = Arc::clone(&denied_cb);
                async move {
                    let up = match e {
                        async_nats::Event::Connected => true,
                        async_nats::Event::Disconnected => false,
                        async_nats::Event::ServerError(async_nats::ServerError::Other(m))
                            if m.to_lowercase().contains("permissions violation") =>
                        {
                            if let Ok(mut d) = denied.lock() {
                                d.get_or_insert_with(|| m.clone());
                            }
                            let _ = ev.send(Event::Denied(m));
                            return;
                        }
                        _ => return,
                    };
                    let _ = ev.send(Event::Online(up));
                }
            });
        let client = match connect(&self.url, options, &self.options).await {
            Ok(c) => c,
            Err(e) => return drop(ready.send(Err(e))),
        };
        let js = jetstream::ContextBuilder::new()
            .timeout(self.options.request_timeout)
            .build(client.clone());
        let config = stream_config(&self.url, self.options.replicas);
        let name = config.name.clone();
        // Two people opening a new document at once both try to make its
        // stream: the loser's create fails, and the winner's is there. An
        // existing stream is taken as it is, so what it is gets checked.
        let made = match js.get_or_create_stream(config).await {
            Ok(s) => Ok(s),
            Err(e) => js.get_stream(&name).await.map_err(|_| e),
        };
        let mut stream = match made {
            Ok(s) => s,
            Err(e) => {
                let url = self.url.to_string();
                let refused = denied.lock().ok().and_then(|d| d.clone());
                return drop(ready.send(Err(match refused {
                    Some(why) => LinkError::NotAllowed { url, why },
                    None => LinkError::Stream {
                        url,
                        why: e.to_string(),
                    },
                })));
            }
        };
        let info = match stream.info().await {
            Ok(info) => info.clone(),
            Err(_) => stream.cached_info().clone(),
        };
        if let Err(e) = check_stream(&self.url, &info.config) {
            return drop(ready.send(Err(e)));
        }
        let presence = client.subscribe(self.url.presence_subjects()).await;
        let _ = ready.send(Ok(info.state.last_sequence));

        let live = events.clone();
        let consume = tokio::spawn(consume(
            stream,
            self.url.log_subjects(),
            self.after,
            u64::MAX,
            move |r| live.send(read_event(r)).is_ok(),
        ));
        let listen = presence.ok().map(|sub| {
            let (seen, me) = (Arc::clone(&self.seen), self.me.clone());
            tokio::spawn(listen_presence(sub, seen, me))
        });
        let subject = self.url.log_subject(&self.me).unwrap_or_default();
        let presence_subject = self.url.presence_subject(&self.me).unwrap_or_default();
        let mut checks = Vec::new();
        while let Some(cmd) = cmds.recv().await {
            match cmd {
                Cmd::Stop => break,
                Cmd::Publish(mut p) => {
                    p.msg_id = format!("{}:{}", p.msg_id, self.nonce);
                    tokio::spawn(append(js.clone(), subject.clone(), p, events.clone()));
                }
                Cmd::Presence(bytes) => {
                    let _ = client.publish(presence_subject.clone(), bytes.into()).await;
                }
                Cmd::Snapshot { seq, bytes } => {
                    let (js, url, me, events) = (
                        js.clone(),
                        self.url.clone(),
                        self.me.clone(),
                        events.clone(),
                    );
                    let replicas = self.options.replicas;
                    tokio::spawn(async move {
                        let stored =
                            crate::snapshot::put(&js, &url, &me, replicas, seq, bytes).await;
                        if let Err(e) = stored {
                            let _ = events
                                .send(Event::Error(format!("snapshot at {seq} not stored: {e}")));
                        }
                    });
                }
                Cmd::Check(check) => match check_task(&js, &self.url, *check, &events).await {
                    Ok(reader) => checks.push(reader),
                    Err(e) => {
                        let _ = events.send(Event::Error(e));
                    }
                },
            }
        }
        consume.abort();
        for c in checks {
            c.abort();
        }
        if let Some(l) = listen {
            l.abort();
        }
        let _ = tokio::time::timeout(Duration::from_secs(1), client.flush()).await;
    }
}

/// Keeps the latest presence of everyone but `me` in `seen`, by
/// participant id (from the subject, never from the message).
async fn listen_presence(
    mut sub: async_nats::Subscriber,
    seen: Arc<Mutex<BTreeMap<String, (Instant, Presence)>>>,
    me: String,
) {
    while let Some(m) = sub.next().await {
        let token = m.subject.rsplit('.').next().unwrap_or_default();
        let Some(who) = id_from_token(token) else {
            continue;
        };
        if who == me {
            continue;
        }
        // A message that cannot be drawn is dropped (the sender's
        // problem); the last good one stays.
        if let Ok(p) = Presence::decode(&m.payload) {
            let mut seen = seen.lock().unwrap_or_else(|e| e.into_inner());
            seen.insert(who, (Instant::now(), p));
        }
    }
}

fn read_event(r: Read) -> Event {
    match r {
        Read::Entry { seq, from, bytes } => Event::Entry { seq, from, bytes },
        Read::Error(e) => Event::Error(e),
    }
}

/// Starts a snapshot check: a second reader of the stream from its start
/// up to the snapshot's sequence, feeding `check` on a thread of its own
/// (replaying is CPU work: the host's thread and the network's stay
/// free), whose verdict comes back as an event.
async fn check_task(
    js: &jetstream::Context,
    url: &SessionUrl,
    mut check: SnapshotCheck,
    events: &std_mpsc::Sender<Event>,
) -> Result<tokio::task::JoinHandle<()>, String> {
    let stream = js
        .get_stream(url.stream())
        .await
        .map_err(|e| format!("cannot check the snapshot: {e}"))?;
    let until = check.seq();
    let (tx, rx) = std_mpsc::channel::<Read>();
    let events = events.clone();
    std::thread::Builder::new()
        .name("shapewright-check".into())
        .spawn(move || {
            while let Ok(r) = rx.recv() {
                match r {
                    Read::Entry { seq, from, bytes } => {
                        if let Some(v) = check.feed(seq, &from, &bytes) {
                            let _ = events.send(Event::Checked(v));
                            return;
                        }
                    }
                    Read::Error(e) => {
                        let _ = events.send(Event::Error(format!("snapshot check: {e}")));
                    }
                }
            }
        })
        .map_err(|e| format!("cannot check the snapshot: {e}"))?;
    Ok(tokio::spawn(consume(
        stream,
        url.log_subjects(),
        0,
        until,
        move |r| tx.send(r).is_ok(),
    )))
}

/// Appends one entry, conditionally, and reports how it ended.
async fn append(
    js: jetstream::Context,
    subject: String,
    p: Publish,
    events: std_mpsc::Sender<Event>,
) {
    let msg = jetstream::message::PublishMessage::build()
        .payload(p.bytes.into())
        .message_id(&p.msg_id)
        .expected_last_sequence(p.expected_last_seq);
    let r = match js.send_publish(subject, msg).await {
        Ok(ack) => ack.await,
        Err(e) => Err(e),
    };
    let (result, error) = match r {
        Ok(ack) => (Published::Stored(ack.sequence), None),
        Err(e) if e.kind() == PublishErrorKind::WrongLastSequence => (Published::Conflict, None),
        Err(e) => (
            Published::Failed,
            Some(format!("append of {} failed: {e}", p.msg_id)),
        ),
    };
    let _ = events.send(Event::Published {
        n: p.n,
        result,
        error,
    });
}
