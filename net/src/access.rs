//! Who may do what in which document: the `nats-server` configuration
//! that enforces it on the server (NATS users with subject permissions),
//! so a client that ignores the rules is still refused (issue 35).
//!
//! Per document `DOC` (stream `SW_DOC`, snapshot bucket `SW_DOC_snapshots`,
//! whose stream is `OBJ_SW_DOC_snapshots`), for a member whose user name's
//! subject token is `U` ([`shapewright::doc::shared::subject_token`]):
//! - a **viewer** may read the stream and the snapshots (make its own
//!   consumers, read messages) and send presence on
//!   `sw.DOC.presence.U`, nothing else;
//! - an **editor** may also append on `sw.DOC.log.U` and nowhere else (so
//!   every entry's subject names its sender, and replicas refuse an entry
//!   whose `author` is someone else), create the document's stream and
//!   bucket, and store snapshots under the object name `by.U` only (so a
//!   snapshot's object names its writer);
//! - nobody may delete or purge the document's stream, edit its settings,
//!   delete messages, or publish on another document;
//! - anyone without a grant for `DOC` can do neither (the server refuses
//!   even the stream lookup), and replies reach each member on their own
//!   inbox prefix `_INBOX_U` only, so nobody reads another's deliveries.
//!
//! Passwords: the member list holds bcrypt hashes (`$2a$11$...`), which
//! nats-server checks directly; a clear password in the list is hashed
//! into the generated configuration (the server never sees it in clear)
//! and [`hash_list`] rewrites the list with hashes. [`invite`] adds a
//! member with a fresh random password and returns it once, for their
//! credentials file.
//!
//! Presence for viewers is a choice: being seen in the room changes no
//! document, and a person who cannot be seen is easy to talk over.

use base64::Engine;
use shapewright::doc::shared::subject_token;

use crate::SessionUrl;

/// The bcrypt cost of generated hashes (nats-server's own tool uses 11:
/// about 0.1 s per check here, paid once per connection).
pub const BCRYPT_COST: u32 = 11;

/// What a person may do in one document.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Role {
    /// Read and append.
    Editor,
    /// Read only.
    Viewer,
}

/// A member's password as the list holds it.
#[derive(Clone, PartialEq, Eq)]
pub enum Secret {
    /// A bcrypt hash (`$2a$`, `$2b$`, `$2y$`): what the list should hold.
    Hash(String),
    /// A password in clear (hashed into the configuration; see
    /// [`hash_list`]).
    Clear(String),
}

impl std::fmt::Debug for Secret {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::Hash(h) => write!(f, "Hash({h})"),
            Self::Clear(_) => write!(f, "Clear(<hidden>)"),
        }
    }
}

/// One NATS user and the documents they may use.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Member {
    /// NATS user name (also their participant id).
    pub user: String,
    /// Their password, hashed or in clear.
    pub secret: Secret,
    /// The documents and what they may do in each.
    pub docs: Vec<(String, Role)>,
}

/// Why a member list was refused.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum AccessError {
    /// A line is not `USER PASSWORD-OR-HASH DOC:ROLE...`.
    #[error("line {line}: {why}")]
    Line {
        /// 1-based line number.
        line: usize,
        /// What was wrong.
        why: String,
    },
    /// [`invite`]: the user is already a member.
    #[error("`{0}` is already in the member list")]
    Exists(String),
    /// Hashing failed (the system's random source).
    #[error("could not hash a password: {0}")]
    Hash(String),
}

/// True for a bcrypt hash as nats-server reads it.
fn is_bcrypt(s: &str) -> bool {
    let b = s.as_bytes();
    s.len() == 60
        && s.starts_with("$2")
        && matches!(b[2], b'a' | b'b' | b'y')
        && b[3] == b'$'
        && b[4..6].iter().all(u8::is_ascii_digit)
        && b[6] == b'$'
        && b[7..]
            .iter()
            .all(|c| c.is_ascii_alphanumeric() || *c == b'.' || *c == b'/')
}

impl Member {
    /// Parses a member list: one person per line, `USER PASSWORD-OR-HASH
    /// DOC:editor|viewer ...`; `#` starts a comment. User names are
    /// participant ids (`A-Z a-z 0-9 _ - .`), documents as in
    /// [`SessionUrl`]; a password is a bcrypt hash or a clear password
    /// without spaces, quotes, backslashes or a leading `$`.
    pub fn parse_list(text: &str) -> Result<Vec<Member>, AccessError> {
        let mut out: Vec<Member> = Vec::new();
        for (i, raw) in text.lines().enumerate() {
            let bad = |why: String| AccessError::Line { line: i + 1, why };
            let line = raw.split('#').next().unwrap_or("").trim();
            if line.is_empty() {
                continue;
            }
            let mut words = line.split_whitespace();
            let (Some(user), Some(password)) = (words.next(), words.next()) else {
                return Err(bad("expected USER PASSWORD DOC:ROLE...".into()));
            };
            if subject_token(user).is_none() {
                return Err(bad(format!(
                    "user `{user}` must be 1 to 64 bytes of A-Z a-z 0-9 _ - ."
                )));
            }
            if out.iter().any(|m| m.user == user) {
                return Err(bad(format!("`{user}` is listed twice")));
            }
            let secret = if is_bcrypt(password) {
                Secret::Hash(password.to_string())
            } else if password.starts_with('$') {
                return Err(bad(
                    "a password starting with `$` must be a whole bcrypt hash ($2a$11$ and 53 characters)".into(),
                ));
            } else if password.contains(['"', '\'', '\\']) {
                return Err(bad(
                    "a password may not contain quotes or backslashes".into()
                ));
            } else {
                Secret::Clear(password.to_string())
            };
            let mut docs = Vec::new();
            for grant in words {
                let (doc, role) = grant
                    .split_once(':')
                    .ok_or_else(|| bad(format!("`{grant}` is not DOC:editor or DOC:viewer")))?;
                SessionUrl::parse(&format!("nats://h:1/{doc}")).map_err(|e| bad(e.to_string()))?;
                let role = match role {
                    "editor" => Role::Editor,
                    "viewer" => Role::Viewer,
                    _ => return Err(bad(format!("role `{role}` is not editor or viewer"))),
                };
                docs.push((doc.to_string(), role));
            }
            out.push(Member {
                user: user.to_string(),
                secret,
                docs,
            });
        }
        Ok(out)
    }
}

/// `password`'s bcrypt hash in the `$2a$` form nats-server reads.
pub fn hash_password(password: &str) -> Result<String, AccessError> {
    bcrypt::hash_with_result(password, BCRYPT_COST)
        .map(|h| h.format_for_version(bcrypt::Version::TwoA))
        .map_err(|e| AccessError::Hash(e.to_string()))
}

/// A fresh random password: 24 characters of base64url (144 bits).
pub fn new_password() -> Result<String, AccessError> {
    let mut bytes = [0u8; 18];
    getrandom::getrandom(&mut bytes).map_err(|e| AccessError::Hash(e.to_string()))?;
    Ok(base64::engine::general_purpose::URL_SAFE_NO_PAD.encode(bytes))
}

/// The member list `text` with every clear password replaced by its hash
/// (comments and everything else kept), and how many were replaced.
pub fn hash_list(text: &str) -> Result<(String, usize), AccessError> {
    Member::parse_list(text)?;
    let mut out = String::new();
    let mut n = 0;
    for raw in text.split_inclusive('\n') {
        let line = raw.split('#').next().unwrap_or("");
        match second_word(line) {
            Some((a, b)) if !is_bcrypt(&line[a..b]) => {
                out += &raw[..a];
                out += &hash_password(&line[a..b])?;
                out += &raw[b..];
                n += 1;
            }
            _ => out += raw,
        }
    }
    Ok((out, n))
}

/// The byte span of the second whitespace-separated word of `line`.
fn second_word(line: &str) -> Option<(usize, usize)> {
    let mut spans = Vec::new();
    let mut start = None;
    for (i, c) in line.char_indices().chain([(line.len(), ' ')]) {
        match (c.is_whitespace(), start) {
            (false, None) => start = Some(i),
            (true, Some(s)) => {
                spans.push((s, i));
                start = None;
            }
            _ => {}
        }
    }
    spans.get(1).copied()
}

/// Adds `user` with `docs` to the member list `text` under a fresh
/// password: returns the new list (the password hashed) and the password
/// (for the person's credentials file; it is nowhere else).
pub fn invite(
    text: &str,
    user: &str,
    docs: &[(String, Role)],
) -> Result<(String, String), AccessError> {
    let members = Member::parse_list(text)?;
    if members.iter().any(|m| m.user == user) {
        return Err(AccessError::Exists(user.to_string()));
    }
    let password = new_password()?;
    let grants: Vec<String> = docs
        .iter()
        .map(|(d, r)| {
            format!(
                "{d}:{}",
                if *r == Role::Editor {
                    "editor"
                } else {
                    "viewer"
                }
            )
        })
        .collect();
    let line = format!(
        "{user} {} {}\n",
        hash_password(&password)?,
        grants.join(" ")
    );
    let mut out = text.to_string();
    if !out.is_empty() && !out.ends_with('\n') {
        out.push('\n');
    }
    out += &line;
    // The new line must parse as the rest does.
    Member::parse_list(&out).map_err(|e| match e {
        AccessError::Line { why, .. } => AccessError::Line {
            line: out.lines().count(),
            why,
        },
        e => e,
    })?;
    Ok((out, password))
}

/// The object name `user`'s snapshots are stored under.
pub fn snapshot_object(user: &str) -> Option<String> {
    subject_token(user).map(|t| format!("by.{t}"))
}

/// The subjects `user` may publish to and subscribe to in `doc` as `role`.
fn subjects(doc: &str, user: &str, role: Role) -> (Vec<String>, Vec<String>) {
    let url = SessionUrl {
        servers: Vec::new(),
        doc: doc.to_string(),
        tls: false,
    };
    let stream = url.stream();
    let bucket = url.snapshot_bucket();
    let obj = format!("OBJ_{bucket}");
    let mut publish = Vec::new();
    for s in [&stream, &obj] {
        publish.extend([
            format!("$JS.API.STREAM.INFO.{s}"),
            format!("$JS.API.CONSUMER.CREATE.{s}"),
            format!("$JS.API.CONSUMER.CREATE.{s}.>"),
            format!("$JS.API.CONSUMER.INFO.{s}.>"),
            format!("$JS.API.CONSUMER.DELETE.{s}.>"),
            format!("$JS.API.CONSUMER.MSG.NEXT.{s}.>"),
            format!("$JS.API.STREAM.MSG.GET.{s}"),
            format!("$JS.API.DIRECT.GET.{s}"),
            format!("$JS.API.DIRECT.GET.{s}.>"),
            format!("$JS.ACK.{s}.>"),
            format!("$JS.FC.{s}.>"),
        ]);
    }
    publish.extend(url.presence_subject(user));
    if role == Role::Editor {
        publish.extend(url.log_subject(user));
        if let Some(name) = snapshot_object(user) {
            let meta = base64::engine::general_purpose::URL_SAFE.encode(name);
            publish.push(format!("$O.{bucket}.M.{meta}"));
        }
        publish.extend([
            format!("$JS.API.STREAM.CREATE.{stream}"),
            format!("$JS.API.STREAM.CREATE.{obj}"),
            format!("$JS.API.STREAM.PURGE.{obj}"),
            format!("$O.{bucket}.C.>"),
        ]);
    }
    let subscribe = vec![url.presence_subjects()];
    (publish, subscribe)
}

/// The inbox prefix of `user` (replies to them arrive under it only).
pub fn inbox_prefix(user: &str) -> String {
    format!(
        "_INBOX_{}",
        subject_token(user).unwrap_or_else(|| "_".into())
    )
}

/// The `accounts` block of a `nats-server` configuration giving each
/// member exactly their grants (one account with JetStream on; the server
/// itself still needs `-js`, a store directory and, for a team, TLS; see
/// scripts/nats.sh). Clear passwords are hashed here, so the
/// configuration holds hashes only.
pub fn server_config(members: &[Member]) -> Result<String, AccessError> {
    let quote = |s: &str| format!("\"{s}\"");
    let list = |v: &[String]| v.iter().map(|s| quote(s)).collect::<Vec<_>>().join(", ");
    let mut users = Vec::new();
    for m in members {
        let mut publish = vec!["$JS.API.INFO".to_string()];
        let mut subscribe = vec![format!("{}.>", inbox_prefix(&m.user))];
        for (doc, role) in &m.docs {
            let (p, s) = subjects(doc, &m.user, *role);
            publish.extend(p);
            subscribe.extend(s);
        }
        let hash = match &m.secret {
            Secret::Hash(h) => h.clone(),
            Secret::Clear(p) => hash_password(p)?,
        };
        users.push(format!(
            "      {{ user: {}, password: {},\n        permissions: {{\n          publish: {{ allow: [{}] }},\n          subscribe: {{ allow: [{}] }}\n        }} }}",
            quote(&m.user),
            quote(&hash),
            list(&publish),
            list(&subscribe),
        ));
    }
    Ok(format!(
        "# Shapewright shared sessions: who may do what (generated; passwords as bcrypt hashes).\naccounts: {{\n  SHAPEWRIGHT: {{\n    jetstream: enabled\n    users: [\n{}\n    ]\n  }}\n}}\n",
        users.join(",\n")
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_member_list_parses_and_bad_lines_say_which() {
        let text = "# team\nana s3cret teapot:editor lamp:viewer\n\nvic pw teapot:viewer # guest\n";
        let m = Member::parse_list(text).unwrap();
        assert_eq!(m.len(), 2);
        assert_eq!(
            m[0].docs,
            vec![
                ("teapot".into(), Role::Editor),
                ("lamp".into(), Role::Viewer)
            ]
        );
        assert_eq!(m[0].secret, Secret::Clear("s3cret".into()));
        assert!(!format!("{m:?}").contains("s3cret"));
        for (bad, line) in [
            ("ana\n", 1),
            ("ok pw d:editor\nbo pw d:owner\n", 2),
            ("bo pw d\n", 1),
            ("b/o pw d:editor\n", 1),
            ("bo \"pw d:editor\n", 1),
            ("bo pw d!:editor\n", 1),
            ("bo $2a$11$short d:editor\n", 1),
            ("bo pw d:editor\nbo pw2 d:viewer\n", 2),
        ] {
            match Member::parse_list(bad) {
                Err(AccessError::Line { line: l, .. }) => assert_eq!(l, line, "{bad}"),
                other => panic!("{bad}: {other:?}"),
            }
        }
    }

    #[test]
    fn passwords_end_up_hashed_in_the_list_and_the_configuration() {
        let text = "# team\nana s3cret teapot:editor  # lead\nvic pw teapot:viewer\n";
        let (hashed, n) = hash_list(text).unwrap();
        assert_eq!(n, 2);
        assert!(
            !hashed.contains("s3cret") && !hashed.contains(" pw "),
            "{hashed}"
        );
        assert!(
            hashed.starts_with("# team\nana $2a$11$") && hashed.contains("teapot:editor  # lead\n")
        );
        let m = Member::parse_list(&hashed).unwrap();
        let Secret::Hash(h) = &m[0].secret else {
            panic!("{m:?}")
        };
        assert!(bcrypt::verify("s3cret", h).unwrap());
        // Hashing again changes nothing.
        assert_eq!(hash_list(&hashed).unwrap(), (hashed.clone(), 0));
        // An invitation adds a hashed line and returns the password once.
        let (more, password) =
            invite(&hashed, "ben.k", &[("teapot".into(), Role::Editor)]).unwrap();
        assert_eq!(password.len(), 24);
        assert!(!more.contains(&password));
        let m = Member::parse_list(&more).unwrap();
        let Secret::Hash(h) = &m[2].secret else {
            panic!("{m:?}")
        };
        assert!(bcrypt::verify(&password, h).unwrap());
        assert!(matches!(
            invite(&more, "ana", &[]),
            Err(AccessError::Exists(_))
        ));
        // The server's configuration holds hashes only.
        let config = server_config(&Member::parse_list(text).unwrap()).unwrap();
        assert!(!config.contains("s3cret") && !config.contains("\"pw\""));
        assert_eq!(config.matches("\"$2a$11$").count(), 2, "{config}");
    }

    #[test]
    fn editors_append_and_store_snapshots_only_as_themselves() {
        let (viewer, _) = subjects("teapot", "vic", Role::Viewer);
        let (editor, _) = subjects("teapot", "ana.b", Role::Editor);
        for s in [
            "sw.teapot.log.ana%2Eb",
            "$O.SW_teapot_snapshots.C.>",
            "$JS.API.STREAM.CREATE.SW_teapot",
        ] {
            assert!(!viewer.iter().any(|v| v == s), "{s}");
            assert!(editor.iter().any(|v| v == s), "{s}");
        }
        // Only one log subject, one snapshot name, one presence subject;
        // nothing that deletes, purges or edits the stream.
        let meta = format!(
            "$O.SW_teapot_snapshots.M.{}",
            base64::engine::general_purpose::URL_SAFE.encode("by.ana%2Eb")
        );
        assert!(editor.contains(&meta), "{editor:?}");
        for e in &editor {
            assert!(!e.contains('*'), "{e}");
            assert!(!e.starts_with("sw.") || e.ends_with("ana%2Eb"), "{e}");
            assert!(
                !e.starts_with("$O.SW_teapot_snapshots.M.") || *e == meta,
                "{e}"
            );
            for verb in [
                "DELETE.SW_teapot",
                "PURGE.SW_teapot",
                "UPDATE",
                "MSG.DELETE",
            ] {
                assert!(!e.contains(&format!("STREAM.{verb}")), "{e}");
            }
        }
        assert!(viewer.contains(&"sw.teapot.presence.vic".to_string()));
        assert!(!viewer.iter().any(|v| v.contains("presence.ana")));
        assert_eq!(inbox_prefix("ana.b"), "_INBOX_ana%2Eb");
    }
}
