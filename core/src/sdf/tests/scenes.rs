use crate::doc::{parse_script, run_script, OpLog};
use crate::math::fm::DetMath as _;
use crate::mesh::validate;

fn run(text: &str) -> OpLog {
    let lines = parse_script(text).unwrap();
    let mut log = OpLog::new();
    run_script(&mut log, &lines).unwrap();
    log
}

fn check(text: &str, genus: i64) -> OpLog {
    let log = run(text);
    let m = log.document().combined_mesh();
    let r = validate(&m, &Default::default());
    assert!(r.is_closed_manifold(), "{}", r.problems());
    assert_eq!(r.components, 1);
    assert_eq!(r.genus, Some(genus));
    let again = run(text);
    assert_eq!(
        again.document().content_hash(),
        log.document().content_hash()
    );
    log
}

#[test]
fn cup_scene_is_genus_one() {
    let log = check(include_str!("../../../../tests/data/csg_cup.jsonl"), 1);
    let r = validate(&log.document().combined_mesh(), &Default::default());
    // Body minus hollow plus the handle's share outside the body.
    let body = std::f64::consts::PI * (0.12f64.fpowi(2) * 0.24 - 0.105f64.fpowi(2) * 0.21);
    assert!(
        r.signed_volume > body && r.signed_volume < body * 1.25,
        "{}",
        r.signed_volume
    );
}

#[test]
fn chair_scene_is_one_genus_zero_solid() {
    check(include_str!("../../../../tests/data/csg_chair.jsonl"), 0);
}

#[test]
fn pedestal_scene_is_one_genus_zero_solid() {
    check(include_str!("../../../../tests/data/csg_pedestal.jsonl"), 0);
}
