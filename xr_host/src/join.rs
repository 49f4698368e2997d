//! `--join nats://HOST:PORT/DOC` (run, replay): one person's side of a
//! shared session (issue 23). The rules live in the core
//! (`shapewright::doc::shared`), the transport in `shapewright-net`; this
//! only connects, catches up (from the latest snapshot when there is one)
//! and hands the interaction an [`OpLog`] backed by the session.

use std::time::Duration;

use anyhow::{bail, Result};
use shapewright::doc::shared::{Replica, SharedLog};
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

/// Connects to the shared session at `url`, catches up with it (from the
/// latest snapshot when there is one), and, when the session is empty and
/// a file was opened, starts it from that file.
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
    let me = args.me.clone().unwrap_or_else(|| {
        name.chars()
            .map(|c| {
                if c.is_ascii_alphanumeric() || c == '-' || c == '_' {
                    c
                } else {
                    '_'
                }
            })
            .take(64)
            .collect()
    });
    let colour = shapewright::doc::shared::colour_for(&me);
    let options = LinkOptions {
        replicas: args.replicas.max(1),
        ..Default::default()
    };
    let restored = match shapewright_net::fetch_snapshot(&url, &options)? {
        Some((seq, bytes)) => match Replica::from_snapshot(&bytes) {
            Ok(r) if r.last_seq() == seq => Some(r),
            Ok(_) => None,
            Err(e) => {
                eprintln!("shapewright-xr: the session's snapshot is unusable ({e}); replaying the whole stream");
                None
            }
        },
        None => None,
    };
    let (replica, after) = match restored {
        Some(r) => {
            let seq = r.last_seq();
            (r, seq)
        }
        None => (Replica::new(), 0),
    };
    let mut shared = SharedLog::resume(&me, &name, colour, replica, 1)?;
    let mut link = Link::connect(&url, &me, after, options)?;
    println!(
        "joined {url} as {me} ({} entries to catch up on)",
        link.last_seq_at_connect()
    );
    if !link.catch_up(&mut shared, Duration::from_secs(120)) {
        bail!("could not catch up with {url} in 120 s");
    }
    // Our join comes back before we may create anything.
    let t = std::time::Instant::now();
    while !shared.is_joined() {
        link.pump(&mut shared);
        if t.elapsed() > Duration::from_secs(30) {
            bail!("the server at {url} did not confirm the join in 30 s");
        }
        std::thread::sleep(Duration::from_millis(2));
    }
    if !opened.is_empty() {
        if shared.confirmed().op_count() > 0 {
            bail!("{url} already has a document; join without --open to model on it");
        }
        shared.seed(opened.ops()[..opened.cursor()].to_vec())?;
    }
    Ok((OpLog::from_shared(shared), link))
}
