//! Section template matching (§3.3 "matched to templates"): a closed
//! stroke in its plane is compared with a circle, an ellipse, a rectangle
//! and a regular polygon (corner count from RDP), each fitted to the
//! stroke (center = area centroid, axes = principal axes of the second
//! moments, sizes from extents or mean distances). The similarity score
//! is `1 - rms / r`, where `rms` is the root-mean-square distance from the
//! resampled stroke to the fitted outline and `r` the stroke's mean
//! radius: 1 for a perfect fit, 0 at an error as large as the shape.

use crate::math::fm::DetMath as _;
use glam::{DMat2, DVec2, DVec3};

use super::stroke::{closed_loop_self_intersects, length, rdp_closed, resample};
use super::SketchError;
use crate::gc::Profile;

/// Samples the stroke is resampled to before matching.
pub const MATCH_SAMPLES: usize = 96;

/// The most sides a matched regular polygon has.
pub const MAX_POLYGON_SIDES: usize = 8;

/// The result of matching a closed stroke.
#[derive(Clone, Debug, PartialEq)]
pub struct SectionMatch {
    /// The best template, centered at the origin, unrotated.
    pub profile: Profile,
    /// Its similarity score in `[0, 1]`.
    pub score: f64,
    /// Where the template's center lies in the sketch plane.
    pub center: DVec2,
    /// Rotation of the template in the plane (radians), e.g. for a twist.
    pub rotation: f64,
    /// Every candidate's name and score, best first.
    pub candidates: Vec<(&'static str, f64)>,
    /// The stroke itself as a `Points` profile (centered, counter-clockwise,
    /// simplified), for when no template fits well enough.
    pub sketch: Profile,
}

fn outline(profile: &Profile, center: DVec2, rot: f64) -> Option<Vec<DVec2>> {
    let c = profile.curve().ok()?;
    let m = DMat2::from_angle(rot);
    Some(
        (0..256)
            .map(|i| {
                let p = c.point(i as f64 / 256.0);
                center + m * DVec2::new(p.x, p.y)
            })
            .collect(),
    )
}

fn rms_to(points: &[DVec2], poly: &[DVec2]) -> f64 {
    let n = poly.len();
    let s: f64 = points
        .iter()
        .map(|p| {
            (0..n)
                .map(|i| {
                    let (a, b) = (poly[i], poly[(i + 1) % n]);
                    let ab = b - a;
                    let t = ((*p - a).dot(ab) / ab.length_squared().max(1e-300)).clamp(0.0, 1.0);
                    (a + ab * t - *p).length_squared()
                })
                .fold(f64::INFINITY, f64::min)
        })
        .sum();
    (s / points.len() as f64).sqrt()
}

/// Matches a closed stroke (2D points in its sketch plane, the first
/// point not repeated) against the section templates.
pub fn match_section(points: &[DVec2]) -> Result<SectionMatch, SketchError> {
    if let Some(i) = points.iter().position(|p| !p.is_finite()) {
        return Err(SketchError::NonFinite(i));
    }
    let mut distinct: Vec<DVec2> = Vec::with_capacity(points.len());
    for p in points {
        if distinct.last() != Some(p) {
            distinct.push(*p);
        }
    }
    if distinct.len() > 1 && distinct[0] == distinct[distinct.len() - 1] {
        distinct.pop();
    }
    if distinct.len() < 3 {
        return Err(SketchError::TooFewPoints {
            got: distinct.len(),
            need: 3,
        });
    }
    let total = length(&distinct, true);
    if !(total > 0.0) {
        return Err(SketchError::ZeroLength);
    }
    let mut pts = resample(&distinct, MATCH_SAMPLES, true)?;
    if closed_loop_self_intersects(&pts) {
        return Err(SketchError::SelfIntersecting);
    }
    let n = pts.len();
    // Area and area centroid (shoelace).
    let (mut a2, mut cx, mut cy) = (0.0, 0.0, 0.0);
    for i in 0..n {
        let (p, q) = (pts[i], pts[(i + 1) % n]);
        let cr = p.x * q.y - q.x * p.y;
        a2 += cr;
        cx += (p.x + q.x) * cr;
        cy += (p.y + q.y) * cr;
    }
    if !(a2.abs() > 1e-9 * total * total) {
        return Err(SketchError::ZeroLength);
    }
    if a2 < 0.0 {
        pts[1..].reverse();
    }
    let center = DVec2::new(cx, cy) / (3.0 * a2);
    // Principal axes of the samples.
    let (mut sxx, mut sxy, mut syy) = (0.0, 0.0, 0.0);
    for p in &pts {
        let d = *p - center;
        sxx += d.x * d.x;
        sxy += d.x * d.y;
        syy += d.y * d.y;
    }
    let phi = 0.5 * (2.0 * sxy).fatan2(sxx - syy);
    let (e1, e2) = (
        DVec2::new(phi.fcos(), phi.fsin()),
        DVec2::new(-phi.fsin(), phi.fcos()),
    );
    let ext1 = pts
        .iter()
        .map(|p| (*p - center).dot(e1).abs())
        .fold(0.0, f64::max);
    let ext2 = pts
        .iter()
        .map(|p| (*p - center).dot(e2).abs())
        .fold(0.0, f64::max);
    let r_mean = pts.iter().map(|p| (*p - center).length()).sum::<f64>() / n as f64;
    let mut cands: Vec<(&'static str, Profile, f64)> = vec![
        ("circle", Profile::Circle { radius: r_mean }, 0.0),
        ("ellipse", Profile::Ellipse { rx: ext1, ry: ext2 }, phi),
        (
            "rectangle",
            Profile::Rectangle {
                width: 2.0 * ext1,
                height: 2.0 * ext2,
            },
            phi,
        ),
    ];
    // Polygons up to 8 sides: beyond that a regular polygon is within a
    // few percent of its circle, and a noisy hand-drawn circle simplifies
    // to 9 to 12 corners often enough to win by noise alone.
    let corners = rdp_closed(&pts, 0.1 * r_mean);
    if (3..=MAX_POLYGON_SIDES).contains(&corners.len()) {
        let radius =
            corners.iter().map(|c| (*c - center).length()).sum::<f64>() / corners.len() as f64;
        // Rotation: the circular mean of the corner angles modulo 2π/n.
        let k = corners.len() as f64;
        let (mut sn, mut cs) = (0.0, 0.0);
        for c in &corners {
            let d = *c - center;
            let a = d.y.fatan2(d.x) * k;
            sn += a.fsin();
            cs += a.fcos();
        }
        cands.push((
            "polygon",
            Profile::Polygon {
                sides: corners.len() as u32,
                radius,
            },
            sn.fatan2(cs) / k,
        ));
    }
    let mut scored: Vec<(&'static str, Profile, f64, f64)> = cands
        .into_iter()
        .filter_map(|(name, prof, rot)| {
            let o = outline(&prof, center, rot)?;
            let score = (1.0 - rms_to(&pts, &o) / r_mean).clamp(0.0, 1.0);
            Some((name, prof, rot, score))
        })
        .collect();
    // Best first; on a tie the simpler template (earlier in the list) wins.
    scored.sort_by(|a, b| b.3.total_cmp(&a.3));
    let best = scored.first().cloned().ok_or(SketchError::ZeroLength)?;
    let simplified = rdp_closed(&pts, 0.01 * r_mean);
    let sketch = Profile::Points {
        points: simplified
            .iter()
            .map(|p| [p.x - center.x, p.y - center.y])
            .collect(),
    };
    Ok(SectionMatch {
        profile: best.1,
        score: best.3,
        center,
        rotation: best.2,
        candidates: scored.iter().map(|s| (s.0, s.3)).collect(),
        sketch,
    })
}

/// A section as it was drawn: a profile in its sketch plane's `(x, y)`
/// coordinates, turned by `rotation` (radians) in that plane.
#[derive(Clone, Debug, PartialEq)]
pub struct DrawnSection {
    /// The profile, unturned (a template centered at the origin, or the
    /// drawn loop in the plane's coordinates).
    pub profile: Profile,
    /// The template's turn in the sketch plane (0 for a drawn loop).
    pub rotation: f64,
}

impl SectionMatch {
    /// The section a user drew: the best template, turned as it was
    /// drawn, when its score reaches `min_score`; else the drawn loop.
    pub fn drawn(&self, min_score: f64) -> DrawnSection {
        if self.score >= min_score {
            DrawnSection {
                profile: self.profile.clone(),
                rotation: self.rotation,
            }
        } else {
            DrawnSection {
                profile: self.sketch.clone(),
                rotation: 0.0,
            }
        }
    }
}

impl DrawnSection {
    /// The section as a key section of a frame whose local `x` and `y`
    /// axes are the world directions `r` and `s` (a GC's section frame),
    /// the section drawn in `plane`: a template and the twist that turns
    /// it as it was drawn (the direction of its local `x` axis, projected
    /// into the frame; templates are symmetric about that axis, so a
    /// plane facing the other way changes nothing), or the drawn loop
    /// mapped into the frame point by point (twist 0). A circle has no
    /// turn to keep: twist 0.
    pub fn in_frame(&self, plane: &super::SketchPlane, r: DVec3, s: DVec3) -> (Profile, f64) {
        let to_frame = |w: DVec3| DVec2::new(w.dot(r), w.dot(s));
        match &self.profile {
            Profile::Circle { .. } => (self.profile.clone(), 0.0),
            Profile::Points { points } => (
                Profile::Points {
                    points: points
                        .iter()
                        .map(|p| {
                            let q = to_frame(plane.x * p[0] + plane.y * p[1]);
                            [q.x, q.y]
                        })
                        .collect(),
                },
                0.0,
            ),
            other => {
                let axis = plane.x * self.rotation.fcos() + plane.y * self.rotation.fsin();
                let a = to_frame(axis);
                let twist = if a.length() > 1e-12 {
                    a.y.fatan2(a.x)
                } else {
                    0.0
                };
                (other.clone(), twist)
            }
        }
    }
}

/// [`match_section`] for a 3D stroke projected onto `plane`.
pub fn match_section_stroke(
    points: &[DVec3],
    plane: &super::SketchPlane,
) -> Result<SectionMatch, SketchError> {
    let p2 = super::project_stroke(points, plane)?;
    match_section(&p2)
}
