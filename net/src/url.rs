//! `nats://HOST:PORT/DOC` or `tls://HOST:PORT/DOC`: where a shared
//! session lives. Passwords never go in the address (it shows in `ps`,
//! in shell history and in logs): they come from a credentials file
//! ([`crate::Credentials`]); an address with `USER:PASSWORD@` is refused
//! with a message saying so.

use shapewright::doc::shared::subject_token;

/// A session address: the server and the document's name on it.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct SessionUrl {
    /// `HOST:PORT` (several, comma-separated, for a cluster).
    pub servers: Vec<String>,
    /// The document: 1 to 64 bytes of `A-Z a-z 0-9 _ -`.
    pub doc: String,
    /// `tls://`: the connection must be TLS (it also is whenever the
    /// credentials name a CA certificate).
    pub tls: bool,
}

/// Why a session address was refused.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum UrlError {
    /// Not `nats://HOST:PORT/DOC`.
    #[error("`{0}` is not a session address: expected nats://HOST:PORT/DOC or tls://HOST:PORT/DOC (for example tls://192.168.1.20:4222/teapot)")]
    Shape(String),
    /// The document name has characters a stream name cannot.
    #[error("document name `{0}` must be 1 to 64 bytes of A-Z a-z 0-9 _ -")]
    Doc(String),
    /// The address holds a user and password (the old form).
    #[error("a session address no longer holds a password (it would show in `ps`, shell history and logs): use {0} and put the user and password in a credentials file (--credentials FILE or the environment variable SHAPEWRIGHT_SESSION_CREDENTIALS; `shapewright-xr session-access --invite` writes one)")]
    Password(String),
}

impl SessionUrl {
    /// Parses `nats://HOST:PORT[,HOST:PORT...]/DOC` (or `tls://...`).
    pub fn parse(text: &str) -> Result<Self, UrlError> {
        let shape = || UrlError::Shape(text.chars().take(200).collect());
        let (tls, rest) = match (text.strip_prefix("nats://"), text.strip_prefix("tls://")) {
            (Some(rest), _) => (false, rest),
            (_, Some(rest)) => (true, rest),
            _ => return Err(shape()),
        };
        let (authority, doc) = rest.split_once('/').ok_or_else(shape)?;
        if let Some((_, hosts)) = authority.rsplit_once('@') {
            let scheme = if tls { "tls" } else { "nats" };
            let doc: String = doc.chars().take(80).collect();
            let hosts: String = hosts.chars().take(200).collect();
            return Err(UrlError::Password(format!("{scheme}://{hosts}/{doc}")));
        }
        let servers: Vec<String> = authority.split(',').map(str::to_string).collect();
        for s in &servers {
            let (host, port) = s.rsplit_once(':').ok_or_else(shape)?;
            if host.is_empty() || port.parse::<u16>().is_err() {
                return Err(shape());
            }
        }
        if doc.is_empty()
            || doc.len() > 64
            || !doc
                .bytes()
                .all(|b| b.is_ascii_alphanumeric() || b == b'_' || b == b'-')
        {
            return Err(UrlError::Doc(doc.chars().take(80).collect()));
        }
        Ok(Self {
            servers,
            doc: doc.to_string(),
            tls,
        })
    }

    /// The servers as the NATS client takes them (`tls://` when TLS is
    /// required).
    pub fn server_urls(&self) -> Vec<String> {
        let scheme = if self.tls { "tls" } else { "nats" };
        self.servers
            .iter()
            .map(|s| format!("{scheme}://{s}"))
            .collect()
    }

    /// The JetStream stream holding the document's entries.
    pub fn stream(&self) -> String {
        format!("SW_{}", self.doc)
    }

    /// The subjects of the document's stream: one per person.
    pub fn log_subjects(&self) -> String {
        format!("sw.{}.log.>", self.doc)
    }

    /// The one subject of streams made before issue 35 (everyone on it).
    pub fn old_log_subject(&self) -> String {
        format!("sw.{}.log", self.doc)
    }

    /// The subject participant `who` appends on (the server lets only
    /// them publish there). `None` when `who` is not a participant id.
    pub fn log_subject(&self, who: &str) -> Option<String> {
        subject_token(who).map(|t| format!("sw.{}.log.{t}", self.doc))
    }

    /// The subject participant `who` sends presence on (not stored).
    pub fn presence_subject(&self, who: &str) -> Option<String> {
        subject_token(who).map(|t| format!("sw.{}.presence.{t}", self.doc))
    }

    /// Everyone's presence.
    pub fn presence_subjects(&self) -> String {
        format!("sw.{}.presence.*", self.doc)
    }

    /// The object-store bucket holding snapshots.
    pub fn snapshot_bucket(&self) -> String {
        format!("SW_{}_snapshots", self.doc)
    }
}

impl std::fmt::Display for SessionUrl {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let scheme = if self.tls { "tls" } else { "nats" };
        write!(f, "{scheme}://{}/{}", self.servers.join(","), self.doc)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn addresses_parse_or_say_what_is_wrong() {
        let u = SessionUrl::parse("nats://127.0.0.1:4222/teapot").unwrap();
        assert_eq!(u.servers, ["127.0.0.1:4222"]);
        assert_eq!(u.doc, "teapot");
        assert_eq!(u.stream(), "SW_teapot");
        assert!(!u.tls);
        let u = SessionUrl::parse("tls://a:1,b:2/chair-2").unwrap();
        assert_eq!(u.servers, ["a:1", "b:2"]);
        assert_eq!(u.server_urls(), ["tls://a:1", "tls://b:2"]);
        assert!(u.tls);
        assert_eq!(u.to_string(), "tls://a:1,b:2/chair-2");
        assert_eq!(u.log_subject("ana.b").unwrap(), "sw.chair-2.log.ana%2Eb");
        assert_eq!(u.log_subject("a b"), None);
        for bad in [
            "http://a:1/x",
            "nats://a/x",
            "nats://a:1",
            "nats://a:99999/x",
        ] {
            assert!(
                matches!(SessionUrl::parse(bad), Err(UrlError::Shape(_))),
                "{bad}"
            );
        }
        for bad in ["nats://a:1/", "nats://a:1/x.y", "nats://a:1/x y"] {
            assert!(
                matches!(SessionUrl::parse(bad), Err(UrlError::Doc(_))),
                "{bad}"
            );
        }
        // The old form is refused, and the message does not repeat the
        // password.
        let e = SessionUrl::parse("nats://ana:s3cret@a:1/x").unwrap_err();
        let text = e.to_string();
        assert!(matches!(e, UrlError::Password(_)), "{text}");
        assert!(
            !text.contains("s3cret") && text.contains("use nats://a:1/x"),
            "{text}"
        );
    }
}
