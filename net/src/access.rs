//! Who may do what in which document: the `nats-server` configuration
//! that enforces it on the server (NATS users with subject permissions),
//! so a client that ignores the rules is still refused.
//!
//! Per document `DOC` (stream `SW_DOC`, snapshot bucket `SW_DOC_snapshots`,
//! whose stream is `OBJ_SW_DOC_snapshots`):
//! - a **viewer** may read the stream and the snapshots (make its own
//!   consumers, read messages) and send its own presence, nothing else;
//! - an **editor** may also append to `sw.DOC.log`, create the document's
//!   stream and bucket, and write snapshots;
//! - anyone without a grant for `DOC` can do neither (the server refuses
//!   even the stream lookup).
//!
//! Presence for viewers is a choice: being seen in the room changes no
//! document, and a person who cannot be seen is easy to talk over. Each
//! person may send presence only under their own name.

use crate::SessionUrl;

/// What a person may do in one document.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Role {
    /// Read and append.
    Editor,
    /// Read only.
    Viewer,
}

/// One NATS user and the documents they may use.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Member {
    /// NATS user name (also their participant id in presence subjects).
    pub user: String,
    /// Their password.
    pub password: String,
    /// The documents and what they may do in each.
    pub docs: Vec<(String, Role)>,
}

/// Why a member list was refused.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum AccessError {
    /// A line is not `USER PASSWORD DOC:ROLE...`.
    #[error("line {line}: {why}")]
    Line {
        /// 1-based line number.
        line: usize,
        /// What was wrong.
        why: String,
    },
}

impl Member {
    /// Parses a member list: one person per line, `USER PASSWORD
    /// DOC:editor|viewer ...`; `#` starts a comment. User names are
    /// participant ids (`A-Z a-z 0-9 _ - .`), documents as in
    /// [`SessionUrl`], passwords without spaces or quotes.
    pub fn parse_list(text: &str) -> Result<Vec<Member>, AccessError> {
        let mut out = Vec::new();
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
            if !shapewright::doc::shared::valid_author(user) {
                return Err(bad(format!(
                    "user `{user}` must be 1 to 64 bytes of A-Z a-z 0-9 _ - ."
                )));
            }
            if password.contains(['"', '\'', '\\']) {
                return Err(bad(
                    "a password may not contain quotes or backslashes".into()
                ));
            }
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
                password: password.to_string(),
                docs,
            });
        }
        Ok(out)
    }
}

/// The subjects `user` may publish to and subscribe to in `doc` as `role`.
fn subjects(doc: &str, user: &str, role: Role) -> (Vec<String>, Vec<String>) {
    let url = SessionUrl {
        servers: Vec::new(),
        doc: doc.to_string(),
        user: None,
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
    publish.push(url.presence_subject(user));
    if role == Role::Editor {
        publish.extend([
            url.log_subject(),
            format!("$JS.API.STREAM.CREATE.{stream}"),
            format!("$JS.API.STREAM.CREATE.{obj}"),
            format!("$JS.API.STREAM.PURGE.{obj}"),
            format!("$O.{bucket}.>"),
        ]);
    }
    let subscribe = vec![format!("sw.{doc}.presence.*")];
    (publish, subscribe)
}

/// The `accounts` block of a `nats-server` configuration giving each
/// member exactly their grants (one account with JetStream on; the server
/// itself still needs `-js` and a store directory).
pub fn server_config(members: &[Member]) -> String {
    let quote = |s: &str| format!("\"{s}\"");
    let list = |v: &[String]| v.iter().map(|s| quote(s)).collect::<Vec<_>>().join(", ");
    let mut users = Vec::new();
    for m in members {
        let mut publish = vec!["$JS.API.INFO".to_string()];
        let mut subscribe = vec!["_INBOX.>".to_string()];
        for (doc, role) in &m.docs {
            let (p, s) = subjects(doc, &m.user, *role);
            publish.extend(p);
            subscribe.extend(s);
        }
        users.push(format!(
            "      {{ user: {}, password: {},\n        permissions: {{\n          publish: {{ allow: [{}] }},\n          subscribe: {{ allow: [{}] }}\n        }} }}",
            quote(&m.user),
            quote(&m.password),
            list(&publish),
            list(&subscribe),
        ));
    }
    format!(
        "# Shapewright shared sessions: who may do what (generated).\naccounts: {{\n  SHAPEWRIGHT: {{\n    jetstream: enabled\n    users: [\n{}\n    ]\n  }}\n}}\n",
        users.join(",\n")
    )
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
        for (bad, line) in [
            ("ana\n", 1),
            ("ok pw d:editor\nbo pw d:owner\n", 2),
            ("bo pw d\n", 1),
            ("b/o pw d:editor\n", 1),
            ("bo \"pw d:editor\n", 1),
            ("bo pw d!:editor\n", 1),
        ] {
            match Member::parse_list(bad) {
                Err(AccessError::Line { line: l, .. }) => assert_eq!(l, line, "{bad}"),
                other => panic!("{bad}: {other:?}"),
            }
        }
    }

    #[test]
    fn only_editors_may_append_or_write_snapshots() {
        let (viewer, _) = subjects("teapot", "vic", Role::Viewer);
        let (editor, _) = subjects("teapot", "ana", Role::Editor);
        for s in [
            "sw.teapot.log",
            "$O.SW_teapot_snapshots.>",
            "$JS.API.STREAM.CREATE.SW_teapot",
        ] {
            assert!(!viewer.iter().any(|v| v == s), "{s}");
            assert!(editor.iter().any(|v| v == s), "{s}");
        }
        assert!(viewer.contains(&"sw.teapot.presence.vic".to_string()));
        assert!(!viewer.iter().any(|v| v.contains("presence.ana")));
    }
}
