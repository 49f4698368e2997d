//! [`Link`]: one participant's connection to a session's stream. It runs
//! the NATS client on its own thread (a current-thread tokio runtime) and
//! talks to the host through channels, so a host's frame loop only calls
//! [`Link::pump`], which never blocks: it hands arrived entries to the
//! [`SharedLog`] and the log's next entry to the server.
//!
//! On the server: one JetStream stream per document (`SW_<doc>`, file
//! storage, a two-minute de-duplication window), entries appended on
//! `sw.<doc>.log` with `Nats-Msg-Id` = author:counter and
//! `Nats-Expected-Last-Sequence` = the last sequence the author had seen;
//! presence on `sw.<doc>.presence.<who>`, plain NATS (never stored);
//! snapshots in the object store bucket `SW_<doc>_snapshots`.

use std::collections::BTreeMap;
use std::sync::mpsc as std_mpsc;
use std::sync::{Arc, Mutex};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use async_nats::jetstream::{self, consumer, context::PublishErrorKind, stream};
use futures_util::StreamExt;
use shapewright::doc::shared::{Presence, Publish, Published, SharedLog, MAX_ENTRY_BYTES};
use shapewright::doc::OpLog;
use tokio::sync::mpsc;

use crate::SessionUrl;

/// Why a link could not start.
#[derive(Debug, thiserror::Error)]
pub enum LinkError {
    /// The server did not answer (not running, wrong address, refused).
    #[error("cannot reach the session server {url}: {why}")]
    Unreachable {
        /// The address.
        url: String,
        /// What the client said.
        why: String,
    },
    /// The server answered but JetStream refused the document's stream
    /// (JetStream off: start the server with `-js`; or not allowed).
    #[error("the server at {url} would not open the document's stream: {why}")]
    Stream {
        /// The address.
        url: String,
        /// What the server said.
        why: String,
    },
    /// The server refused this user: a wrong user or password, or no
    /// grant for this document (see [`crate::access`]).
    #[error("the server at {url} does not let you into this document: {why}")]
    NotAllowed {
        /// The address.
        url: String,
        /// What the server said.
        why: String,
    },
    /// The operating system refused the link's thread.
    #[error("could not start the network thread: {0}")]
    Thread(#[from] std::io::Error),
}

/// How a link is set up.
#[derive(Clone, Debug)]
pub struct LinkOptions {
    /// Replicas of the stream when this link creates it (3 on a
    /// three-node cluster).
    pub replicas: usize,
    /// How long to wait for the first connection.
    pub connect_timeout: Duration,
    /// How long a request (append, stream lookup) may take.
    pub request_timeout: Duration,
}

impl Default for LinkOptions {
    fn default() -> Self {
        Self {
            replicas: 1,
            connect_timeout: Duration::from_secs(5),
            request_timeout: Duration::from_secs(3),
        }
    }
}

enum Cmd {
    /// The link is dropped (presence channels may still hold senders).
    Stop,
    Publish(Publish),
    Presence(Vec<u8>),
    Snapshot {
        seq: u64,
        bytes: Vec<u8>,
    },
}

/// How long the stream subscription may deliver nothing before the link
/// asks the server whether it missed something.
const STALL_CHECK: Duration = Duration::from_secs(1);

/// The object holding the latest snapshot in the bucket.
const SNAPSHOT_OBJECT: &str = "latest";

enum Event {
    Entry {
        seq: u64,
        bytes: Vec<u8>,
    },
    Published {
        n: u64,
        result: Published,
        error: Option<String>,
    },
    Online(bool),
    /// The server refused a publish (the message of its permissions
    /// violation).
    Denied(String),
    Error(String),
}

/// What one [`Link::pump`] did.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Pumped {
    /// Stream entries applied.
    pub entries: usize,
    /// Appends started.
    pub published: usize,
    /// The author and counter of each entry applied, in order.
    pub arrived: Vec<(String, u64)>,
}

/// What one [`Link::pump_log`] brought.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct PumpReport {
    /// Stream entries applied.
    pub entries: usize,
    /// The session's messages for this person: their edits refused or
    /// skipped, restored (see [`shapewright::doc::shared::Notice`]).
    pub notices: Vec<String>,
    /// The link's errors since the last pump, for the host's log.
    pub errors: Vec<String>,
    /// The server is reachable.
    pub online: bool,
    /// The server refused this person's edits (a viewer).
    pub view_only: bool,
}

impl PumpReport {
    /// Whether the document may have changed (entries arrived, or an
    /// edit of this person's was taken back).
    pub fn changed(&self) -> bool {
        self.entries > 0 || !self.notices.is_empty()
    }
}

/// A participant's connection to a session.
pub struct Link {
    url: SessionUrl,
    stream_last: u64,
    me: String,
    cmds: Option<mpsc::UnboundedSender<Cmd>>,
    events: std_mpsc::Receiver<Event>,
    thread: Option<JoinHandle<()>>,
    online: bool,
    blocked_since: Option<Instant>,
    /// After a failed append (server unreachable, no stream), the next
    /// one waits until then.
    retry_at: Option<Instant>,
    presence: PresenceChannel,
    errors: Vec<String>,
    /// The server refused our appends: we may only view the document.
    view_only: bool,
}

impl Link {
    /// Connects participant `me` to the session at `url`, creating the
    /// document's stream if it is new, and starts receiving its entries
    /// after sequence `after` (0: from the start; a late joiner restored
    /// from a snapshot passes the snapshot's sequence). Fails with a clear
    /// error when the server cannot be reached at all; once connected,
    /// losing the server is not an error: the link reconnects by itself
    /// and [`Link::is_online`] says so meanwhile.
    pub fn connect(
        url: &SessionUrl,
        me: &str,
        after: u64,
        options: LinkOptions,
    ) -> Result<Self, LinkError> {
        let (cmd_tx, cmd_rx) = mpsc::unbounded_channel();
        let (ev_tx, ev_rx) = std_mpsc::channel();
        let (ready_tx, ready_rx) = std_mpsc::sync_channel(1);
        let seen = Arc::new(Mutex::new(BTreeMap::new()));
        let task = Task {
            url: url.clone(),
            me: me.to_string(),
            after,
            options: options.clone(),
            seen: Arc::clone(&seen),
        };
        let thread = std::thread::Builder::new()
            .name("shapewright-net".into())
            .spawn(move || {
                let rt = match tokio::runtime::Builder::new_current_thread()
                    .enable_all()
                    .build()
                {
                    Ok(rt) => rt,
                    Err(e) => {
                        let _ = ready_tx.send(Err(LinkError::Thread(e)));
                        return;
                    }
                };
                rt.block_on(task.run(cmd_rx, ev_tx, ready_tx));
            })?;
        let wait = options.connect_timeout + options.request_timeout + Duration::from_secs(1);
        let ready = ready_rx.recv_timeout(wait).unwrap_or_else(|_| {
            Err(LinkError::Unreachable {
                url: url.to_string(),
                why: format!("no answer in {} s", wait.as_secs()),
            })
        });
        let stream_last = match ready {
            Ok(last) => last,
            Err(e) => {
                drop(cmd_tx);
                let _ = thread.join();
                return Err(e);
            }
        };
        Ok(Self {
            stream_last,
            url: url.clone(),
            me: me.to_string(),
            presence: PresenceChannel {
                tx: cmd_tx.clone(),
                seen,
            },
            cmds: Some(cmd_tx),
            events: ev_rx,
            thread: Some(thread),
            online: true,
            blocked_since: None,
            retry_at: None,
            errors: Vec::new(),
            view_only: false,
        })
    }

    /// The session's address.
    pub fn url(&self) -> &SessionUrl {
        &self.url
    }

    /// The stream's last sequence when the link connected: a joiner has
    /// caught up once its log has applied this far.
    pub fn last_seq_at_connect(&self) -> u64 {
        self.stream_last
    }

    /// Pumps `log` until it has applied the stream as it was at connect
    /// (joining: the document as the others have it), or `limit` passes.
    /// Returns whether it caught up.
    pub fn catch_up(&mut self, log: &mut SharedLog, limit: Duration) -> bool {
        let t = Instant::now();
        while log.confirmed().last_seq() < self.stream_last {
            if t.elapsed() > limit {
                return false;
            }
            if self.pump(log).entries == 0 {
                std::thread::sleep(Duration::from_millis(2));
            }
        }
        true
    }

    /// False while the server is unreachable (edits go on locally and are
    /// rebased and sent on reconnect).
    pub fn is_online(&self) -> bool {
        self.online
    }

    /// True once the server refused an append: this user may only view the
    /// document (their log was told, see
    /// [`shapewright::doc::shared::SharedLog::deny`]).
    pub fn is_view_only(&self) -> bool {
        self.view_only
    }

    /// Takes the errors the link met since the last call (a lost stream
    /// subscription, a refused append), for the host's log.
    pub fn take_errors(&mut self) -> Vec<String> {
        std::mem::take(&mut self.errors)
    }

    /// Applies every entry that arrived to `log`, reports append results to
    /// it, and starts its next append. Never blocks.
    pub fn pump(&mut self, log: &mut SharedLog) -> Pumped {
        let mut done = self.receive(log);
        if let (Some((seq, bytes)), Some(tx)) = (log.snapshot_due(), &self.cmds) {
            let _ = tx.send(Cmd::Snapshot { seq, bytes });
        }
        if self.retry_at.is_some_and(|t| Instant::now() < t) {
            return done;
        }
        if let Some(p) = log.next_publish() {
            if let Some(tx) = &self.cmds {
                if tx.send(Cmd::Publish(p)).is_ok() {
                    done.published += 1;
                }
            }
        }
        done
    }

    /// [`Self::pump`] for a host's [`OpLog`] (one made by
    /// [`OpLog::from_shared`]), with the person's messages and the link's
    /// state; `None` when `log` is not shared.
    pub fn pump_log(&mut self, log: &mut OpLog) -> Option<PumpReport> {
        let (pumped, notices) = log.with_shared(|log| {
            let p = self.pump(log);
            (p, log.take_notices())
        })?;
        Some(PumpReport {
            entries: pumped.entries,
            notices: notices.into_iter().map(|n| n.message).collect(),
            errors: self.take_errors(),
            online: self.online,
            view_only: self.view_only,
        })
    }

    /// [`Self::pump`] without appending: applies what arrived (a reader
    /// that never writes to the stream).
    pub fn receive(&mut self, log: &mut SharedLog) -> Pumped {
        let mut done = Pumped::default();
        loop {
            match self.events.try_recv() {
                Ok(Event::Entry { seq, bytes }) => {
                    if let Some(key) = log.integrate(seq, &bytes) {
                        done.arrived.push(key);
                    }
                    done.entries += 1;
                }
                Ok(Event::Published { n, result, error }) => {
                    log.published(n, result);
                    if result == Published::Conflict {
                        self.blocked_since.get_or_insert_with(Instant::now);
                    }
                    if result == Published::Failed {
                        self.retry_at = Some(Instant::now() + Duration::from_millis(250));
                    }
                    if let Some(e) = error {
                        // One message per failing entry, not one per retry.
                        if self.errors.last() != Some(&e) {
                            self.errors.push(e);
                        }
                    }
                }
                Ok(Event::Online(up)) => {
                    self.online = up;
                    if !up {
                        log.connection_lost();
                    }
                }
                Ok(Event::Denied(why)) => {
                    if why.contains(&self.url.log_subject()) {
                        self.view_only = true;
                        log.deny("the session's server lets you view this document, not edit it");
                    }
                    self.errors.push(format!("the server refused: {why}"));
                }
                Ok(Event::Error(e)) => self.errors.push(e),
                Err(_) => break,
            }
        }
        // A conflict waits for the entry that won; should none come (the
        // stream changed under us), try again after a second.
        if !log.is_blocked() {
            self.blocked_since = None;
        } else if self
            .blocked_since
            .is_some_and(|t| t.elapsed() > Duration::from_secs(1))
        {
            log.unblock();
            self.blocked_since = None;
        }
        done
    }

    /// Presence in both directions, for any thread (see
    /// [`PresenceChannel`]).
    pub fn presence(&self) -> PresenceChannel {
        self.presence.clone()
    }

    /// This participant's id.
    pub fn me(&self) -> &str {
        &self.me
    }
}

/// Presence in both directions: sends this participant's and holds the
/// latest of every other participant. Cloneable and usable from any
/// thread (a host's frame thread, while the [`Link`] lives with the log on
/// the commit thread); the network thread fills it directly, so reading it
/// never waits for an op to apply. Works until the link is dropped.
#[derive(Clone)]
pub struct PresenceChannel {
    tx: mpsc::UnboundedSender<Cmd>,
    seen: Arc<Mutex<BTreeMap<String, (Instant, Presence)>>>,
}

impl PresenceChannel {
    /// Sends `p` (not stored; hosts send at most
    /// [`shapewright::doc::shared::PRESENCE_HZ`] per second).
    pub fn send(&self, p: &Presence) {
        let _ = self.tx.send(Cmd::Presence(p.to_bytes()));
    }

    /// The latest presence of each other participant heard from within
    /// `max_age`, by participant id.
    pub fn others(&self, max_age: Duration) -> Vec<(String, Presence)> {
        let seen = self.seen.lock().unwrap_or_else(|e| e.into_inner());
        seen.iter()
            .filter(|(_, (t, _))| t.elapsed() <= max_age)
            .map(|(who, (_, p))| (who.clone(), p.clone()))
            .collect()
    }
}

impl Drop for Link {
    fn drop(&mut self) {
        if let Some(tx) = self.cmds.take() {
            let _ = tx.send(Cmd::Stop);
        }
        if let Some(t) = self.thread.take() {
            let _ = t.join();
        }
    }
}

struct Task {
    url: SessionUrl,
    me: String,
    after: u64,
    options: LinkOptions,
    seen: Arc<Mutex<BTreeMap<String, (Instant, Presence)>>>,
}

impl Task {
    async fn run(
        self,
        mut cmds: mpsc::UnboundedReceiver<Cmd>,
        events: std_mpsc::Sender<Event>,
        ready: std_mpsc::SyncSender<Result<u64, LinkError>>,
    ) {
        let ev = events.clone();
        // A permissions violation while connecting makes the connect's
        // error a clear "not allowed".
        let denied = std::sync::Arc::new(std::sync::Mutex::new(None::<String>));
        let denied_cb = std::sync::Arc::clone(&denied);
        let mut options = async_nats::ConnectOptions::new()
            .connection_timeout(self.options.connect_timeout)
            .request_timeout(Some(self.options.request_timeout))
            .reconnect_delay_callback(|attempts| {
                Duration::from_millis((100 * attempts as u64).min(1000))
            })
            .event_callback(move |e| {
                let ev = ev.clone();
                let denied = std::sync::Arc::clone(&denied_cb);
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
        if let Some((u, p)) = &self.url.user {
            options = options.user_and_password(u.clone(), p.clone());
        }
        let unreachable = |why: String| LinkError::Unreachable {
            url: self.url.to_string(),
            why,
        };
        let client = match tokio::time::timeout(
            self.options.connect_timeout,
            options.connect(self.url.servers.clone()),
        )
        .await
        {
            Ok(Ok(c)) => c,
            Ok(Err(e)) => return drop(ready.send(Err(connect_error(&self.url, e)))),
            Err(_) => return drop(ready.send(Err(unreachable("timed out".into())))),
        };
        let js = jetstream::ContextBuilder::new()
            .timeout(self.options.request_timeout)
            .build(client.clone());
        let config = stream::Config {
            name: self.url.stream(),
            subjects: vec![self.url.log_subject()],
            storage: stream::StorageType::File,
            num_replicas: self.options.replicas,
            duplicate_window: Duration::from_secs(120),
            max_message_size: (MAX_ENTRY_BYTES + 4096) as i32,
            ..Default::default()
        };
        let name = config.name.clone();
        // Two people opening a new document at once both try to make its
        // stream: the loser's create fails, and the winner's is there.
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
        let presence = client
            .subscribe(format!("sw.{}.presence.*", self.url.doc))
            .await;
        let last = match stream.info().await {
            Ok(info) => info.state.last_sequence,
            Err(_) => stream.cached_info().state.last_sequence,
        };
        let _ = ready.send(Ok(last));

        let consume = tokio::spawn(consume(
            stream,
            self.url.log_subject(),
            self.after,
            events.clone(),
        ));
        let listen = presence.ok().map(|mut sub| {
            let (seen, me) = (Arc::clone(&self.seen), self.me.clone());
            tokio::spawn(async move {
                while let Some(m) = sub.next().await {
                    let who = m.subject.rsplit('.').next().unwrap_or_default();
                    if who == me {
                        continue;
                    }
                    // A message that cannot be drawn is dropped (the
                    // sender's problem); the last good one stays.
                    if let Ok(p) = Presence::decode(&m.payload) {
                        let mut seen = seen.lock().unwrap_or_else(|e| e.into_inner());
                        seen.insert(who.to_string(), (Instant::now(), p));
                    }
                }
            })
        });
        let subject = self.url.log_subject();
        let presence_subject = self.url.presence_subject(&self.me);
        while let Some(cmd) = cmds.recv().await {
            match cmd {
                Cmd::Stop => break,
                Cmd::Publish(p) => {
                    tokio::spawn(append(js.clone(), subject.clone(), p, events.clone()));
                }
                Cmd::Presence(bytes) => {
                    let _ = client.publish(presence_subject.clone(), bytes.into()).await;
                }
                Cmd::Snapshot { seq, bytes } => {
                    let (js, bucket, events) =
                        (js.clone(), self.url.snapshot_bucket(), events.clone());
                    let replicas = self.options.replicas;
                    tokio::spawn(async move {
                        if let Err(e) = put_snapshot(&js, bucket, replicas, seq, bytes).await {
                            let _ = events
                                .send(Event::Error(format!("snapshot at {seq} not stored: {e}")));
                        }
                    });
                }
            }
        }
        consume.abort();
        if let Some(l) = listen {
            l.abort();
        }
        let _ = tokio::time::timeout(Duration::from_secs(1), client.flush()).await;
    }
}

/// A failed connect as the host shows it: a refused user or password is
/// "not allowed", anything else "unreachable".
fn connect_error(url: &SessionUrl, e: async_nats::ConnectError) -> LinkError {
    let url = url.to_string();
    let why = e.to_string();
    match e.kind() {
        async_nats::ConnectErrorKind::AuthorizationViolation
        | async_nats::ConnectErrorKind::Authentication => LinkError::NotAllowed { url, why },
        _ => LinkError::Unreachable { url, why },
    }
}

async fn snapshot_store(
    js: &jetstream::Context,
    bucket: String,
    replicas: usize,
) -> Result<jetstream::object_store::ObjectStore, String> {
    match js.get_object_store(&bucket).await {
        Ok(s) => Ok(s),
        Err(_) => js
            .create_object_store(jetstream::object_store::Config {
                bucket,
                storage: stream::StorageType::File,
                num_replicas: replicas,
                ..Default::default()
            })
            .await
            .map_err(|e| e.to_string()),
    }
}

async fn put_snapshot(
    js: &jetstream::Context,
    bucket: String,
    replicas: usize,
    seq: u64,
    bytes: Vec<u8>,
) -> Result<(), String> {
    let store = snapshot_store(js, bucket, replicas).await?;
    let meta = jetstream::object_store::ObjectMetadata {
        name: SNAPSHOT_OBJECT.into(),
        description: Some(format!("seq={seq}")),
        ..Default::default()
    };
    store
        .put(meta, &mut bytes.as_slice())
        .await
        .map(|_| ())
        .map_err(|e| e.to_string())
}

/// The latest snapshot of the session at `url` (the sequence it covers
/// and its bytes), or `None` when none was written yet. A late joiner
/// loads it ([`shapewright::doc::shared::Replica::from_snapshot`]) and
/// connects after its sequence instead of replaying the whole stream.
pub fn fetch_snapshot(
    url: &SessionUrl,
    options: &LinkOptions,
) -> Result<Option<(u64, Vec<u8>)>, LinkError> {
    let rt = tokio::runtime::Builder::new_current_thread()
        .enable_all()
        .build()?;
    rt.block_on(async {
        let unreachable = |why: String| LinkError::Unreachable {
            url: url.to_string(),
            why,
        };
        let mut connect =
            async_nats::ConnectOptions::new().connection_timeout(options.connect_timeout);
        if let Some((u, p)) = &url.user {
            connect = connect.user_and_password(u.clone(), p.clone());
        }
        let client = tokio::time::timeout(
            options.connect_timeout,
            connect.connect(url.servers.clone()),
        )
        .await
        .map_err(|_| unreachable("timed out".into()))?
        .map_err(|e| connect_error(url, e))?;
        let js = jetstream::ContextBuilder::new()
            .timeout(options.request_timeout)
            .build(client);
        let Ok(store) = js.get_object_store(url.snapshot_bucket()).await else {
            return Ok(None);
        };
        let Ok(mut object) = store.get(SNAPSHOT_OBJECT).await else {
            return Ok(None);
        };
        let seq = object
            .info()
            .description
            .as_deref()
            .and_then(|d| d.strip_prefix("seq="))
            .and_then(|n| n.parse::<u64>().ok());
        let mut bytes = Vec::new();
        use tokio::io::AsyncReadExt;
        if object.read_to_end(&mut bytes).await.is_err() {
            return Ok(None);
        }
        Ok(seq.map(|s| (s, bytes)))
    })
}

/// Delivers the stream's entries after `last`, in order, for as long as
/// the host listens; re-subscribes from the last one delivered whenever
/// the subscription breaks (server restart, lost connection).
async fn consume(
    mut stream: jetstream::stream::Stream,
    subject: String,
    mut last: u64,
    events: std_mpsc::Sender<Event>,
) {
    loop {
        let config = consumer::pull::OrderedConfig {
            filter_subject: subject.clone(),
            deliver_policy: if last == 0 {
                consumer::DeliverPolicy::All
            } else {
                consumer::DeliverPolicy::ByStartSequence {
                    start_sequence: last + 1,
                }
            },
            ..Default::default()
        };
        let messages = match stream.create_consumer(config).await {
            Ok(c) => c.messages().await.map_err(|e| e.to_string()),
            Err(e) => Err(e.to_string()),
        };
        match messages {
            Ok(mut messages) => loop {
                let m = match tokio::time::timeout(STALL_CHECK, messages.next()).await {
                    Ok(Some(m)) => m,
                    Ok(None) => break,
                    Err(_) => {
                        // Quiet for a while: fine if the stream is too. An
                        // ordered consumer whose server died in a cluster
                        // can go quiet with no error while the stream
                        // moves on (seen with nats-server 2.9.10).
                        match stream.info().await {
                            Ok(info) if info.state.last_sequence > last => {
                                let msg = format!(
                                    "stream subscription stalled at {last} of {}; resubscribing",
                                    info.state.last_sequence
                                );
                                if events.send(Event::Error(msg)).is_err() {
                                    return;
                                }
                                break;
                            }
                            _ => continue,
                        }
                    }
                };
                match m {
                    Ok(m) => {
                        let Ok(info) = m.info() else { continue };
                        let seq = info.stream_sequence;
                        if seq <= last {
                            continue;
                        }
                        last = seq;
                        let bytes = m.payload.to_vec();
                        if events.send(Event::Entry { seq, bytes }).is_err() {
                            return;
                        }
                    }
                    Err(e) => {
                        let msg = format!("stream subscription lost ({e}); resubscribing");
                        if events.send(Event::Error(msg)).is_err() {
                            return;
                        }
                        break;
                    }
                }
            },
            Err(e) => {
                let msg = format!("cannot subscribe to the stream ({e}); retrying");
                if events.send(Event::Error(msg)).is_err() {
                    return;
                }
            }
        }
        tokio::time::sleep(Duration::from_millis(250)).await;
    }
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
