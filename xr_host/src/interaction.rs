//! The interaction step both frame loops (headset, headless) and `replay`
//! run: one raw [`interact::InputFrame`] in, a
//! [`shapewright::interact::Session`] stepped, its command applied to the
//! [`OpLog`], autosave ticked, and the [`Scene`] (document mesh, drag
//! preview, rays and sketch) brought up to date for the renderer.
//!
//! Persistence: an optional [`Autosaver`] saves the log as USD (with its
//! history, so `run --open` continues it and undo works) every N changes
//! or T seconds, and [`Interaction::save_now`] is called on session loss,
//! instance loss and exit. A failed save is reported (stderr and
//! [`InteractionStats::save_errors`]) and retried at the next trigger; it
//! never stops the session.
//!
//! Tools come from [`interact::tool_named`], so every tool the core
//! registers is available to `--tool` without a list here.

use std::sync::Arc;

use glam::{DMat4, Mat4};
use shapewright::doc::{OpLog, ScriptCommand};
use shapewright::interact::{self, apply_command, tool_named, Session, Similarity, TraceError};
use shapewright::mesh::TriMesh;
use shapewright_usd::Autosaver;

use crate::gfx::LineVertex;
use crate::xr::{FrameSink, InputFrame, LifecycleEvent};

/// What the renderer draws for the document and the active tool.
#[derive(Clone, Debug, Default)]
pub struct Scene {
    /// Bumped whenever [`Scene::document`] changes (re-upload then).
    pub version: u64,
    /// All objects of the document in one mesh (model space, normals set);
    /// None when the document is empty.
    pub document: Option<Arc<TriMesh>>,
    /// World (stage) from model.
    pub model_to_world: Mat4,
    /// The object being dragged, where it would land (model space).
    pub preview: Option<Arc<TriMesh>>,
    /// Rays and the sketch in progress (world space), as segment pairs.
    pub lines: Vec<LineVertex>,
}

/// Counters of an interaction run.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct InteractionStats {
    /// Frames stepped.
    pub frames: u64,
    /// Commands the tool produced.
    pub commands: u64,
    /// Commands the log refused (the message of each).
    pub rejected: Vec<String>,
    /// Saves done (autosave, loss, exit).
    pub saves: usize,
    /// Saves that failed (the message of each).
    pub save_errors: Vec<String>,
}

/// A session, its log, its autosaver and the scene.
pub struct Interaction {
    session: Session,
    log: OpLog,
    autosave: Option<Autosaver>,
    scene: Scene,
    stats: InteractionStats,
}

const RAY_COLORS: [[f32; 3]; 2] = [[0.3, 0.6, 1.0], [1.0, 0.5, 0.2]];
const HIT_COLOR: [f32; 3] = [0.3, 1.0, 0.4];
const SKETCH_COLOR: [f32; 3] = [1.0, 0.9, 0.2];

fn to_mat4(s: &Similarity) -> Mat4 {
    Mat4::from_cols_array(&DMat4::from(s.to_affine()).to_cols_array().map(|x| x as f32))
}

impl Interaction {
    /// Runs the tool named `tool` on `log` (empty, or loaded to continue
    /// its history), the document placed in the stage by `model`.
    pub fn new(
        tool: &str,
        model: Similarity,
        log: OpLog,
        autosave: Option<Autosaver>,
    ) -> Result<Self, TraceError> {
        let session = Session::new(tool_named(tool)?, model);
        let mut me = Self {
            session,
            log,
            autosave,
            scene: Scene {
                model_to_world: to_mat4(&model),
                ..Default::default()
            },
            stats: InteractionStats::default(),
        };
        me.rebuild_document();
        Ok(me)
    }

    /// One frame: step the session, apply its command, tick autosave,
    /// update the scene. Returns the command, if the tool produced one.
    pub fn step(&mut self, frame: &interact::InputFrame) -> Option<ScriptCommand> {
        self.stats.frames += 1;
        let cmd = self.session.step(frame, self.log.document());
        if let Some(c) = &cmd {
            self.stats.commands += 1;
            match apply_command(&mut self.log, c) {
                Ok(()) => {
                    self.rebuild_document();
                    if let Some(a) = &mut self.autosave {
                        let r = a.changed(&self.log);
                        self.note_save(r.map(|saved| saved as usize));
                    }
                }
                Err(e) => self.stats.rejected.push(e.to_string()),
            }
        } else if let Some(a) = &mut self.autosave {
            let r = a.tick(&self.log);
            self.note_save(r.map(|saved| saved as usize));
        }
        self.update_preview();
        cmd
    }

    /// Saves now if there is an autosaver and anything is unsaved (or the
    /// file was never written). Returns whether it saved.
    pub fn save_now(&mut self) -> bool {
        let Some(a) = &mut self.autosave else {
            return false;
        };
        if a.unsaved_changes() == 0 && a.saves() > 0 {
            return false;
        }
        let r = a.save_now(&self.log);
        let ok = r.is_ok();
        self.note_save(r.map(|()| 1));
        ok
    }

    fn note_save(&mut self, r: Result<usize, shapewright_usd::SaveError>) {
        match r {
            Ok(n) => self.stats.saves += n,
            Err(e) => {
                eprintln!("shapewright-xr: autosave failed (will retry): {e}");
                self.stats.save_errors.push(e.to_string());
            }
        }
    }

    fn rebuild_document(&mut self) {
        let doc = self.log.document();
        self.scene.version += 1;
        self.scene.document = (!doc.is_empty()).then(|| {
            let mut m = doc.combined_mesh();
            m.compute_normals();
            Arc::new(m)
        });
    }

    fn update_preview(&mut self) {
        let p = self.session.preview();
        let doc = self.log.document();
        self.scene.preview = p.preview_mesh(doc).map(|m| {
            let mut m = Arc::unwrap_or_clone(m);
            m.compute_normals();
            Arc::new(m)
        });
        let lines = &mut self.scene.lines;
        lines.clear();
        let v = |p: glam::DVec3, color| LineVertex {
            pos: p.as_vec3().to_array(),
            color,
        };
        for (ray, color) in p.rays.iter().zip(RAY_COLORS) {
            if let Some(r) = ray {
                let c = if r.hit { HIT_COLOR } else { color };
                lines.push(v(r.origin, c));
                lines.push(v(r.origin + r.dir * r.length, c));
            }
        }
        let model = self.session.model();
        for w in p.sketch.windows(2) {
            lines.push(v(model.apply(w[0]), SKETCH_COLOR));
            lines.push(v(model.apply(w[1]), SKETCH_COLOR));
        }
    }

    /// Changes not yet on disk (0 without an autosaver).
    pub fn unsaved_changes(&self) -> usize {
        self.autosave.as_ref().map_or(0, Autosaver::unsaved_changes)
    }

    /// The log.
    pub fn log(&self) -> &OpLog {
        &self.log
    }

    /// The scene to draw.
    pub fn scene(&self) -> &Scene {
        &self.scene
    }

    /// The counters.
    pub fn stats(&self) -> &InteractionStats {
        &self.stats
    }

    /// The session (preview, gestures).
    pub fn session(&self) -> &Session {
        &self.session
    }
}

impl FrameSink for Interaction {
    fn frame(&mut self, frame: &InputFrame) {
        self.step(&frame.to_interact());
    }

    fn lifecycle(&mut self, event: &LifecycleEvent) {
        if matches!(
            event,
            LifecycleEvent::SessionLost | LifecycleEvent::InstanceLost
        ) {
            self.save_now();
        }
    }

    fn scene(&self) -> Option<&Scene> {
        Some(&self.scene)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use shapewright::interact::{replay, Trace};
    use shapewright_usd::{load_file, AutosaveSettings, LoadOptions, SaveOptions};

    fn fixture() -> Trace {
        let p = concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../tests/data/primitives_session.trace.jsonl"
        );
        Trace::from_jsonl(&std::fs::read_to_string(p).unwrap()).unwrap()
    }

    #[test]
    fn stepping_a_trace_matches_the_core_replay_bit_for_bit() {
        let trace = fixture();
        let model = trace.header.model.similarity().unwrap();
        let mut it = Interaction::new(&trace.header.tool, model, OpLog::new(), None).unwrap();
        let mut rays = 0;
        for f in &trace.frames {
            it.step(f);
            rays += usize::from(!it.scene().lines.is_empty());
        }
        let core = replay(&trace).unwrap();
        assert_eq!(it.stats().commands as usize, core.commands.len());
        assert_eq!(it.stats().rejected.len(), core.rejected.len());
        assert_eq!(it.log().len(), core.log.len());
        assert_eq!(
            it.log().document().content_hash(),
            core.log.document().content_hash()
        );
        // The scene follows: the document mesh has every object, and the
        // controllers' rays were drawn on most frames.
        let doc = it.scene().document.as_ref().unwrap();
        assert_eq!(
            doc.triangle_count(),
            core.log.document().combined_mesh().triangle_count()
        );
        assert!(rays * 2 >= trace.frames.len(), "{rays}");
        assert!(it.scene().version as usize > core.log.cursor());
    }

    #[test]
    fn unknown_tools_are_typed_errors() {
        let e = Interaction::new("nope", Similarity::IDENTITY, OpLog::new(), None).err();
        assert!(matches!(e, Some(TraceError::UnknownTool(t)) if t == "nope"));
    }

    #[test]
    fn session_loss_saves_every_op_and_reopening_continues_the_history() {
        let dir = std::env::temp_dir().join(format!("sw_xr_interaction_{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("s.usda");
        let trace = fixture();
        let model = trace.header.model.similarity().unwrap();
        // Only the loss triggers a save: no op or time trigger fires.
        let settings = AutosaveSettings {
            every_ops: usize::MAX,
            every: std::time::Duration::from_secs(3600),
        };
        let saver = Autosaver::new(&path, settings, SaveOptions::default());
        let mut it = Interaction::new("object", model, OpLog::new(), Some(saver)).unwrap();
        let half = trace.frames.len() / 2;
        for f in &trace.frames[..half] {
            it.step(f);
        }
        assert!(!path.exists(), "nothing saved before the loss");
        let acknowledged = it.log().len();
        assert!(acknowledged >= 2, "{acknowledged}");
        it.lifecycle(&LifecycleEvent::SessionLost);
        let loaded = load_file(&path, LoadOptions::default()).unwrap();
        assert_eq!(loaded.log.len(), acknowledged);
        assert_eq!(
            loaded.log.document().content_hash(),
            it.log().document().content_hash()
        );
        // Continue from the file: the history is kept, new ops append to
        // it, the exit save has them all, and undo reaches back into the
        // saved history.
        let saver = Autosaver::new(&path, AutosaveSettings::default(), SaveOptions::default());
        let mut cont = Interaction::new("object", model, loaded.log, Some(saver)).unwrap();
        for f in &trace.frames[half..] {
            cont.step(f);
        }
        let kept = it.log().cursor();
        assert!(cont.log().len() > kept);
        assert_eq!(cont.log().ops()[..kept], it.log().ops()[..kept]);
        cont.save_now();
        let reopened = load_file(&path, LoadOptions::default()).unwrap();
        assert_eq!(reopened.log.ops(), cont.log().ops());
        assert_eq!(reopened.log.cursor(), cont.log().cursor());
        let mut log = reopened.log;
        while log.cursor() > 0 {
            log.undo().unwrap();
        }
        assert!(log.document().is_empty());
        let _ = std::fs::remove_dir_all(&dir);
    }
}
