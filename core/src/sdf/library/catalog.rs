//! The catalog: component families ([`Category`]), one [`Entry`] per
//! component, the starters, and lookup by name or family; the SDF of a
//! component mesh from the shared cache.

use std::sync::OnceLock;

use serde::{Deserialize, Serialize};

use super::kit::Detail;
use super::{furniture, misc, starters, vessels};
use crate::mesh::TriMesh;
use crate::sdf::SdfError;

/// The fixed list of component families.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Category {
    /// Boxes, spheres, cylinders, cones, tori, prisms.
    Primitive,
    /// Chair and table legs, stretchers, feet.
    Leg,
    /// Seats and cushions.
    Seat,
    /// Chair backs.
    Back,
    /// Handles, grips and armrests.
    Handle,
    /// Spouts and nozzles.
    Spout,
    /// Knobs.
    Knob,
    /// Lids and caps.
    Lid,
    /// Lamp shades (open shells).
    Shade,
    /// Bases, stands and saucers.
    Base,
    /// Wheels, tyres, gears.
    Wheel,
    /// Brackets and plates.
    Bracket,
    /// Vessel bodies: cups, vases, bottles, bowls, pots.
    Body,
    /// Organic blends.
    Organic,
}

impl Category {
    /// Every category, in palette order.
    pub const ALL: [Category; 14] = [
        Category::Primitive,
        Category::Leg,
        Category::Seat,
        Category::Back,
        Category::Handle,
        Category::Spout,
        Category::Knob,
        Category::Lid,
        Category::Shade,
        Category::Base,
        Category::Wheel,
        Category::Bracket,
        Category::Body,
        Category::Organic,
    ];

    /// Its name (as serialized).
    pub fn name(self) -> &'static str {
        match self {
            Category::Primitive => "primitive",
            Category::Leg => "leg",
            Category::Seat => "seat",
            Category::Back => "back",
            Category::Handle => "handle",
            Category::Spout => "spout",
            Category::Knob => "knob",
            Category::Lid => "lid",
            Category::Shade => "shade",
            Category::Base => "base",
            Category::Wheel => "wheel",
            Category::Bracket => "bracket",
            Category::Body => "body",
            Category::Organic => "organic",
        }
    }
}

/// One library component.
#[derive(Clone, Copy, Debug)]
pub struct Entry {
    /// Unique name (what `Component::Library` names).
    pub name: &'static str,
    /// Its family.
    pub category: Category,
    pub(crate) build: fn(Detail) -> TriMesh,
}

impl Entry {
    /// The component's closed mesh (before normalization).
    pub fn mesh(&self) -> TriMesh {
        (self.build)(Detail::Full)
    }

    /// The palette thumbnail: the same shape, low-poly (a few hundred
    /// triangles), closed.
    pub fn preview(&self) -> TriMesh {
        (self.build)(Detail::Preview)
    }
}

/// Names of the original 22 starter components, in their original order
/// (the CSG tool's menu is built from it).
pub const STARTER_NAMES: &[&str] = &[
    // primitives
    "box",
    "sphere",
    "cylinder",
    "cone",
    "torus",
    "capsule",
    "ellipsoid",
    // chair parts
    "chair_seat",
    "chair_back",
    "chair_leg",
    "chair_leg_square",
    "chair_armrest",
    "chair_crossbar",
    // cup and handle parts
    "cup_body",
    "cup_hollow",
    "cup_handle",
    "cup_saucer",
    "cup_rim",
    // organic
    "blob",
    "bean",
    "mushroom",
    "snowman",
];

/// Every library component: the starters first, then the families.
pub fn catalog() -> &'static [Entry] {
    static C: OnceLock<Vec<Entry>> = OnceLock::new();
    C.get_or_init(|| {
        let mut v = starters::entries();
        v.extend(furniture::entries());
        v.extend(vessels::entries());
        v.extend(misc::entries());
        v
    })
}

/// The entry named `name`.
pub fn entry(name: &str) -> Result<&'static Entry, SdfError> {
    catalog()
        .iter()
        .find(|e| e.name == name)
        .ok_or_else(|| SdfError::UnknownComponent(name.to_owned()))
}

/// The library's entries of one category, in catalog order.
pub fn in_category(c: Category) -> impl Iterator<Item = &'static Entry> {
    catalog().iter().filter(move |e| e.category == c)
}

/// The closed mesh of library component `name` (before normalization).
pub fn starter_mesh(name: &str) -> Result<TriMesh, SdfError> {
    Ok(entry(name)?.mesh())
}

/// The normalized SDF of `mesh` from the [`crate::sdf::volume::default_cache`]
/// (for callers that do not hold the host's cache).
pub fn cached_component_sdf(
    mesh: &TriMesh,
) -> Result<std::sync::Arc<crate::sdf::dense::DenseSdf>, SdfError> {
    crate::sdf::volume::default_cache().component_sdf(mesh)
}
