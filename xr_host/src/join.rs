//! `--join tls://HOST:PORT/DOC` (run, replay): one person's side of a
//! shared session (issues 23 and 35). The rules live in the core
//! (`shapewright::doc::shared`), the transport in `shapewright-net`; this
//! only reads the person's credentials file, connects, catches up (from
//! the latest snapshot when there is one, checked in the background) and
//! hands the interaction an [`OpLog`] backed by the session. Also
//! `session-access`: the server's rules for a member list, hashing its
//! passwords, and inviting a member.

use std::path::{Path, PathBuf};

use anyhow::{bail, Context, Result};
use shapewright::doc::OpLog;
use shapewright_net::access::{self, Member, Role};
use shapewright_net::{Credentials, Link, LinkOptions, SessionUrl};

/// The shared-session arguments of `run` and `replay`.
#[derive(clap::Args, Debug)]
pub struct JoinArgs {
    /// Join a shared session: tls://HOST:PORT/DOC (a NATS server with
    /// JetStream, e.g. scripts/nats.sh; nats:// on a server without TLS).
    /// Each person undoes their own edits. No password here: see
    /// --credentials.
    #[arg(long, value_name = "URL")]
    pub join: Option<String>,
    /// Your credentials file for the session's server (user, password,
    /// the team's CA certificate; `session-access --invite` writes one).
    /// Default: the file $SHAPEWRIGHT_SESSION_CREDENTIALS names.
    #[arg(long, value_name = "FILE")]
    pub credentials: Option<PathBuf>,
    /// Your name in a shared session (default: $USER).
    #[arg(long)]
    pub name: Option<String>,
    /// Your participant id in a shared session: keep it to keep your undo
    /// history across restarts (default: the name, made safe).
    #[arg(long)]
    pub me: Option<String>,
    /// Replicas of the document's stream when this joiner creates it (3
    /// on a three-server cluster: it survives one server's loss).
    #[arg(long, default_value_t = 1)]
    pub replicas: usize,
}

/// `log` alone, or, with `--join`, the shared session's log and link.
pub fn join(args: &JoinArgs, log: OpLog) -> Result<(OpLog, Option<Link>)> {
    match &args.join {
        Some(url) => {
            let (log, link) = join_session(url, args, log)?;
            Ok((log, Some(link)))
        }
        None => Ok((log, None)),
    }
}

/// Connects to the shared session at `url` and catches up with it (see
/// [`shapewright_net::join::join`]).
pub fn join_session(
    url: &str,
    args: &JoinArgs,
    opened: OpLog,
) -> Result<(OpLog, shapewright_net::Link)> {
    let url = SessionUrl::parse(url)?;
    let name = args
        .name
        .clone()
        .or_else(|| std::env::var("USER").ok())
        .unwrap_or_else(|| "someone".into());
    let me = args
        .me
        .clone()
        .unwrap_or_else(|| shapewright_net::join::participant_id(&name));
    let credentials = match &args.credentials {
        Some(path) => Some(Credentials::read(path)?),
        None => None,
    };
    let options = LinkOptions {
        replicas: args.replicas.max(1),
        credentials,
        ..Default::default()
    };
    let (log, link, messages) = shapewright_net::join::join(&url, &name, &me, options, &opened)?;
    for m in messages {
        println!("shapewright-xr: {m}");
    }
    Ok((log, link))
}

/// `session-access`: the server's rules for a member list, and keeping
/// the list's passwords hashed.
#[derive(clap::Args, Debug)]
pub struct AccessArgs {
    /// The member list: lines `USER PASSWORD-OR-BCRYPT-HASH DOC:editor|viewer ...`.
    pub users: PathBuf,
    /// Rewrite the member list with every clear password replaced by its
    /// bcrypt hash (the people keep their passwords).
    #[arg(long, conflicts_with = "invite")]
    pub hash: bool,
    /// Add USER to the member list with a fresh random password (stored
    /// only as its hash) and write their credentials file.
    #[arg(long, value_name = "USER")]
    pub invite: Option<String>,
    /// With --invite: a document and role, DOC:editor or DOC:viewer
    /// (repeat for more).
    #[arg(long = "grant", value_name = "DOC:ROLE", requires = "invite")]
    pub grants: Vec<String>,
    /// With --invite: the team's CA certificate, named in the credentials
    /// file (scripts/session_certs.sh made it).
    #[arg(long, value_name = "FILE", requires = "invite")]
    pub ca: Option<PathBuf>,
    /// With --invite: where to write the credentials file (default:
    /// USER.credentials beside the member list).
    #[arg(long, value_name = "FILE", requires = "invite")]
    pub out: Option<PathBuf>,
}

/// Runs `session-access`: prints the nats-server configuration for the
/// member list (passwords as bcrypt hashes), or hashes the list's clear
/// passwords (`--hash`), or invites a member (`--invite`).
pub fn session_access(args: &AccessArgs) -> Result<()> {
    let path = &args.users;
    let text = if args.invite.is_some() && !path.exists() {
        String::new()
    } else {
        std::fs::read_to_string(path)
            .with_context(|| format!("cannot read the member list {}", path.display()))?
    };
    if args.hash {
        let (hashed, n) =
            access::hash_list(&text).with_context(|| format!("member list {}", path.display()))?;
        shapewright_atomic::write_bytes(path, hashed.as_bytes())?;
        eprintln!(
            "{}: {n} passwords replaced by their bcrypt hashes",
            path.display()
        );
        return Ok(());
    }
    if let Some(user) = &args.invite {
        return invite(path, &text, user, args);
    }
    let members =
        Member::parse_list(&text).with_context(|| format!("member list {}", path.display()))?;
    if members.is_empty() {
        bail!("the member list {} names nobody", path.display());
    }
    let clear = members
        .iter()
        .filter(|m| matches!(m.secret, access::Secret::Clear(_)))
        .count();
    if clear > 0 {
        eprintln!(
            "shapewright-xr: {clear} passwords in {} are in clear (the configuration holds their hashes); run `shapewright-xr session-access {} --hash` to keep only hashes there too",
            path.display(),
            path.display()
        );
    }
    print!("{}", access::server_config(&members)?);
    Ok(())
}

fn invite(path: &Path, text: &str, user: &str, args: &AccessArgs) -> Result<()> {
    let mut docs = Vec::new();
    for g in &args.grants {
        let role = match g.rsplit_once(':') {
            Some((d, "editor")) => (d.to_string(), Role::Editor),
            Some((d, "viewer")) => (d.to_string(), Role::Viewer),
            _ => bail!("--grant {g}: expected DOC:editor or DOC:viewer"),
        };
        docs.push(role);
    }
    let (list, password) = access::invite(text, user, &docs)
        .with_context(|| format!("member list {}", path.display()))?;
    let out = args
        .out
        .clone()
        .unwrap_or_else(|| path.with_file_name(format!("{user}.credentials")));
    let ca = match &args.ca {
        Some(ca) => Some(
            std::fs::canonicalize(ca)
                .with_context(|| format!("the CA certificate {}", ca.display()))?,
        ),
        None => None,
    };
    let creds = Credentials {
        user: Some(user.to_string()),
        password: Some(password),
        ca,
    };
    creds
        .write(&out)
        .with_context(|| format!("cannot write {}", out.display()))?;
    shapewright_atomic::write_bytes(path, list.as_bytes())?;
    eprintln!(
        "{}: added `{user}` (password hashed); their credentials are in {} (give it to them, then delete your copy); restart the server with the new list",
        path.display(),
        out.display()
    );
    Ok(())
}
