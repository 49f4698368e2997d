//! Two recorded headset sessions played at once as two people of one
//! shared session (issue 23's "two-person session trace"): two
//! `shapewright-xr replay --join` processes against a real nats-server on
//! 127.0.0.1. Both end with the same document, bit for bit, equal to one
//! replay of the stream, and it holds both people's work.

use std::path::Path;
use std::process::Command;

use shapewright_net::testkit::{read_stream, Server};

fn content_line(out: &str) -> String {
    out.lines()
        .find_map(|l| l.strip_prefix("content    "))
        .unwrap_or_else(|| panic!("no content line in:\n{out}"))
        .to_string()
}

#[test]
fn two_recorded_sessions_played_at_once_build_one_model() {
    let server = Server::start();
    let url = server.url("two");
    let data = Path::new(env!("CARGO_MANIFEST_DIR")).join("../tests/data");
    let bin = env!("CARGO_BIN_EXE_shapewright-xr");
    let play = |trace: &str, me: &str| {
        Command::new(bin)
            .arg("replay")
            .arg(data.join(trace))
            .args(["--join", &url.to_string(), "--me", me, "--quiet-secs", "1"])
            .output()
            .expect("shapewright-xr runs")
    };
    let (a, b) = std::thread::scope(|s| {
        let a = s.spawn(|| play("primitives_session.trace.jsonl", "ana"));
        let b = s.spawn(|| play("csg_cup.trace.jsonl", "ben"));
        (a.join().unwrap(), b.join().unwrap())
    });
    let (a_out, b_out) = (
        String::from_utf8_lossy(&a.stdout),
        String::from_utf8_lossy(&b.stdout),
    );
    assert!(
        a.status.success(),
        "{a_out}\n{}",
        String::from_utf8_lossy(&a.stderr)
    );
    assert!(
        b.status.success(),
        "{b_out}\n{}",
        String::from_utf8_lossy(&b.stderr)
    );
    let (ha, hb) = (content_line(&a_out), content_line(&b_out));
    assert_eq!(ha, hb, "both replicas agree");
    let solo = read_stream(&url);
    assert_eq!(ha, format!("{:016x}", solo.document().content_hash()));
    // Both people's work is in it: Ana's solids and Ben's CSG volume.
    let doc = solo.document();
    let kinds: Vec<&str> = doc.objects().map(|(_, o)| o.kind.name()).collect();
    assert!(
        kinds.contains(&"solid") && kinds.contains(&"sdf_volume"),
        "{kinds:?}"
    );
    let mut people: Vec<&str> = solo.participants().iter().map(|p| p.id.as_str()).collect();
    people.sort();
    assert_eq!(people, ["ana", "ben"]);
    for (id, _) in doc.objects() {
        assert!(
            id.0 >> 24 == 1 || id.0 >> 24 == 2,
            "{id} is in ana's or ben's id range"
        );
    }
}
