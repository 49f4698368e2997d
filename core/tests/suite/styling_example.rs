//! The styled curve-network example (`tests/data/curve_network.jsonl`):
//! replays to a closed, oriented 2-manifold with bit-identical replay, and
//! is written as STL (to `$CARGO_TARGET_TMPDIR/curve_network.stl`) for
//! rendering.

use shapewright::doc::{parse_script, run_script, ObjectKind, OpLog};
use shapewright::mesh::{validate, write_stl};

#[test]
fn curve_network_example_is_printable_and_replays() {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let text = std::fs::read_to_string(root.join("tests/data/curve_network.jsonl")).unwrap();
    let lines = parse_script(&text).unwrap();
    let mut log = OpLog::new();
    run_script(&mut log, &lines).unwrap();
    let doc = log.document();
    let (_, obj) = doc.objects().next().unwrap();
    let ObjectKind::CurveNetwork(net) = &obj.kind else {
        panic!("expected a curve network");
    };
    assert_eq!(net.patches.len(), 6);
    for k in 0..6 {
        eprintln!("patch {k} centre {:?}", net.patch_point(k, 0.5, 0.5));
    }
    assert!(
        net.junction_gap() < 1e-9,
        "junction gap {}",
        net.junction_gap()
    );
    let mesh = doc.combined_mesh();
    let report = validate(&mesh, &Default::default());
    assert!(report.is_closed_manifold(), "{:?}", report.problems());
    assert_eq!(report.genus, Some(0));
    assert_eq!(report.components, 1);
    // The box is 0.2 m on a side with bowed edges and a domed top.
    let v = mesh.signed_volume();
    assert!(v > 0.009 && v < 0.014, "volume {v}");
    let replayed = OpLog::replay(log.ops().to_vec(), log.len()).unwrap();
    assert_eq!(replayed.document().content_hash(), doc.content_hash());
    let out = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("curve_network.stl");
    let mut f = std::fs::File::create(&out).unwrap();
    write_stl(&mesh, &mut f).unwrap();
    eprintln!(
        "wrote {} ({} triangles, volume {v:.6})",
        out.display(),
        mesh.triangles.len()
    );
}
