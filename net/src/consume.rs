//! Reading a document's stream in order, for as long as someone listens:
//! the live entries of a [`crate::Link`], and the replay that checks a
//! joiner's snapshot.

use std::time::Duration;

use async_nats::jetstream::{self, consumer};
use futures_util::StreamExt;

/// How long the stream subscription may deliver nothing before the link
/// asks the server whether it missed something.
const STALL_CHECK: Duration = Duration::from_secs(1);

/// What the stream reader reports.
pub(crate) enum Read {
    /// The message at `seq`, sent on the subject whose last token is
    /// `from`.
    Entry {
        seq: u64,
        from: String,
        bytes: Vec<u8>,
    },
    /// The subscription broke or stalled (it resubscribes by itself).
    Error(String),
}

/// Delivers the stream's messages after `last`, in order, until one at or
/// past `until` was delivered or nobody listens; re-subscribes from the
/// last one delivered whenever the subscription breaks (server restart,
/// lost connection).
pub(crate) async fn consume(
    mut stream: jetstream::stream::Stream,
    subject: String,
    mut last: u64,
    until: u64,
    out: impl Fn(Read) -> bool,
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
                                if !out(Read::Error(msg)) {
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
                        let from = m.subject.rsplit('.').next().unwrap_or_default();
                        let read = Read::Entry {
                            seq,
                            from: from.to_string(),
                            bytes: m.payload.to_vec(),
                        };
                        if !out(read) || seq >= until {
                            return;
                        }
                    }
                    Err(e) => {
                        let msg = format!("stream subscription lost ({e}); resubscribing");
                        if !out(Read::Error(msg)) {
                            return;
                        }
                        break;
                    }
                }
            },
            Err(e) => {
                let msg = format!("cannot subscribe to the stream ({e}); retrying");
                if !out(Read::Error(msg)) {
                    return;
                }
            }
        }
        tokio::time::sleep(Duration::from_millis(250)).await;
    }
}
