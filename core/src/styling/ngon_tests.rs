//! Multi-sided patches (issue 18): 5- to 16-sided loops fill with patches
//! that contain their curves, are smooth across the mesh's internal seams,
//! mesh closed, and take the surface smoother, sharpener and puller.

use super::curve::{fit_curve, FitMode};
use super::net_tests::edge_samples;
use super::network::{CurveNetwork, Piece};
use super::ngon::MAX_SIDES;
use super::polygon::NgonDomain;
use super::surface::SurfaceWeights;
use super::StylingError;
use crate::math::fm::DetMath as _;
use crate::math::{DVec2, DVec3};
use crate::mesh::validate;

fn add(net: &mut CurveNetwork, a: DVec3, b: DVec3, bow: DVec3) {
    let s = edge_samples(a.to_array(), b.to_array(), bow.to_array());
    let c = fit_curve(&s, FitMode::Interpolate, None).unwrap();
    net.add_curve(c, 1e-3).unwrap();
}

/// A prism over a regular `n`-gon (circumradius `r`, height `h`), every
/// edge bowed outwards; with `wave > 0` the corners of both caps rise and
/// fall by `wave` around the polygon and the cap edges bow up by
/// `wave / 2`, so the caps are not planar. `2n` polygon edges (bottom cap
/// first) and `n` verticals.
pub(crate) fn prism(n: usize, r: f64, h: f64, wave: f64, resolution: u32) -> CurveNetwork {
    let mut net = CurveNetwork::new(resolution, 6).unwrap();
    let corner = |k: usize, z: f64| {
        let a = std::f64::consts::TAU * k as f64 / n as f64;
        DVec3::new(
            r * a.fcos(),
            r * a.fsin(),
            z + wave * (2.0 * a + 0.3).fsin(),
        )
    };
    for z in [0.0, h] {
        for k in 0..n {
            let (a, b) = (corner(k, z), corner(k + 1, z));
            let out = ((a + b) * 0.5).with_z(0.0).normalize() * 0.006 + DVec3::Z * (0.5 * wave);
            add(&mut net, a, b, out);
        }
    }
    for k in 0..n {
        let a = corner(k, 0.0);
        add(&mut net, a, corner(k, h), a.with_z(0.0).normalize() * 0.006);
    }
    net
}

/// Piece `p` of `net` at `s ∈ [0, 1]` along its direction.
pub(crate) fn on(net: &CurveNetwork, p: &Piece, s: f64) -> DVec3 {
    let (ta, tb) = (
        net.param(p.from, p.curve).unwrap(),
        net.param(p.to, p.curve).unwrap(),
    );
    net.curve(p.curve).unwrap().point(ta + (tb - ta) * s)
}

/// Largest distance between any patch's boundary and its curves (17
/// samples per piece).
pub(crate) fn boundary_gap(net: &CurveNetwork) -> f64 {
    let mut worst: f64 = 0.0;
    for (k, patch) in net.patches.iter().enumerate() {
        let pc = &patch.pieces;
        let n = pc.len();
        for i in 0..=16 {
            let s = i as f64 / 16.0;
            if n > 4 {
                let dom = NgonDomain::regular(n);
                for (q, piece) in pc.iter().enumerate() {
                    let p = dom.vertex(q).lerp(dom.vertex(q + 1), s);
                    let d = net.patch_point(k, p.x, p.y).distance(on(net, piece, s));
                    worst = worst.max(d);
                }
                continue;
            }
            worst = worst.max(net.patch_point(k, s, 0.0).distance(on(net, &pc[0], s)));
            worst = worst.max(net.patch_point(k, 1.0, s).distance(on(net, &pc[1], s)));
            worst = worst.max(
                net.patch_point(k, s, 1.0)
                    .distance(on(net, &pc[2], 1.0 - s)),
            );
            if n == 4 {
                worst = worst.max(
                    net.patch_point(k, 0.0, s)
                        .distance(on(net, &pc[3], 1.0 - s)),
                );
            }
        }
    }
    worst
}

/// Crease angle (degrees) of the surface `f` across the domain segment
/// `a -> b` at parameter `t`: the normals just left and right of the
/// segment, each from one-sided differences that stay on its side.
fn crease_deg(f: &dyn Fn(DVec2) -> DVec3, a: DVec2, b: DVec2, t: f64) -> f64 {
    let h = 1e-6;
    let p = a.lerp(b, t);
    let tau = (b - a).normalize();
    let nu = tau.perp();
    let along = f(p + tau * h) - f(p - tau * h);
    let left = along.cross(f(p) - f(p - nu * h));
    let right = along.cross(f(p + nu * h) - f(p));
    left.angle_between(right).to_degrees()
}

/// The worst crease angle over `count` points spread over the spokes of
/// the n-sided patch `k` (the internal seams of its mesh), away from their
/// ends (the centre, where all spokes meet, and the boundary).
pub(crate) fn worst_seam_angle(net: &CurveNetwork, k: usize, count: usize) -> f64 {
    let n = net.patches[k].pieces.len();
    let dom = NgonDomain::regular(n);
    let f = |p: DVec2| net.patch_point(k, p.x, p.y);
    (0..count)
        .map(|i| {
            let spoke = i % n;
            let t = 0.05 + 0.9 * (i / n) as f64 / (count / n).max(1) as f64;
            crease_deg(&f, dom.mid(spoke), dom.centre(), t)
        })
        .fold(0.0, f64::max)
}

#[test]
fn the_seam_measure_sees_a_crease() {
    // A surface folded along the x axis by 10 degrees, probed across it.
    let k = (10f64).to_radians().ftan();
    let fold = |p: DVec2| DVec3::new(p.x, p.y, k * p.y.max(0.0));
    let a = crease_deg(&fold, DVec2::new(-1.0, 0.0), DVec2::new(1.0, 0.0), 0.3);
    assert!((a - 10.0).abs() < 0.01, "measured {a}");
    let smooth = |p: DVec2| DVec3::new(p.x, p.y, 0.3 * p.y * p.y + p.x * p.y);
    let a = crease_deg(&smooth, DVec2::new(-1.0, 0.0), DVec2::new(1.0, 0.0), 0.3);
    assert!(a < 1e-3, "measured {a}");
}

/// The n-sided cap patch (the first patch with `n` pieces) of a filled prism.
fn cap(net: &CurveNetwork, n: usize) -> usize {
    net.patches
        .iter()
        .position(|p| p.pieces.len() == n)
        .unwrap()
}

#[test]
fn multisided_loops_fill_smooth_closed_and_on_their_curves() {
    for n in [5usize, 6, 8, 12] {
        let mut net = prism(n, 0.1, 0.12, 0.015, 8);
        let filled = net.fill_all().unwrap();
        assert_eq!(filled.len(), n + 2, "{n}: n quads and 2 caps");
        let gap = boundary_gap(&net);
        assert!(gap < 1e-9, "{n}: boundary gap {gap}");
        for k in 0..net.patches.len() {
            if net.patches[k].pieces.len() == n {
                let worst = worst_seam_angle(&net, k, 100);
                assert!(worst < 1.0, "{n}-sided patch {k}: crease {worst} degrees");
                // The cap is curved, not planar: its normals turn by
                // several degrees between the centre and each quad's middle.
                let dom = NgonDomain::regular(n);
                let f = |p: DVec2| net.patch_point(k, p.x, p.y);
                let normal = |p: DVec2| {
                    let h = 1e-6;
                    let du = f(p + DVec2::X * h) - f(p - DVec2::X * h);
                    let dv = f(p + DVec2::Y * h) - f(p - DVec2::Y * h);
                    du.cross(dv).normalize()
                };
                let n0 = normal(dom.centre());
                let turn = (0..n)
                    .map(|q| {
                        let p = super::ngon::ngon_chart(&dom, q, 0.5, 0.5);
                        normal(p).angle_between(n0).to_degrees()
                    })
                    .fold(0.0, f64::max);
                assert!(
                    turn > 5.0,
                    "{n}: the cap's normals turn only {turn} degrees"
                );
            }
        }
        let m = net.mesh();
        let r = validate(&m, &Default::default());
        assert!(r.is_closed_manifold(), "{n}: {}", r.problems());
        assert_eq!(r.genus, Some(0), "{n}");
    }
}

#[test]
fn the_transfinite_patch_reproduces_a_plane_and_lies_inside_its_loop() {
    // Planar loops give planar patches (each corner interpolant is an
    // affine combination of points on the plane).
    for n in [5usize, 9, 16] {
        let mut net = prism(n, 0.1, 0.1, 0.0, 8);
        net.fill_all().unwrap();
        let k = cap(&net, n);
        let z0 = net.node_point(net.patches[k].pieces[0].from).z;
        let dom = NgonDomain::regular(n);
        for i in 0..50 {
            let q = i % n;
            let p = super::ngon::ngon_chart(&dom, q, 0.13 + 0.017 * i as f64 % 0.8, 0.4);
            let s = net.patch_point(k, p.x, p.y);
            assert!((s.z - z0).abs() < 1e-12, "{n}: {}", s.z - z0);
            assert!(
                s.with_z(0.0).length() < 0.1 + 0.006,
                "{n}: outside the loop"
            );
        }
    }
}

fn surface_weights() -> SurfaceWeights {
    SurfaceWeights { wb: 1.0, ws: 0.0 }
}

#[test]
fn surface_tools_shape_multisided_patches() {
    for n in [5usize, 6, 8, 12] {
        let mut net = prism(n, 0.1, 0.12, 0.015, 8);
        net.fill_all().unwrap();
        let k = cap(&net, n);
        let w = surface_weights();
        let d0 = net.patches[k].disp.clone();
        assert_eq!(d0.len(), 36);
        // Puller: the patch centre follows the pointer to 6 mm above it.
        let c0 = net.patch_point(k, 0.5, 0.5);
        let target = c0 + DVec3::new(0.004, -0.002, 0.03);
        let mut sys = net.surface_system(k, &w).unwrap();
        let base0 = net.patch_base_point(k, 0.5, 0.5).unwrap();
        let path: Vec<DVec3> = (1..=5).map(|i| c0.lerp(target, i as f64 / 5.0)).collect();
        let pulled = sys.pull(&d0, 0.5, 0.5, base0, 1e6, &path).unwrap();
        let mut p = net.clone();
        p.patches[k].disp = pulled.clone();
        let miss = p.patch_point(k, 0.5, 0.5).distance(target);
        assert!(miss < 1e-3, "{n}: puller missed by {miss}");
        assert!(boundary_gap(&p) < 1e-9, "{n}: pull moved the boundary");
        let crease = worst_seam_angle(&p, k, 100);
        assert!(crease < 1.0, "{n}: pulled patch creased {crease} degrees");
        let r = validate(&p.mesh(), &Default::default());
        assert!(r.is_closed_manifold(), "{n}: {}", r.problems());
        // Smoother from the pulled shape: the energy falls every frame and
        // the shape goes to the minimal-energy one as w_q = f^k.
        let dmin = sys.minimal(&pulled).unwrap();
        let e_min = sys.energy(&dmin);
        let gap = |d: &[[f64; 3]]| {
            d.iter()
                .zip(&dmin)
                .map(|(a, b)| DVec3::from_array(*a).distance(DVec3::from_array(*b)))
                .fold(0.0, f64::max)
        };
        let gap0 = gap(&pulled);
        assert!(gap0 > 1e-3, "{n}: the pull must leave something to smooth");
        let mut prev = sys.energy(&pulled);
        for frames in 1..=5 {
            let (d, wq) = sys.equilibrium_frames(&pulled, 0.7, frames, 1.0).unwrap();
            let e = sys.energy(&d);
            assert!(e < prev, "{n}: smoother frame {frames} raised the energy");
            assert!(
                (gap(&d) - wq * gap0).abs() < 1e-9,
                "{n}: d_k = wq d0 + (1 - wq) dmin"
            );
            prev = e;
        }
        assert!(prev >= e_min - 1e-12);
        let (smoothed, _) = sys.equilibrium_frames(&pulled, 0.7, 5, 1.0).unwrap();
        let mut s = net.clone();
        s.patches[k].disp = smoothed;
        assert!(boundary_gap(&s) < 1e-9);
        assert!(worst_seam_angle(&s, k, 100) < 1.0);
        let drop = s.patch_point(k, 0.5, 0.5).distance(target);
        assert!(
            drop > 0.2 * 0.03,
            "{n}: smoothing lowers the pulled bump ({drop})"
        );
        // Sharpener: moves away from the minimal surface by w_q, energy up.
        let (sharp, wq) = sys.equilibrium_frames(&pulled, 1.3, 4, 2.0).unwrap();
        assert!((wq - 1.3f64.fpowi(4).min(2.0)).abs() < 1e-12);
        assert!((gap(&sharp) - wq * gap0).abs() < 1e-9);
        assert!(sys.energy(&sharp) > sys.energy(&pulled));
        let mut h = net.clone();
        h.patches[k].disp = sharp;
        assert!(boundary_gap(&h) < 1e-9);
        assert!(worst_seam_angle(&h, k, 100) < 1.0);
        assert!(validate(&h.mesh(), &Default::default()).is_closed_manifold());
        // One symbolic analysis and one numeric factorization per system
        // for the smoother/sharpener frames (the puller's matrix differs).
        assert!(sys.solver.refactor_count <= 3);
    }
}

#[test]
fn loops_up_to_the_maximum_fill_and_longer_ones_are_refused() {
    let mut net = prism(MAX_SIDES, 0.1, 0.1, 0.01, 8);
    let filled = net.fill_all().unwrap();
    assert_eq!(filled.len(), MAX_SIDES + 2);
    let k = cap(&net, MAX_SIDES);
    assert!(worst_seam_angle(&net, k, 100) < 1.0);
    assert!(validate(&net.mesh(), &Default::default()).is_closed_manifold());
    let big = prism(MAX_SIDES + 1, 0.1, 0.1, 0.0, 8);
    let lp: Vec<Piece> = (0..MAX_SIDES + 1)
        .map(|k| big.pieces().into_iter().find(|p| p.curve == k).unwrap())
        .collect();
    assert_eq!(
        big.check_loop(&lp),
        Err(StylingError::LoopSize(MAX_SIDES + 1))
    );
    assert!(big.find_loops().iter().all(|l| l.len() <= MAX_SIDES));
    // An odd resolution cannot mesh an n-sided patch.
    let mut odd = prism(5, 0.1, 0.12, 0.0, 9);
    let lp = odd.find_loops().into_iter().find(|l| l.len() == 5).unwrap();
    assert_eq!(odd.fill(&lp), Err(StylingError::OddResolution(9)));
    // A pull point outside the pentagon is a typed error.
    let mut net = prism(5, 0.1, 0.12, 0.0, 8);
    net.fill_all().unwrap();
    let k = cap(&net, 5);
    let mut sys = net.surface_system(k, &surface_weights()).unwrap();
    let d0 = net.patches[k].disp.clone();
    let e = sys.pull(&d0, 0.02, 0.02, DVec3::ZERO, 10.0, &[DVec3::ZERO]);
    assert!(matches!(e, Err(StylingError::BadParameter(_))), "{e:?}");
}
