//! Held surface tools on n-sided patches (issue 33): the sharpener at any
//! setting stops before the patch overhangs its boundary (so it still
//! prints), the path's positions decide where the tools act, and the
//! headset's defaults change a patch by a few centimetres a second.

use super::network::CurveNetwork;
use super::patch::MeshSample;
use super::surface_hold::PatchSampler;
use crate::doc::print_document;
use crate::doc::{Op, OpLog};
use crate::math::fm::DetMath as _;
use crate::math::DVec3;
use crate::print::PrintSettings;

/// The ops of a flat regular `n`-gon of circumradius `r` (model metres)
/// in the plane z = 0, each side bowed 4% outwards, filled, and its
/// centre pulled up to `bump` by the surface puller.
pub(crate) fn ngon_ops(n: usize, r: f64, bump: f64) -> Vec<Op> {
    bowed_ngon_ops(n, r, bump, 0.04)
}

/// [`ngon_ops`] with each side's middle pushed out by `bow` times the
/// distance of the side's middle from the centre (0: straight sides).
fn bowed_ngon_ops(n: usize, r: f64, bump: f64, bow: f64) -> Vec<Op> {
    let mut lines =
        vec![r#"{"op":"curve_network_create","resolution":24,"surface_n":8}"#.to_string()];
    let corner = |k: usize| {
        let a = std::f64::consts::TAU * k as f64 / n as f64;
        DVec3::new(r * a.fcos(), r * a.fsin(), 0.0)
    };
    for k in 0..n {
        let (a, b) = (corner(k), corner(k + 1));
        let out = (a + b) * 0.5 * bow;
        let pts: Vec<[f64; 3]> = (0..9)
            .map(|i| {
                let t = i as f64 / 8.0;
                (a.lerp(b, t) + out * (4.0 * t * (1.0 - t))).to_array()
            })
            .collect();
        lines.push(format!(
            r#"{{"op":"curve_draw","id":1,"samples":{},"fit":{{"mode":"interpolate"}},"resample":null,"snap_tol":0.002}}"#,
            serde_json::to_string(&pts).unwrap()
        ));
    }
    lines.push(r#"{"op":"curve_fill_auto","id":1}"#.to_string());
    let path: Vec<[f64; 3]> = (1..=10)
        .map(|i| [0.0, 0.0, bump * i as f64 / 10.0])
        .collect();
    lines.push(format!(
        r#"{{"op":"surface_pull","id":1,"patch":0,"weights":{{"wb":1.0,"ws":0.0}},"wpp":2000.0,"u0":0.5,"v0":0.5,"path":{}}}"#,
        serde_json::to_string(&path).unwrap()
    ));
    lines
        .iter()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect()
}

pub(crate) fn net_of(log: &OpLog) -> CurveNetwork {
    match &log.document().objects().next().unwrap().1.kind {
        crate::doc::ObjectKind::CurveNetwork(n) => n.clone(),
        _ => unreachable!(),
    }
}

fn log_of(ops: &[Op]) -> OpLog {
    let mut log = OpLog::new();
    for op in ops {
        log.apply(op.clone()).unwrap();
    }
    log
}

/// The patch's centre height (its domain centre is (½, ½) for any sides).
fn centre_z(net: &CurveNetwork) -> f64 {
    net.patch_point(0, 0.5, 0.5).z
}

/// Triangles of patch 0's mesh facing down (against the loop's normal,
/// +z here), and how far its mesh reaches sideways past the boundary's
/// circumradius `r`. Triangles with two corners at one point (the
/// collapsed side of a 3-sided patch, which the network's mesh drops)
/// face nowhere and are not counted.
fn overhang(net: &CurveNetwork, r: f64) -> (usize, f64) {
    let m = net.patch_mesh(0);
    let p = |i: u32| DVec3::from_array(m.positions[i as usize]);
    let nz = |t: &[u32; 3]| (p(t[1]) - p(t[0])).cross(p(t[2]) - p(t[0])).z;
    let collapsed = |t: &[u32; 3]| p(t[0]) == p(t[1]) || p(t[1]) == p(t[2]) || p(t[2]) == p(t[0]);
    // The mesh's orientation follows the loop's direction: "up" is the
    // side its vector area points to.
    let up = m.triangles.iter().map(nz).sum::<f64>().signum();
    let down = m
        .triangles
        .iter()
        .filter(|t| !collapsed(t) && nz(t) * up <= 0.0)
        .count();
    let wide = m
        .positions
        .iter()
        .map(|q| DVec3::from_array(*q).truncate().length())
        .fold(0.0, f64::max);
    (down, wide - r * 1.05)
}

fn sharpen(f: f64, wq_max: f64, path: &[[f64; 3]], extra: &str) -> Op {
    serde_json::from_str(&format!(
        r#"{{"op":"surface_sharpen","id":1,"patch":0,"weights":{{"wb":1.0,"ws":0.0}},"f":{f},"wq_max":{wq_max},"path":{}{extra}}}"#,
        serde_json::to_string(path).unwrap()
    ))
    .unwrap()
}

/// Issue 33: "stronger settings make the patch overhang its boundary, and
/// on 7-, 12- and 16-gons the print then refuses to thicken it". The
/// strongest sharpener a file may ask for (f = 2, w_q up to 100, global,
/// unbounded steps) held for a second stops before any triangle of the
/// patch turns over, and the patch prints as a 2 mm shell. (Before: the
/// 4.3 cm bump of a 15 cm hexagon grew to 4.3 m and spread to 1.8 m, and
/// the 16-gon's shell passed through itself in 17,101 triangle pairs.)
///
/// Not yet the 12- and 16-gons: their flat patch's mesh already has
/// triangles turned over at the corners (24 and 512, areas about 1e-7
/// and 1e-6 m²: the n-gon chart puts the samples next to a corner just
/// outside it), a meshing fault of `ngon` this test does not cover.
#[test]
fn no_sharpener_setting_makes_a_patch_overhang_or_refuse_to_print() {
    let still: Vec<[f64; 3]> = vec![[0.0, 0.0, 0.05]; 72];
    for n in [6usize, 7] {
        let mut flat = ngon_ops(n, 0.15, 0.047);
        flat.pop();
        let (down, _) = overhang(&net_of(&log_of(&flat)), 0.15);
        assert_eq!(down, 0, "{n}-gon: the flat patch has triangles facing down");
        let mut log = log_of(&ngon_ops(n, 0.15, 0.047));
        let (down, _) = overhang(&net_of(&log), 0.15);
        assert_eq!(
            down, 0,
            "{n}-gon: the pulled patch has triangles facing down"
        );
        let z0 = centre_z(&net_of(&log));
        log.apply(sharpen(2.0, 100.0, &still, "")).unwrap();
        let net = net_of(&log);
        let (down, wide) = overhang(&net, 0.15);
        println!(
            "{n}-gon: centre {z0:.4} -> {:.4} m, {down} triangles facing down, {wide:.4} m past the boundary",
            centre_z(&net)
        );
        assert!(
            centre_z(&net) > z0 + 0.01,
            "{n}-gon: the sharpener did nothing"
        );
        assert_eq!(down, 0, "{n}-gon: the patch overhangs its boundary");
        assert!(
            wide <= 0.0,
            "{n}-gon: the patch reaches {wide} m past its boundary"
        );
        let printed = print_document(log.document(), &PrintSettings::default());
        assert!(printed.is_ok(), "{n}-gon: {}", printed.err().unwrap());
    }
}

/// Issue 33: "surface tools use only the drag path's length, not its
/// positions". Two sharpeners of the same length, one dragged over the
/// patch's -x side and one over its +x side, give different patches, each
/// raised where its path passed and hardly on the other side. (Before,
/// the two ops gave the same bits.)
#[test]
fn the_path_decides_where_a_surface_tool_acts() {
    let base = log_of(&ngon_ops(6, 0.15, 0.047));
    let before = net_of(&base);
    let run = |x: f64| {
        let path: Vec<[f64; 3]> = (0..40)
            .map(|i| [x, -0.06 + 0.12 * i as f64 / 39.0, 0.04])
            .collect();
        let mut log = log_of(&ngon_ops(6, 0.15, 0.047));
        log.apply(sharpen(1.05, 4.0, &path, r#","radius":0.03"#))
            .unwrap();
        net_of(&log)
    };
    let (left, right) = (run(-0.07), run(0.07));
    // The patch height at the domain points over (∓0.07, 0): measured on
    // the mesh, the nearest vertex to each.
    let height_near = |net: &CurveNetwork, x: f64| {
        let m = net.patch_mesh(0);
        m.positions
            .iter()
            .map(|p| DVec3::from_array(*p))
            .min_by(|a, b| {
                let da = (a.truncate() - DVec3::new(x, 0.0, 0.0).truncate()).length();
                let db = (b.truncate() - DVec3::new(x, 0.0, 0.0).truncate()).length();
                da.total_cmp(&db)
            })
            .unwrap()
            .z
    };
    let rise = |net: &CurveNetwork, x: f64| height_near(net, x) - height_near(&before, x);
    let (ll, lr) = (rise(&left, -0.07), rise(&left, 0.07));
    let (rl, rr) = (rise(&right, -0.07), rise(&right, 0.07));
    println!("left path: -x rose {ll:.5}, +x {lr:.5}; right path: -x {rl:.5}, +x {rr:.5}");
    assert_ne!(left.patches[0].disp, right.patches[0].disp);
    assert!(ll > 0.002 && rr > 0.002, "each path raised its side");
    assert!(
        ll > 4.0 * lr.abs() && rr > 4.0 * rl.abs(),
        "and hardly the other"
    );
}

/// The sampler the held tools watch the mesh with agrees with the patch's
/// own evaluation (a sharpened hexagon and a 7-gon).
#[test]
fn the_held_tools_sample_the_mesh_that_prints() {
    for n in [4usize, 6, 7] {
        let log = log_of(&ngon_ops(n, 0.15, 0.047));
        let net = net_of(&log);
        let (samples, tris) = net.patch_samples(0);
        let s = PatchSampler::new(&net, 0, &samples);
        let mesh = net.patch_mesh(0);
        assert_eq!(mesh.triangles, tris);
        let points: Vec<DVec3> = mesh
            .positions
            .iter()
            .map(|p| DVec3::from_array(*p))
            .collect();
        let gap = s.max_gap_to(&points, &net.patches[0].disp);
        assert!(gap < 1e-12, "{n} sides: the sampler is {gap} m off");
        assert!(samples.iter().any(|x| matches!(x, MeshSample::At(_))));
    }
}

/// Issue 33, still open: "on 7-, 12- and 16-gons the print then refuses
/// to thicken it". The 6- and 7-gons are covered above; the 12- and
/// 16-gons of [`ngon_ops`] do not print even before any tool: their flat
/// patch has 24 and 512 triangles facing down at the corners, and the
/// print refuses it ("the shell passes through itself (342 triangle
/// pairs)" for the 12-gon, "vertex 16 has no normal" for the 16-gon;
/// after the strongest sharpener 392 and 742 pairs). Their sides, bowed
/// 4% outwards, meet at reflex corners (about 183 and 201 degrees against
/// the regular domain's 150 and 157.5). With straight sides they print.
///
/// Why no domain or chart change fixes it: near corner `k` the corner
/// blend `B_k` is 1 with zero gradient, so the patch is
/// `Q_k + (P_k(s_k) - Q_k) + (P_{k-1}(s_{k-1}) - Q_k)` to first order,
/// with both side parameters in `[0, 1]`: a point of the cone spanned by
/// the two pieces' tangents at the corner. At a reflex corner that cone is
/// the outside of the loop, whatever the domain's angles (and a polygon
/// whose 16 corners are all reflex does not exist). The patch itself
/// folds there, not only its mesh. Tried (issue 33 notes): a side-based
/// patch (Kato's blends `∝ 1 / d_k²` of ribbons `P_k(t_k) + d_k c N ×
/// chord_k`, `t_k` the projection on side `k`, pieces continued past
/// their ends by their end quadratics) has no triangle facing down for
/// any n of 3..=16, straight or bowed up to 8%, and makes this test pass;
/// but its in-plane parameterization is so much closer to the energy's
/// minimum that the held sharpener above no longer folds anything in the
/// plane, runs to `w_q` about 40 on the hexagon (centre 4.3 cm -> 1.72 m)
/// and that spike's shell passes through itself (86 pairs): the overhang
/// guard alone does not keep the 6-gon printable then.
#[test]
#[ignore = "still failing (issue 33): bowed 12- and 16-gon patches fold at their reflex corners"]
fn sharpened_twelve_and_sixteen_gons_print() {
    let still: Vec<[f64; 3]> = vec![[0.0, 0.0, 0.05]; 72];
    for n in [12usize, 16] {
        let mut log = log_of(&ngon_ops(n, 0.15, 0.047));
        log.apply(sharpen(2.0, 100.0, &still, "")).unwrap();
        let (down, _) = overhang(&net_of(&log), 0.15);
        let printed = print_document(log.document(), &PrintSettings::default());
        assert!(
            down == 0 && printed.is_ok(),
            "{n}-gon: {down} triangles facing down, print: {:?}",
            printed.err().map(|e| e.to_string())
        );
    }
}

/// Issue 33: every loop of 3 to 16 sides, straight or bowed as in
/// [`ngon_ops`], fills with a flat patch none of whose triangles faces
/// down, and prints. (Now: straight ones all do; bowed 3- to 11-gons do,
/// the 12- to 16-gons have 24, 156, 280, 420 and 512 triangles facing
/// down and do not print, for the reason given above.)
#[test]
#[ignore = "still failing (issue 33): bowed 12- to 16-gon patches fold at their reflex corners"]
fn flat_patches_of_every_size_face_up_and_print() {
    let mut bad = Vec::new();
    for bow in [0.0, 0.04] {
        for n in 3usize..=16 {
            let mut flat = bowed_ngon_ops(n, 0.15, 0.047, bow);
            flat.pop();
            let log = log_of(&flat);
            let (down, _) = overhang(&net_of(&log), 0.15);
            let printed = print_document(log.document(), &PrintSettings::default());
            println!(
                "bow {bow}, {n}-gon: {down} triangles facing down, print {}",
                printed
                    .as_ref()
                    .map_or_else(|e| e.to_string(), |_| "ok".into())
            );
            if down != 0 || printed.is_err() {
                bad.push(format!("bow {bow}, {n}-gon: {down} facing down"));
            }
        }
    }
    assert!(bad.is_empty(), "{bad:?}");
}
