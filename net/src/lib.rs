//! Shared sessions over NATS JetStream (issues 23 and 35): the transport
//! for [`shapewright::doc::shared`], which holds all the rules (order,
//! per-person undo, ids, rebase, who may author what, snapshot checks).
//! This crate only connects a participant's
//! [`shapewright::doc::shared::SharedLog`] to a document's stream, over
//! TLS with a member's own credentials when the team set them up
//! ([`access`], [`Credentials`], scripts/session_certs.sh).
//!
//! Why NATS JetStream and not a server of our own: it gives one total order
//! per stream, appends conditional on the last sequence, de-duplication by
//! message id, durable file storage, an object store for snapshots,
//! clustering with replicated streams, TLS, bcrypt-hashed passwords and
//! per-user subject permissions, all in a packaged, maintained server
//! (`nats-server -js`). Why `async-nats`: it is the maintained Rust client
//! (TLS through rustls); it runs on its own thread here so hosts stay
//! synchronous.

#![forbid(unsafe_code)]

pub mod access;
mod connect;
mod consume;
mod credentials;
pub mod join;
mod link;
mod snapshot;
mod task;
#[cfg(feature = "testkit")]
pub mod testkit;
mod url;

pub use credentials::{Credentials, CredentialsError, CREDENTIALS_ENV};
pub use link::{Link, LinkError, LinkOptions, PresenceChannel, PumpReport, Pumped, SnapshotState};
pub use snapshot::{fetch_snapshot, StoredSnapshot};
pub use url::{SessionUrl, UrlError};
