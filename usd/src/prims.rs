//! A small tree of prims to author (`PrimOut`, `AttrOut`) and its conversion
//! to an `openusd` layer, written as usda by `openusd`'s `TextWriter`.
//!
//! Object kinds contribute prims through this model (see [`crate::kinds`]),
//! so they never touch `openusd` spec fields directly and every attribute is
//! authored the same way: schema attributes non-custom, our own
//! `shapewright:*` attributes custom, log attributes `uniform`.

use openusd::sdf::{self, ChildrenKey, FieldKey, SpecType, Specifier, Value, Variability};

use crate::SaveError;

/// A prim to author: `def <type_name> "<name>"` with attributes and children.
#[derive(Clone, Debug, PartialEq)]
pub struct PrimOut {
    /// Prim name (a valid USD identifier).
    pub name: String,
    /// Schema type, e.g. `Mesh`, `Xform`, `NurbsCurves`, `Scope`.
    pub type_name: &'static str,
    /// Attributes in authored order.
    pub attrs: Vec<AttrOut>,
    /// Child prims in authored order.
    pub children: Vec<PrimOut>,
}

/// An attribute to author.
#[derive(Clone, Debug, PartialEq)]
pub struct AttrOut {
    /// Attribute name, possibly namespaced (`shapewright:ops`).
    pub name: String,
    /// USD value type name, e.g. `point3f[]`, `int[]`, `string`.
    pub type_name: &'static str,
    /// The default value.
    pub value: Value,
    /// `uniform` variability (not animatable).
    pub uniform: bool,
    /// `custom` (not declared by the prim's schema).
    pub custom: bool,
    /// `interpolation` metadata for primvar-like attributes (`vertex`, ...).
    pub interpolation: Option<&'static str>,
}

impl AttrOut {
    /// A schema attribute (non-custom, varying).
    pub fn schema(name: &str, type_name: &'static str, value: Value) -> Self {
        Self {
            name: name.to_owned(),
            type_name,
            value,
            uniform: false,
            custom: false,
            interpolation: None,
        }
    }

    /// A schema attribute declared `uniform` by its schema.
    pub fn schema_uniform(name: &str, type_name: &'static str, value: Value) -> Self {
        Self {
            uniform: true,
            ..Self::schema(name, type_name, value)
        }
    }

    /// One of our own attributes: custom and uniform.
    pub fn custom(name: &str, type_name: &'static str, value: Value) -> Self {
        Self {
            uniform: true,
            custom: true,
            ..Self::schema(name, type_name, value)
        }
    }
}

impl PrimOut {
    /// A prim without attributes or children.
    pub fn new(name: impl Into<String>, type_name: &'static str) -> Self {
        Self {
            name: name.into(),
            type_name,
            attrs: Vec::new(),
            children: Vec::new(),
        }
    }
}

/// Stage (layer) metadata, always authored explicitly.
#[derive(Clone, Debug, PartialEq)]
pub struct StageMeta {
    /// `defaultPrim`: the name of a root prim.
    pub default_prim: String,
    /// `upAxis`: `"Y"` or `"Z"`.
    pub up_axis: &'static str,
    /// `metersPerUnit`.
    pub meters_per_unit: f64,
    /// `doc` string of the layer.
    pub doc: String,
}

/// Builds the layer for `roots` under `meta`.
pub fn build_layer(meta: &StageMeta, roots: &[PrimOut]) -> Result<sdf::Data, SaveError> {
    let mut data = sdf::Data::new();
    let root = sdf::Path::abs_root();
    let spec = data.create_spec(root.clone(), SpecType::PseudoRoot);
    spec.add(
        FieldKey::DefaultPrim,
        Value::Token(meta.default_prim.as_str().into()),
    );
    spec.add("upAxis", Value::Token(meta.up_axis.into()));
    spec.add("metersPerUnit", Value::Double(meta.meters_per_unit));
    spec.add(FieldKey::Documentation, Value::String(meta.doc.clone()));
    spec.add(
        ChildrenKey::PrimChildren,
        Value::TokenVec(roots.iter().map(|p| p.name.as_str().into()).collect()),
    );
    for p in roots {
        add_prim(&mut data, &root, p)?;
    }
    Ok(data)
}

fn bad_name(name: &str) -> SaveError {
    SaveError::Author(format!("`{name}` is not a valid prim or attribute name"))
}

fn add_prim(data: &mut sdf::Data, parent: &sdf::Path, p: &PrimOut) -> Result<(), SaveError> {
    if !is_identifier(&p.name) {
        return Err(bad_name(&p.name));
    }
    let path = parent
        .append_path(p.name.as_str())
        .map_err(|_| bad_name(&p.name))?;
    let spec = data.create_spec(path.clone(), SpecType::Prim);
    spec.add(FieldKey::Specifier, Value::Specifier(Specifier::Def));
    spec.add(FieldKey::TypeName, Value::Token(p.type_name.into()));
    if !p.attrs.is_empty() {
        spec.add(
            ChildrenKey::PropertyChildren,
            Value::TokenVec(p.attrs.iter().map(|a| a.name.as_str().into()).collect()),
        );
    }
    if !p.children.is_empty() {
        spec.add(
            ChildrenKey::PrimChildren,
            Value::TokenVec(p.children.iter().map(|c| c.name.as_str().into()).collect()),
        );
    }
    for a in &p.attrs {
        if !a.name.split(':').all(is_identifier) {
            return Err(bad_name(&a.name));
        }
        let ap = path
            .append_property(a.name.as_str())
            .map_err(|_| bad_name(&a.name))?;
        let spec = data.create_spec(ap, SpecType::Attribute);
        spec.add(FieldKey::TypeName, Value::Token(a.type_name.into()));
        spec.add(FieldKey::Custom, Value::Bool(a.custom));
        if a.uniform {
            spec.add(
                FieldKey::Variability,
                Value::Variability(Variability::Uniform),
            );
        }
        if let Some(i) = a.interpolation {
            spec.add("interpolation", Value::Token(i.into()));
        }
        spec.add(FieldKey::Default, a.value.clone());
    }
    for c in &p.children {
        add_prim(data, &path, c)?;
    }
    Ok(())
}

/// True for a USD identifier: `[A-Za-z_][A-Za-z0-9_]*`.
pub fn is_identifier(s: &str) -> bool {
    let mut chars = s.chars();
    matches!(chars.next(), Some(c) if c == '_' || c.is_ascii_alphabetic())
        && chars.all(|c| c == '_' || c.is_ascii_alphanumeric())
}
