//! `--join nats://HOST:PORT/DOC` (run, replay): one person's side of a
//! shared session (issue 23). The rules live in the core
//! (`shapewright::doc::shared`), the transport in `shapewright-net`; this
//! only connects, catches up (from the latest snapshot when there is one)
//! and hands the interaction an [`OpLog`] backed by the session.

use anyhow::{bail, Result};
use shapewright::doc::OpLog;
use shapewright_net::{Link, LinkOptions, SessionUrl};

/// The shared-session arguments of `run` and `replay`.
#[derive(clap::Args, Debug)]
pub struct JoinArgs {
    /// Join a shared session: nats://HOST:PORT/DOC (a NATS server with
    /// JetStream, e.g. scripts/nats.sh). Each person undoes their own
    /// edits.
    #[arg(long, value_name = "URL")]
    pub join: Option<String>,
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
    let options = LinkOptions {
        replicas: args.replicas.max(1),
        ..Default::default()
    };
    let (log, link, messages) = shapewright_net::join::join(&url, &name, &me, options, &opened)?;
    for m in messages {
        println!("shapewright-xr: {m}");
    }
    Ok((log, link))
}

/// `session-access FILE`: the nats-server configuration for the member
/// list in `path` (see [`shapewright_net::access`]).
pub fn access_config(path: &std::path::Path) -> Result<String> {
    use anyhow::Context;
    let text = std::fs::read_to_string(path)
        .with_context(|| format!("cannot read the member list {}", path.display()))?;
    let members = shapewright_net::access::Member::parse_list(&text)
        .with_context(|| format!("member list {}", path.display()))?;
    if members.is_empty() {
        bail!("the member list {} names nobody", path.display());
    }
    Ok(shapewright_net::access::server_config(&members))
}
