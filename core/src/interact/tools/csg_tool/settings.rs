//! The CSG tool's choices and settings: [`SceneOperate`] (paper 2 §4.2),
//! [`CsgToolSettings`] and the component menu ([`MENU_LIBRARY`]).

use crate::sdf::library::STARTER_NAMES;
use crate::sdf::volume::DEFAULT_STEP;
use crate::sdf::Component;
use crate::solid::SolidShape;

/// A SceneOperate choice (paper 2 §4.2).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SceneOperate {
    /// Add with union.
    Union,
    /// Add with intersection.
    Intersect,
    /// Add with subtraction.
    Subtract,
    /// Remove the selected operand.
    Cancel,
}

impl SceneOperate {
    /// The four choices in menu order.
    pub const ALL: [SceneOperate; 4] = [
        SceneOperate::Union,
        SceneOperate::Intersect,
        SceneOperate::Subtract,
        SceneOperate::Cancel,
    ];

    /// Its name.
    pub fn name(self) -> &'static str {
        match self {
            SceneOperate::Union => "union",
            SceneOperate::Intersect => "intersect",
            SceneOperate::Subtract => "subtract",
            SceneOperate::Cancel => "cancel",
        }
    }
}

/// Settings of the CSG tool.
#[derive(Clone, Debug, PartialEq)]
pub struct CsgToolSettings {
    /// How far rays reach (metres).
    pub reach: f64,
    /// Seconds a gesture survives lost tracking before it is cancelled.
    pub grace: f64,
    /// Grid step of volumes the tool creates.
    pub step: f64,
    /// The component menu.
    pub components: Vec<Component>,
    /// Where a copy goes relative to its original (model units).
    pub copy_offset: [f64; 3],
    /// Two presses of `select` within this many seconds are a double click.
    pub double_click: f64,
}

/// The library components on the tool's menu after its primitives, in
/// menu order: the library's starter components after its seven
/// primitive solids (`STARTER_NAMES`, whose order is fixed: models and
/// traces name them), so a component added to the library never shifts
/// the menu.
pub const MENU_LIBRARY: &[&str] = STARTER_NAMES.split_at(7).1;

impl Default for CsgToolSettings {
    fn default() -> Self {
        let solid = |shape| Component::Solid { shape };
        let mut components = vec![
            solid(SolidShape::Cylinder {
                radius: 0.05,
                height: 0.1,
            }),
            solid(SolidShape::Torus {
                major_radius: 0.04,
                minor_radius: 0.01,
            }),
            solid(SolidShape::Sphere { radius: 0.05 }),
            solid(SolidShape::Box {
                size: [0.1, 0.1, 0.1],
            }),
            solid(SolidShape::Cone {
                radius: 0.05,
                height: 0.1,
            }),
            solid(SolidShape::Capsule {
                radius: 0.03,
                length: 0.06,
            }),
        ];
        components.extend(MENU_LIBRARY.iter().map(|n| Component::Library {
            name: (*n).to_string(),
        }));
        Self {
            reach: 5.0,
            grace: 0.25,
            step: DEFAULT_STEP,
            components,
            copy_offset: [0.15, 0.0, 0.0],
            double_click: 0.4,
        }
    }
}
