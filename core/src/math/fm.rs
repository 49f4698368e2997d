//! Deterministic float math: the same bits on every platform (issue 32).
//!
//! The op log promises bit-identical replay, and exported files and content
//! hashes are compared byte for byte across hosts. `f64::sin`, `ln`,
//! `powf` and the other transcendental methods of `std` call the platform's
//! C library (glibc on Linux, mingw/msvcrt on Windows, the system libm on
//! macOS and Android), and those libraries round differently in the last
//! ulp: a Windows replay of a trace used to differ from the Linux one in
//! the last bits of its geometry.
//!
//! [`DetMath`] gives every such function a twin with an `f` prefix
//! (`x.fsin()`, `y.fatan2(x)`, `f64::fcos`) computed by the pure-Rust
//! [`libm`] crate (a port of musl's), compiled into the binary and so the
//! same on every target. `powi` is here too ([`DetMath::fpowi`]): std's
//! lowers to `llvm.powi`, whose result the Rust docs leave unspecified
//! across platforms and versions (compiler-rt's and libgcc's `__powidf2`
//! agree today, and constant operands are folded with the build host's
//! `pow`); ours is the same repeated squaring, written out.
//!
//! The workspace's `clippy.toml` disallows the `std` methods, so a new call
//! fails `cargo clippy -- -D warnings`; `scripts/dev/det_math.py` rewrites
//! call sites mechanically. `sqrt`, `mul_add`, `abs`, `floor` and the
//! arithmetic operators are exactly rounded by IEEE 754 and stay as they are.

/// Transcendental functions that give the same bits on every platform.
///
/// Each method is the `std` method of the same name without the `f`, with
/// the same arguments; see the [module docs](self) for why.
pub trait DetMath: Copy {
    /// `sin` (radians).
    fn fsin(self) -> Self;
    /// `cos` (radians).
    fn fcos(self) -> Self;
    /// `tan` (radians).
    fn ftan(self) -> Self;
    /// `(sin, cos)` (radians).
    fn fsin_cos(self) -> (Self, Self);
    /// `asin`, in `[-π/2, π/2]`.
    fn fasin(self) -> Self;
    /// `acos`, in `[0, π]`.
    fn facos(self) -> Self;
    /// `atan`, in `[-π/2, π/2]`.
    fn fatan(self) -> Self;
    /// `atan2(self, other)`: the angle of `(other, self)`, in `[-π, π]`.
    fn fatan2(self, other: Self) -> Self;
    /// `sinh`.
    fn fsinh(self) -> Self;
    /// `cosh`.
    fn fcosh(self) -> Self;
    /// `tanh`.
    fn ftanh(self) -> Self;
    /// `asinh`.
    fn fasinh(self) -> Self;
    /// `acosh`.
    fn facosh(self) -> Self;
    /// `atanh`.
    fn fatanh(self) -> Self;
    /// `e^self`.
    fn fexp(self) -> Self;
    /// `2^self`.
    fn fexp2(self) -> Self;
    /// `e^self - 1`, accurate near zero.
    fn fexp_m1(self) -> Self;
    /// Natural logarithm.
    fn fln(self) -> Self;
    /// `ln(1 + self)`, accurate near zero.
    fn fln_1p(self) -> Self;
    /// Base-2 logarithm.
    fn flog2(self) -> Self;
    /// Base-10 logarithm.
    fn flog10(self) -> Self;
    /// Logarithm in `base` (`ln(self) / ln(base)`, as std computes it).
    fn flog(self, base: Self) -> Self;
    /// `self^n`.
    fn fpowf(self, n: Self) -> Self;
    /// `self^n` by repeated squaring (compiler-rt's `__powidf2` order).
    fn fpowi(self, n: i32) -> Self;
    /// Cube root.
    fn fcbrt(self) -> Self;
    /// `sqrt(self² + other²)` without undue overflow.
    fn fhypot(self, other: Self) -> Self;
}

macro_rules! det_math {
    ($t:ty, $sin:ident, $cos:ident, $tan:ident, $sincos:ident, $asin:ident, $acos:ident,
     $atan:ident, $atan2:ident, $sinh:ident, $cosh:ident, $tanh:ident, $asinh:ident,
     $acosh:ident, $atanh:ident, $exp:ident, $exp2:ident, $expm1:ident, $log:ident,
     $log1p:ident, $log2:ident, $log10:ident, $pow:ident, $cbrt:ident, $hypot:ident) => {
        impl DetMath for $t {
            #[inline]
            fn fsin(self) -> Self {
                libm::$sin(self)
            }
            #[inline]
            fn fcos(self) -> Self {
                libm::$cos(self)
            }
            #[inline]
            fn ftan(self) -> Self {
                libm::$tan(self)
            }
            #[inline]
            fn fsin_cos(self) -> (Self, Self) {
                libm::$sincos(self)
            }
            #[inline]
            fn fasin(self) -> Self {
                libm::$asin(self)
            }
            #[inline]
            fn facos(self) -> Self {
                libm::$acos(self)
            }
            #[inline]
            fn fatan(self) -> Self {
                libm::$atan(self)
            }
            #[inline]
            fn fatan2(self, other: Self) -> Self {
                libm::$atan2(self, other)
            }
            #[inline]
            fn fsinh(self) -> Self {
                libm::$sinh(self)
            }
            #[inline]
            fn fcosh(self) -> Self {
                libm::$cosh(self)
            }
            #[inline]
            fn ftanh(self) -> Self {
                libm::$tanh(self)
            }
            #[inline]
            fn fasinh(self) -> Self {
                libm::$asinh(self)
            }
            #[inline]
            fn facosh(self) -> Self {
                libm::$acosh(self)
            }
            #[inline]
            fn fatanh(self) -> Self {
                libm::$atanh(self)
            }
            #[inline]
            fn fexp(self) -> Self {
                libm::$exp(self)
            }
            #[inline]
            fn fexp2(self) -> Self {
                libm::$exp2(self)
            }
            #[inline]
            fn fexp_m1(self) -> Self {
                libm::$expm1(self)
            }
            #[inline]
            fn fln(self) -> Self {
                libm::$log(self)
            }
            #[inline]
            fn fln_1p(self) -> Self {
                libm::$log1p(self)
            }
            #[inline]
            fn flog2(self) -> Self {
                libm::$log2(self)
            }
            #[inline]
            fn flog10(self) -> Self {
                libm::$log10(self)
            }
            #[inline]
            fn flog(self, base: Self) -> Self {
                libm::$log(self) / libm::$log(base)
            }
            #[inline]
            fn fpowf(self, n: Self) -> Self {
                libm::$pow(self, n)
            }
            #[inline]
            fn fpowi(self, n: i32) -> Self {
                let mut base = self;
                let mut e = n.unsigned_abs();
                let mut acc: $t = 1.0;
                loop {
                    if e & 1 == 1 {
                        acc *= base;
                    }
                    e >>= 1;
                    if e == 0 {
                        break;
                    }
                    base *= base;
                }
                if n < 0 {
                    1.0 / acc
                } else {
                    acc
                }
            }
            #[inline]
            fn fcbrt(self) -> Self {
                libm::$cbrt(self)
            }
            #[inline]
            fn fhypot(self, other: Self) -> Self {
                libm::$hypot(self, other)
            }
        }
    };
}

det_math!(
    f64, sin, cos, tan, sincos, asin, acos, atan, atan2, sinh, cosh, tanh, asinh, acosh, atanh,
    exp, exp2, expm1, log, log1p, log2, log10, pow, cbrt, hypot
);
det_math!(
    f32, sinf, cosf, tanf, sincosf, asinf, acosf, atanf, atan2f, sinhf, coshf, tanhf, asinhf,
    acoshf, atanhf, expf, exp2f, expm1f, logf, log1pf, log2f, log10f, powf, cbrtf, hypotf
);

#[cfg(test)]
mod tests {
    use super::DetMath;

    /// Inputs spread over the ranges the geometry uses (angles, lengths,
    /// weights), with a few hard cases for argument reduction.
    fn inputs() -> Vec<f64> {
        let mut v: Vec<f64> = (0..2000).map(|i| (i as f64 - 1000.0) * 0.01237).collect();
        v.extend([
            1e-300,
            1e-9,
            0.5,
            1.0,
            std::f64::consts::PI,
            1e6,
            1e22,
            710.0,
        ]);
        v
    }

    fn ulps(a: f64, b: f64) -> u64 {
        if a == b || (a.is_nan() && b.is_nan()) {
            return 0;
        }
        (a.to_bits() as i64).abs_diff(b.to_bits() as i64)
    }

    /// Each twin is the function it names: a swapped argument or a wrong
    /// libm entry point is off by far more than the 8 ulps allowed (musl's
    /// `atanh` is 4 ulps from glibc's at 0.6988...; the rest within 1-2).
    #[test]
    // The one place std's platform math is called on purpose: as the
    // reference the twins are checked against.
    #[allow(clippy::disallowed_methods)]
    fn twins_agree_with_std_within_a_few_ulps() {
        type Pair = (&'static str, fn(f64) -> f64, fn(f64) -> f64);
        let unary: [Pair; 21] = [
            ("sin", f64::fsin, f64::sin),
            ("cos", f64::fcos, f64::cos),
            ("tan", f64::ftan, f64::tan),
            ("sin_cos.0", |x| x.fsin_cos().0, |x| x.sin_cos().0),
            ("sin_cos.1", |x| x.fsin_cos().1, |x| x.sin_cos().1),
            ("asin", |x| (x * 0.05).fasin(), |x| (x * 0.05).asin()),
            ("acos", |x| (x * 0.05).facos(), |x| (x * 0.05).acos()),
            ("atan", f64::fatan, f64::atan),
            ("sinh", |x| (x * 0.1).fsinh(), |x| (x * 0.1).sinh()),
            ("cosh", |x| (x * 0.1).fcosh(), |x| (x * 0.1).cosh()),
            ("tanh", f64::ftanh, f64::tanh),
            ("asinh", f64::fasinh, f64::asinh),
            ("acosh", |x| x.abs().facosh(), |x| x.abs().acosh()),
            ("atanh", |x| (x * 0.05).fatanh(), |x| (x * 0.05).atanh()),
            ("exp", |x| (x * 0.1).fexp(), |x| (x * 0.1).exp()),
            ("exp2", |x| (x * 0.1).fexp2(), |x| (x * 0.1).exp2()),
            ("exp_m1", f64::fexp_m1, f64::exp_m1),
            ("ln", |x| x.abs().fln(), |x| x.abs().ln()),
            ("ln_1p", |x| x.abs().fln_1p(), |x| x.abs().ln_1p()),
            ("log2", |x| x.abs().flog2(), |x| x.abs().log2()),
            ("cbrt", f64::fcbrt, f64::cbrt),
        ];
        for x in inputs() {
            for (name, ours, std) in unary {
                let (a, b) = (ours(x), std(x));
                assert!(ulps(a, b) <= 8, "{name}({x}): {a} vs {b}");
            }
            let y = 0.7 - x * 0.3;
            let pairs = [
                ("log10", x.abs().flog10(), x.abs().log10()),
                ("log", x.abs().flog(3.0), x.abs().log(3.0)),
                ("atan2", x.fatan2(y), x.atan2(y)),
                ("hypot", x.fhypot(y), x.hypot(y)),
                ("powf", x.abs().fpowf(y * 0.1), x.abs().powf(y * 0.1)),
                ("powi", x.fpowi(7), x.powi(7)),
                ("powi-", x.fpowi(-3), x.powi(-3)),
            ];
            for (name, a, b) in pairs {
                assert!(ulps(a, b) <= 8, "{name}({x}): {a} vs {b}");
            }
            let xf = x as f32;
            for (name, a, b) in [
                ("sinf", xf.fsin(), xf.sin()),
                ("atan2f", xf.fatan2(0.5), xf.atan2(0.5)),
                ("expf", (xf * 0.1).fexp(), (xf * 0.1).exp()),
            ] {
                let d = (a.to_bits() as i32).abs_diff(b.to_bits() as i32);
                assert!(d <= 8, "{name}({xf}): {a} vs {b}");
            }
        }
    }

    /// `fpowi` is plain repeated squaring: exact where the product is.
    #[test]
    fn powi_edges() {
        assert_eq!(3.0f64.fpowi(0), 1.0);
        assert_eq!(f64::NAN.fpowi(0), 1.0);
        assert_eq!(2.0f64.fpowi(-3), 0.125);
        assert_eq!((-1.5f64).fpowi(3), -3.375);
        assert_eq!(10.0f64.fpowi(22), 1e22);
        assert_eq!(2.0f64.fpowi(i32::MIN), 0.0);
        assert_eq!(1.1f64.fpowi(2), 1.1 * 1.1);
    }

    /// The bits themselves, pinned: a `libm` update that rounds any of
    /// these differently changes content hashes, and should be seen here
    /// first (FNV-1a over every result's bits, on any platform).
    #[test]
    fn results_are_pinned() {
        let mut h: u64 = 0xcbf2_9ce4_8422_2325;
        let mut eat = |v: f64| {
            for b in v.to_bits().to_le_bytes() {
                h = (h ^ b as u64).wrapping_mul(0x0000_0100_0000_01b3);
            }
        };
        for x in inputs() {
            let y = 0.7 - x * 0.3;
            for v in [
                x.fsin(),
                x.fcos(),
                x.ftan(),
                x.fsin_cos().0,
                x.fsin_cos().1,
                (x * 0.05).fasin(),
                (x * 0.05).facos(),
                x.fatan(),
                x.fatan2(y),
                (x * 0.1).fexp(),
                x.abs().fln(),
                x.abs().flog2(),
                x.abs().flog10(),
                x.abs().fpowf(y * 0.1),
                x.fpowi(5),
                x.fcbrt(),
                x.fhypot(y),
                x.ftanh(),
                x.fexp_m1(),
                x.abs().fln_1p(),
                (x as f32).fsin() as f64,
                (x as f32).fatan2(y as f32) as f64,
            ] {
                eat(v);
            }
        }
        assert_eq!(
            h, 0xb352_476f_69d2_43f7,
            "update the pinned hash only with a libm version change"
        );
    }
}
