//! Joining a session as a host does it (the headset host and the Blender
//! add-on share this): the person's credentials (from the options, or the
//! file [`crate::CREDENTIALS_ENV`] names), the latest snapshot when there
//! is one (checked against the stream in the background), the tail of
//! the stream, the join confirmed, and an empty session seeded from the
//! file the person opened.

use std::time::{Duration, Instant};

use shapewright::doc::shared::{colour_for, Replica, SharedError, SharedLog};
use shapewright::doc::{LogError, OpLog};

use crate::{fetch_snapshot, Credentials, CredentialsError, Link, LinkError, LinkOptions};
use crate::{SessionUrl, StoredSnapshot};

/// Why joining failed. Nothing was written to the session.
#[derive(Debug, thiserror::Error)]
pub enum JoinError {
    /// The server could not be reached or would not let us in.
    #[error(transparent)]
    Link(#[from] LinkError),
    /// The credentials file could not be read.
    #[error(transparent)]
    Credentials(#[from] CredentialsError),
    /// The participant was refused (bad id or name, session full).
    #[error(transparent)]
    Shared(#[from] SharedError),
    /// The session's history could not become a log.
    #[error(transparent)]
    Log(#[from] LogError),
    /// The server stopped answering while we caught up or joined.
    #[error("{url}: {what}")]
    Stalled {
        /// The address.
        url: String,
        /// What did not happen in time.
        what: String,
    },
    /// A file was opened into a session that already has a document.
    #[error("{0} already has a document; join without opening a file to model on it")]
    NotEmpty(String),
    /// A file was opened into a session this person may only view.
    #[error("{0} lets you view but not edit, so the file you opened cannot start it")]
    ViewOnly(String),
}

/// A participant id from a person's name: ASCII letters, digits, `-` and
/// `_` kept, anything else `_`, at most 64 bytes.
pub fn participant_id(name: &str) -> String {
    let id: String = name
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || c == '-' || c == '_' {
                c
            } else {
                '_'
            }
        })
        .take(64)
        .collect();
    if id.is_empty() {
        "someone".into()
    } else {
        id
    }
}

/// Joins the session at `url` as `me` (shown as `name` in the colour
/// [`colour_for`] gives `me`; with credentials, `me` is their user name,
/// the only one the server lets this person write as): restores the
/// newest snapshot and checks it against the stream in the background
/// ([`Link::check_snapshot`]; replaying the whole stream at once if there
/// is none or it is unusable, with a note in the returned messages),
/// catches up, waits for the join to come back, and, when `opened` holds
/// a file's history and the session is empty, starts the session from
/// it. Returns the person's log (an ordinary [`OpLog`] backed by the
/// session), the link, and messages for the person.
pub fn join(
    url: &SessionUrl,
    name: &str,
    me: &str,
    mut options: LinkOptions,
    opened: &OpLog,
) -> Result<(OpLog, Link, Vec<String>), JoinError> {
    let mut messages = Vec::new();
    let stalled = |what: &str| JoinError::Stalled {
        url: url.to_string(),
        what: what.to_string(),
    };
    if options.credentials.is_none() {
        options.credentials = Credentials::from_env()?;
    }
    let user = options.credentials.as_ref().and_then(|c| c.user.clone());
    let me = match user {
        Some(user) if user != me => {
            messages.push(format!(
                "you are `{user}` in this session (your user name on its server)"
            ));
            user
        }
        _ => me.to_string(),
    };
    let me = me.as_str();
    let stored = fetch_snapshot(url, &options)?;
    let restored = match &stored {
        Some(StoredSnapshot { seq, bytes, writer }) => match Replica::from_snapshot(bytes) {
            Ok(r) if r.last_seq() == *seq => Some(r),
            Ok(_) => {
                messages.push(format!(
                    "`{writer}`'s snapshot does not hold the sequence it claims; replaying the whole stream"
                ));
                None
            }
            Err(e) => {
                messages.push(format!(
                    "`{writer}`'s snapshot is unusable ({e}); replaying the whole stream"
                ));
                None
            }
        },
        None => None,
    };
    let replica = restored.unwrap_or_default();
    let after = replica.last_seq();
    let mut shared = SharedLog::resume(me, name, colour_for(me), replica, 1)?;
    let mut link = Link::connect(url, me, after, options)?;
    if let (Some(s), true) = (stored, after > 0) {
        messages.push(format!(
            "started from `{}`'s snapshot at entry {}; checking it against the stream",
            s.writer, s.seq
        ));
        link.check_snapshot(s.seq, s.bytes, &s.writer);
    }
    messages.push(format!(
        "joined {url} as {me} ({} entries to catch up on)",
        link.last_seq_at_connect() - after.min(link.last_seq_at_connect())
    ));
    if !link.catch_up(&mut shared, Duration::from_secs(120)) {
        return Err(stalled("could not catch up in 120 s"));
    }
    // Our join comes back before we may create anything (a viewer's is
    // refused instead).
    let t = Instant::now();
    while !shared.is_joined() && !link.is_view_only() {
        link.pump(&mut shared);
        if t.elapsed() > Duration::from_secs(30) {
            return Err(stalled("the server did not confirm the join in 30 s"));
        }
        std::thread::sleep(Duration::from_millis(2));
    }
    if link.is_view_only() {
        messages.push("you may view this document but not edit it".into());
    }
    if !opened.is_empty() {
        if link.is_view_only() {
            return Err(JoinError::ViewOnly(url.to_string()));
        }
        if shared.confirmed().op_count() > 0 {
            return Err(JoinError::NotEmpty(url.to_string()));
        }
        shared.seed(opened.ops()[..opened.cursor()].to_vec())?;
    }
    Ok((OpLog::from_shared(shared), link, messages))
}
