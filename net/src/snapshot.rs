//! Snapshots in the JetStream object store: each editor stores theirs
//! under the object name `by.<their subject token>` (the only one the
//! server lets them write, see [`crate::access`]), so a snapshot's object
//! names who stored it. A late joiner takes the newest that the stream
//! has reached, and checks it against the stream's replay
//! ([`shapewright::doc::shared::SnapshotCheck`]): a snapshot is a claim,
//! never the truth.

use async_nats::jetstream::{self, object_store, stream};
use base64::Engine;
use futures_util::TryStreamExt;
use shapewright::doc::shared::id_from_token;
use tokio::io::AsyncReadExt;

use crate::access::snapshot_object;
use crate::connect::{client_options, connect};
use crate::{LinkError, LinkOptions, SessionUrl};

/// A snapshot as stored: the sequence it says it covers, its bytes, and
/// the participant whose object it is.
#[derive(Clone, Debug)]
pub struct StoredSnapshot {
    /// The stream sequence it claims to hold the replica at.
    pub seq: u64,
    /// Its bytes ([`shapewright::doc::shared::Replica::from_snapshot`]).
    pub bytes: Vec<u8>,
    /// Who stored it (the object's name; under a member list only they
    /// can write it).
    pub writer: String,
}

async fn store(
    js: &jetstream::Context,
    bucket: String,
    replicas: usize,
) -> Result<object_store::ObjectStore, String> {
    match js.get_object_store(&bucket).await {
        Ok(s) => Ok(s),
        Err(_) => js
            .create_object_store(object_store::Config {
                bucket,
                storage: stream::StorageType::File,
                num_replicas: replicas,
                ..Default::default()
            })
            .await
            .map_err(|e| e.to_string()),
    }
}

/// Stores `bytes`, the replica at `seq`, as `me`'s snapshot.
pub(crate) async fn put(
    js: &jetstream::Context,
    url: &SessionUrl,
    me: &str,
    replicas: usize,
    seq: u64,
    bytes: Vec<u8>,
) -> Result<(), String> {
    let name = snapshot_object(me).ok_or("not a participant id")?;
    let store = store(js, url.snapshot_bucket(), replicas).await?;
    let meta = object_store::ObjectMetadata {
        name,
        description: Some(format!("seq={seq}")),
        ..Default::default()
    };
    store
        .put(meta, &mut bytes.as_slice())
        .await
        .map(|_| ())
        .map_err(|e| e.to_string())
}

/// The writer a snapshot's metadata subject names (`$O.B.M.<base64 of
/// by.TOKEN>`), read from the subject itself, never from the message.
fn writer_of(subject: &str) -> Option<(String, String)> {
    let encoded = subject.rsplit('.').next()?;
    let name = base64::engine::general_purpose::URL_SAFE
        .decode(encoded)
        .ok()
        .and_then(|b| String::from_utf8(b).ok())?;
    let writer = id_from_token(name.strip_prefix("by.")?)?;
    Some((name, writer))
}

/// The newest snapshot of the session at `url` that the stream has
/// reached (its claimed sequence is at most the stream's last), or
/// `None` when there is none (no snapshots yet, or none readable). A
/// late joiner loads it, connects after its sequence and checks it
/// ([`crate::Link::check_snapshot`]).
pub fn fetch_snapshot(
    url: &SessionUrl,
    options: &LinkOptions,
) -> Result<Option<StoredSnapshot>, LinkError> {
    let rt = tokio::runtime::Builder::new_current_thread()
        .enable_all()
        .build()?;
    rt.block_on(async {
        let client = connect(url, client_options(url, "someone", options), options).await?;
        let js = jetstream::ContextBuilder::new()
            .timeout(options.request_timeout)
            .build(client);
        let Ok(mut log) = js.get_stream(url.stream()).await else {
            return Ok(None);
        };
        let last = match log.info().await {
            Ok(info) => info.state.last_sequence,
            Err(_) => return Ok(None),
        };
        let bucket = url.snapshot_bucket();
        let Ok(objects) = js.get_stream(format!("OBJ_{bucket}")).await else {
            return Ok(None);
        };
        let Ok(store) = js.get_object_store(&bucket).await else {
            return Ok(None);
        };
        let mut names = Vec::new();
        if let Ok(mut subjects) = objects.info_with_subjects(format!("$O.{bucket}.M.>")).await {
            while let Ok(Some((subject, _))) = subjects.try_next().await {
                names.extend(writer_of(&subject));
            }
        }
        let mut found = Vec::new();
        for (name, writer) in names {
            let Ok(info) = store.info(&name).await else {
                continue;
            };
            let seq = info
                .description
                .as_deref()
                .and_then(|d| d.strip_prefix("seq="))
                .and_then(|n| n.parse::<u64>().ok());
            if let Some(seq) = seq.filter(|&s| s > 0 && s <= last) {
                found.push((seq, name, writer));
            }
        }
        // Newest first; a snapshot that does not read (its chunks were
        // tampered with: the digest fails) gives way to the next.
        found.sort_by(|a, b| b.cmp(a));
        for (seq, name, writer) in found {
            let Ok(mut object) = store.get(&name).await else {
                continue;
            };
            let mut bytes = Vec::new();
            if object.read_to_end(&mut bytes).await.is_ok() {
                return Ok(Some(StoredSnapshot { seq, bytes, writer }));
            }
        }
        Ok(None)
    })
}
