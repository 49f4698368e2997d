//! [`Link`]: one participant's connection to a session's stream. It runs
//! the NATS client on its own thread (a current-thread tokio runtime) and
//! talks to the host through channels, so a host's frame loop only calls
//! [`Link::pump`], which never blocks: it hands arrived entries to the
//! [`SharedLog`] and the log's next entry to the server.
//!
//! On the server: one JetStream stream per document (`SW_<doc>`, file
//! storage, a two-minute de-duplication window, deletes and purges
//! refused), each person appending on their own subject
//! `sw.<doc>.log.<token>` ([`shapewright::doc::shared::subject_token`])
//! with `Nats-Msg-Id` = author:counter:nonce (the nonce is this link's,
//! random, so nobody can pre-empt an entry's id and have it dropped as a
//! duplicate) and `Nats-Expected-Last-Sequence` = the last sequence the
//! author had seen; presence on `sw.<doc>.presence.<token>`, plain NATS
//! (never stored); snapshots in the object store bucket
//! `SW_<doc>_snapshots` (see [`crate::fetch_snapshot`]).

use std::collections::BTreeMap;
use std::sync::mpsc as std_mpsc;
use std::sync::{Arc, Mutex};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use shapewright::doc::shared::{Presence, Publish, Published, SharedLog, SnapshotCheck, Verdict};
use shapewright::doc::OpLog;
use tokio::sync::mpsc;

use crate::task::{nonce, Task};
use crate::{Credentials, SessionUrl};

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
    /// The server's certificate is not signed by the team's CA (or the
    /// server speaks no TLS, or its name is not in its certificate).
    #[error("the session server {url} failed the TLS check: {why} (is `ca` in your credentials file the team's CA certificate, and the server's certificate made for the name in the address? see scripts/session_certs.sh)")]
    Tls {
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
    /// The document's stream was made by a Shapewright from before
    /// per-person subjects (issue 35): its entries cannot say who sent
    /// them, so it is not joined.
    #[error("{url}: the document's stream {stream} was made by an older Shapewright, where an entry's author was whatever its sender wrote, so it is not joined; open its last autosave (shapewright-DOC.usda) and start a new document from it with --open, or ask the server's operator to remove the stream {stream}")]
    OldStream {
        /// The address.
        url: String,
        /// The stream.
        stream: String,
    },
    /// The document's stream exists with settings Shapewright does not
    /// make (someone made it by hand, or made it first with others).
    #[error("{url}: the document's stream {stream} was not made by Shapewright ({why}), so its history cannot be trusted; ask the server's operator to remove it")]
    Foreign {
        /// The address.
        url: String,
        /// The stream.
        stream: String,
        /// What is wrong with it.
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
    /// The participant id cannot be a subject token.
    #[error("participant id `{0}` must be 1 to 64 bytes of A-Z a-z 0-9 _ - .")]
    BadParticipant(String),
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
    /// User, password and CA certificate (none: an open server without
    /// TLS). [`crate::join::join`] reads them from the environment when
    /// unset.
    pub credentials: Option<Credentials>,
}

impl Default for LinkOptions {
    fn default() -> Self {
        Self {
            replicas: 1,
            connect_timeout: Duration::from_secs(5),
            request_timeout: Duration::from_secs(3),
            credentials: None,
        }
    }
}

pub(crate) enum Cmd {
    /// The link is dropped (presence channels may still hold senders).
    Stop,
    Publish(Publish),
    Presence(Vec<u8>),
    Snapshot {
        seq: u64,
        bytes: Vec<u8>,
    },
    /// Replay the stream up to the snapshot's sequence and compare.
    Check(Box<SnapshotCheck>),
}

pub(crate) enum Event {
    Entry {
        seq: u64,
        from: String,
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
    /// The snapshot check's verdict.
    Checked(Verdict),
}

/// Where a joiner's snapshot check stands ([`Link::check_snapshot`]).
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum SnapshotState {
    /// No snapshot was loaded (the whole stream was replayed).
    None,
    /// The stream is being replayed in the background to check it.
    Checking {
        /// Who stored the snapshot.
        writer: String,
    },
    /// It was the stream's replay, byte for byte.
    Confirmed,
    /// It was not: the document is now the stream's.
    Replaced {
        /// Who stored the snapshot.
        writer: String,
    },
}

struct Checking {
    writer: String,
    /// Entries applied since the snapshot, for the replay to catch up.
    live: Vec<(u64, String, Vec<u8>)>,
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
    checking: Option<Checking>,
    snapshot: SnapshotState,
}

impl Link {
    /// Connects participant `me` to the session at `url`, creating the
    /// document's stream if it is new, and starts receiving its entries
    /// after sequence `after` (0: from the start; a late joiner restored
    /// from a snapshot passes the snapshot's sequence). Fails with a clear
    /// error when the server cannot be reached at all, refuses the user
    /// or the TLS check, or holds a stream Shapewright did not make this
    /// way; once connected, losing the server is not an error: the link
    /// reconnects by itself and [`Link::is_online`] says so meanwhile.
    pub fn connect(
        url: &SessionUrl,
        me: &str,
        after: u64,
        options: LinkOptions,
    ) -> Result<Self, LinkError> {
        if url.log_subject(me).is_none() {
            return Err(LinkError::BadParticipant(me.chars().take(80).collect()));
        }
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
            nonce: nonce(),
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
            checking: None,
            snapshot: SnapshotState::None,
        })
    }

    /// Checks the snapshot this link's log started from (`bytes`, stored
    /// by `writer`, claiming the stream up to `seq`, which must be the
    /// `after` this link connected with): the stream is replayed up to
    /// `seq` on a thread of its own and compared; should the snapshot
    /// differ, a later [`Self::pump`] switches the log to the stream's
    /// document and tells its person (see
    /// [`shapewright::doc::shared::SnapshotCheck`]).
    pub fn check_snapshot(&mut self, seq: u64, bytes: Vec<u8>, writer: &str) {
        let Some(tx) = &self.cmds else { return };
        let check = Box::new(SnapshotCheck::new(seq, bytes));
        if tx.send(Cmd::Check(check)).is_ok() {
            self.checking = Some(Checking {
                writer: writer.to_string(),
                live: Vec::new(),
            });
            self.snapshot = SnapshotState::Checking {
                writer: writer.to_string(),
            };
        }
    }

    /// Where the check of the snapshot this link's log started from
    /// stands.
    pub fn snapshot_state(&self) -> &SnapshotState {
        &self.snapshot
    }

    fn settle(&mut self, log: &mut SharedLog, verdict: Verdict) {
        let Some(c) = self.checking.take() else {
            return;
        };
        let why = format!(
            "the snapshot you joined from (stored by `{}`) is not what the session's stream holds: your document is now the stream's, and your edits since joining were applied to it again",
            c.writer
        );
        self.snapshot = match verdict {
            Verdict::Same => SnapshotState::Confirmed,
            differs => {
                differs.settle(log, &c.live, &why);
                self.errors.push(why);
                SnapshotState::Replaced { writer: c.writer }
            }
        };
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
                Ok(Event::Entry { seq, from, bytes }) => {
                    if let Some(key) = log.integrate(seq, &from, &bytes) {
                        done.arrived.push(key);
                    }
                    done.entries += 1;
                    if let Some(c) = &mut self.checking {
                        c.live.push((seq, from, bytes));
                    }
                }
                Ok(Event::Checked(verdict)) => self.settle(log, verdict),
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
                    let mine = self.url.log_subject(&self.me).unwrap_or_default();
                    if why.contains(&mine) {
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
