//! `nats://[USER:PASS@]HOST:PORT/DOC`: where a shared session lives.

/// A session address: the server and the document's name on it.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct SessionUrl {
    /// `HOST:PORT` (several, comma-separated, for a cluster).
    pub servers: Vec<String>,
    /// The document: 1 to 64 bytes of `A-Z a-z 0-9 _ -`.
    pub doc: String,
    /// NATS user and password, if the server asks for them.
    pub user: Option<(String, String)>,
}

/// Why a session address was refused.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum UrlError {
    /// Not `nats://HOST:PORT/DOC`.
    #[error("`{0}` is not a session address: expected nats://HOST:PORT/DOC (for example nats://127.0.0.1:4222/teapot)")]
    Shape(String),
    /// The document name has characters a stream name cannot.
    #[error("document name `{0}` must be 1 to 64 bytes of A-Z a-z 0-9 _ -")]
    Doc(String),
}

impl SessionUrl {
    /// Parses `nats://[USER:PASS@]HOST:PORT[,HOST:PORT...]/DOC`.
    pub fn parse(text: &str) -> Result<Self, UrlError> {
        let shape = || UrlError::Shape(text.chars().take(200).collect());
        let rest = text.strip_prefix("nats://").ok_or_else(shape)?;
        let (authority, doc) = rest.split_once('/').ok_or_else(shape)?;
        let (user, hosts) = match authority.rsplit_once('@') {
            Some((cred, hosts)) => {
                let (u, p) = cred.split_once(':').ok_or_else(shape)?;
                (Some((u.to_string(), p.to_string())), hosts)
            }
            None => (None, authority),
        };
        let servers: Vec<String> = hosts.split(',').map(str::to_string).collect();
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
            user,
        })
    }

    /// The JetStream stream holding the document's entries.
    pub fn stream(&self) -> String {
        format!("SW_{}", self.doc)
    }

    /// The subject entries are appended on.
    pub fn log_subject(&self) -> String {
        format!("sw.{}.log", self.doc)
    }

    /// The subject participant `who` sends presence on (not stored).
    pub fn presence_subject(&self, who: &str) -> String {
        format!("sw.{}.presence.{}", self.doc, who.replace('.', "_"))
    }

    /// The object-store bucket holding snapshots.
    pub fn snapshot_bucket(&self) -> String {
        format!("SW_{}_snapshots", self.doc)
    }
}

impl std::fmt::Display for SessionUrl {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "nats://{}/{}", self.servers.join(","), self.doc)
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
        let u = SessionUrl::parse("nats://ana:pw@a:1,b:2/chair-2").unwrap();
        assert_eq!(u.servers, ["a:1", "b:2"]);
        assert_eq!(u.user, Some(("ana".into(), "pw".into())));
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
    }
}
