//! The palette of a modeler [`crate::interact::Session`]: the menu the off
//! hand carries (issue 19), as plain data both hosts draw — the OpenXR host
//! with its renderer, the Blender VR session with its overlay — and pick
//! from the same way.
//!
//! **What it holds**, row by row from the top: the tools; undo, redo, save
//! and the snapping settings (grid step, angle step); then the active
//! tool's choice groups ([`ChoiceGroup`]: shape type, SDF component, CSG
//! operation, brush preset and size, curve mode, ...), each a header and
//! its options, [`PAGE`] options at a time with `<` / `>` to page through
//! longer lists (the SDF library has 60 and more components).
//!
//! **Where it is:** [`PaletteView::pose`] is the palette's plane in the
//! world: its lower edge sits [`LIFT`] above the off hand's grip (or
//! wrist), however many rows the active tool's choices take,
//! its +Z faces the head and its +Y is as close to world up as that
//! allows, so it reads upright whichever way the wrist turns. Items are
//! rectangles in that plane, in metres.
//!
//! **How it is picked:** by the dominant hand's ray (a controller's aim,
//! the trigger's press edge picks) or by touch (a tracked index fingertip
//! within [`TOUCH`] of the plane picks on entering). Layout and picking
//! are pure functions of the inputs, so a replayed trace picks the same
//! items bit for bit.

use crate::math::{DQuat, DVec3};

use crate::interact::input::Pose;

/// Width and height of a button (metres).
pub const BUTTON: [f64; 2] = [0.05, 0.02];
/// Gap between buttons (metres).
pub const GAP: f64 = 0.004;
/// Buttons per row.
pub const COLUMNS: usize = 5;
/// Options shown per page of a choice group (two rows of four, the fifth
/// column holds the page buttons).
pub const PAGE: usize = 8;
/// How far above the off hand the palette's lower edge floats (metres):
/// a tall palette grows upwards and never reaches down into the hand.
pub const LIFT: f64 = 0.06;
/// A fingertip this close to the plane touches it (metres).
pub const TOUCH: f64 = 0.01;

/// One choice a tool offers: a name and its options, one of them active.
#[derive(Clone, Debug, PartialEq)]
pub struct ChoiceGroup {
    /// The header ("Shape", "Component", ...).
    pub name: &'static str,
    /// Option labels.
    pub options: Vec<String>,
    /// The active option (may be out of range when there is none).
    pub active: usize,
}

/// What picking an item does.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PaletteAction {
    /// Switch to tool `i` of [`crate::interact::TOOL_NAMES`].
    Tool(usize),
    /// Choose `option` of the active tool's group `group`.
    Choice {
        /// The group index.
        group: usize,
        /// The option index.
        option: usize,
    },
    /// Show the next (`+1`) or previous (`-1`) page of a group.
    Page {
        /// The group index.
        group: usize,
        /// Direction.
        delta: i32,
    },
    /// Undo the last op.
    Undo,
    /// Redo the next op.
    Redo,
    /// Save the document now.
    Save,
    /// Cycle the grid step ([`GRID_STEPS`]).
    Grid,
    /// Cycle the angle step ([`ANGLE_STEPS`]).
    Angle,
    /// Toggle snapping to other objects ([`crate::interact::tools::snap`]).
    Objects,
    /// Cycle the mirror plane: off, across x, y, z (through the active
    /// tool's object), at the off hand, off ([`MirrorMode`]).
    Mirror,
    /// A header: not pickable.
    None,
}

/// Grid steps the palette cycles through (metres; 0: off).
pub const GRID_STEPS: [f64; 5] = [0.0, 0.001, 0.005, 0.01, 0.05];
/// Angle steps the palette cycles through (degrees; 0: off).
pub const ANGLE_STEPS: [f64; 3] = [0.0, 15.0, 45.0];

/// Snapping of drags, chosen in the palette and applied by every tool that
/// drags (per drag: the preview shows what it snapped to).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Snap {
    /// Translation grid step in model metres (0: off).
    pub grid: f64,
    /// Rotation step in degrees (0: off).
    pub angle: f64,
    /// Snap to other objects' centres, axes and surfaces
    /// ([`crate::interact::tools::snap::snap_to_objects`]).
    pub objects: bool,
    /// Mirror symmetry: strokes (sculpt, curves) are mirrored across this
    /// plane (document space), placed through the palette.
    pub mirror: Option<Mirror>,
}

/// How the mirror plane was placed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MirrorMode {
    /// Across the document's x axis (a y-z plane).
    X,
    /// Across y.
    Y,
    /// Across z.
    Z,
    /// Through the off hand's grip, across its sideways (x) axis: the
    /// plane the user holds the palette hand in when picking it.
    Hand,
}

impl MirrorMode {
    /// The next mode of the palette's cycle (`None`: mirror off).
    pub fn next(mode: Option<MirrorMode>) -> Option<MirrorMode> {
        match mode {
            None => Some(Self::X),
            Some(Self::X) => Some(Self::Y),
            Some(Self::Y) => Some(Self::Z),
            Some(Self::Z) => Some(Self::Hand),
            Some(Self::Hand) => None,
        }
    }

    /// The palette's label.
    pub fn label(mode: Option<MirrorMode>) -> &'static str {
        match mode {
            None => "Mirror off",
            Some(Self::X) => "Mirror x",
            Some(Self::Y) => "Mirror y",
            Some(Self::Z) => "Mirror z",
            Some(Self::Hand) => "Mirror at hand",
        }
    }
}

/// A placed mirror plane and how it was placed.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Mirror {
    /// How it was placed (the palette's label).
    pub mode: MirrorMode,
    /// The plane (document space).
    pub plane: crate::math::MirrorPlane,
}

impl Snap {
    /// `v` rounded to the grid (unchanged when the grid is off).
    pub fn translate(&self, v: DVec3) -> DVec3 {
        if self.grid > 0.0 {
            (v / self.grid).round() * self.grid
        } else {
            v
        }
    }

    /// `q` with its rotation angle rounded to the angle step about its own
    /// axis (unchanged when off).
    pub fn rotate(&self, q: DQuat) -> DQuat {
        if self.angle <= 0.0 {
            return q;
        }
        let (axis, angle) = q.to_axis_angle();
        let step = self.angle.to_radians();
        let snapped = (angle / step).round() * step;
        if snapped == 0.0 || !axis.is_finite() {
            DQuat::IDENTITY
        } else {
            DQuat::from_axis_angle(axis.normalize(), snapped)
        }
    }
}

/// One item of the palette.
#[derive(Clone, Debug, PartialEq)]
pub struct PaletteItem {
    /// What picking it does ([`PaletteAction::None`] for headers).
    pub action: PaletteAction,
    /// The label.
    pub label: String,
    /// `[x0, y0, x1, y1]` in the palette plane (metres, +Y up, centred).
    pub rect: [f64; 4],
    /// Shown as chosen (the active tool, the active option, a setting on).
    pub active: bool,
}

impl PaletteItem {
    /// Whether the plane point `(x, y)` is inside.
    pub fn contains(&self, x: f64, y: f64) -> bool {
        x >= self.rect[0] && x <= self.rect[2] && y >= self.rect[1] && y <= self.rect[3]
    }
}

/// The palette as the hosts draw it this frame.
#[derive(Clone, Debug, PartialEq)]
pub struct PaletteView {
    /// The plane (world): centre, +X right, +Y up, +Z toward the head.
    pub pose: Pose,
    /// `[width, height]` of the panel (metres).
    pub size: [f64; 2],
    /// Everything on it.
    pub items: Vec<PaletteItem>,
    /// The item the pointer is on.
    pub hovered: Option<usize>,
    /// Where the pointer meets the plane (world), if it does.
    pub pointer: Option<DVec3>,
}

impl PaletteView {
    /// The world position of plane point `(x, y)`.
    pub fn to_world(&self, x: f64, y: f64) -> DVec3 {
        self.pose.position + self.pose.orientation * DVec3::new(x, y, 0.0)
    }

    /// The item at plane point `(x, y)` that can be picked.
    pub fn item_at(&self, x: f64, y: f64) -> Option<usize> {
        self.items
            .iter()
            .position(|i| i.action != PaletteAction::None && i.contains(x, y))
    }

    /// Where a ray meets the plane: `(x, y, distance)`, if in front of it
    /// and within the panel.
    pub fn ray_hit(&self, origin: DVec3, dir: DVec3) -> Option<(f64, f64, f64)> {
        let n = self.pose.orientation * DVec3::Z;
        let denom = dir.dot(n);
        if denom.abs() < 1e-9 {
            return None;
        }
        let t = (self.pose.position - origin).dot(n) / denom;
        if t.is_nan() || t <= 0.0 {
            return None;
        }
        let local = self.pose.orientation.inverse() * (origin + dir * t - self.pose.position);
        let (hw, hh) = (self.size[0] / 2.0, self.size[1] / 2.0);
        (local.x.abs() <= hw && local.y.abs() <= hh).then_some((local.x, local.y, t))
    }

    /// A point's plane coordinates and signed height above the plane.
    pub fn local(&self, p: DVec3) -> DVec3 {
        self.pose.orientation.inverse() * (p - self.pose.position)
    }

    /// The labels, in order (for tests and logs).
    pub fn labels(&self) -> Vec<&str> {
        self.items.iter().map(|i| i.label.as_str()).collect()
    }
}

/// The palette's orientation for an off hand at `anchor` seen from `head`:
/// +Z toward the head, +Y as close to the head's up as that allows (so
/// the panel reads upright in the view, not rolled by the perspective);
/// world up without a head.
pub fn facing(anchor: DVec3, head: Option<Pose>) -> DQuat {
    let mut z = head.map_or(DVec3::Z, |h| h.position - anchor);
    if z.length_squared() < 1e-12 || !z.is_finite() {
        z = DVec3::Z;
    }
    let z = z.normalize();
    let up = head.map_or(DVec3::Y, |h| h.orientation * DVec3::Y);
    let mut x = up.cross(z);
    if x.length_squared() < 1e-9 || !x.is_finite() {
        x = DVec3::Y.cross(z);
    }
    if x.length_squared() < 1e-9 {
        x = DVec3::X;
    }
    let x = x.normalize();
    let y = z.cross(x);
    DQuat::from_mat3(&glam::DMat3::from_cols(x, y, z)).normalize()
}

/// The palette's labels of [`crate::interact::TOOL_NAMES`], in order.
pub const TOOL_LABELS: [&str; 5] = ["Object", "GC", "CSG", "Curve", "Sculpt"];

/// What the layout needs to know.
pub struct LayoutInput<'a> {
    /// Tool labels, in [`crate::interact::TOOL_NAMES`] order.
    pub tools: &'a [&'a str],
    /// The active tool.
    pub active_tool: usize,
    /// The active tool's choice groups.
    pub groups: &'a [ChoiceGroup],
    /// The page shown of each group.
    pub pages: &'a [usize],
    /// Snapping now.
    pub snap: Snap,
}

fn cell(col: usize, row: usize, cols: usize) -> [f64; 4] {
    // Rows grow downward from y = 0; the caller centres the panel.
    let x0 = col as f64 * (BUTTON[0] + GAP);
    let y1 = -(row as f64) * (BUTTON[1] + GAP);
    let w = BUTTON[0] * cols as f64 + GAP * (cols as f64 - 1.0);
    [x0, y1 - BUTTON[1], x0 + w, y1]
}

/// Human label of a length in metres.
pub fn length_label(m: f64) -> String {
    if m == 0.0 {
        "off".into()
    } else if m < 0.01 {
        format!("{} mm", (m * 1000.0).round())
    } else {
        format!("{} cm", (m * 100.0 * 10.0).round() / 10.0)
    }
}

/// The palette's items and panel size for `input` (panel centred on 0).
pub fn layout(input: &LayoutInput) -> (Vec<PaletteItem>, [f64; 2]) {
    let mut items = Vec::new();
    let mut row = 0;
    for (i, t) in input.tools.iter().enumerate() {
        items.push(PaletteItem {
            action: PaletteAction::Tool(i),
            label: t.to_string(),
            rect: cell(i % COLUMNS, row + i / COLUMNS, 1),
            active: i == input.active_tool,
        });
    }
    row += input.tools.len().div_ceil(COLUMNS);
    let snap = input.snap;
    for (col, (action, label, active)) in [
        (PaletteAction::Undo, "Undo".to_string(), false),
        (PaletteAction::Redo, "Redo".to_string(), false),
        (PaletteAction::Save, "Save".to_string(), false),
        (
            PaletteAction::Grid,
            format!("Grid {}", length_label(snap.grid)),
            snap.grid > 0.0,
        ),
        (
            PaletteAction::Angle,
            if snap.angle > 0.0 {
                format!("Angle {}°", snap.angle)
            } else {
                "Angle off".to_string()
            },
            snap.angle > 0.0,
        ),
    ]
    .into_iter()
    .enumerate()
    {
        items.push(PaletteItem {
            action,
            label,
            rect: cell(col, row, 1),
            active,
        });
    }
    row += 1;
    items.push(PaletteItem {
        action: PaletteAction::Objects,
        label: if snap.objects {
            "Snap to objects: on".to_string()
        } else {
            "Snap to objects: off".to_string()
        },
        rect: cell(0, row, 2),
        active: snap.objects,
    });
    items.push(PaletteItem {
        action: PaletteAction::Mirror,
        label: MirrorMode::label(snap.mirror.map(|m| m.mode)).to_string(),
        rect: cell(2, row, 2),
        active: snap.mirror.is_some(),
    });
    row += 1;
    for (g, group) in input.groups.iter().enumerate() {
        items.push(PaletteItem {
            action: PaletteAction::None,
            label: group.name.to_string(),
            rect: cell(0, row, COLUMNS),
            active: false,
        });
        row += 1;
        let pages = group.options.len().div_ceil(PAGE).max(1);
        let page = input.pages.get(g).copied().unwrap_or(0).min(pages - 1);
        let shown = page * PAGE..((page + 1) * PAGE).min(group.options.len());
        let rows = shown.len().div_ceil(COLUMNS - 1).max(1);
        for (k, o) in shown.enumerate() {
            items.push(PaletteItem {
                action: PaletteAction::Choice {
                    group: g,
                    option: o,
                },
                label: group.options[o].clone(),
                rect: cell(k % (COLUMNS - 1), row + k / (COLUMNS - 1), 1),
                active: o == group.active,
            });
        }
        if pages > 1 {
            for (r, (delta, label)) in [(-1, "<"), (1, ">")].into_iter().enumerate() {
                items.push(PaletteItem {
                    action: PaletteAction::Page { group: g, delta },
                    label: format!("{label} {}/{pages}", page + 1),
                    rect: cell(COLUMNS - 1, row + r.min(rows - 1), 1),
                    active: false,
                });
            }
            if rows == 1 {
                // Both page buttons on one row: halve them side by side.
                let n = items.len();
                let [x0, y0, x1, y1] = items[n - 1].rect;
                let mid = (x0 + x1) / 2.0;
                items[n - 2].rect = [x0, y0, mid - GAP / 2.0, y1];
                items[n - 1].rect = [mid + GAP / 2.0, y0, x1, y1];
            }
        }
        row += rows;
    }
    let width = BUTTON[0] * COLUMNS as f64 + GAP * (COLUMNS as f64 - 1.0);
    let height = row as f64 * (BUTTON[1] + GAP) - GAP;
    let pad = GAP * 2.0;
    for it in &mut items {
        it.rect[0] -= width / 2.0;
        it.rect[2] -= width / 2.0;
        it.rect[1] += height / 2.0;
        it.rect[3] += height / 2.0;
    }
    (items, [width + 2.0 * pad, height + 2.0 * pad])
}

#[cfg(test)]
mod tests {
    use super::*;

    fn groups() -> Vec<ChoiceGroup> {
        vec![
            ChoiceGroup {
                name: "Shape",
                options: (0..3).map(|i| format!("s{i}")).collect(),
                active: 1,
            },
            ChoiceGroup {
                name: "Component",
                options: (0..20).map(|i| format!("c{i}")).collect(),
                active: 9,
            },
        ]
    }

    #[test]
    fn items_do_not_overlap_and_fit_the_panel() {
        let g = groups();
        let (items, size) = layout(&LayoutInput {
            tools: &["object", "gc", "csg", "curve", "sculpt"],
            active_tool: 2,
            groups: &g,
            pages: &[0, 1],
            snap: Snap::default(),
        });
        for (i, a) in items.iter().enumerate() {
            assert!(a.rect[0] >= -size[0] / 2.0 && a.rect[2] <= size[0] / 2.0);
            assert!(a.rect[1] >= -size[1] / 2.0 && a.rect[3] <= size[1] / 2.0);
            for b in &items[i + 1..] {
                let overlap = a.rect[0] < b.rect[2]
                    && b.rect[0] < a.rect[2]
                    && a.rect[1] < b.rect[3]
                    && b.rect[1] < a.rect[3];
                assert!(!overlap, "{} overlaps {}", a.label, b.label);
            }
        }
        // Page 2 of 3 of the components shows c8..c15, c9 active.
        let comps: Vec<_> = items
            .iter()
            .filter(|i| matches!(i.action, PaletteAction::Choice { group: 1, .. }))
            .collect();
        assert_eq!(comps.len(), PAGE);
        assert_eq!(comps[0].label, "c8");
        assert!(comps[1].active && comps[1].label == "c9");
        assert!(items.iter().any(|i| i.label == "> 2/3"));
        assert!(items.iter().any(|i| i.active && i.label == "csg"));
    }

    #[test]
    fn rays_pick_what_they_point_at() {
        let g = groups();
        let (items, size) = layout(&LayoutInput {
            tools: &["object", "gc"],
            active_tool: 0,
            groups: &g,
            pages: &[0, 0],
            snap: Snap::default(),
        });
        let head = DVec3::new(0.3, 1.6, 0.4);
        let anchor = DVec3::new(-0.2, 1.1, -0.3);
        let view = PaletteView {
            pose: Pose::new(
                anchor,
                facing(anchor, Some(Pose::new(head, DQuat::IDENTITY))),
            ),
            size,
            items,
            hovered: None,
            pointer: None,
        };
        // Upright for a level head: +X is level, +Z points at the head.
        let q = view.pose.orientation;
        assert!((q * DVec3::X).y.abs() < 1e-12);
        assert!((q * DVec3::Z).dot((head - anchor).normalize()) > 1.0 - 1e-12);
        for (k, it) in view.items.iter().enumerate() {
            let c = view.to_world(
                (it.rect[0] + it.rect[2]) / 2.0,
                (it.rect[1] + it.rect[3]) / 2.0,
            );
            let origin = head + DVec3::new(0.05, -0.2, 0.0);
            let (x, y, t) = view.ray_hit(origin, (c - origin).normalize()).unwrap();
            assert!(t > 0.0);
            let want = (it.action != PaletteAction::None).then_some(k);
            assert_eq!(view.item_at(x, y), want, "{}", it.label);
        }
        // Pointing away misses.
        assert!(view.ray_hit(head, (head - anchor).normalize()).is_none());
    }

    #[test]
    fn snapping_rounds_to_the_step() {
        let s = Snap {
            grid: 0.01,
            angle: 15.0,
            ..Snap::default()
        };
        let v = s.translate(DVec3::new(0.0149, -0.0251, 0.3));
        assert!((v - DVec3::new(0.01, -0.03, 0.3)).length() < 1e-12);
        let q = s.rotate(DQuat::from_rotation_y(22.0f64.to_radians()));
        let (axis, angle) = q.to_axis_angle();
        assert!((angle.to_degrees() - 15.0).abs() < 1e-9 && (axis - DVec3::Y).length() < 1e-9);
        assert_eq!(
            s.rotate(DQuat::from_rotation_z(0.1f64.to_radians())),
            DQuat::IDENTITY
        );
        let off = Snap::default();
        assert_eq!(off.translate(DVec3::splat(0.123)), DVec3::splat(0.123));
        assert_eq!(length_label(0.005), "5 mm");
        assert_eq!(length_label(0.05), "5 cm");
    }
}
