//! [`Driver`]: a puppet and a modeler [`Session`] in lockstep, so a script
//! can open the palette, find an item where the session draws it, aim the
//! dominant controller at it and click — the way a user picks from the
//! palette. What it records is an ordinary modeler trace: replaying it
//! (without the driver) gives the same commands, bit for bit.

use crate::doc::{OpLog, ScriptCommand};
use crate::math::{DQuat, DVec3};

use super::{Button, Puppet};
use crate::interact::input::{Hand, Pose};
use crate::interact::palette::{PaletteAction, PaletteItem, PaletteView};
use crate::interact::session::Session;
use crate::interact::tools::TOOL_NAMES;
use crate::interact::trace::{ModelPlacement, Trace, TraceHeader, TRACE_FORMAT, TRACE_VERSION};

const R: Hand = Hand::Right;
const L: Hand = Hand::Left;

/// A puppet driving a modeler session, the log applied as it goes.
pub struct Driver {
    /// The puppet (script moves and presses on it, then [`Driver::sync`]).
    pub puppet: Puppet,
    session: Session,
    /// The log the session's commands are applied to.
    pub log: OpLog,
    fed: usize,
    start: String,
    model: ModelPlacement,
    /// Commands produced so far.
    pub commands: Vec<ScriptCommand>,
    /// Commands the log refused (message of each).
    pub rejected: Vec<String>,
    /// Saves asked for through the palette.
    pub saves: usize,
}

impl Driver {
    /// A modeler session at `fps` with `start` active, the model on the
    /// desk, the head looking down at it, both controllers in front of the
    /// user (left lower, holding the palette).
    pub fn new(fps: f64, start: &str) -> Driver {
        let model = ModelPlacement::desk();
        let session = Session::modeler(start, R, model.similarity().expect("desk placement"))
            .expect("a registered tool");
        let mut puppet = Puppet::new(fps);
        // Looking down at the desk, where the model and the hands are.
        puppet
            .look_at(DVec3::new(0.0, 0.95, -0.5))
            .controller(L, Pose::new(DVec3::new(-0.25, 1.05, -0.3), DQuat::IDENTITY))
            .controller(R, Pose::new(DVec3::new(0.2, 1.1, -0.3), DQuat::IDENTITY));
        Driver {
            puppet,
            session,
            log: OpLog::new(),
            fed: 0,
            start: start.to_string(),
            model,
            commands: Vec::new(),
            rejected: Vec::new(),
            saves: 0,
        }
    }

    /// Feeds the frames the puppet recorded since the last sync.
    pub fn sync(&mut self) -> &mut Self {
        let frames = &self.puppet.frames()[self.fed..];
        for f in frames {
            if let Some(cmd) = self.session.step(f, self.log.document()) {
                if let Err(e) = self.log.apply_command(&cmd) {
                    self.rejected.push(format!("{}: {e}", cmd.name()));
                }
                self.commands.push(cmd);
            }
            self.saves += self.session.take_save_requests() as usize;
        }
        self.fed = self.puppet.frames().len();
        self
    }

    /// The session (after a [`Driver::sync`]).
    pub fn session(&self) -> &Session {
        &self.session
    }

    /// Opens the palette (the left menu button) unless it is open.
    pub fn open_palette(&mut self) -> &mut Self {
        self.sync();
        if self.session.palette().is_none() {
            self.puppet.click(L, Button::Menu);
            self.sync();
        }
        self
    }

    /// Closes the palette if it is open.
    pub fn close_palette(&mut self) -> &mut Self {
        self.sync();
        if self.session.palette().is_some() {
            self.puppet.click(L, Button::Menu);
            self.sync();
        }
        self
    }

    /// Aims the right controller at the first item `which` accepts and
    /// clicks the trigger. Errors name what was missing.
    pub fn pick(&mut self, which: impl Fn(&PaletteItem) -> bool) -> Result<&mut Self, String> {
        self.open_palette();
        let view: PaletteView = self
            .session
            .palette()
            .ok_or("the palette is closed")?
            .clone();
        let k = view
            .items
            .iter()
            .position(|i| i.action != PaletteAction::None && which(i))
            .ok_or_else(|| format!("no such item among {:?}", view.labels()))?;
        let r = view.items[k].rect;
        let target = view.to_world((r[0] + r[2]) / 2.0, (r[1] + r[3]) / 2.0);
        let n = view.pose.orientation * DVec3::Z;
        let side = view.pose.orientation * DVec3::X;
        let from = view.pose.position + n * 0.3 + side * 0.25 - DVec3::Y * 0.05;
        self.puppet.aim(R, from, target, 0.15);
        self.sync();
        let hovered = self.session.palette().and_then(|v| v.hovered);
        if hovered != Some(k) {
            return Err(format!(
                "aimed at `{}` but the palette shows {hovered:?} hovered",
                view.items[k].label
            ));
        }
        self.puppet.click(R, Button::Select);
        self.sync();
        Ok(self)
    }

    /// Picks the tool called `name`.
    pub fn pick_tool(&mut self, name: &str) -> Result<&mut Self, String> {
        let k = TOOL_NAMES
            .iter()
            .position(|n| *n == name)
            .ok_or_else(|| format!("no tool {name}"))?;
        self.pick(|i| i.action == PaletteAction::Tool(k))
    }

    /// Picks `action` (undo, redo, save, grid, angle).
    pub fn pick_action(&mut self, action: PaletteAction) -> Result<&mut Self, String> {
        self.pick(|i| i.action == action)
    }

    /// Picks option `option` of the active tool's group `group`, paging
    /// forward until it is shown.
    pub fn pick_choice(&mut self, group: usize, option: usize) -> Result<&mut Self, String> {
        let shown = |i: &PaletteItem| i.action == PaletteAction::Choice { group, option };
        for _ in 0..64 {
            self.open_palette();
            let view = self.session.palette().ok_or("the palette is closed")?;
            if view.items.iter().any(shown) {
                return self.pick(shown);
            }
            let next = PaletteAction::Page { group, delta: 1 };
            if !view.items.iter().any(|i| i.action == next) {
                return Err(format!("group {group} has no option {option}"));
            }
            self.pick(|i| i.action == next)?;
        }
        Err(format!("option {option} of group {group} never showed"))
    }

    /// The recorded trace (a modeler trace starting with the first tool).
    pub fn trace(&self, note: &str) -> Trace {
        let t = self.puppet.trace(self.model, note);
        Trace {
            header: TraceHeader {
                format: TRACE_FORMAT.to_string(),
                version: TRACE_VERSION,
                tool: self.start.clone(),
                modeler: true,
                ..t.header
            },
            frames: t.frames,
        }
    }
}
