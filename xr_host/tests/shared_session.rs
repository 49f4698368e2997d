//! Two recorded headset sessions played at once as two people of one
//! shared session (issue 23's "two-person session trace"): two
//! `shapewright-xr replay --join` processes against a real nats-server on
//! 127.0.0.1. Both end with the same document, bit for bit, equal to one
//! replay of the stream, and it holds both people's work.

use std::path::Path;
use std::process::Command;

use shapewright_net::testkit::{credentials_file, options, read_stream, Server};

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
            .arg("--credentials")
            .arg(credentials_file())
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

/// Presence: while Ben plays his recorded session, Ana stands across the
/// model (her head, hands and selection sent at 30 Hz as the headset
/// host sends them). Ben's headset draws her as an avatar with her name
/// and colour (his headset view is rendered to PNG), and she hears his.
#[test]
fn each_person_sees_the_others_as_avatars() {
    use shapewright::doc::shared::{id_range, Presence, PresencePose, SharedLog};
    use shapewright::interact::Trace;
    use shapewright_net::Link;
    use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
    use std::time::Duration;

    let server = Server::start();
    let url = server.url("presence");
    let data = Path::new(env!("CARGO_MANIFEST_DIR")).join("../tests/data");
    let trace_path = data.join("lamp_session.trace.jsonl");
    let trace = Trace::from_jsonl(&std::fs::read_to_string(&trace_path).unwrap()).unwrap();
    let to_model = trace.header.model.similarity().unwrap().inverse();
    let pose = |p: [f64; 3], q: glam::DQuat| PresencePose {
        p: to_model.apply(glam::DVec3::from(p)).as_vec3().to_array(),
        q: (to_model.rotate * q).normalize().as_quat().to_array(),
    };
    // Seated across the desk from Ben (who stands at 1.6 m looking down
    // at the lamp he makes), facing him, both hands out, with Ben's first
    // object selected.
    let facing = glam::DQuat::from_rotation_y(std::f64::consts::PI);
    let ana_presence = Presence {
        head: Some(pose([0.0, 1.0, -0.95], facing)),
        hands: [
            Some(pose([0.2, 0.85, -0.75], facing)),
            Some(pose([-0.2, 0.85, -0.75], facing)),
        ],
        selected: Some(id_range(2).0),
        ..Presence::empty()
    };
    let mut ana = SharedLog::new("ana", "Ana", [0.95, 0.35, 0.55]).unwrap();
    let mut link = Link::connect(&url, "ana", 0, options()).unwrap();
    let t = std::time::Instant::now();
    while !ana.is_joined() {
        link.pump(&mut ana);
        assert!(t.elapsed() < Duration::from_secs(20), "ana did not join");
        std::thread::sleep(Duration::from_millis(2));
    }
    let stop = AtomicBool::new(false);
    let heard = AtomicUsize::new(0);
    let dir = std::env::temp_dir().join(format!("sw_presence_{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let png = dir.join("ben_sees_ana.png");
    let out = std::thread::scope(|s| {
        s.spawn(|| {
            let channel = link.presence();
            while !stop.load(Ordering::Relaxed) {
                link.pump(&mut ana);
                channel.send(&ana_presence);
                let others = channel.others(Duration::from_secs(2));
                if others
                    .iter()
                    .any(|(who, p)| who == "ben" && p.head.is_some())
                {
                    heard.fetch_add(1, Ordering::Relaxed);
                }
                std::thread::sleep(Duration::from_millis(33));
            }
        });
        let out = Command::new(env!("CARGO_BIN_EXE_shapewright-xr"))
            .arg("replay")
            .arg(&trace_path)
            .args(["--join", &url.to_string(), "--me", "ben", "--name", "Ben"])
            .arg("--credentials")
            .arg(credentials_file())
            .args(["--quiet-secs", "0.5", "--view-at", "43.5"])
            .arg("--view-png")
            .arg(&png)
            .output()
            .expect("shapewright-xr runs");
        stop.store(true, Ordering::Relaxed);
        out
    });
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{stdout}\n{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let drawn: usize = stdout
        .lines()
        .find_map(|l| l.strip_prefix("people     "))
        .and_then(|l| l.split_whitespace().next()?.parse().ok())
        .unwrap_or_else(|| panic!("no people line in:\n{stdout}"));
    assert_eq!(drawn, 1, "Ben's headset drew Ana");
    assert!(
        heard.load(Ordering::Relaxed) > 0,
        "Ana heard Ben's presence"
    );
    assert!(std::fs::metadata(&png).unwrap().len() > 10_000);
    eprintln!("Ben's view: {}", png.display());
}
