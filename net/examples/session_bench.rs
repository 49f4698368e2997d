//! The shared-session benchmark (issues 23 and 35), against a real
//! `nats-server -js` it starts on 127.0.0.1, over TLS (certificates from
//! scripts/session_certs.sh, verified by every client):
//! - op round trip: a nudge applied by one person until it is applied by
//!   each other person, with 2 and 16 people each editing at 10 ops/s
//!   (one thread per person, as one host each; all on this machine);
//! - joining a 10,000-op document: from the latest snapshot plus the
//!   tail (and how long the background check of that snapshot against
//!   the stream takes), and by replaying the whole stream;
//! - the single-user apply time of the same op, for comparison.
//!
//! `cargo run --release -p shapewright-net --example session_bench [SECS
//! [REPS]]` (default 5 s, 3 reps) prints one JSON line per row (read by
//! scripts/bench/run_all.py): the round-trip p99 as [median, min, max]
//! over the reps.

use std::collections::HashMap;
use std::sync::{Arc, Barrier, Mutex};
use std::time::{Duration, Instant};

use shapewright::doc::shared::{Replica, SharedLog};
use shapewright::doc::{ObjectId, Op, OpLog};
use shapewright_net::testkit::{options, Server};
use shapewright_net::{fetch_snapshot, Link, SessionUrl, SnapshotState};

fn op(json: &str) -> Op {
    serde_json::from_str(json).expect("a valid op")
}

fn sphere(x: f64) -> Op {
    op(&format!(
        r#"{{"op":"add_solid","shape":{{"kind":"sphere","radius":0.1}},"segments":16,"transform":{{"translate":[{x},0,0]}}}}"#
    ))
}

fn nudge(id: ObjectId) -> Op {
    op(&format!(
        r#"{{"op":"transform_by","id":{},"transform":{{"translate":[0,0.001,0]}}}}"#,
        id.0
    ))
}

fn quantile(v: &mut [f64], q: f64) -> f64 {
    v.sort_by(f64::total_cmp);
    if v.is_empty() {
        return f64::NAN;
    }
    v[((v.len() - 1) as f64 * q).round() as usize]
}

fn wait_joined(link: &mut Link, log: &mut SharedLog) {
    let t = Instant::now();
    while !log.is_joined() || log.pending_count() > 0 {
        link.pump(log);
        assert!(t.elapsed() < Duration::from_secs(30), "join not confirmed");
        std::thread::sleep(Duration::from_millis(1));
    }
}

/// `people` threads, each nudging its own sphere at `rate` Hz for `secs`;
/// returns every (author -> other) round trip in ms.
fn round_trips(url: &SessionUrl, people: usize, rate: f64, secs: f64) -> Vec<f64> {
    let sent: Arc<Mutex<HashMap<(String, u64), Instant>>> = Arc::default();
    let trips: Arc<Mutex<Vec<f64>>> = Arc::default();
    let start = Arc::new(Barrier::new(people));
    let threads: Vec<_> = (0..people)
        .map(|i| {
            let (url, sent, trips, start) =
                (url.clone(), sent.clone(), trips.clone(), start.clone());
            std::thread::spawn(move || {
                let me = format!("p{i}");
                let mut log = SharedLog::new(&me, &me, [0.5; 3]).unwrap();
                let mut link = Link::connect(&url, &me, 0, options()).unwrap();
                wait_joined(&mut link, &mut log);
                let id = log.apply(sphere(i as f64)).unwrap().created.unwrap();
                wait_joined(&mut link, &mut log);
                start.wait();
                let period = Duration::from_secs_f64(1.0 / rate);
                // Spread the people over the period.
                let mut next = Instant::now() + period.mul_f64(i as f64 / people as f64);
                let end = Instant::now() + Duration::from_secs_f64(secs);
                let mut quiet_until = end + Duration::from_secs(2);
                loop {
                    let now = Instant::now();
                    if now >= next && now < end {
                        let n = log.next_n();
                        log.apply(nudge(id)).unwrap();
                        sent.lock().unwrap().insert((me.clone(), n), Instant::now());
                        next += period;
                    }
                    let p = link.pump(&mut log);
                    if !p.arrived.is_empty() {
                        let at = Instant::now();
                        let sent = sent.lock().unwrap();
                        let mut t = trips.lock().unwrap();
                        for key in &p.arrived {
                            if key.0 != me {
                                if let Some(s) = sent.get(key) {
                                    t.push((at - *s).as_secs_f64() * 1e3);
                                }
                            }
                        }
                        quiet_until = quiet_until.max(Instant::now() + Duration::from_millis(500));
                    }
                    if now > quiet_until && log.pending_count() == 0 {
                        break;
                    }
                    std::thread::sleep(Duration::from_micros(200));
                }
            })
        })
        .collect();
    for t in threads {
        t.join().unwrap();
    }
    let v = trips.lock().unwrap().clone();
    v
}

fn load() -> String {
    std::fs::read_to_string("/proc/loadavg")
        .map(|s| s.split_whitespace().next().unwrap_or("?").to_string())
        .unwrap_or_default()
}

fn main() {
    // A failure in one person's thread ends the run (the others would
    // wait for it at the start barrier forever).
    let default = std::panic::take_hook();
    std::panic::set_hook(Box::new(move |info| {
        default(info);
        std::process::exit(101);
    }));
    let secs: f64 = std::env::args()
        .nth(1)
        .and_then(|a| a.parse().ok())
        .unwrap_or(5.0);
    let reps: usize = std::env::args()
        .nth(2)
        .and_then(|a| a.parse().ok())
        .unwrap_or(3);
    let server = Server::start();
    for people in [2, 16] {
        let la = load();
        let (mut p50s, mut p99s, mut maxes, mut n) = (Vec::new(), Vec::new(), Vec::new(), 0);
        for rep in 0..reps {
            let url = server.url(&format!("rt{people}x{rep}"));
            let mut v = round_trips(&url, people, 10.0, secs);
            n += v.len();
            p50s.push(quantile(&mut v, 0.5));
            p99s.push(quantile(&mut v, 0.99));
            maxes.push(quantile(&mut v, 1.0));
        }
        let p50 = quantile(&mut p50s, 0.5);
        let (p99, lo, hi) = (
            quantile(&mut p99s, 0.5),
            quantile(&mut p99s, 0.0),
            quantile(&mut p99s, 1.0),
        );
        let max = quantile(&mut maxes, 1.0);
        println!(
            "{{\"row\":\"round_trip\",\"people\":{people},\"rate_hz\":10,\"secs\":{secs},\"reps\":{reps},\"samples\":{n},\"p50_ms\":{p50:.3},\"p99_ms\":[{p99:.3},{lo:.3},{hi:.3}],\"max_ms\":{max:.3},\"load_before\":\"{la}\",\"load_after\":\"{}\"}}",
            load()
        );
    }

    // A 10,000-op document: one sphere nudged 9,999 times.
    let url = server.url("join10k");
    let mut log = SharedLog::new("w", "writer", [0.5; 3]).unwrap();
    let mut link = Link::connect(&url, "w", 0, options()).unwrap();
    wait_joined(&mut link, &mut log);
    let id = log.apply(sphere(0.0)).unwrap().created.unwrap();
    let mut solo = OpLog::new();
    let solo_id = solo.apply(sphere(0.0)).unwrap().created.unwrap();
    let mut apply_ms = Vec::new();
    for _ in 1..10_000 {
        log.apply(nudge(id)).unwrap();
        let t = Instant::now();
        solo.apply(nudge(solo_id)).unwrap();
        apply_ms.push(t.elapsed().as_secs_f64() * 1e3);
        while log.pending_count() > 16 {
            link.pump(&mut log);
        }
        link.pump(&mut log);
    }
    wait_joined(&mut link, &mut log);
    // The writer's own boundary snapshot is stored in the background.
    std::thread::sleep(Duration::from_millis(500));
    let entries = log.confirmed().last_seq();
    let la = load();
    let mut from_snapshot = Vec::new();
    let mut replayed = Vec::new();
    let mut checked = Vec::new();
    let mut tail = 0;
    for rep in 0..3 {
        let me = format!("late{rep}");
        let t = Instant::now();
        let stored = fetch_snapshot(&url, &options())
            .unwrap()
            .expect("a snapshot");
        let seq = stored.seq;
        let replica = Replica::from_snapshot(&stored.bytes).unwrap();
        let mut j = SharedLog::resume(&me, &me, [0.5; 3], replica, 1).unwrap();
        let mut l = Link::connect(&url, &me, seq, options()).unwrap();
        l.check_snapshot(seq, stored.bytes, &stored.writer);
        assert!(l.catch_up(&mut j, Duration::from_secs(60)));
        from_snapshot.push(t.elapsed().as_secs_f64() * 1e3);
        tail = entries - seq;
        assert_eq!(j.document().content_hash(), log.document().content_hash());
        while matches!(l.snapshot_state(), SnapshotState::Checking { .. }) {
            l.receive(&mut j);
            assert!(t.elapsed() < Duration::from_secs(120), "check stalled");
            std::thread::sleep(Duration::from_millis(2));
        }
        assert_eq!(l.snapshot_state(), &SnapshotState::Confirmed);
        checked.push(t.elapsed().as_secs_f64() * 1e3);
        let t = Instant::now();
        let mut j = SharedLog::new(&me, &me, [0.5; 3]).unwrap();
        let mut l = Link::connect(&url, &me, 0, options()).unwrap();
        assert!(l.catch_up(&mut j, Duration::from_secs(120)));
        replayed.push(t.elapsed().as_secs_f64() * 1e3);
        assert_eq!(j.document().content_hash(), log.document().content_hash());
    }
    let (s50, r50) = (
        quantile(&mut from_snapshot, 0.5),
        quantile(&mut replayed, 0.5),
    );
    let (smin, smax) = (
        quantile(&mut from_snapshot, 0.0),
        quantile(&mut from_snapshot, 1.0),
    );
    let (rmin, rmax) = (quantile(&mut replayed, 0.0), quantile(&mut replayed, 1.0));
    let c50 = quantile(&mut checked, 0.5);
    println!(
        "{{\"row\":\"join\",\"entries\":{entries},\"tail\":{tail},\"snapshot_ms\":{s50:.1},\"snapshot_spread\":[{smin:.1},{smax:.1}],\"checked_ms\":{c50:.1},\"replay_ms\":{r50:.1},\"replay_spread\":[{rmin:.1},{rmax:.1}],\"reps\":3,\"load_before\":\"{la}\",\"load_after\":\"{}\"}}",
        load()
    );
    let a50 = quantile(&mut apply_ms, 0.5);
    let a99 = quantile(&mut apply_ms, 0.99);
    println!("{{\"row\":\"single_user_apply\",\"op\":\"transform_by\",\"samples\":{},\"p50_ms\":{a50:.4},\"p99_ms\":{a99:.4}}}", apply_ms.len());
}
