//! Shared sessions over NATS JetStream (issue 23): the transport for
//! [`shapewright::doc::shared`], which holds all the rules (order, per-person
//! undo, ids, rebase). This crate only connects a participant's
//! [`shapewright::doc::shared::SharedLog`] to a document's stream.
//!
//! Why NATS JetStream and not a server of our own: it gives one total order
//! per stream, appends conditional on the last sequence, de-duplication by
//! message id, durable file storage, an object store for snapshots and
//! clustering with replicated streams, all in a packaged, maintained server
//! (`nats-server -js`). Why `async-nats`: it is the maintained Rust client;
//! it runs on its own thread here so hosts stay synchronous.

#![forbid(unsafe_code)]

pub mod access;
pub mod join;
mod link;
#[cfg(feature = "testkit")]
pub mod testkit;
mod url;

pub use link::{fetch_snapshot, Link, LinkError, LinkOptions, PresenceChannel, PumpReport, Pumped};
pub use url::{SessionUrl, UrlError};
