//! Paced runs: input through a real runtime, stepped deterministically.
//!
//! A runtime driven by a test client (Monado's `remote` driver) keeps only
//! the latest packet and runs its own clock, so a host that steps its tools
//! on every display frame steps some packets twice and misses others, and
//! the tools (3-second holds, velocities) see the runtime's clock. A paced
//! run removes both: the client tells the host, over a loopback TCP
//! connection, "step `seq` at trace time `t`"; the host steps its tools exactly once for that
//! request, with the input it read from the runtime, at time `t`, waits for
//! the commit to land, and answers with its op count. The client sends the
//! next packet only after the answer.
//!
//! **Which packet did the runtime deliver?** The client stamps every packet
//! with a tag in the left eye's field of view (`angle_up =
//! TAG_BASE + tag * TAG_STEP`, exact in f32, and at least 2 rad, which no
//! real half field of view reaches), which the host reads back through
//! `xrLocateViews` before anything else in the frame. The client
//! sends each trace frame twice, tagged `2 seq + 1` and then `2 seq + 2`;
//! the runtime copies packets whole, one after another, so once the host
//! sees `2 seq + 2` the copy of frame `seq` has finished, and everything
//! read after the tag in that frame (actions, grip, aim, head, joints) is
//! frame `seq`, never half of the previous one. Until then the host renders
//! and reads as usual but steps nothing.
//!
//! Protocol (JSON lines): client -> host `{"seq":N,"time":T}` or
//! `{"end":true}`; host -> client `{"seq":N,"frame":F,"ops":O,"commands":C}`
//! after stepping `seq`, where `frame` is the host's display-frame count.
//!
//! Transport: TCP on a loopback address the client listens on
//! (`--pace 127.0.0.1:PORT`), the same on every OS (a Unix socket has no
//! Windows twin in std). Other addresses are refused: pacing drives the
//! tools, which no other machine should do.

use std::io::{BufRead, BufReader, Write};
use std::net::{SocketAddr, TcpStream};
use std::sync::mpsc::{self, Receiver, TryRecvError};
use std::time::{Duration, Instant};

use serde::{Deserialize, Serialize};

/// The fov value of tag 0 (more than any real half-angle, < pi/2).
pub const TAG_BASE: f32 = 2.0;
/// The fov step per tag (2^-21: exact in [2, 4), whose f32 spacing is
/// 2^-22, for tags below 2^22).
pub const TAG_STEP: f32 = 1.0 / 2_097_152.0;

/// The fov angle carrying `tag`.
pub fn tag_angle(tag: u32) -> f32 {
    TAG_BASE + tag as f32 * TAG_STEP
}

/// The tag an angle carries, if it is one.
pub fn angle_tag(angle: f32) -> Option<u32> {
    if !(TAG_BASE..2.0 * TAG_BASE).contains(&angle) {
        return None;
    }
    let t = ((angle - TAG_BASE) / TAG_STEP).round();
    (tag_angle(t as u32) == angle).then_some(t as u32)
}

/// A request from the client.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(untagged)]
pub enum Request {
    /// Step trace frame `seq` at `time` seconds.
    Step {
        /// The frame number (0-based).
        seq: u32,
        /// Its time in seconds.
        time: f64,
    },
    /// The trace is over: end the session.
    End {
        /// Always true.
        end: bool,
    },
}

/// The host's answer after a step.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct Ack {
    /// The request's frame number.
    pub seq: u32,
    /// The host's display frame at which it stepped.
    pub frame: u64,
    /// Ops in the log after the step's commit.
    pub ops: u64,
    /// Commands the tools produced so far.
    pub commands: u64,
}

/// Why pacing failed.
#[derive(Debug, thiserror::Error)]
pub enum PaceError {
    /// The client could not be reached.
    #[error("cannot connect to the pace client at {addr}: {source}")]
    Connect {
        /// The client's address.
        addr: SocketAddr,
        /// The OS error.
        source: std::io::Error,
    },
    /// The address is not a loopback one.
    #[error("the pace client must listen on a loopback address (127.0.0.1 or ::1), not {0}")]
    NotLoopback(SocketAddr),
    /// Writing an acknowledgement failed.
    #[error("pace socket: {0}")]
    Io(#[from] std::io::Error),
    /// The client sent something that is not a request.
    #[error("pace socket: bad request {line:?}: {message}")]
    Bad {
        /// The line.
        line: String,
        /// Why.
        message: String,
    },
}

/// The host's side of a paced run.
pub struct Pacer {
    out: TcpStream,
    requests: Receiver<Result<Request, PaceError>>,
    pending: Option<(u32, f64)>,
    ended: bool,
    /// Steps done.
    pub steps: u64,
    /// Display frames that waited for the runtime to deliver the tagged
    /// packet (read, rendered, not stepped).
    pub waits: u64,
}

impl Pacer {
    /// Connects to the client listening at `addr` (a loopback address;
    /// retrying for up to 10 s while it appears).
    pub fn connect(addr: SocketAddr) -> Result<Self, PaceError> {
        if !addr.ip().is_loopback() {
            return Err(PaceError::NotLoopback(addr));
        }
        let start = Instant::now();
        let stream = loop {
            match TcpStream::connect(addr) {
                Ok(s) => break s,
                Err(_) if start.elapsed() < Duration::from_secs(10) => {
                    std::thread::sleep(Duration::from_millis(20));
                }
                Err(source) => return Err(PaceError::Connect { addr, source }),
            }
        };
        // Acknowledgements are small and awaited one by one.
        stream.set_nodelay(true)?;
        let reader = stream.try_clone()?;
        let (tx, requests) = mpsc::channel();
        std::thread::Builder::new()
            .name("shapewright-pace".into())
            .spawn(move || {
                for line in BufReader::new(reader).lines() {
                    let r = match line {
                        Ok(l) if l.trim().is_empty() => continue,
                        Ok(l) => serde_json::from_str(&l).map_err(|e| PaceError::Bad {
                            line: l,
                            message: e.to_string(),
                        }),
                        Err(e) => Err(PaceError::Io(e)),
                    };
                    let stop = r.is_err();
                    if tx.send(r).is_err() || stop {
                        return;
                    }
                }
                // EOF: the client is gone; the run ends like `end`.
                let _ = tx.send(Ok(Request::End { end: true }));
            })?;
        Ok(Self {
            out: stream,
            requests,
            pending: None,
            ended: false,
            steps: 0,
            waits: 0,
        })
    }

    /// Takes in requests that arrived; returns the pending step, if any.
    pub fn poll(&mut self) -> Result<Option<(u32, f64)>, PaceError> {
        while self.pending.is_none() && !self.ended {
            match self.requests.try_recv() {
                Ok(Ok(Request::Step { seq, time })) => self.pending = Some((seq, time)),
                Ok(Ok(Request::End { .. })) | Err(TryRecvError::Disconnected) => self.ended = true,
                Ok(Err(e)) => return Err(e),
                Err(TryRecvError::Empty) => break,
            }
        }
        Ok(self.pending)
    }

    /// Whether the client said the trace is over (or hung up).
    pub fn ended(&self) -> bool {
        self.ended && self.pending.is_none()
    }

    /// The step to take now, given the tag read from the runtime this
    /// frame: Some(time) when the pending request's packet has fully
    /// arrived (tag `2 seq + 2`).
    pub fn admit(&mut self, tag: Option<u32>) -> Option<f64> {
        let (seq, time) = self.pending?;
        if tag == Some(2 * seq + 2) {
            Some(time)
        } else {
            self.waits += 1;
            None
        }
    }

    /// Acknowledges the pending step.
    pub fn ack(&mut self, frame: u64, ops: u64, commands: u64) -> Result<(), PaceError> {
        let Some((seq, _)) = self.pending.take() else {
            return Ok(());
        };
        self.steps += 1;
        let mut line = serde_json::to_string(&Ack {
            seq,
            frame,
            ops,
            commands,
        })
        .map_err(std::io::Error::other)?;
        line.push('\n');
        self.out.write_all(line.as_bytes())?;
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tags_round_trip_exactly_and_reject_other_angles() {
        for t in [0u32, 1, 2, 3, 1000, 2229, 65_535, (1 << 22) - 1] {
            assert_eq!(angle_tag(tag_angle(t)), Some(t), "{t}");
        }
        // No real fov is a tag; nor is anything between two tags.
        for deg in 1..90 {
            let a = (deg as f32).to_radians();
            assert_eq!(angle_tag(a), None, "{deg}");
            assert_eq!(angle_tag(-a), None, "{deg}");
        }
        assert_eq!(angle_tag(4.0), None);
        assert_eq!(angle_tag(tag_angle(7) + TAG_STEP * 0.5), None);
    }

    #[test]
    fn requests_parse_and_acks_print() {
        let r: Request = serde_json::from_str(r#"{"seq":3,"time":0.12}"#).unwrap();
        assert_eq!(r, Request::Step { seq: 3, time: 0.12 });
        let e: Request = serde_json::from_str(r#"{"end":true}"#).unwrap();
        assert_eq!(e, Request::End { end: true });
        let a = Ack {
            seq: 3,
            frame: 10,
            ops: 2,
            commands: 2,
        };
        let s = serde_json::to_string(&a).unwrap();
        assert_eq!(serde_json::from_str::<Ack>(&s).unwrap(), a);
    }

    #[test]
    fn a_step_waits_for_the_second_copy_of_its_packet() {
        let listener = std::net::TcpListener::bind("127.0.0.1:0").unwrap();
        let addr = listener.local_addr().unwrap();
        let client = std::thread::spawn(move || {
            let (mut s, _) = listener.accept().unwrap();
            s.write_all(b"{\"seq\":0,\"time\":0.5}\n").unwrap();
            let mut acks = BufReader::new(s.try_clone().unwrap()).lines();
            let a: Ack = serde_json::from_str(&acks.next().unwrap().unwrap()).unwrap();
            s.write_all(b"{\"end\":true}\n").unwrap();
            a
        });
        let mut p = Pacer::connect(addr).unwrap();
        let deadline = Instant::now() + Duration::from_secs(5);
        while p.poll().unwrap().is_none() {
            assert!(Instant::now() < deadline);
            std::thread::sleep(Duration::from_millis(1));
        }
        // The old packet, then the first copy: no step yet.
        assert_eq!(p.admit(None), None);
        assert_eq!(p.admit(Some(1)), None);
        assert_eq!(p.admit(Some(2)), Some(0.5));
        p.ack(7, 1, 1).unwrap();
        let a = client.join().unwrap();
        assert_eq!((a.seq, a.frame, a.ops), (0, 7, 1));
        while !p.ended() {
            p.poll().unwrap();
            assert!(Instant::now() < deadline);
            std::thread::sleep(Duration::from_millis(1));
        }
        assert_eq!((p.steps, p.waits), (1, 2));
    }

    #[test]
    fn only_loopback_clients_pace() {
        let addr: SocketAddr = "192.0.2.1:4000".parse().unwrap();
        assert!(matches!(
            Pacer::connect(addr),
            Err(PaceError::NotLoopback(a)) if a == addr
        ));
    }
}
