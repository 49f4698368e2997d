//! [`Session`]: the per-frame driver both hosts run — sanitizer, one
//! gesture classifier per hand, and the active tool. For a tool that reads
//! hands, an untracked hand with a controller is made from the controller
//! ([`crate::interact::gesture::controller_hand`]).
//!
//! Two kinds of session:
//! - [`Session::modeler`] (what `run` and the Blender VR session use): every
//!   tool of [`TOOL_NAMES`] at once, switched through the off hand's
//!   [`crate::interact::palette`] without losing the document, the history or
//!   any tool's choices. The off hand's controller `menu` button toggles
//!   the palette; a tracked off hand held palm up shows it while it stays
//!   up. The dominant hand picks: its controller ray and the trigger's
//!   press edge, or its index fingertip touching an item. While the
//!   pointer is on the palette, the active tool does not see the dominant
//!   hand's buttons (a pick is never also an edit), and the off hand's
//!   `menu` press never reaches a tool.
//! - [`Session::new`]: one tool, no palette (single-tool traces recorded
//!   before the modeler, and tools under test).

use crate::doc::{Document, ScriptCommand};
use crate::math::MirrorPlane;

use crate::interact::gesture::controller_hand::controller_hand;
use crate::interact::gesture::similarity::Similarity;
use crate::interact::gesture::{GestureClassifier, GestureState};
use crate::interact::input::{
    ControllerButtons, Frame, Hand, HandJoints, InputFrame, Joint, Sanitizer,
};
use crate::interact::palette::{
    self, facing, LayoutInput, Mirror, MirrorMode, PaletteAction, PaletteView, Snap, ANGLE_STEPS,
    GRID_STEPS, LIFT, TOUCH,
};
use crate::interact::tools::{tool_named, Preview, Tool, ToolContext, UnknownTool, TOOL_NAMES};

/// Palm normal · world up above which an off hand counts as palm up.
const PALM_UP: f64 = 0.7;

/// The palette state of a modeler session.
struct Modeler {
    dominant: Hand,
    /// Opened by the menu button (stays until pressed again).
    open_by_button: bool,
    /// Shown because the off hand is palm up.
    open_by_palm: bool,
    /// The page shown of each tool's groups.
    pages: Vec<Vec<usize>>,
    snap: Snap,
    view: Option<PaletteView>,
    prev_menu: bool,
    prev_select: bool,
    /// The fingertip was in the touch zone last frame.
    touching: bool,
    /// The dominant hand's thumb and index touched last frame.
    pinched: bool,
    /// The item the hand's ray last hovered, and when.
    hover_seen: Option<(usize, f64)>,
    /// The dominant trigger went down on the palette and is still held:
    /// its buttons stay hidden from the tools until it is released, even
    /// if the palette changed shape or closed under it.
    held: bool,
    saves: u32,
}

/// Raw frames in, at most one command per frame out.
pub struct Session {
    sanitizer: Sanitizer,
    /// The sanitizer of [`Session::display_frame`] (its own state, so the
    /// tool's input counts are not touched).
    display_sanitizer: Sanitizer,
    classifiers: [GestureClassifier; 2],
    gestures: [GestureState; 2],
    model: Similarity,
    tools: Vec<Box<dyn Tool>>,
    active: usize,
    modeler: Option<Modeler>,
    last_frame: Option<Frame>,
}

impl Session {
    /// A session running `tool` alone, with the document placed in the
    /// world by `model` (model to stage space).
    pub fn new(tool: Box<dyn Tool>, model: Similarity) -> Self {
        Self::with_tools(vec![tool], 0, None, model)
    }

    /// A modeler session: every tool, `start` active, the palette on the
    /// hand other than `dominant`.
    pub fn modeler(start: &str, dominant: Hand, model: Similarity) -> Result<Self, UnknownTool> {
        let tools = TOOL_NAMES
            .iter()
            .map(|n| tool_named(n))
            .collect::<Result<Vec<_>, _>>()?;
        let active = TOOL_NAMES
            .iter()
            .position(|n| *n == start)
            .ok_or_else(|| UnknownTool(start.to_string()))?;
        let pages = tools.iter().map(|t| vec![0; t.choices().len()]).collect();
        let m = Modeler {
            dominant,
            open_by_button: false,
            open_by_palm: false,
            pages,
            snap: Snap::default(),
            view: None,
            prev_menu: false,
            prev_select: false,
            touching: false,
            pinched: false,
            hover_seen: None,
            held: false,
            saves: 0,
        };
        Ok(Self::with_tools(tools, active, Some(m), model))
    }

    fn with_tools(
        tools: Vec<Box<dyn Tool>>,
        active: usize,
        modeler: Option<Modeler>,
        model: Similarity,
    ) -> Self {
        let classifiers = [GestureClassifier::default(), GestureClassifier::default()];
        let gestures = [classifiers[0].state(), classifiers[1].state()];
        Self {
            sanitizer: Sanitizer::default(),
            display_sanitizer: Sanitizer::default(),
            classifiers,
            gestures,
            model,
            tools,
            active,
            modeler,
            last_frame: None,
        }
    }

    /// Feeds one raw frame. A frame the sanitizer rejects changes nothing
    /// and returns `None`.
    pub fn step(&mut self, raw: &InputFrame, doc: &Document) -> Option<ScriptCommand> {
        let mut frame = self.sanitizer.accept(raw)?;
        let mut palette_cmd = None;
        if self.modeler.is_some() {
            palette_cmd = self.palette_step(&mut frame, doc);
        }
        self.hands_from_controllers(&mut frame);
        let tool = &mut self.tools[self.active];
        for (i, c) in self.classifiers.iter_mut().enumerate() {
            self.gestures[i] = c.update(frame.time, frame.hands[i].as_ref(), frame.head.as_ref());
        }
        let out = if palette_cmd.is_some() {
            // At most one command per frame: the pick's. The tool skips
            // this frame (its buttons were masked anyway).
            palette_cmd
        } else {
            let cx = ToolContext {
                frame: &frame,
                gestures: &self.gestures,
                doc,
                model: &self.model,
                snap: self.modeler.as_ref().map_or(Snap::default(), |m| m.snap),
            };
            tool.update(&cx)
        };
        self.last_frame = Some(frame);
        out
    }

    /// A tool that works with hands gets a hand made from each controller
    /// where no hand is tracked.
    fn hands_from_controllers(&self, frame: &mut Frame) {
        if self.tools[self.active].uses_hands() {
            for hand in Hand::BOTH {
                let i = hand.index();
                if frame.hands[i].is_none() {
                    frame.hands[i] = frame.controllers[i]
                        .as_ref()
                        .and_then(|c| controller_hand(c, hand));
                }
            }
        }
    }

    /// The newest input as the user's head, hands and controllers are
    /// drawn from it, for a frame the tool has not stepped yet (a host
    /// holds frames while a command of the tool's is being committed):
    /// sanitized as [`Session::step`] does, by a sanitizer of its own, with
    /// the hands the tool makes from controllers. `None` when the frame is
    /// unusable (bad time).
    pub fn display_frame(&mut self, raw: &InputFrame) -> Option<Frame> {
        let mut frame = self.display_sanitizer.accept(raw)?;
        self.hands_from_controllers(&mut frame);
        Some(frame)
    }

    /// The palette part of a modeler frame: open or close it, lay it out,
    /// point at it, pick. Masks the inputs the palette consumed.
    fn palette_step(&mut self, frame: &mut Frame, doc: &Document) -> Option<ScriptCommand> {
        let m = self.modeler.as_mut()?;
        let off = m.dominant.other().index();
        let dom = m.dominant.index();
        // The off hand's menu button toggles; the press never reaches a tool.
        let menu = frame.controllers[off]
            .as_ref()
            .and_then(|c| c.buttons)
            .is_some_and(|b| b.menu);
        if menu && !m.prev_menu {
            m.open_by_button = !m.open_by_button;
        }
        m.prev_menu = menu;
        if let Some(b) = frame.controllers[off]
            .as_mut()
            .and_then(|c| c.buttons.as_mut())
        {
            b.menu = false;
        }
        // A tracked off hand palm up shows it.
        let palm = frame.hands[off].as_ref().and_then(|h| h.pose(Joint::Palm));
        m.open_by_palm =
            palm.is_some_and(|p| (p.orientation * -glam::DVec3::Y).dot(glam::DVec3::Y) > PALM_UP);
        let select = select_of(frame, dom);
        m.held &= select;
        if m.held {
            mask_buttons(frame, dom);
        }
        if !(m.open_by_button || m.open_by_palm) {
            m.view = None;
            m.touching = false;
            m.prev_select = select;
            return None;
        }
        let anchor = frame.controllers[off]
            .as_ref()
            .and_then(|c| c.grip)
            .map(|g| g.position)
            .or(palm.map(|p| p.position));
        let Some(anchor) = anchor else {
            // Nothing to hold it: hide it until the off hand is back.
            m.view = None;
            return None;
        };
        let head = frame.head;
        let groups = self.tools[self.active].choices();
        let pages = &mut m.pages[self.active];
        pages.resize(groups.len(), 0);
        let (items, size) = palette::layout(&LayoutInput {
            tools: &palette::TOOL_LABELS,
            active_tool: self.active,
            groups: &groups,
            pages,
            snap: m.snap,
        });
        let center = anchor + glam::DVec3::Y * (LIFT + size[1] / 2.0);
        let mut view = PaletteView {
            pose: crate::interact::input::Pose::new(center, facing(center, head)),
            size,
            items,
            hovered: None,
            pointer: None,
        };
        // Point: the dominant controller's aim ray, else its fingertip.
        let mut picked = false;
        let aim = frame.controllers[dom].as_ref().and_then(|c| c.aim);
        if let Some(aim) = aim {
            let dir = aim.orientation * -glam::DVec3::Z;
            if let Some((x, y, t)) = view.ray_hit(aim.position, dir) {
                view.pointer = Some(aim.position + dir * t);
                view.hovered = view.item_at(x, y);
                picked = select && !m.prev_select;
                m.held |= picked;
                mask_buttons(frame, dom);
            }
            m.touching = false;
        } else if let Some(tip) = frame.hands[dom]
            .as_ref()
            .and_then(|h| h.pos(Joint::IndexTip))
        {
            let l = view.local(tip);
            let inside = l.x.abs() <= view.size[0] / 2.0 && l.y.abs() <= view.size[1] / 2.0;
            let near = inside && l.z > -2.0 * TOUCH && l.z < 4.0 * TOUCH;
            let touching = inside && l.z > -2.0 * TOUCH && l.z < TOUCH;
            let pinched = frame.hands[dom].as_ref().and_then(pinch_closed);
            if near {
                view.pointer = Some(view.to_world(l.x, l.y));
                view.hovered = view.item_at(l.x, l.y);
                picked = touching && !m.touching;
                frame.hands[dom] = None;
            } else if let Some((origin, dir)) = frame.hands[dom].as_ref().and_then(hand_ray) {
                // From afar: the hand's ray (wrist through the index
                // knuckle), picked by closing a pinch. Closing a pinch
                // jolts the knuckle (and tracking jitters), so the pick
                // goes to what the ray hovered up to PINCH_MEMORY ago.
                if let Some((x, y, t)) = view.ray_hit(origin, dir) {
                    view.pointer = Some(origin + dir * t);
                    view.hovered = view.item_at(x, y);
                    frame.hands[dom] = None;
                }
                if let Some(k) = view.hovered {
                    m.hover_seen = Some((k, frame.time));
                }
                if pinched == Some(true) && !m.pinched {
                    let recent = m
                        .hover_seen
                        .filter(|(_, t)| frame.time - t <= PINCH_MEMORY)
                        .map(|(k, _)| k);
                    if view.hovered.is_none() {
                        view.hovered = recent;
                    }
                    picked = view.hovered.is_some();
                }
            }
            m.touching = touching;
            m.pinched = pinched.unwrap_or(false);
        }
        m.prev_select = select;
        let action = view
            .hovered
            .filter(|_| picked)
            .map(|i| view.items[i].action);
        m.view = Some(view);
        let action = action?;
        self.apply(action, doc, frame)
    }

    /// Does what a picked item says.
    fn apply(
        &mut self,
        action: PaletteAction,
        doc: &Document,
        frame: &Frame,
    ) -> Option<ScriptCommand> {
        let m = self.modeler.as_mut()?;
        match action {
            PaletteAction::Tool(i) if i < self.tools.len() => {
                if i != self.active {
                    self.tools[self.active].cancel();
                    self.active = i;
                }
                None
            }
            PaletteAction::Choice { group, option } => {
                self.tools[self.active].choose(doc, group, option)
            }
            PaletteAction::Page { group, delta } => {
                let n = self.tools[self.active]
                    .choices()
                    .get(group)
                    .map_or(1, |g| g.options.len().div_ceil(palette::PAGE).max(1));
                if let Some(p) = m.pages[self.active].get_mut(group) {
                    *p = (*p as i64 + delta as i64).rem_euclid(n as i64) as usize;
                }
                None
            }
            PaletteAction::Undo => Some(ScriptCommand::Undo),
            PaletteAction::Redo => Some(ScriptCommand::Redo),
            PaletteAction::Save => {
                m.saves += 1;
                None
            }
            PaletteAction::Grid => {
                m.snap.grid = next_step(&GRID_STEPS, m.snap.grid);
                None
            }
            PaletteAction::Angle => {
                m.snap.angle = next_step(&ANGLE_STEPS, m.snap.angle);
                None
            }
            PaletteAction::Objects => {
                m.snap.objects = !m.snap.objects;
                None
            }
            PaletteAction::Mirror => {
                let off = m.dominant.other().index();
                let tool = &self.tools[self.active];
                let centre = tool.mirror_centre(doc);
                // The tool's own view of the model (the sculpt tool turns
                // it), else the session's.
                let model = tool.preview().view.unwrap_or(self.model);
                let mut mode = m.snap.mirror.map(|x| x.mode);
                // A mode that cannot be placed now (no off hand for "at
                // hand") is passed over.
                m.snap.mirror = loop {
                    mode = MirrorMode::next(mode);
                    let Some(next) = mode else { break None };
                    if let Some(plane) = mirror_plane(next, centre, doc, frame, off, &model) {
                        break Some(Mirror { mode: next, plane });
                    }
                };
                None
            }
            PaletteAction::Tool(_) | PaletteAction::None => None,
        }
    }

    /// Switches the active tool's slot to another tool, cancelling any
    /// gesture of the old one.
    pub fn set_tool(&mut self, tool: Box<dyn Tool>) {
        self.tools[self.active].cancel();
        self.tools[self.active] = tool;
    }

    /// Makes the tool named `name` active (a modeler session: the tool
    /// keeps its choices; a single-tool session: a fresh tool).
    pub fn select_tool(&mut self, name: &str) -> Result<(), UnknownTool> {
        match self.tools.iter().position(|t| t.name() == name) {
            Some(i) if self.modeler.is_some() => {
                if i != self.active {
                    self.tools[self.active].cancel();
                    self.active = i;
                }
                Ok(())
            }
            _ => {
                let t = tool_named(name)?;
                if self.modeler.is_some() {
                    return Err(UnknownTool(name.to_string()));
                }
                self.set_tool(t);
                Ok(())
            }
        }
    }

    /// The active tool.
    pub fn tool(&self) -> &dyn Tool {
        self.tools[self.active].as_ref()
    }

    /// The active tool's preview.
    pub fn preview(&self) -> &Preview {
        self.tools[self.active].preview()
    }

    /// The palette to draw, when open (modeler sessions only).
    pub fn palette(&self) -> Option<&PaletteView> {
        self.modeler.as_ref()?.view.as_ref()
    }

    /// Snapping now (off outside a modeler session).
    pub fn snap(&self) -> Snap {
        self.modeler.as_ref().map_or(Snap::default(), |m| m.snap)
    }

    /// Saves asked for through the palette since the last call (the host
    /// saves; the core has no files).
    pub fn take_save_requests(&mut self) -> u32 {
        self.modeler
            .as_mut()
            .map_or(0, |m| std::mem::take(&mut m.saves))
    }

    /// The gestures of the left and right hand.
    pub fn gestures(&self) -> &[GestureState; 2] {
        &self.gestures
    }

    /// The last accepted frame.
    pub fn last_frame(&self) -> Option<&Frame> {
        self.last_frame.as_ref()
    }

    /// What the input sanitizer accepted and dropped so far.
    pub fn input_stats(&self) -> crate::interact::input::SanitizerStats {
        self.sanitizer.stats()
    }

    /// The model placement.
    pub fn model(&self) -> &Similarity {
        &self.model
    }
}

/// How long (seconds) an item stays pickable by a pinch after the hand's
/// ray left it.
const PINCH_MEMORY: f64 = 0.15;

/// Thumb and index tips closer than this pick (metres): the gesture
/// classifier's "pinch closed" threshold.
const PINCH_PICK: f64 = 0.014;

/// A tracked hand's thumb and index tips touch (`None`: not tracked).
fn pinch_closed(h: &HandJoints) -> Option<bool> {
    Some(h.pos(Joint::ThumbTip)?.distance(h.pos(Joint::IndexTip)?) < PINCH_PICK)
}

/// A tracked hand's pointing ray: from the index knuckle, along the
/// wrist-to-knuckle direction (stable while the fingers pinch).
fn hand_ray(h: &HandJoints) -> Option<(glam::DVec3, glam::DVec3)> {
    let (wrist, knuckle) = (h.pos(Joint::Wrist)?, h.pos(Joint::IndexProximal)?);
    let dir = (knuckle - wrist).normalize_or_zero();
    (dir != glam::DVec3::ZERO).then_some((knuckle, dir))
}

fn select_of(frame: &Frame, hand: usize) -> bool {
    frame.controllers[hand]
        .as_ref()
        .and_then(|c| c.buttons)
        .is_some_and(|b| b.select > 0.5)
}

fn mask_buttons(frame: &mut Frame, hand: usize) {
    if let Some(b) = frame.controllers[hand]
        .as_mut()
        .and_then(|c| c.buttons.as_mut())
    {
        *b = ControllerButtons::default();
    }
}

/// The step after `now` in `steps`, wrapping (the first when `now` is not
/// one of them).
fn next_step(steps: &[f64], now: f64) -> f64 {
    let i = steps.iter().position(|s| *s == now).map_or(0, |i| i + 1);
    steps[i % steps.len()]
}

/// The mirror plane `mode` places (document space): across a document
/// axis through `centre` (the active tool's object), else through the
/// centre of the document's bounds, else the origin; or through the off
/// hand's grip across its sideways axis. `None` when the off hand is not
/// tracked for [`MirrorMode::Hand`].
fn mirror_plane(
    mode: MirrorMode,
    centre: Option<glam::DVec3>,
    doc: &Document,
    frame: &Frame,
    off: usize,
    model: &Similarity,
) -> Option<MirrorPlane> {
    use glam::DVec3;
    let centre = || {
        centre
            .or_else(|| {
                let (lo, hi) = doc
                    .objects()
                    .filter_map(|(_, o)| o.mesh.bbox())
                    .reduce(|a, b| (a.0.min(b.0), a.1.max(b.1)))?;
                Some((lo + hi) * 0.5)
            })
            .unwrap_or(DVec3::ZERO)
    };
    let (point, normal) = match mode {
        MirrorMode::X => (centre(), DVec3::X),
        MirrorMode::Y => (centre(), DVec3::Y),
        MirrorMode::Z => (centre(), DVec3::Z),
        MirrorMode::Hand => {
            let grip = frame.controllers[off]
                .as_ref()
                .and_then(|c| c.grip)
                .or_else(|| frame.hands[off].as_ref().and_then(|h| h.pose(Joint::Palm)))?;
            let to_doc = model.inverse();
            (
                to_doc.apply(grip.position),
                to_doc.apply_dir(grip.orientation * DVec3::X),
            )
        }
    };
    MirrorPlane::new(point, normal).ok()
}
