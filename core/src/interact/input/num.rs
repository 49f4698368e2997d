//! Serde for numbers that may be non-finite: finite values as JSON
//! numbers (unchanged), NaN and infinities as the strings `"NaN"`, `"inf"`,
//! `"-inf"`.

use serde::de::{self, Deserializer, SeqAccess, Visitor};
use serde::ser::{SerializeTuple, Serializer};
use serde::{Deserialize, Serialize};

/// One number, finite or not.
#[derive(Clone, Copy)]
struct Lenient(f64);

impl Serialize for Lenient {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        let x = self.0;
        if x.is_finite() {
            s.serialize_f64(x)
        } else if x.is_nan() {
            s.serialize_str("NaN")
        } else if x > 0.0 {
            s.serialize_str("inf")
        } else {
            s.serialize_str("-inf")
        }
    }
}

struct LenientVisitor;

impl Visitor<'_> for LenientVisitor {
    type Value = Lenient;
    fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
        f.write_str(r#"a number, "NaN", "inf" or "-inf""#)
    }
    fn visit_f64<E>(self, v: f64) -> Result<Lenient, E> {
        Ok(Lenient(v))
    }
    fn visit_i64<E>(self, v: i64) -> Result<Lenient, E> {
        Ok(Lenient(v as f64))
    }
    fn visit_u64<E>(self, v: u64) -> Result<Lenient, E> {
        Ok(Lenient(v as f64))
    }
    fn visit_str<E: de::Error>(self, v: &str) -> Result<Lenient, E> {
        match v {
            "NaN" | "nan" => Ok(Lenient(f64::NAN)),
            "inf" | "Infinity" => Ok(Lenient(f64::INFINITY)),
            "-inf" | "-Infinity" => Ok(Lenient(f64::NEG_INFINITY)),
            _ => Err(E::invalid_value(de::Unexpected::Str(v), &self)),
        }
    }
}

impl<'de> Deserialize<'de> for Lenient {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Lenient, D::Error> {
        d.deserialize_any(LenientVisitor)
    }
}

fn ser_array<S: Serializer, const N: usize>(v: [f64; N], s: S) -> Result<S::Ok, S::Error> {
    let mut t = s.serialize_tuple(N)?;
    for x in v {
        t.serialize_element(&Lenient(x))?;
    }
    t.end()
}

fn de_array<'de, D: Deserializer<'de>, const N: usize>(d: D) -> Result<[f64; N], D::Error> {
    struct ArrayVisitor<const N: usize>;
    impl<'de, const N: usize> Visitor<'de> for ArrayVisitor<N> {
        type Value = [f64; N];
        fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
            write!(f, "an array of {N} numbers")
        }
        fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<[f64; N], A::Error> {
            let mut out = [0.0; N];
            for (i, o) in out.iter_mut().enumerate() {
                let Lenient(x) = seq
                    .next_element()?
                    .ok_or_else(|| de::Error::invalid_length(i, &self))?;
                *o = x;
            }
            if seq.next_element::<de::IgnoredAny>()?.is_some() {
                return Err(de::Error::invalid_length(N + 1, &self));
            }
            Ok(out)
        }
    }
    d.deserialize_tuple(N, ArrayVisitor::<N>)
}

/// A single `f64`.
pub mod f64 {
    use super::*;
    /// Serializes.
    pub fn serialize<S: Serializer>(x: &f64, s: S) -> Result<S::Ok, S::Error> {
        Lenient(*x).serialize(s)
    }
    /// Deserializes.
    pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<f64, D::Error> {
        Lenient::deserialize(d).map(|l| l.0)
    }
}

/// `[f64; 2]`.
pub mod arr2 {
    use super::*;
    /// Serializes.
    pub fn serialize<S: Serializer>(x: &[f64; 2], s: S) -> Result<S::Ok, S::Error> {
        ser_array(*x, s)
    }
    /// Deserializes.
    pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<[f64; 2], D::Error> {
        de_array(d)
    }
}

/// `DVec3` as `[x, y, z]`.
pub mod vec3 {
    use super::*;
    use crate::math::DVec3;
    /// Serializes.
    pub fn serialize<S: Serializer>(v: &DVec3, s: S) -> Result<S::Ok, S::Error> {
        ser_array(v.to_array(), s)
    }
    /// Deserializes.
    pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<DVec3, D::Error> {
        de_array(d).map(DVec3::from_array)
    }
}

/// `DQuat` as `[x, y, z, w]`.
pub mod quat {
    use super::*;
    use crate::math::DQuat;
    /// Serializes.
    pub fn serialize<S: Serializer>(q: &DQuat, s: S) -> Result<S::Ok, S::Error> {
        ser_array(q.to_array(), s)
    }
    /// Deserializes.
    pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<DQuat, D::Error> {
        de_array(d).map(DQuat::from_array)
    }
}
