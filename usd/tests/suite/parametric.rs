//! NurbsCurves / NurbsPatch prims: the exact Coons-to-NURBS conversion of
//! styling patches, the prims of every GC and curve-network example, and
//! the load-time cross-check.

use crate::common;

use shapewright::doc::ObjectKind;
use shapewright::math::fm::DetMath as _;
use shapewright::math::DVec3;
use shapewright::nurbs::segment;
use shapewright::nurbs::uniform_samples as params;
use shapewright::nurbs::{interpolate, ParamMethod};
use shapewright_usd::coons::patch_surface;
use shapewright_usd::parametric::{parts, Part};
use shapewright_usd::{load_from_str, save_to_string, LoadOptions, Mismatch, SaveOptions};

fn script(name: &str) -> String {
    let (_, text) = common::scripts()
        .into_iter()
        .find(|(p, _)| p.file_name().is_some_and(|f| f == name))
        .unwrap_or_else(|| panic!("no script {name}"));
    text
}

#[test]
fn segment_is_the_curve_over_its_span() {
    let pts: Vec<DVec3> = (0..9)
        .map(|i| {
            let t = i as f64 * 0.7;
            DVec3::new(t.fcos(), t.fsin(), 0.3 * t)
        })
        .collect();
    let c = interpolate(&pts, 3, ParamMethod::ChordLength).unwrap();
    let (a, b) = c.domain();
    for (lo, hi) in [(a, b), (a, 0.4), (0.25, b), (0.1, 0.9), (0.3, 0.31)] {
        let s = segment(&c, lo, hi).unwrap();
        assert_eq!(s.domain(), (lo, hi));
        for t in params(lo, hi, 16) {
            let d = (s.point(t) - c.point(t)).length();
            assert!(d < 1e-12, "[{lo}, {hi}] at {t}: {d}");
        }
    }
    assert!(segment(&c, 0.5, 0.5).is_err());
    assert!(segment(&c, -1.0, 0.5).is_err());
}

#[test]
fn styling_patches_convert_exactly() {
    let log = common::run(&script("curve_network.jsonl"));
    let mut checked = 0;
    for (_, obj) in log.document().objects() {
        let ObjectKind::CurveNetwork(net) = &obj.kind else {
            continue;
        };
        assert!(!net.patches.is_empty());
        for k in 0..net.patches.len() {
            let s = patch_surface(net, k).unwrap();
            assert_eq!((s.degree_u, s.degree_v), (3, 3));
            assert!(s.control.iter().all(|c| c.w == 1.0));
            for u in params(0.0, 1.0, 10) {
                for v in params(0.0, 1.0, 10) {
                    let d = (s.point(u, v) - net.patch_point(k, u, v)).length();
                    assert!(d < 1e-9, "patch {k} at ({u}, {v}): {d}");
                    checked += 1;
                }
            }
        }
    }
    assert!(checked >= 121);
}

#[test]
fn every_gc_and_network_example_has_its_prims() {
    let mut objects = 0;
    for (path, text) in common::scripts() {
        let log = common::run(&text);
        let usda = save_to_string(&log, &SaveOptions::default()).unwrap();
        for (id, obj) in log.document().objects() {
            let expect: Vec<String> = match &obj.kind {
                ObjectKind::GcAssembly(a) => (0..a.parts.len())
                    .flat_map(|i| {
                        [
                            format!("def NurbsCurves \"Part{i}_Spine\""),
                            format!("def NurbsCurves \"Part{i}_Sections\""),
                            format!("def NurbsPatch \"Part{i}_Surface\""),
                        ]
                    })
                    .collect(),
                // 3- and 4-sided patches are one bicubic surface; more
                // sides: the patch's mesh and its boundary curves.
                ObjectKind::CurveNetwork(n) => std::iter::once("def NurbsCurves \"Curves\"".into())
                    .chain(n.patches.iter().enumerate().flat_map(|(k, p)| {
                        if p.pieces.len() <= 4 {
                            vec![format!("def NurbsPatch \"Patch{k}\"")]
                        } else {
                            vec![
                                format!("def Mesh \"Patch{k}\""),
                                format!("def NurbsCurves \"Patch{k}_Boundary\""),
                            ]
                        }
                    }))
                    .collect(),
                _ => continue,
            };
            objects += 1;
            let start = usda
                .find(&format!("def Xform \"Object_{}\"", id.0))
                .unwrap();
            let end = usda[start + 1..]
                .find("def Xform \"Object_")
                .map_or(usda.len(), |e| start + 1 + e);
            for e in expect {
                assert!(
                    usda[start..end].contains(&e),
                    "{}: {id}: {e}",
                    path.display()
                );
            }
            // Sections are the placed key sections; the surface passes
            // through each at its v (exact skinning).
            if let ObjectKind::GcAssembly(a) = &obj.kind {
                let made = parts(&obj.kind);
                assert!(made.problems.is_empty(), "{:?}", made.problems);
                let ps = made.parts;
                for (i, part) in a.parts.iter().enumerate() {
                    let Part::Curves { curves, .. } = &ps[3 * i + 1] else {
                        panic!("sections")
                    };
                    let Part::Patch { surface, .. } = &ps[3 * i + 2] else {
                        panic!("surface")
                    };
                    for (sec, curve) in part.gc.sections.iter().zip(curves) {
                        let (u0, u1) = curve.domain();
                        for u in params(u0, u1, 8) {
                            let d = (surface.point(u, sec.v) - curve.point(u)).length();
                            assert!(d < 1e-9, "{}: part {i} v={}: {d}", path.display(), sec.v);
                        }
                    }
                }
            }
        }
    }
    assert!(objects >= 8, "{objects} parametric objects");
}

#[test]
fn edited_parametric_prims_are_reported() {
    let log = common::run(&script("vase.jsonl"));
    let usda = save_to_string(&log, &SaveOptions::default()).unwrap();
    let clean = load_from_str(&usda, LoadOptions::default()).unwrap();
    assert!(clean.report.is_consistent(), "{}", clean.report);
    // Change one knot of the spine.
    let at = usda.find("def NurbsCurves \"Part0_Spine\"").unwrap();
    let k = at + usda[at..].find("double[] knots = [").unwrap() + "double[] knots = [".len();
    let end = k + usda[k..].find(',').unwrap();
    let mut text = usda.clone();
    text.replace_range(k..end, "-0.5");
    let loaded = load_from_str(&text, LoadOptions::default()).unwrap();
    assert_eq!(loaded.report.mismatches.len(), 1, "{}", loaded.report);
    assert!(matches!(
        &loaded.report.mismatches[0],
        Mismatch::Parametric { prim, detail, .. } if prim == "Part0_Spine" && detail.contains("knots")
    ));
    // A removed patch prim is reported as missing.
    let text = usda.replace(
        "def NurbsPatch \"Part0_Surface\"",
        "def NurbsPatch \"Other\"",
    );
    let loaded = load_from_str(&text, LoadOptions::default()).unwrap();
    assert!(loaded.report.mismatches.iter().any(|m| matches!(
        m,
        Mismatch::Parametric { prim, detail, .. } if prim == "Part0_Surface" && detail == "missing"
    )));
}
