//! Connecting to a session's server: the client's options (credentials,
//! TLS verified against the team's CA, the member's own inbox prefix) and
//! the document's stream, made with settings that keep it append-only,
//! and refused when someone made it otherwise.

use std::time::Duration;

use async_nats::jetstream::stream;
use shapewright::doc::shared::MAX_ENTRY_BYTES;

use crate::access::inbox_prefix;
use crate::{LinkError, LinkOptions, SessionUrl};

/// The NATS client options for `url` (without event callbacks): the
/// user and password from the credentials, TLS when the address says
/// `tls://` or the credentials name a CA (then the server's certificate
/// must be signed by it), and replies on the user's own inbox prefix
/// (the server lets each member read only theirs).
pub(crate) fn client_options(
    url: &SessionUrl,
    me: &str,
    options: &LinkOptions,
) -> async_nats::ConnectOptions {
    let creds = options.credentials.as_ref();
    let user = creds.and_then(|c| c.user.as_deref()).unwrap_or(me);
    let mut c = async_nats::ConnectOptions::new()
        .connection_timeout(options.connect_timeout)
        .request_timeout(Some(options.request_timeout))
        .custom_inbox_prefix(inbox_prefix(user));
    if let Some(creds) = creds {
        if let (Some(u), Some(p)) = (&creds.user, &creds.password) {
            c = c.user_and_password(u.clone(), p.clone());
        }
        if let Some(ca) = &creds.ca {
            c = c.add_root_certificates(ca.clone()).require_tls(true);
        }
    }
    if url.tls {
        c = c.require_tls(true);
    }
    c
}

/// Connects with `c` to `url`'s servers within the connect timeout.
pub(crate) async fn connect(
    url: &SessionUrl,
    c: async_nats::ConnectOptions,
    options: &LinkOptions,
) -> Result<async_nats::Client, LinkError> {
    match tokio::time::timeout(options.connect_timeout, c.connect(url.server_urls())).await {
        Ok(Ok(client)) => Ok(client),
        Ok(Err(e)) => Err(connect_error(url, e)),
        Err(_) => Err(LinkError::Unreachable {
            url: url.to_string(),
            why: "timed out".into(),
        }),
    }
}

/// A failed connect as the host shows it: a refused user or password is
/// "not allowed", a certificate the CA did not sign says so, anything
/// else is "unreachable".
pub(crate) fn connect_error(url: &SessionUrl, e: async_nats::ConnectError) -> LinkError {
    let url = url.to_string();
    let why = e.to_string();
    // rustls' refusals of the server's certificate come as I/O errors.
    let tls = ["certificate", "tls", "handshake"]
        .iter()
        .any(|w| why.to_lowercase().contains(w));
    match e.kind() {
        async_nats::ConnectErrorKind::AuthorizationViolation
        | async_nats::ConnectErrorKind::Authentication => LinkError::NotAllowed { url, why },
        async_nats::ConnectErrorKind::Tls => LinkError::Tls { url, why },
        async_nats::ConnectErrorKind::Io if tls => LinkError::Tls { url, why },
        _ => LinkError::Unreachable { url, why },
    }
}

/// The document's stream as Shapewright makes it: one subject per person,
/// file storage, nothing ever removed (no limits, no age, deletes and
/// purges refused by the server itself), no rollups, no sources.
pub(crate) fn stream_config(url: &SessionUrl, replicas: usize) -> stream::Config {
    stream::Config {
        name: url.stream(),
        subjects: vec![url.log_subjects()],
        storage: stream::StorageType::File,
        num_replicas: replicas,
        duplicate_window: Duration::from_secs(120),
        max_message_size: (MAX_ENTRY_BYTES + 4096) as i32,
        deny_delete: true,
        deny_purge: true,
        allow_rollup: false,
        ..Default::default()
    }
}

/// Refuses a document stream that Shapewright did not make this way: one
/// from before issue 35 (a single subject for everyone, so its entries
/// cannot say who sent them), or one whose settings let entries vanish,
/// be rewritten or come from elsewhere (someone made it by hand, or a
/// dishonest editor made it first).
pub(crate) fn check_stream(url: &SessionUrl, c: &stream::Config) -> Result<(), LinkError> {
    if c.subjects == [url.old_log_subject()] {
        return Err(LinkError::OldStream {
            url: url.to_string(),
            stream: url.stream(),
        });
    }
    let mut wrong = Vec::new();
    if c.subjects != [url.log_subjects()] {
        wrong.push(format!("subjects {:?}", c.subjects));
    }
    if !c.deny_delete || !c.deny_purge {
        wrong.push("deleting or purging allowed".to_string());
    }
    if c.allow_rollup {
        wrong.push("rollups allowed".to_string());
    }
    if c.max_messages > 0
        || c.max_bytes > 0
        || c.max_messages_per_subject > 0
        || !c.max_age.is_zero()
        || c.retention != stream::RetentionPolicy::Limits
    {
        wrong.push("entries expire or are removed".to_string());
    }
    if c.mirror.is_some()
        || c.sources.as_ref().is_some_and(|s| !s.is_empty())
        || c.republish.is_some()
        || c.sealed
    {
        wrong.push("sourced, mirrored, republished or sealed".to_string());
    }
    if wrong.is_empty() {
        Ok(())
    } else {
        Err(LinkError::Foreign {
            url: url.to_string(),
            stream: url.stream(),
            why: wrong.join("; "),
        })
    }
}
