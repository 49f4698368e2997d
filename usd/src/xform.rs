//! Evaluating a prim's `xformOpOrder` stack to a matrix (UsdGeomXformable).
//!
//! Own code rather than `openusd`'s `Xformable::local_to_parent_transform`,
//! which maps every op it does not recognise (and every value of an
//! unexpected type) to the identity: an importer that silently drops a
//! transform gives wrong geometry without a word. Here every op kind of
//! UsdGeomXformOp is evaluated (translate, scale, rotateX/Y/Z, the six
//! rotateABC orders, orient, transform, the `!invert!` prefix, the
//! `!resetXformStack!` sentinel, suffixed ops like `translate:pivot`), and
//! anything else is an [`ImportError`].
//!
//! Conventions: USD multiplies row vectors (`p' = p·M`, translation in the
//! last row, ops in `xformOpOrder` applied last-first); glam multiplies
//! column vectors, so a USD matrix read row-major is glam's column-major
//! transpose and the stack is `M = op0 · op1 · … · opN` (opN applies first).
// Reads outside data: no indexing that can panic (issue 22).
#![deny(clippy::indexing_slicing)]

use openusd::sdf::{self, Value};
use openusd::usd::{Stage, TimeCode};
use shapewright::math::{DMat4, DQuat, DVec3};

use crate::ImportError;

/// The local transform of the prim at `path` and whether its stack starts
/// with `!resetXformStack!` (ignore the parents' transforms).
pub fn local_transform(stage: &impl Attrs, path: &sdf::Path) -> Result<(DMat4, bool), ImportError> {
    let read_err = |message: String| ImportError::Read {
        path: path.as_str().to_owned(),
        message,
    };
    let order = match stage.attr(path, "xformOpOrder").map_err(read_err)? {
        None => return Ok((DMat4::IDENTITY, false)),
        Some(Value::TokenVec(v)) => v.iter().map(|t| t.as_str().to_owned()).collect(),
        Some(Value::StringVec(v)) => v,
        Some(Value::TokenListOp(op)) => op
            .flatten()
            .into_iter()
            .map(|t| t.as_str().to_owned())
            .collect::<Vec<_>>(),
        Some(other) => {
            return Err(read_err(format!(
                "xformOpOrder is not a token array: {other:?}"
            )))
        }
    };
    let mut m = DMat4::IDENTITY;
    let mut reset = false;
    for (i, name) in order.iter().enumerate() {
        if name == "!resetXformStack!" {
            if i != 0 {
                return Err(read_err(format!(
                    "!resetXformStack! at position {i} of xformOpOrder (only valid first)"
                )));
            }
            reset = true;
            continue;
        }
        let (invert, attr_name) = match name.strip_prefix("!invert!") {
            Some(rest) => (true, rest),
            None => (false, name.as_str()),
        };
        let value = stage.attr(path, attr_name).map_err(read_err)?;
        let op = op_matrix(path, attr_name, value)?;
        let op = if invert {
            if op.determinant().abs() < 1e-300 {
                return Err(read_err(format!("!invert!{attr_name} is singular")));
            }
            op.inverse()
        } else {
            op
        };
        m *= op;
    }
    if !m.is_finite() {
        return Err(read_err("the xformOp stack is not finite".to_owned()));
    }
    Ok((m, reset))
}

/// The local-to-world transform of the prim at `path`: its stack times its
/// ancestors', stopping at a `!resetXformStack!`.
pub fn world_transform(stage: &Stage, path: &sdf::Path) -> Result<DMat4, ImportError> {
    let mut m = DMat4::IDENTITY;
    let mut p = Some(path.clone());
    while let Some(cur) = p {
        if cur.is_abs_root() {
            break;
        }
        let (local, reset) = local_transform(stage, &cur)?;
        m = local * m;
        if reset {
            break;
        }
        p = cur.parent();
    }
    Ok(m)
}

/// Where attribute values come from: a composed [`Stage`], or one layer
/// without composition arcs ([`FlatLayer`]).
pub trait Attrs {
    /// Value of `prim.name`: its default, else its earliest time sample.
    fn attr(&self, prim: &sdf::Path, name: &str) -> Result<Option<Value>, String>;
}

impl Attrs for Stage {
    fn attr(&self, prim: &sdf::Path, name: &str) -> Result<Option<Value>, String> {
        attr(self, prim, name)
    }
}

/// One layer read as it is: right when it has no composition arcs (no
/// references, payloads, inherits, specializes, variants or sublayers),
/// where the composed stage is the layer itself.
pub struct FlatLayer<'a>(pub &'a dyn openusd::sdf::AbstractData);

impl Attrs for FlatLayer<'_> {
    fn attr(&self, prim: &sdf::Path, name: &str) -> Result<Option<Value>, String> {
        let p = prim
            .append_property(name)
            .map_err(|e| format!("bad attribute name `{name}`: {e}"))?;
        let field = |key: &str| {
            self.0
                .try_field(&p, key)
                .map_err(|e| format!("{name}: {e}"))
                .map(|v| v.map(std::borrow::Cow::into_owned))
        };
        match field("default")? {
            Some(Value::ValueBlock) => Ok(None),
            Some(v) => Ok(Some(v)),
            None => Ok(match field("timeSamples")? {
                Some(Value::TimeSamples(samples)) => samples
                    .into_iter()
                    .min_by(|a, b| a.0.total_cmp(&b.0))
                    .map(|(_, v)| v)
                    .filter(|v| !matches!(v, Value::ValueBlock)),
                _ => None,
            }),
        }
    }
}

/// Value of `prim.name` on a stage: its default, else its earliest time sample.
pub fn attr(stage: &Stage, prim: &sdf::Path, name: &str) -> Result<Option<Value>, String> {
    let p = prim
        .append_property(name)
        .map_err(|e| format!("bad attribute name `{name}`: {e}"))?;
    let a = stage.attribute(p);
    match a.get::<Value>().map_err(|e| format!("{name}: {e:#}"))? {
        Some(Value::ValueBlock) => Ok(None),
        Some(v) => Ok(Some(v)),
        None => a
            .get_at::<Value>(TimeCode::EARLIEST)
            .map_err(|e| format!("{name}: {e:#}")),
    }
}

fn vec3(v: &Value) -> Option<DVec3> {
    Some(match v {
        Value::Vec3d(a) => DVec3::new(a.x, a.y, a.z),
        Value::Vec3f(a) => DVec3::new(a.x.into(), a.y.into(), a.z.into()),
        Value::Vec3h(a) => DVec3::new(a.x.to_f64(), a.y.to_f64(), a.z.to_f64()),
        Value::Vec3i(a) => DVec3::new(a.x.into(), a.y.into(), a.z.into()),
        _ => return None,
    })
}

fn scalar(v: &Value) -> Option<f64> {
    Some(match v {
        Value::Double(d) => *d,
        Value::Float(f) => (*f).into(),
        Value::Half(h) => h.to_f64(),
        Value::Int(i) => (*i).into(),
        Value::Int64(i) => *i as f64,
        _ => return None,
    })
}

fn quat(v: &Value) -> Option<DQuat> {
    // Gf quaternions are (real, i, j, k); glam's are (x, y, z, w).
    let [w, x, y, z] = match v {
        Value::Quatd(q) => [q.w, q.x, q.y, q.z],
        Value::Quatf(q) => [q.w, q.x, q.y, q.z].map(f64::from),
        Value::Quath(q) => [q.w, q.x, q.y, q.z].map(|h| h.to_f64()),
        _ => return None,
    };
    let q = DQuat::from_xyzw(x, y, z, w);
    let len = q.length();
    (len.is_finite() && len > 1e-12).then(|| q / len)
}

fn op_matrix(path: &sdf::Path, name: &str, value: Option<Value>) -> Result<DMat4, ImportError> {
    let unsupported = || ImportError::UnsupportedXformOp {
        path: path.as_str().to_owned(),
        op: name.to_owned(),
    };
    let bad = |what: &str| ImportError::Read {
        path: path.as_str().to_owned(),
        message: format!("xformOp `{name}` {what}"),
    };
    let kind = name
        .strip_prefix("xformOp:")
        .ok_or_else(unsupported)?
        .split(':')
        .next()
        .unwrap_or_default();
    let Some(value) = value else {
        return Err(bad("is listed in xformOpOrder but has no value"));
    };
    let v3 = || vec3(&value).ok_or_else(|| bad("is not a 3-vector"));
    let s = || scalar(&value).ok_or_else(|| bad("is not a scalar"));
    let deg = |a: f64| a.to_radians();
    let rot = |axis: char, a: f64| match axis {
        'X' => DMat4::from_rotation_x(deg(a)),
        'Y' => DMat4::from_rotation_y(deg(a)),
        _ => DMat4::from_rotation_z(deg(a)),
    };
    Ok(match kind {
        "translate" => DMat4::from_translation(v3()?),
        "translateX" => DMat4::from_translation(DVec3::X * s()?),
        "translateY" => DMat4::from_translation(DVec3::Y * s()?),
        "translateZ" => DMat4::from_translation(DVec3::Z * s()?),
        "scale" => DMat4::from_scale(v3()?),
        "scaleX" => DMat4::from_scale(DVec3::new(s()?, 1.0, 1.0)),
        "scaleY" => DMat4::from_scale(DVec3::new(1.0, s()?, 1.0)),
        "scaleZ" => DMat4::from_scale(DVec3::new(1.0, 1.0, s()?)),
        "rotateX" | "rotateY" | "rotateZ" => {
            let axis = kind.chars().last().unwrap_or('Z');
            rot(axis, s()?)
        }
        "rotateXYZ" | "rotateXZY" | "rotateYXZ" | "rotateYZX" | "rotateZXY" | "rotateZYX" => {
            // rotateABC rotates about A first, then B, then C: M = Rc·Rb·Ra.
            let a = v3()?.to_array();
            let mut m = DMat4::IDENTITY;
            for axis in kind.trim_start_matches("rotate").chars() {
                let angle = match axis {
                    'X' => a[0],
                    'Y' => a[1],
                    _ => a[2],
                };
                m = rot(axis, angle) * m;
            }
            m
        }
        "orient" => {
            DMat4::from_quat(quat(&value).ok_or_else(|| bad("is not a non-zero quaternion"))?)
        }
        "transform" => match value {
            Value::Matrix4d(m) => DMat4::from_cols_array(&m.0),
            _ => return Err(bad("is not a matrix4d")),
        },
        _ => return Err(unsupported()),
    })
}
