//! The palette as both hosts draw it (issue 36): a draw list of quads with
//! roles and labels with the room they have, in world (stage) space, and
//! one theme. The layout of [`PaletteView`] is the core's; so are the
//! depth offsets that keep labels in front of buttons and buttons in front
//! of the panel, the colour of each role, and how a label fits its button.
//! A host only measures text with its own font and fills triangles: the
//! OpenXR host with its glyph outlines (`xr_host/src/ui.rs`), Blender with
//! `gpu` and `blf` (`shapewright_blender/xr.py`, `draw.py`).

use crate::math::DVec3;

use super::palette::{PaletteAction, PaletteView};

/// What a quad or label is, for its colour ([`PaletteRole::color`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PaletteRole {
    /// The panel behind everything.
    Panel,
    /// A button that can be picked.
    Button,
    /// A chosen button (the active tool, option or setting).
    Active,
    /// The button under the pointer.
    Hover,
    /// Where the pointer meets the panel.
    Pointer,
    /// A button's label.
    Label,
    /// A group header's label (headers have no button).
    Header,
}

impl PaletteRole {
    /// Every role, in declaration order.
    pub const ALL: [PaletteRole; 7] = [
        Self::Panel,
        Self::Button,
        Self::Active,
        Self::Hover,
        Self::Pointer,
        Self::Label,
        Self::Header,
    ];

    /// The theme: linear RGB in 0..1, the same in every host.
    pub const fn color(self) -> [f32; 3] {
        match self {
            Self::Panel => [0.05, 0.055, 0.07],
            Self::Button => [0.2, 0.22, 0.27],
            Self::Active => [0.18, 0.42, 0.78],
            Self::Hover | Self::Pointer => [0.95, 0.62, 0.2],
            Self::Label => [0.95, 0.96, 0.98],
            Self::Header => [0.6, 0.66, 0.74],
        }
    }

    /// Its name (hosts without the enum, such as Python, key on it).
    pub const fn name(self) -> &'static str {
        match self {
            Self::Panel => "panel",
            Self::Button => "button",
            Self::Active => "active",
            Self::Hover => "hover",
            Self::Pointer => "pointer",
            Self::Label => "label",
            Self::Header => "header",
        }
    }
}

/// A filled quad: corners counter-clockwise seen from the head, starting
/// at the lower left (world).
#[derive(Clone, Debug, PartialEq)]
pub struct PaletteQuad {
    /// Lower left, lower right, upper right, upper left.
    pub corners: [DVec3; 4],
    /// Its colour's role.
    pub role: PaletteRole,
}

/// A label and the room it has on its button (world).
#[derive(Clone, Debug, PartialEq)]
pub struct PaletteLabel {
    /// The text.
    pub text: String,
    /// [`PaletteRole::Label`] or [`PaletteRole::Header`].
    pub role: PaletteRole,
    /// The lower left corner of its room, lifted in front of the button.
    pub corner: DVec3,
    /// Unit vector along the text.
    pub right: DVec3,
    /// Unit vector up the letters.
    pub up: DVec3,
    /// Width and height of its room (metres).
    pub room: [f64; 2],
}

impl PaletteLabel {
    /// The em height of a label that fits (metres).
    pub const EM: f64 = 0.0105;
    /// The margin each side of a button's label (metres).
    pub const PAD: f64 = 0.003;

    /// Where and how big the host draws this label with its font: `advance`
    /// is the text's width at an em height of 1, `cap` the height of its
    /// capitals at an em of 1. Returns the baseline's start (world) and the
    /// em height (metres). A label too long for its button shrinks to the
    /// button's width less [`Self::PAD`] each side; a button's label is
    /// centred, a header's starts at its room's left edge; the capitals
    /// are centred vertically.
    pub fn place(&self, advance: f64, cap: f64) -> (DVec3, f64) {
        let [w, h] = self.room;
        let mut em = Self::EM;
        if advance * em > w - 2.0 * Self::PAD && advance > 0.0 {
            em = (w - 2.0 * Self::PAD) / advance;
        }
        let width = advance * em;
        let left = match self.role {
            PaletteRole::Header => 0.0,
            _ => (w - width) / 2.0,
        };
        let base = (h - cap * em) / 2.0;
        (self.corner + self.right * left + self.up * base, em)
    }
}

/// Everything a host draws of the open palette, back to front.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PaletteDraw {
    /// The panel, the buttons, then the pointer.
    pub quads: Vec<PaletteQuad>,
    /// One per item, in the palette's order.
    pub labels: Vec<PaletteLabel>,
}

/// How far in front of the plane (towards the head) each layer is drawn
/// (metres): the panel just behind it, buttons on it, labels and the
/// pointer in front, so no layer fights another for depth.
const PANEL_Z: f64 = -0.001;
const LABEL_Z: f64 = 0.0008;
const POINTER_Z: f64 = 0.0015;
/// The pointer's square side (metres).
const POINTER: f64 = 0.003;

impl PaletteView {
    /// The palette as quads and labels in world space ([`PaletteDraw`]).
    pub fn draw_list(&self) -> PaletteDraw {
        let q = self.pose.orientation;
        let (x, y, z) = (q * DVec3::X, q * DVec3::Y, q * DVec3::Z);
        let c = self.pose.position;
        let at = |px: f64, py: f64, dz: f64| c + x * px + y * py + z * dz;
        let rect = |a: DVec3, w: f64, h: f64| [a, a + x * w, a + x * w + y * h, a + y * h];
        let (w, h) = (self.size[0], self.size[1]);
        let mut out = PaletteDraw::default();
        out.quads.push(PaletteQuad {
            corners: rect(at(-w / 2.0, -h / 2.0, PANEL_Z), w, h),
            role: PaletteRole::Panel,
        });
        for (k, it) in self.items.iter().enumerate() {
            let [x0, y0, x1, y1] = it.rect;
            let (bw, bh) = (x1 - x0, y1 - y0);
            let header = it.action == PaletteAction::None;
            if !header {
                let role = if self.hovered == Some(k) {
                    PaletteRole::Hover
                } else if it.active {
                    PaletteRole::Active
                } else {
                    PaletteRole::Button
                };
                out.quads.push(PaletteQuad {
                    corners: rect(at(x0, y0, 0.0), bw, bh),
                    role,
                });
            }
            out.labels.push(PaletteLabel {
                text: it.label.clone(),
                role: if header {
                    PaletteRole::Header
                } else {
                    PaletteRole::Label
                },
                corner: at(x0, y0, LABEL_Z),
                right: x,
                up: y,
                room: [bw, bh],
            });
        }
        if let Some(p) = self.pointer {
            let a = p + z * POINTER_Z - (x + y) * (POINTER / 2.0);
            out.quads.push(PaletteQuad {
                corners: rect(a, POINTER, POINTER),
                role: PaletteRole::Pointer,
            });
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::interact::input::Pose;
    use crate::interact::palette::PaletteItem;
    use crate::math::DQuat;

    fn view() -> PaletteView {
        let item = |action, label: &str, rect, active| PaletteItem {
            action,
            label: label.into(),
            rect,
            active,
        };
        PaletteView {
            pose: Pose {
                position: DVec3::new(0.1, 1.2, -0.3),
                // About 40 degrees about +Y.
                orientation: DQuat::from_xyzw(0.0, 0.3428978, 0.0, 0.9393727).normalize(),
            },
            size: [0.3, 0.1],
            items: vec![
                item(
                    PaletteAction::None,
                    "Tools",
                    [-0.14, 0.03, 0.14, 0.045],
                    false,
                ),
                item(
                    PaletteAction::Undo,
                    "Undo",
                    [-0.14, 0.0, -0.09, 0.02],
                    false,
                ),
                item(PaletteAction::Redo, "Redo", [-0.08, 0.0, -0.03, 0.02], true),
                item(
                    PaletteAction::Save,
                    "A very long label",
                    [-0.02, 0.0, 0.03, 0.02],
                    false,
                ),
            ],
            hovered: Some(1),
            pointer: Some(DVec3::new(0.1, 1.2, -0.3)),
        }
    }

    #[test]
    fn the_draw_list_has_the_panel_a_quad_per_button_and_a_label_per_item() {
        let v = view();
        let d = v.draw_list();
        let roles: Vec<_> = d.quads.iter().map(|q| q.role).collect();
        use PaletteRole::*;
        assert_eq!(roles, [Panel, Hover, Active, Button, Pointer]);
        let labels: Vec<_> = d.labels.iter().map(|l| (l.text.as_str(), l.role)).collect();
        assert_eq!(
            labels,
            [
                ("Tools", Header),
                ("Undo", Label),
                ("Redo", Label),
                ("A very long label", Label)
            ]
        );
        // The quads are the items' rectangles in the plane, layered in depth.
        for (q, dz) in d.quads.iter().zip([PANEL_Z, 0.0, 0.0, 0.0, POINTER_Z]) {
            for p in q.corners {
                assert!((v.local(p).z - dz).abs() < 1e-12, "{:?}", q.role);
            }
        }
        let undo = &d.quads[1].corners;
        assert!((v.local(undo[0]) - DVec3::new(-0.14, 0.0, 0.0)).length() < 1e-12);
        assert!((v.local(undo[2]) - DVec3::new(-0.09, 0.02, 0.0)).length() < 1e-12);
        // Counter-clockwise seen from the head (+Z).
        let n = (undo[1] - undo[0]).cross(undo[3] - undo[0]);
        assert!(n.dot(v.pose.orientation * DVec3::Z) > 0.0);
    }

    #[test]
    fn a_label_is_centred_on_its_button_and_shrinks_to_fit_it() {
        let v = view();
        let d = v.draw_list();
        let (cap, pad) = (0.73, PaletteLabel::PAD);
        // "Undo" fits at the full em: centred both ways.
        let (o, em) = d.labels[1].place(2.0, cap);
        assert_eq!(em, PaletteLabel::EM);
        let l = v.local(o);
        assert!((l.x - (-0.115 - em)).abs() < 1e-12, "{l}");
        assert!((l.y - (0.02 - cap * em) / 2.0).abs() < 1e-12);
        assert!((l.z - LABEL_Z).abs() < 1e-12);
        // The long one shrinks to the button less a pad each side.
        let (o, em) = d.labels[3].place(8.0, cap);
        assert!(em < PaletteLabel::EM);
        assert!((8.0 * em - (0.05 - 2.0 * pad)).abs() < 1e-12);
        assert!((v.local(o).x - (-0.02 + pad)).abs() < 1e-12);
        // A header starts at its room's left edge.
        let (o, _) = d.labels[0].place(3.0, cap);
        assert!((v.local(o).x - -0.14).abs() < 1e-12);
        // Empty text never divides by zero.
        let (o, em) = d.labels[1].place(0.0, cap);
        assert!(o.is_finite() && em == PaletteLabel::EM);
    }

    #[test]
    fn every_role_has_a_colour_and_a_distinct_name() {
        let names: std::collections::BTreeSet<_> =
            PaletteRole::ALL.iter().map(|r| r.name()).collect();
        assert_eq!(names.len(), PaletteRole::ALL.len());
        for r in PaletteRole::ALL {
            assert!(r.color().iter().all(|c| (0.0..=1.0).contains(c)));
        }
        assert_ne!(PaletteRole::Active.color(), PaletteRole::Button.color());
    }
}
