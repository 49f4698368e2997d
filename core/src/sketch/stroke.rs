//! Stroke preprocessing: projection onto the sketch plane, arc-length
//! resampling and Ramer-Douglas-Peucker simplification.

use glam::{DVec2, DVec3};

use super::SketchError;

/// A sketch plane: a point and a unit normal, with an in-plane basis.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SketchPlane {
    /// A point of the plane (the 2D origin).
    pub origin: DVec3,
    /// Unit normal.
    pub normal: DVec3,
    /// In-plane x axis.
    pub x: DVec3,
    /// In-plane y axis (`normal x x`).
    pub y: DVec3,
}

impl SketchPlane {
    /// The plane through `origin` with normal `normal`; the x axis is the
    /// projection of `x_hint` (or any perpendicular when it is parallel).
    pub fn new(origin: DVec3, normal: DVec3, x_hint: DVec3) -> Result<Self, SketchError> {
        if !origin.is_finite() || !x_hint.is_finite() {
            return Err(SketchError::BadPlane);
        }
        let n = normal
            .try_normalize()
            .filter(|n| n.is_finite())
            .ok_or(SketchError::BadPlane)?;
        let x = (x_hint - n * n.dot(x_hint))
            .try_normalize()
            .unwrap_or_else(|| n.any_orthonormal_vector());
        Ok(Self {
            origin,
            normal: n,
            x,
            y: n.cross(x),
        })
    }

    /// 2D coordinates of the orthogonal projection of `p`.
    pub fn project(&self, p: DVec3) -> DVec2 {
        let d = p - self.origin;
        DVec2::new(d.dot(self.x), d.dot(self.y))
    }

    /// The 3D point of plane coordinates `q`.
    pub fn lift(&self, q: DVec2) -> DVec3 {
        self.origin + self.x * q.x + self.y * q.y
    }
}

/// Projects a stroke onto the plane, rejecting non-finite points and
/// dropping consecutive repeats.
pub fn project_stroke(points: &[DVec3], plane: &SketchPlane) -> Result<Vec<DVec2>, SketchError> {
    if let Some(i) = points.iter().position(|p| !p.is_finite()) {
        return Err(SketchError::NonFinite(i));
    }
    let mut out: Vec<DVec2> = Vec::with_capacity(points.len());
    for p in points {
        let q = plane.project(*p);
        if out.last() != Some(&q) {
            out.push(q);
        }
    }
    Ok(out)
}

/// Total length of a polyline (closed: including the closing segment).
pub fn length(points: &[DVec2], closed: bool) -> f64 {
    let mut l: f64 = points.windows(2).map(|w| (w[1] - w[0]).length()).sum();
    if closed && points.len() > 1 {
        l += (points[0] - points[points.len() - 1]).length();
    }
    l
}

/// `n` points equally spaced by arc length (open: first and last kept;
/// closed: starting at the first point, the closing segment included).
pub fn resample(points: &[DVec2], n: usize, closed: bool) -> Result<Vec<DVec2>, SketchError> {
    if points.len() < 2 {
        return Err(SketchError::TooFewPoints {
            got: points.len(),
            need: 2,
        });
    }
    if n < 2 {
        return Err(SketchError::BadParameter {
            what: "sample count",
            value: n as f64,
        });
    }
    let mut pts = points.to_vec();
    if closed {
        pts.push(points[0]);
    }
    let total = length(&pts, false);
    if !(total > 0.0) {
        return Err(SketchError::ZeroLength);
    }
    let segs = if closed { n } else { n - 1 };
    let step = total / segs as f64;
    let mut out = Vec::with_capacity(n);
    let mut seg = 0;
    let mut acc = 0.0; // arc length at pts[seg]
    for k in 0..n {
        let target = k as f64 * step;
        while seg + 2 < pts.len() && acc + (pts[seg + 1] - pts[seg]).length() < target {
            acc += (pts[seg + 1] - pts[seg]).length();
            seg += 1;
        }
        let d = (pts[seg + 1] - pts[seg]).length();
        let f = if d > 0.0 {
            ((target - acc) / d).clamp(0.0, 1.0)
        } else {
            0.0
        };
        out.push(pts[seg] + (pts[seg + 1] - pts[seg]) * f);
    }
    if !closed {
        out[n - 1] = points[points.len() - 1];
    }
    Ok(out)
}

fn seg_dist(p: DVec2, a: DVec2, b: DVec2) -> f64 {
    let ab = b - a;
    let l2 = ab.length_squared();
    let t = if l2 > 0.0 {
        ((p - a).dot(ab) / l2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (a + ab * t - p).length()
}

/// Ramer-Douglas-Peucker simplification of an open polyline: keeps the end
/// points and every point farther than `eps` from the simplified chord.
pub fn rdp(points: &[DVec2], eps: f64) -> Vec<DVec2> {
    if points.len() < 3 {
        return points.to_vec();
    }
    let mut keep = vec![false; points.len()];
    keep[0] = true;
    keep[points.len() - 1] = true;
    let mut stack = vec![(0usize, points.len() - 1)];
    while let Some((a, b)) = stack.pop() {
        let mut best = (0.0, 0usize);
        for i in a + 1..b {
            let d = seg_dist(points[i], points[a], points[b]);
            if d > best.0 {
                best = (d, i);
            }
        }
        if best.0 > eps {
            keep[best.1] = true;
            stack.push((a, best.1));
            stack.push((best.1, b));
        }
    }
    points
        .iter()
        .zip(keep)
        .filter(|(_, k)| *k)
        .map(|(p, _)| *p)
        .collect()
}

/// RDP for a closed loop: split at the point farthest from the first, so
/// the corners of a polygon survive whatever point the stroke started at.
/// Returns the kept vertices without repeating the first.
pub fn rdp_closed(points: &[DVec2], eps: f64) -> Vec<DVec2> {
    if points.len() < 4 {
        return points.to_vec();
    }
    let far = (1..points.len())
        .max_by(|&i, &j| {
            (points[i] - points[0])
                .length_squared()
                .total_cmp(&(points[j] - points[0]).length_squared())
        })
        .unwrap_or(1);
    let mut first: Vec<DVec2> = points[..=far].to_vec();
    let mut second: Vec<DVec2> = points[far..].to_vec();
    second.push(points[0]);
    first = rdp(&first, eps);
    second = rdp(&second, eps);
    first.pop();
    second.pop();
    first.extend(second);
    // RDP splits a straight side at its noisiest point when that point is
    // the farthest from the chord (and the loop's start point may lie
    // mid-side): drop every vertex within eps of its neighbours' chord.
    loop {
        let n = first.len();
        if n <= 3 {
            break;
        }
        let flat =
            (0..n).find(|&i| seg_dist(first[i], first[(i + n - 1) % n], first[(i + 1) % n]) <= eps);
        match flat {
            Some(i) => {
                first.remove(i);
            }
            None => break,
        }
    }
    first
}

/// True when two non-adjacent segments of the closed loop cross.
pub fn closed_loop_self_intersects(points: &[DVec2]) -> bool {
    let p: Vec<[f64; 2]> = points.iter().map(|q| [q.x, q.y]).collect();
    crate::gc::loop_self_intersects(&p)
}
