//! Rotation-minimizing frames by the double reflection method (Wang,
//! Jüttler, Zheng, Liu: "Computation of rotation minimizing frames", ACM
//! TOG 2008, Algorithm 1). Each step reflects the previous frame in the
//! bisecting plane of the two sample points, then in the plane that maps
//! the reflected tangent onto the next tangent. The error is O(h^4) per
//! unit length; on a planar curve a reference vector normal to the plane
//! stays exactly normal to it (both reflections keep it, up to rounding).

use glam::DVec3;

/// An orthonormal frame along a curve: `tangent`, the rotation-minimizing
/// reference `r`, and `s = tangent x r` (so `(r, s, tangent)` is
/// right-handed).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Frame {
    /// The curve point.
    pub origin: DVec3,
    /// Unit tangent.
    pub tangent: DVec3,
    /// Unit reference vector, perpendicular to the tangent.
    pub r: DVec3,
    /// `tangent x r`.
    pub s: DVec3,
}

impl Frame {
    /// A frame at `origin` with tangent `t` and reference as close as
    /// possible to `r_hint` (Gram-Schmidt). `None` when `t` is zero or
    /// `r_hint` is parallel to it.
    pub fn new(origin: DVec3, t: DVec3, r_hint: DVec3) -> Option<Self> {
        let t = t.try_normalize()?;
        let r = (r_hint - t * t.dot(r_hint)).try_normalize()?;
        Some(Self {
            origin,
            tangent: t,
            r,
            s: t.cross(r),
        })
    }

    /// Maps local coordinates `(x along r, y along s, z along tangent)` to
    /// world space.
    pub fn to_world(&self, local: DVec3) -> DVec3 {
        self.origin + self.r * local.x + self.s * local.y + self.tangent * local.z
    }

    /// Maps a world point to local coordinates (inverse of [`Self::to_world`]).
    pub fn to_local(&self, p: DVec3) -> DVec3 {
        let d = p - self.origin;
        DVec3::new(d.dot(self.r), d.dot(self.s), d.dot(self.tangent))
    }
}

/// Below this squared length a reflection vector is rounding noise: its
/// direction is arbitrary, and reflecting about it would flip a random
/// component of the frame (the step is then skipped; the final projection
/// absorbs the difference, at most ~1e-12).
const NOISE2: f64 = 1e-24;

/// One double-reflection step from `prev` to the point `x1` with unit
/// tangent `t1`. Coincident points keep the previous reference (projected).
pub fn rmf_step(prev: &Frame, x1: DVec3, t1: DVec3) -> Frame {
    let v1 = x1 - prev.origin;
    let c1 = v1.dot(v1);
    let (r_l, t_l) = if c1 > NOISE2 {
        (
            prev.r - v1 * (2.0 / c1 * v1.dot(prev.r)),
            prev.tangent - v1 * (2.0 / c1 * v1.dot(prev.tangent)),
        )
    } else {
        (prev.r, prev.tangent)
    };
    let v2 = t1 - t_l;
    let c2 = v2.dot(v2);
    let r1 = if c2 > NOISE2 {
        r_l - v2 * (2.0 / c2 * v2.dot(r_l))
    } else {
        r_l
    };
    // Re-orthonormalize against rounding drift.
    let r1 = (r1 - t1 * t1.dot(r1)).normalize_or(prev.r);
    Frame {
        origin: x1,
        tangent: t1,
        r: r1,
        s: t1.cross(r1),
    }
}

/// Rotation-minimizing frames at `points` with unit `tangents`, starting
/// from `first` (whose origin and tangent should be `points[0]`,
/// `tangents[0]`).
pub fn double_reflection(first: Frame, points: &[DVec3], tangents: &[DVec3]) -> Vec<Frame> {
    let mut out = Vec::with_capacity(points.len());
    out.push(first);
    for i in 1..points.len().min(tangents.len()) {
        let f = rmf_step(&out[i - 1], points[i], tangents[i]);
        out.push(f);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::fm::DetMath as _;

    #[test]
    fn helix_frames_are_orthonormal_and_rotation_minimizing() {
        // On a helix the RMF rotates relative to the Frenet frame at the rate
        // of the torsion; check orthonormality and that r' has no component
        // along s (the defining property of an RMF), by finite differences.
        let n = 2000;
        let (a, b) = (1.0, 0.3);
        let pt = |t: f64| DVec3::new(a * t.fcos(), a * t.fsin(), b * t);
        let tg = |t: f64| DVec3::new(-a * t.fsin(), a * t.fcos(), b).normalize();
        let ts: Vec<f64> = (0..=n).map(|i| 6.0 * i as f64 / n as f64).collect();
        let pts: Vec<DVec3> = ts.iter().map(|t| pt(*t)).collect();
        let tgs: Vec<DVec3> = ts.iter().map(|t| tg(*t)).collect();
        let f0 = Frame::new(pts[0], tgs[0], DVec3::X).unwrap();
        let frames = double_reflection(f0, &pts, &tgs);
        for w in frames.windows(2) {
            let f = &w[0];
            assert!((f.r.length() - 1.0).abs() < 1e-12);
            assert!(f.r.dot(f.tangent).abs() < 1e-12);
            // Midpoint rule: r' . s = 0 up to O(h^3).
            let dr = w[1].r - w[0].r;
            let s_mid = (w[0].s + w[1].s) * 0.5;
            assert!(dr.dot(s_mid).abs() < 1e-8, "{}", dr.dot(s_mid));
        }
    }

    /// A step to the same point with the same tangent, re-normalized (so it
    /// differs in the last bits), must not move the frame: the difference
    /// vector is rounding noise and reflecting about it flipped `r` by up to
    /// 0.04 (found by the GC rigid-motion volume test).
    #[test]
    fn noise_step_keeps_the_frame() {
        let mut worst = 0.0f64;
        let mut noisy = 0;
        for k in 0..200 {
            let a = k as f64 * 0.137;
            let d = DVec3::new(a.fcos(), (1.3 * a).fsin(), 0.7 + 0.1 * a.fsin());
            let t = d.normalize();
            let f = Frame::new(DVec3::new(1.0, 2.0, 3.0), t, DVec3::new(0.3, 1.0, -0.2))
                .expect("frame");
            noisy += usize::from(f.tangent != t);
            let g = rmf_step(&f, f.origin, t);
            worst = worst.max(g.r.distance(f.r)).max(g.s.distance(f.s));
        }
        assert!(noisy > 0, "no case had a re-normalization difference");
        assert!(worst < 1e-12, "frame moved by {worst}");
    }

    #[test]
    fn planar_curve_keeps_the_plane_normal() {
        let pts: Vec<DVec3> = (0..100)
            .map(|i| {
                let t = i as f64 * 0.05;
                DVec3::new(t, t.fsin(), 0.0)
            })
            .collect();
        let tgs: Vec<DVec3> = (0..100)
            .map(|i| DVec3::new(1.0, (i as f64 * 0.05).fcos(), 0.0).normalize())
            .collect();
        let f0 = Frame::new(pts[0], tgs[0], DVec3::Z).unwrap();
        for f in double_reflection(f0, &pts, &tgs) {
            assert!((f.r - DVec3::Z).length() < 1e-12);
        }
    }
}
