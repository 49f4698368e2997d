//! The forms: one entry per op a desktop host offers as a typed form, in
//! the order its menus list them, with every field's kind, default and
//! choices. Defaults the headset's tools also use come from their
//! settings (one value for both hosts); the rest are the desktop's own
//! and say why where it is not obvious.

use serde::Serialize;
use serde_json::{json, Value};

use crate::gc::Resolution;
use crate::interact::tools::curve_tool::CurveToolSettings;
use crate::sculpt::{BrushShape, Falloff, StrokeSettings, Warp};
use crate::solid::{DEFAULT_SEGMENTS, SOLID_KINDS};

/// What a field holds, and so how a host shows it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum FieldKind {
    /// An object id; -1 means the host's active object.
    Target,
    /// A whole number.
    Int,
    /// A number.
    Float,
    /// Yes or no.
    Bool,
    /// Three numbers (a point, a direction, a scale).
    Vec3,
    /// One of `items`.
    Enum,
    /// A rotation, a quaternion `[x, y, z, w]` (hosts may show Euler angles).
    Rotation,
    /// A nested value (a solver's weights, a stroke's settings), shown as
    /// one field per member from the op's schema.
    Struct,
    /// A sketch: points `[[x, y, z], ...]` in metres.
    Points,
    /// A picked loop as text: "curve from to" triples separated by commas.
    Pieces,
    /// Text.
    String,
    /// A component of the starter library, by name.
    Library,
    /// A mesh the host reads from its own data and passes as
    /// `{"name", "positions", "triangles"}` (the form shows its name).
    Mesh,
}

/// One field of a form.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct FormField {
    /// Its name: the op's field of the same name when it has one.
    pub name: &'static str,
    /// What it holds.
    pub kind: FieldKind,
    /// Its default (metres, radians, quaternions).
    pub default: Value,
    /// The choices of an `enum` field.
    pub items: Vec<&'static str>,
    /// A label, when the name does not make one.
    pub label: &'static str,
    /// Help text, for a field the op does not have as such (a template's
    /// size, a location); else the schema's doc of the field it stands for.
    pub doc: &'static str,
    /// The schema field it stands for when its name differs: an op and a
    /// field (`["gc_create", "resolution", "u"]`) or a type and a member
    /// (`["@Profile", "radius"]`). Empty: the op's field of the same name.
    pub like: Vec<&'static str>,
    /// Its unit (`"m"`, `"rad"`) where the schema gives none.
    pub unit: Option<&'static str>,
    /// A value meaning "none" (not range-checked), e.g. resample 0.
    pub none_at: Option<Value>,
    /// For `struct` fields: members that are lengths where the schema
    /// gives no unit, by their name under the field.
    pub units: Vec<(&'static str, &'static str)>,
}

/// How a form's values become its op.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Build {
    /// The values are the op's fields as they are.
    Verbatim,
    /// Built from the values alone (templates, placements, nested values).
    Values,
    /// Built with the sketch pipeline, and the document when a sketch
    /// starts on an object (a child, a new spine).
    Sketch,
    /// Built from a mesh the host reads (`FieldKind::Mesh`).
    HostMesh,
}

/// One op offered as a form.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Form {
    /// The op's name (the first op built, for forms that build several).
    pub op: &'static str,
    /// Its fields, in the order a form shows them.
    pub fields: Vec<FormField>,
    /// How its values become the op.
    pub build: Build,
    /// The field a sketch fills (`"points"`), or empty.
    pub sketch: &'static str,
    /// The kind of object it edits, when its target field alone does not
    /// say (the path tools edit curve networks).
    pub target_kind: Option<&'static str>,
    /// It has nothing to do without a sketch.
    pub needs_points: bool,
}

fn field(name: &'static str, kind: FieldKind, default: Value) -> FormField {
    FormField {
        name,
        kind,
        default,
        items: Vec::new(),
        label: "",
        doc: "",
        like: Vec::new(),
        unit: None,
        none_at: None,
        units: Vec::new(),
    }
}

impl FormField {
    fn items(mut self, items: &[&'static str]) -> Self {
        self.items = items.to_vec();
        self
    }
    fn label(mut self, label: &'static str) -> Self {
        self.label = label;
        self
    }
    fn doc(mut self, doc: &'static str) -> Self {
        self.doc = doc;
        self
    }
    fn like(mut self, like: &[&'static str]) -> Self {
        self.like = like.to_vec();
        self
    }
    fn unit(mut self, unit: &'static str) -> Self {
        self.unit = Some(unit);
        self
    }
}

impl Form {
    fn new(op: &'static str, fields: Vec<FormField>) -> Self {
        Self {
            op,
            fields,
            build: Build::Verbatim,
            sketch: "",
            target_kind: None,
            needs_points: false,
        }
    }
    fn built(mut self, build: Build) -> Self {
        self.build = build;
        self
    }
    fn sketched(mut self) -> Self {
        self.sketch = "points";
        self
    }
    fn edits(mut self, kind: &'static str) -> Self {
        self.target_kind = Some(kind);
        self
    }
    fn needs_points(mut self) -> Self {
        self.needs_points = true;
        self
    }
}

use FieldKind as K;

const PROFILE_TEMPLATES: &[&str] = &["circle", "ellipse", "polygon", "rectangle"];
const TEMPLATE_DOC: &str = "Section template: circle, ellipse, regular polygon or rectangle";
const SIZE_A_DOC: &str =
    "Circle or polygon radius, ellipse semi-axis rx, rectangle width (positive)";
const SIZE_B_DOC: &str =
    "Ellipse semi-axis ry, rectangle height (positive); unused by circles and polygons";
const DIMENSIONS_DOC: &str = "The solid's size along its x, y and z (its bounding box): a round \
     shape's diameter is x; a cylinder's, cone's or capsule's height z; a torus's tube diameter z";
/// `curve_fill_loop`'s pieces, as a form takes them.
pub(crate) const PIECES_DOC: &str = "The loop's pieces head to tail, each \"curve from to\" (a \
     curve and two of its nodes), separated by commas: e.g. \"0 0 1, 1 0 1, 2 0 1\"";
const IDENTITY: [f64; 4] = [0.0, 0.0, 0.0, 1.0];

fn v(value: impl Serialize) -> Value {
    serde_json::to_value(value).expect("a form default is plain data")
}

/// A section template and its sizes (`size_a` 5 cm: a body-sized part).
fn template_fields(size_a: f64, size_b: f64) -> Vec<FormField> {
    vec![
        field("template", K::Enum, json!("circle"))
            .items(PROFILE_TEMPLATES)
            .doc(TEMPLATE_DOC),
        field("size_a", K::Float, json!(size_a))
            .label("Radius / width")
            .doc(SIZE_A_DOC)
            .like(&["@Profile", "radius"]),
        field("size_b", K::Float, json!(size_b))
            .label("Height / ry")
            .doc(SIZE_B_DOC)
            .like(&["@Profile", "ry"]),
        field("sides", K::Int, json!(6)).like(&["@Profile", "sides"]),
    ]
}

fn shape_type_fields() -> Vec<FormField> {
    vec![
        field("shape_type", K::Enum, json!("solid"))
            .items(&["solid", "shell", "container"])
            .like(&["@ShapeType", "type"]),
        field("thickness", K::Float, json!(0.004)).like(&["@ShapeType", "thickness"]),
        field("closed_end", K::Enum, json!("start"))
            .items(&["start", "end"])
            .like(&["@ShapeType", "closed_end"]),
    ]
}

fn solid_fields() -> Vec<FormField> {
    vec![
        field("shape", K::Enum, json!("sphere"))
            .items(&SOLID_KINDS)
            .like(&["@SolidShape", "kind"]),
        field("dimensions", K::Vec3, json!([0.1, 0.1, 0.1]))
            .doc(DIMENSIONS_DOC)
            .unit("m"),
    ]
}

/// Location, rotation and scale (the first `n`).
fn place_fields(n: usize) -> Vec<FormField> {
    let mut out = vec![
        field("location", K::Vec3, json!([0.0, 0.0, 0.0])).like(&["@Transform", "translate"]),
        field("rotation", K::Rotation, v(IDENTITY)).doc("Rotation"),
        field("scale", K::Vec3, json!([1.0, 1.0, 1.0])).like(&["@Transform", "scale"]),
    ];
    out.truncate(n);
    out
}

fn target(name: &'static str) -> FormField {
    field(name, K::Target, json!(-1))
}

fn gc_part() -> Vec<FormField> {
    vec![target("id"), field("part", K::Int, json!(0))]
}

fn points() -> FormField {
    field("points", K::Points, json!(""))
}

fn cat(parts: Vec<Vec<FormField>>) -> Vec<FormField> {
    parts.into_iter().flatten().collect()
}

/// A styling tool held along a sketched path on one curve or patch.
fn path_tool(op: &'static str, element: &'static str, params: Vec<FormField>) -> Form {
    let fields = cat(vec![
        vec![target("id"), field(element, K::Int, json!(0))],
        params,
        vec![points()],
    ]);
    Form::new(op, fields)
        .built(Build::Values)
        .sketched()
        .edits("curve_network")
        .needs_points()
}

fn hand(name: &'static str, doc: &'static str, at: [f64; 3]) -> FormField {
    field(name, K::Vec3, v(at)).doc(doc).unit("m")
}

/// Every form, in the order a host's menus list them.
pub fn forms() -> Vec<Form> {
    [
        gc_forms(),
        csg_forms(),
        curve_forms(),
        sculpt_forms(),
        object_forms(),
    ]
    .concat()
}

/// Generalized cylinders (paper 1).
fn gc_forms() -> Vec<Form> {
    let res = Resolution::DEFAULT;
    vec![
        Form::new(
            "gc_create",
            cat(vec![
                vec![
                    field("location", K::Vec3, json!([0.0, 0.0, 0.0]))
                        .doc("Where the straight spine starts (no sketch)")
                        .unit("m"),
                    field("length", K::Float, json!(0.2))
                        .doc("Length of the straight spine along +Z (no sketch)")
                        .unit("m"),
                    field("plane_normal", K::Vec3, json!([0.0, 1.0, 0.0])),
                    points(),
                ],
                template_fields(0.05, 0.03),
                shape_type_fields(),
                vec![
                    field("res_u", K::Int, json!(res.u)).like(&["gc_create", "resolution", "u"]),
                    field("res_v", K::Int, json!(res.v)).like(&["gc_create", "resolution", "v"]),
                ],
            ]),
        )
        .built(Build::Sketch)
        .sketched(),
        Form::new(
            "gc_bend",
            cat(vec![
                gc_part(),
                vec![
                    field("section", K::Int, json!(1)),
                    field("to", K::Vec3, json!([0.0, 0.0, 0.1])),
                ],
            ]),
        ),
        Form::new("gc_replace_spine", cat(vec![gc_part(), vec![points()]]))
            .built(Build::Sketch)
            .sketched()
            .edits("gc_assembly")
            .needs_points(),
        Form::new(
            "gc_resize",
            cat(vec![
                gc_part(),
                vec![
                    field("section", K::Int, json!(0)),
                    field("factor", K::Float, json!(1.2)),
                ],
            ]),
        ),
        Form::new(
            "gc_shift",
            cat(vec![
                gc_part(),
                vec![
                    field("section", K::Int, json!(1)),
                    field("v", K::Float, json!(0.5)),
                ],
            ]),
        ),
        Form::new(
            "gc_twist",
            cat(vec![
                gc_part(),
                vec![
                    field("section", K::Int, json!(1)),
                    field("angle", K::Float, json!(0.5)),
                ],
            ]),
        ),
        Form::new(
            "gc_replace_section",
            cat(vec![
                gc_part(),
                vec![field("section", K::Int, json!(0))],
                template_fields(0.05, 0.03),
                vec![
                    points(),
                    field("plane_normal", K::Vec3, json!([0.0, 0.0, 1.0]))
                        .doc("Normal of the sketched loop's plane"),
                ],
            ]),
        )
        .built(Build::Sketch)
        .sketched()
        .edits("gc_assembly"),
        Form::new(
            "gc_delete_section",
            cat(vec![gc_part(), vec![field("section", K::Int, json!(1))]]),
        )
        .built(Build::Values),
        Form::new(
            "gc_insert_section",
            cat(vec![gc_part(), vec![field("v", K::Float, json!(0.5))]]),
        ),
        Form::new("gc_set_shape", cat(vec![gc_part(), shape_type_fields()])).built(Build::Values),
        Form::new(
            "gc_add_child",
            cat(vec![
                vec![
                    target("id"),
                    points(),
                    field("parent", K::Int, json!(0)),
                    field("at", K::Vec3, json!([0.0, 0.0, 0.0])),
                    field("length", K::Float, json!(0.1))
                        .doc("Length of a straight stub (no sketch)")
                        .unit("m"),
                    field("end", K::Enum, json!("auto"))
                        .items(&["auto", "free", "parent"])
                        .doc(
                            "Where the spine ends: free (a spout), on the parent (a handle), or \
                             auto: on the parent when a sketch ends on it",
                        ),
                ],
                // A child's section: handle- and spout-sized.
                template_fields(0.008, 0.005),
                shape_type_fields(),
            ]),
        )
        .built(Build::Sketch)
        .sketched()
        .edits("gc_assembly"),
        Form::new(
            "gc_copy",
            cat(vec![
                gc_part(),
                vec![field("mirror", K::Bool, json!(false))],
                place_fields(2),
            ]),
        )
        .built(Build::Values),
        Form::new("gc_transform_part", cat(vec![gc_part(), place_fields(2)])).built(Build::Values),
    ]
}

/// CSG with the component library (paper 2).
fn csg_forms() -> Vec<Form> {
    vec![
        Form::new("sdf_create", vec![field("step", K::Float, json!(0.01))]),
        Form::new(
            "sdf_add_operand",
            cat(vec![
                vec![
                    target("volume"),
                    field("component", K::Enum, json!("library"))
                        .items(&["library", "solid"])
                        .doc("A library component or a solid"),
                    field("library", K::Library, json!("chair_seat"))
                        .doc("The starter-library component"),
                ],
                solid_fields(),
                vec![field("csg", K::Enum, json!("union")).items(&[
                    "union",
                    "subtract",
                    "intersect",
                ])],
                place_fields(3),
            ]),
        )
        .built(Build::Values),
        Form::new(
            "sdf_set_operand_transform",
            cat(vec![
                vec![target("volume"), field("operand", K::Int, json!(0))],
                place_fields(3),
            ]),
        )
        .built(Build::Values),
        Form::new(
            "sdf_scale_two_hand",
            vec![
                target("volume"),
                field("operand", K::Int, json!(0)),
                field("axis", K::Enum, json!("uniform")).items(&["x", "y", "z", "uniform"]),
                hand(
                    "left_start",
                    "The left hand's position when the gesture began",
                    [0.0; 3],
                ),
                hand(
                    "right_start",
                    "The right hand's position when the gesture began",
                    [0.2, 0.0, 0.0],
                ),
                hand(
                    "left_end",
                    "The left hand's position when the gesture ended",
                    [0.0; 3],
                ),
                hand(
                    "right_end",
                    "The right hand's position when the gesture ended",
                    [0.3, 0.0, 0.0],
                ),
            ],
        )
        .built(Build::Values),
        Form::new("sdf_update", vec![target("volume")]),
        Form::new(
            "sdf_cancel_operand",
            vec![target("volume"), field("operand", K::Int, json!(0))],
        ),
        Form::new(
            "sdf_copy_operand",
            cat(vec![
                vec![target("volume"), field("operand", K::Int, json!(0))],
                place_fields(3),
            ]),
        )
        .built(Build::Values),
        Form::new(
            "sdf_import_component",
            vec![
                target("volume"),
                field("name", K::String, json!(""))
                    .doc("The component's name; empty: the mesh object's name"),
                field("mesh", K::Mesh, json!("")).doc(
                    "The mesh object to import (closed, outward normals); empty: the selected \
                     mesh that is not a Shapewright object",
                ),
            ],
        )
        .built(Build::HostMesh),
        Form::new(
            "sdf_set_step",
            vec![target("volume"), field("step", K::Float, json!(0.01))],
        ),
    ]
}

/// Curve drawing and styling (paper 3): the curve tools' weights are the
/// headset's (`CurveToolSettings`).
fn curve_forms() -> Vec<Form> {
    let curve = CurveToolSettings::default();
    // One surface tool's equilibrium (the styled fixtures' weights).
    let surface_eq = || {
        vec![
            field("weights", K::Struct, v(curve.surface)),
            field("f", K::Float, json!(0.8)),
            field("wq_max", K::Float, json!(1.0)),
        ]
    };
    vec![
        Form::new(
            "curve_network_create",
            vec![
                field("resolution", K::Int, json!(curve.resolution)),
                field("surface_n", K::Int, json!(curve.surface_n)),
            ],
        ),
        Form::new(
            "curve_draw",
            vec![
                target("id"),
                points(),
                field("fit", K::Enum, json!("interpolate")).items(&["interpolate", "approximate"]),
                field("tol", K::Float, json!(0.002))
                    .doc("Approximation tolerance (approximate fit)")
                    .like(&["@FitMode", "tol"]),
                FormField {
                    none_at: Some(json!(0.0)),
                    ..field("resample", K::Float, json!(0.0))
                        .doc("Arc-length resampling spacing applied first; 0: none")
                        .like(&["curve_draw", "resample"])
                },
                field("snap_tol", K::Float, json!(0.002)),
            ],
        )
        .built(Build::Values)
        .sketched()
        .edits("curve_network")
        .needs_points(),
        path_tool(
            "curve_smooth",
            "curve",
            vec![field("params", K::Struct, v(curve.smooth))],
        ),
        path_tool(
            "curve_sharpen",
            "curve",
            vec![
                field("params", K::Struct, v(curve.sharpen)),
                FormField {
                    units: vec![("max_step", "m")],
                    ..field("limits", K::Struct, v(curve.sharpen_limits))
                },
            ],
        ),
        path_tool(
            "curve_pull",
            "curve",
            vec![field("params", K::Struct, v(curve.pull))],
        ),
        Form::new(
            "curve_delete",
            vec![target("id"), field("curve", K::Int, json!(0))],
        ),
        Form::new(
            "curve_fill_loop",
            vec![
                target("id"),
                field("pieces", K::Pieces, json!("")).doc(PIECES_DOC),
            ],
        )
        .built(Build::Values),
        Form::new("curve_fill_auto", vec![target("id")]),
        path_tool("surface_smooth", "patch", surface_eq()),
        path_tool("surface_sharpen", "patch", surface_eq()),
        path_tool(
            "surface_pull",
            "patch",
            vec![
                field("weights", K::Struct, v(curve.surface)),
                field("wpp", K::Float, json!(curve.surface_wpp)),
                field("u0", K::Float, json!(0.5)),
                field("v0", K::Float, json!(0.5)),
            ],
        ),
    ]
}

/// Warp brushes (paper 4).
fn sculpt_forms() -> Vec<Form> {
    vec![
        Form::new(
            "sculpt_create",
            cat(vec![
                vec![
                    field("base", K::Enum, json!("sphere"))
                        .items(&["sphere", "box"])
                        .like(&["@SculptBase", "kind"]),
                    field("size_a", K::Float, json!(0.3))
                        .label("Radius / half size")
                        .doc("Sphere radius; half the box's edge")
                        .like(&["@SculptBase", "radius"]),
                    field("edge_length", K::Float, json!(0.03))
                        .like(&["@SculptBase", "edge_length"]),
                ],
                place_fields(3),
            ]),
        )
        .built(Build::Values),
        Form::new(
            "sculpt_stroke",
            vec![
                target("id"),
                FormField {
                    units: vec![
                        ("brush_radius", "m"),
                        ("brush_radii", "m"),
                        ("brush_half_length", "m"),
                        ("influence", "m"),
                    ],
                    ..field("settings", K::Struct, v(desk_stroke()))
                },
                points(),
            ],
        )
        .built(Build::Values)
        .sketched()
        .edits("sculpt_mesh")
        .needs_points(),
    ]
}

/// Solids and the document's own ops (hosts give these their own
/// operators: Blender's Add menu, Shift-D, X).
fn object_forms() -> Vec<Form> {
    vec![
        Form::new(
            "add_solid",
            cat(vec![
                solid_fields(),
                vec![field("segments", K::Int, json!(DEFAULT_SEGMENTS))],
                place_fields(2),
            ]),
        )
        .built(Build::Values),
        Form::new(
            "edit_solid",
            cat(vec![
                vec![target("id")],
                solid_fields(),
                vec![field("segments", K::Int, json!(DEFAULT_SEGMENTS))],
            ]),
        )
        .built(Build::Values),
        Form::new(
            "transform_by",
            vec![
                target("id"),
                field("offset", K::Vec3, json!([0.0, 0.0, 0.0])).like(&["@Transform", "translate"]),
                field("rotation", K::Rotation, v(IDENTITY)).doc("Rotation"),
                field("scale", K::Vec3, json!([1.0, 1.0, 1.0])).like(&["@Transform", "scale"]),
            ],
        )
        .built(Build::Values),
        Form::new("duplicate", vec![target("id")]),
        Form::new("delete", vec![target("id")]),
    ]
}

/// A desktop stroke's settings: a local 2 cm brush whose weights fall to
/// 0 at 5 cm from it (a 0.3 m brush with 0.7 m influence used to drag a
/// whole sphere). The headset's brushes are its presets
/// (`BrushToolSettings`), sized for a hand, not a mouse.
fn desk_stroke() -> StrokeSettings {
    StrokeSettings {
        brush: BrushShape::Sphere { radius: 0.02 },
        brush_scale: 1.0,
        influence: 0.05,
        falloff: Falloff::Smooth,
        warp: Warp::Drag,
        max_edge_rel: 0.1,
        min_edge_rel: 0.03,
    }
}

/// The form of op `op`, if it has one.
pub fn form_named(op: &str) -> Option<Form> {
    forms().into_iter().find(|f| f.op == op)
}
