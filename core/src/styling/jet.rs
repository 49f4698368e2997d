//! Second-order jets in two variables: a value with its gradient and
//! Hessian, carried through arithmetic by the product and chain rules.
//!
//! The multi-sided patches ([`super::ngon`]) are rational blends of curve
//! evaluations over a polygon; their thin-plate energy needs exact second
//! derivatives in the domain coordinates `(x, y)`. Forward-mode jets give
//! them without finite differences (whose error would leak into the energy
//! matrix) and without hand-expanded formulas for every term.

use std::ops::{Add, Mul, Sub};

use crate::math::DVec3;

/// A scalar `f(x, y)` with `f_x, f_y, f_xx, f_xy, f_yy` at one point.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Jet {
    /// Value.
    pub v: f64,
    /// `∂f/∂x`.
    pub x: f64,
    /// `∂f/∂y`.
    pub y: f64,
    /// `∂²f/∂x²`.
    pub xx: f64,
    /// `∂²f/∂x∂y`.
    pub xy: f64,
    /// `∂²f/∂y²`.
    pub yy: f64,
}

impl Jet {
    /// A constant.
    pub const fn constant(v: f64) -> Self {
        Self {
            v,
            x: 0.0,
            y: 0.0,
            xx: 0.0,
            xy: 0.0,
            yy: 0.0,
        }
    }

    /// The affine function `a x + b y + c` (at any point: its derivatives
    /// do not depend on it), valued `v` here.
    pub const fn affine(v: f64, a: f64, b: f64) -> Self {
        Self {
            v,
            x: a,
            y: b,
            xx: 0.0,
            xy: 0.0,
            yy: 0.0,
        }
    }

    /// `1 / self` (the caller keeps `self.v` away from zero).
    pub fn recip(self) -> Self {
        let r = 1.0 / self.v;
        let r2 = r * r;
        let r3 = r2 * r;
        Self {
            v: r,
            x: -self.x * r2,
            y: -self.y * r2,
            xx: 2.0 * self.x * self.x * r3 - self.xx * r2,
            xy: 2.0 * self.x * self.y * r3 - self.xy * r2,
            yy: 2.0 * self.y * self.y * r3 - self.yy * r2,
        }
    }

    /// `f(self)` for a scalar function with `f, f', f''` at `self.v`.
    pub fn compose(self, f: f64, f1: f64, f2: f64) -> Self {
        Self {
            v: f,
            x: f1 * self.x,
            y: f1 * self.y,
            xx: f2 * self.x * self.x + f1 * self.xx,
            xy: f2 * self.x * self.y + f1 * self.xy,
            yy: f2 * self.y * self.y + f1 * self.yy,
        }
    }

    /// `g(self)` for a curve `g` with `g, g', g''` at `self.v`.
    pub fn compose_curve(self, g: [DVec3; 3]) -> VJet {
        VJet {
            v: g[0],
            x: g[1] * self.x,
            y: g[1] * self.y,
            xx: g[2] * (self.x * self.x) + g[1] * self.xx,
            xy: g[2] * (self.x * self.y) + g[1] * self.xy,
            yy: g[2] * (self.y * self.y) + g[1] * self.yy,
        }
    }
}

impl Add for Jet {
    type Output = Jet;
    fn add(self, o: Jet) -> Jet {
        Jet {
            v: self.v + o.v,
            x: self.x + o.x,
            y: self.y + o.y,
            xx: self.xx + o.xx,
            xy: self.xy + o.xy,
            yy: self.yy + o.yy,
        }
    }
}

impl Sub for Jet {
    type Output = Jet;
    fn sub(self, o: Jet) -> Jet {
        Jet {
            v: self.v - o.v,
            x: self.x - o.x,
            y: self.y - o.y,
            xx: self.xx - o.xx,
            xy: self.xy - o.xy,
            yy: self.yy - o.yy,
        }
    }
}

impl Mul for Jet {
    type Output = Jet;
    fn mul(self, o: Jet) -> Jet {
        Jet {
            v: self.v * o.v,
            x: self.x * o.v + self.v * o.x,
            y: self.y * o.v + self.v * o.y,
            xx: self.xx * o.v + 2.0 * self.x * o.x + self.v * o.xx,
            xy: self.xy * o.v + self.x * o.y + self.y * o.x + self.v * o.xy,
            yy: self.yy * o.v + 2.0 * self.y * o.y + self.v * o.yy,
        }
    }
}

/// A point-valued `S(x, y)` with its first and second partial derivatives.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct VJet {
    /// Value.
    pub v: DVec3,
    /// `∂S/∂x`.
    pub x: DVec3,
    /// `∂S/∂y`.
    pub y: DVec3,
    /// `∂²S/∂x²`.
    pub xx: DVec3,
    /// `∂²S/∂x∂y`.
    pub xy: DVec3,
    /// `∂²S/∂y²`.
    pub yy: DVec3,
}

impl VJet {
    /// A constant point.
    pub const fn constant(v: DVec3) -> Self {
        Self {
            v,
            x: DVec3::ZERO,
            y: DVec3::ZERO,
            xx: DVec3::ZERO,
            xy: DVec3::ZERO,
            yy: DVec3::ZERO,
        }
    }

    /// `s * self` for a scalar jet `s`.
    pub fn scale(self, s: Jet) -> Self {
        Self {
            v: self.v * s.v,
            x: self.x * s.v + self.v * s.x,
            y: self.y * s.v + self.v * s.y,
            xx: self.xx * s.v + self.x * (2.0 * s.x) + self.v * s.xx,
            xy: self.xy * s.v + self.x * s.y + self.y * s.x + self.v * s.xy,
            yy: self.yy * s.v + self.y * (2.0 * s.y) + self.v * s.yy,
        }
    }

    /// `[S, S_x, S_y, S_xx, S_xy, S_yy]`, the layout of
    /// [`super::surface::BaseDerivs`].
    pub fn to_array(self) -> [DVec3; 6] {
        [self.v, self.x, self.y, self.xx, self.xy, self.yy]
    }
}

impl Add for VJet {
    type Output = VJet;
    fn add(self, o: VJet) -> VJet {
        VJet {
            v: self.v + o.v,
            x: self.x + o.x,
            y: self.y + o.y,
            xx: self.xx + o.xx,
            xy: self.xy + o.xy,
            yy: self.yy + o.yy,
        }
    }
}

impl Sub for VJet {
    type Output = VJet;
    fn sub(self, o: VJet) -> VJet {
        VJet {
            v: self.v - o.v,
            x: self.x - o.x,
            y: self.y - o.y,
            xx: self.xx - o.xx,
            xy: self.xy - o.xy,
            yy: self.yy - o.yy,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::fm::DetMath as _;

    /// Central differences of a scalar function of `(x, y)`.
    fn fd(f: impl Fn(f64, f64) -> f64, x: f64, y: f64) -> [f64; 5] {
        let h = 1e-4;
        [
            (f(x + h, y) - f(x - h, y)) / (2.0 * h),
            (f(x, y + h) - f(x, y - h)) / (2.0 * h),
            (f(x + h, y) - 2.0 * f(x, y) + f(x - h, y)) / (h * h),
            (f(x + h, y + h) - f(x + h, y - h) - f(x - h, y + h) + f(x - h, y - h)) / (4.0 * h * h),
            (f(x, y + h) - 2.0 * f(x, y) + f(x, y - h)) / (h * h),
        ]
    }

    #[test]
    fn products_quotients_and_compositions_match_differences() {
        let at = |x: f64, y: f64| {
            let a = Jet::affine(0.3 * x - 0.7 * y + 1.1, 0.3, -0.7);
            let b = Jet::affine(0.9 * x + 0.2 * y + 0.4, 0.9, 0.2);
            let s = (a * a * b) * (a + b).recip();
            let t = s.v;
            s.compose(t.fsin(), t.fcos(), -t.fsin())
        };
        let f = |x: f64, y: f64| at(x, y).v;
        for (x, y) in [(0.2, 0.3), (0.7, -0.4), (1.3, 0.9)] {
            let j = at(x, y);
            let d = fd(f, x, y);
            let got = [j.x, j.y, j.xx, j.xy, j.yy];
            for (g, w) in got.iter().zip(d) {
                assert!((g - w).abs() < 1e-6 * (1.0 + w.abs()), "{got:?} vs {d:?}");
            }
        }
    }

    #[test]
    fn vector_jets_follow_the_product_rule() {
        let at = |x: f64, y: f64| {
            let s = Jet::affine(x, 1.0, 0.0)
                * Jet::affine(y, 0.0, 1.0)
                * Jet::affine(x + 2.0 * y, 1.0, 2.0);
            let g = |t: f64| {
                [
                    DVec3::new(t * t, t.fsin(), 1.0 / (1.0 + t)),
                    DVec3::new(2.0 * t, t.fcos(), -1.0 / ((1.0 + t) * (1.0 + t))),
                    DVec3::new(2.0, -t.fsin(), 2.0 / ((1.0 + t) * (1.0 + t) * (1.0 + t))),
                ]
            };
            s.compose_curve(g(s.v))
                .scale(Jet::affine(3.0 * x - y, 3.0, -1.0))
        };
        for (x, y) in [(0.2, 0.3), (0.5, 0.1)] {
            let j = at(x, y);
            for axis in 0..3 {
                let f = |x: f64, y: f64| at(x, y).v[axis];
                let d = fd(f, x, y);
                let got = [j.x[axis], j.y[axis], j.xx[axis], j.xy[axis], j.yy[axis]];
                for (g, w) in got.iter().zip(d) {
                    assert!((g - w).abs() < 1e-6 * (1.0 + w.abs()), "{got:?} vs {d:?}");
                }
            }
        }
    }
}
