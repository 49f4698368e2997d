//! What the headset shows besides the model: the off hand's palette (from
//! the core's [`PaletteView`]: panel, buttons, labels, hover and pointer),
//! the active tool and its choices next to the dominant hand, the live
//! readout of a drag, and refused edits as short red messages that fade.
//! All of it is flat triangles in world space ([`Scene::ui`](crate::gfx::Scene::ui)); the layout
//! and picking are the core's, so this only draws.

use glam::{DVec3, Quat, Vec3};
use shapewright::interact::{palette::facing, Frame, Hand, PaletteRole, PaletteView, Session};
use shapewright::math::fm::DetMath as _;

use crate::gfx::text::{quad, Baseline, Font};
use crate::gfx::LineVertex;

const PANEL: [f32; 3] = PaletteRole::Panel.color();
const STATUS: [f32; 3] = [0.85, 0.9, 0.95];
const READOUT: [f32; 3] = [0.98, 0.8, 0.4];
const REFUSED: [f32; 3] = [1.0, 0.35, 0.3];
/// Seconds a refused-edit message stays, the last of them fading.
pub const MESSAGE_SECS: f64 = 4.0;

/// The em height of the status line next to the hand (metres).
const STATUS_EM: f32 = 0.012;

fn v3(v: DVec3) -> Vec3 {
    v.as_vec3()
}

/// Draws the palette into `out`: the core's draw list
/// ([`PaletteView::draw_list`]) rasterized, its labels measured with `font`.
pub fn palette(font: &mut Font, view: &PaletteView, out: &mut Vec<LineVertex>) {
    let d = view.draw_list();
    for q in &d.quads {
        let [a, b, _, c] = q.corners;
        quad(out, v3(a), v3(b - a), v3(c - a), q.role.color());
    }
    let cap = f64::from(font.cap_height());
    for l in &d.labels {
        let (origin, em) = l.place(f64::from(font.width(&l.text, 1.0)), cap);
        let line = Baseline {
            origin: v3(origin),
            right: v3(l.right),
            up: v3(l.up),
        };
        font.push(out, &l.text, line, em as f32, l.role.color());
    }
}

/// Text lines stacked upward above `anchor`, facing `head`.
fn lines_at(
    font: &mut Font,
    anchor: DVec3,
    head: Option<shapewright::interact::Pose>,
    lines: &[(&str, [f32; 3])],
    out: &mut Vec<LineVertex>,
) {
    let q: Quat = facing(anchor, head).as_quat();
    let (x, y, z) = (q * Vec3::X, q * Vec3::Y, q * Vec3::Z);
    let mut base = v3(anchor) + y * 0.05 + z * 0.01;
    for (text, color) in lines.iter().rev() {
        if text.is_empty() {
            continue;
        }
        let w = font.width(text, STATUS_EM);
        // A dark backing so the text reads against the model.
        let m = STATUS_EM * 0.3;
        quad(
            out,
            base - x * (w / 2.0 + m) - y * m - z * 0.001,
            x * (w + 2.0 * m),
            y * (STATUS_EM + m),
            PANEL,
        );
        let line = Baseline {
            origin: base - x * (w / 2.0),
            right: x,
            up: y,
        };
        font.push(out, text, line, STATUS_EM, *color);
        base += y * (STATUS_EM * 1.5);
    }
}

/// Where the dominant hand is in `frame` (controller grip, else tracked
/// palm).
fn hand_position(frame: Option<&Frame>, hand: Hand) -> Option<DVec3> {
    let f = frame?;
    f.controller(hand)
        .and_then(|c| c.grip)
        .map(|g| g.position)
        .or_else(|| {
            f.hand(hand)
                .and_then(|h| h.pos(shapewright::interact::Joint::Palm))
        })
}

/// Builds the whole overlay of a frame: palette (when open), the status
/// line with the readout next to the dominant hand, the print line (the
/// model's size in mm and whether it fits the document's printer; red
/// while it does not, so the user learns it before leaving the headset),
/// and `message` (a refused edit, wrapped into lines, with its age in
/// seconds) while it is fresh.
pub fn overlay(
    font: &mut Font,
    session: &Session,
    frame: Option<&Frame>,
    message: Option<(&str, f64)>,
    print: Option<&shapewright::print::PrintStatus>,
    out: &mut Vec<LineVertex>,
) {
    out.clear();
    if let Some(view) = session.palette() {
        palette(font, view, out);
    }
    let head = frame.and_then(|f| f.head);
    let Some(hand) = hand_position(frame, Hand::Right) else {
        return;
    };
    let p = session.preview();
    let status = format!("{}  {}", session.tool().name().to_uppercase(), p.mode);
    let mut lines: Vec<(&str, [f32; 3])> = Vec::new();
    if let Some((m, age)) = message {
        let k = (1.0 - age / MESSAGE_SECS).clamp(0.0, 1.0) as f32;
        let color = REFUSED.map(|c| c * k + PANEL[0] * (1.0 - k));
        lines.extend(m.lines().map(|l| (l, color)));
    }
    lines.push((status.trim_end(), STATUS));
    lines.push((&p.readout, READOUT));
    let print_line = print.map(|s| (s.line(), if s.warn() { REFUSED } else { STATUS }));
    if let Some((text, color)) = &print_line {
        lines.push((text, *color));
    }
    lines_at(font, hand, head, &lines, out);
}

fn line(out: &mut Vec<LineVertex>, a: Vec3, b: Vec3, color: [f32; 3]) {
    out.push(LineVertex {
        pos: a.to_array(),
        color,
    });
    out.push(LineVertex {
        pos: b.to_array(),
        color,
    });
}

/// The 12 edges of a box given its corners (corner `i` has bit 0 set for
/// +x, bit 1 for +y, bit 2 for +z).
fn box_edges(out: &mut Vec<LineVertex>, corner: impl Fn(usize) -> Vec3, color: [f32; 3]) {
    for i in 0..8usize {
        for bit in [1, 2, 4] {
            if i & bit == 0 {
                line(out, corner(i), corner(i | bit), color);
            }
        }
    }
}

/// A circle of `r` about `c` in the plane spanned by unit `u`, `v`.
fn circle(out: &mut Vec<LineVertex>, c: Vec3, u: Vec3, v: Vec3, r: f32, color: [f32; 3]) {
    let n = 32;
    let at = |k: usize| {
        let a = k as f32 / n as f32 * std::f32::consts::TAU;
        c + (u * a.fcos() + v * a.fsin()) * r
    };
    for k in 0..n {
        line(out, at(k), at(k + 1), color);
    }
}

const MARK: [f32; 3] = [1.0, 0.55, 0.15];
const BRUSH: [f32; 3] = [0.5, 0.85, 1.0];
const BONE: [f32; 3] = [0.75, 0.8, 0.85];
const MIRROR: [f32; 3] = [0.85, 0.45, 1.0];
/// Half the side of the drawn mirror plane (world metres).
const MIRROR_HALF: f64 = 0.2;

/// What the active tool acts on, as lines (world space): the GC tool's
/// target (a cross at the key point, section or surface point; a ring
/// filling up during a 3 s hold), the sculpt brush (its sphere, solid
/// while stroking), the curve tool's pointed curve or surface point, the
/// CSG tool's selected operand (its axes).
pub fn tool_marks(session: &Session, out: &mut Vec<LineVertex>) {
    let p = session.preview();
    let model = p.view.unwrap_or(*session.model());
    if let Some(g) = p.gc() {
        let world = g.view.map_or(model, |v| v.compose(&model));
        if let Some(t) = &g.target {
            let c = world.apply(t.point()).as_vec3();
            let s = 0.012;
            for d in [Vec3::X, Vec3::Y, Vec3::Z] {
                line(out, c - d * s, c + d * s, MARK);
            }
            if g.hold > 0.0 {
                let r = 0.02;
                let n = (32.0 * g.hold).ceil() as usize;
                for k in 0..n {
                    let a0 = k as f32 / 32.0 * std::f32::consts::TAU;
                    let a1 = (k + 1) as f32 / 32.0 * std::f32::consts::TAU;
                    let at = |a: f32| c + (Vec3::X * a.fcos() + Vec3::Y * a.fsin()) * r;
                    line(out, at(a0), at(a1), MARK);
                }
            }
        }
    }
    let mirror = session.snap().mirror.map(|m| m.plane);
    if let Some(m) = &mirror {
        // The palette's mirror plane: a square with a cross through the
        // point it was placed at.
        let n = model
            .apply_dir(DVec3::from_array(m.normal))
            .normalize_or_zero();
        let c = model.apply(DVec3::from_array(m.point));
        let u = n.any_orthonormal_vector();
        let v = n.cross(u);
        let at = |a: f64, b: f64| (c + (u * a + v * b) * MIRROR_HALF).as_vec3();
        for (a, b) in [
            ((-1.0, -1.0), (1.0, -1.0)),
            ((1.0, -1.0), (1.0, 1.0)),
            ((1.0, 1.0), (-1.0, 1.0)),
            ((-1.0, 1.0), (-1.0, -1.0)),
            ((-1.0, 0.0), (1.0, 0.0)),
            ((0.0, -1.0), (0.0, 1.0)),
        ] {
            line(out, at(a.0, a.1), at(b.0, b.1), MIRROR);
        }
    }
    if let Some(Some(b)) = p.brush() {
        let r = b.radius as f32;
        let color = if b.stroking { MARK } else { BRUSH };
        // The brush, and its mirror image where the mirrored stroke acts.
        let image = mirror.map(|m| model.apply(m.point(model.inverse().apply(b.position))));
        for c in std::iter::once(b.position).chain(image) {
            let c = c.as_vec3();
            circle(out, c, Vec3::X, Vec3::Y, r, color);
            circle(out, c, Vec3::Y, Vec3::Z, r, color);
            circle(out, c, Vec3::Z, Vec3::X, r, color);
        }
    }
    if let Some(c) = p.curve() {
        // The curve point a Table 1 tool would act on, and the surface
        // point a forced smooth, sharpen or pull would act on (a ring).
        if let Some(t) = c.target.filter(|t| t.tool.is_some()) {
            let at = model.apply(t.point).as_vec3();
            for d in [Vec3::X, Vec3::Y, Vec3::Z] {
                line(out, at - d * 0.008, at + d * 0.008, MARK);
            }
        }
        if let Some(t) = &c.patch {
            let at = model.apply(t.at.point).as_vec3();
            circle(out, at, Vec3::X, Vec3::Z, 0.015, MARK);
            circle(out, at, Vec3::X, Vec3::Y, 0.015, MARK);
        }
    }
    if let Some(m) = p.csg().and_then(|c| c.moving_operand) {
        let t = &m.transform;
        let at = model.apply(DVec3::from_array(t.translate)).as_vec3();
        let q = model.rotate * glam::DQuat::from_array(t.rotate);
        for (d, color) in [
            (DVec3::X, [1.0, 0.3, 0.3]),
            (DVec3::Y, [0.3, 1.0, 0.3]),
            (DVec3::Z, [0.3, 0.5, 1.0]),
        ] {
            line(out, at, at + (q * d).as_vec3() * 0.06, color);
        }
    }
}

/// The hands of `frame` as skeletons (wrist to each finger's tip) and its
/// controllers as small boxes at their grips, so the user sees what the
/// system tracks.
pub fn hands_and_controllers(frame: Option<&Frame>, out: &mut Vec<LineVertex>) {
    use shapewright::interact::Joint;
    let Some(f) = frame else {
        return;
    };
    for h in f.hands.iter().flatten() {
        // OpenXR joint order: palm, wrist, then five fingers of 4 (thumb)
        // or 5 joints from metacarpal to tip.
        let chains: [std::ops::Range<usize>; 5] = [2..6, 6..11, 11..16, 16..21, 21..26];
        let at = |i: usize| h.joints[i].map(|p| p.position.as_vec3());
        let wrist = at(Joint::Wrist.index());
        for chain in chains {
            let mut prev = wrist;
            for i in chain {
                let cur = at(i);
                if let (Some(a), Some(b)) = (prev, cur) {
                    line(out, a, b, BONE);
                }
                prev = cur;
            }
        }
    }
    for c in f.controllers.iter().flatten() {
        let Some(g) = c.grip else { continue };
        let q = g.orientation.as_quat();
        let o = g.position.as_vec3();
        let half = Vec3::new(0.02, 0.015, 0.05);
        let corner = |i: usize| {
            let s = Vec3::new(
                if i & 1 == 0 { -1.0 } else { 1.0 },
                if i & 2 == 0 { -1.0 } else { 1.0 },
                if i & 4 == 0 { -1.0 } else { 1.0 },
            );
            o + q * (s * half)
        };
        box_edges(out, corner, BONE);
    }
}

/// Another participant of a shared session as the headset draws them
/// (world space).
pub struct Avatar {
    /// Their name.
    pub name: String,
    /// Their colour.
    pub colour: [f32; 3],
    /// Head position and orientation, when tracked.
    pub head: Option<(Vec3, Quat)>,
    /// Left and right hand, when tracked.
    pub hands: [Option<Vec3>; 2],
    /// The corners of the box around what they selected (corner `i` has
    /// bit 0 for +x, bit 1 for +y, bit 2 for +z).
    pub selected: Option<[Vec3; 8]>,
}

/// The em height of the name above an avatar's head (metres).
const NAME_EM: f32 = 0.03;

/// Others as simple avatars: the head as a ring in the plane of their face
/// with a line where they look, hands as small crosses joined to the head,
/// their selection as a box, all in their colour, and their name above
/// the head facing the viewer (`viewer`: this person's head).
pub fn avatars(
    font: &mut Font,
    others: &[Avatar],
    viewer: Option<shapewright::interact::Pose>,
    lines: &mut Vec<LineVertex>,
    ui: &mut Vec<LineVertex>,
) {
    for a in others {
        let c = a.colour;
        let dim = c.map(|x| x * 0.6);
        if let Some((h, q)) = a.head {
            circle(lines, h, q * Vec3::X, q * Vec3::Y, 0.1, c);
            line(lines, h, h + q * Vec3::NEG_Z * 0.18, c);
            line(lines, h - Vec3::Y * 0.1, h - Vec3::Y * 0.3, dim);
            for hand in a.hands.iter().flatten() {
                line(lines, h - Vec3::Y * 0.3, *hand, dim);
            }
            let label = DVec3::from(h + Vec3::Y * 0.13);
            let em = NAME_EM / STATUS_EM;
            // The status lines' layout at the name's size.
            let mut text = Vec::new();
            lines_at(font, label, viewer, &[(a.name.as_str(), c)], &mut text);
            let anchor = v3(label);
            ui.extend(text.into_iter().map(|v| LineVertex {
                pos: (anchor + (Vec3::from(v.pos) - anchor) * em).to_array(),
                color: v.color,
            }));
        }
        for p in a.hands.iter().flatten() {
            for axis in [Vec3::X, Vec3::Y, Vec3::Z] {
                line(lines, *p - axis * 0.03, *p + axis * 0.03, c);
            }
        }
        if let Some(k) = &a.selected {
            box_edges(lines, |i| k[i], c);
        }
    }
}
