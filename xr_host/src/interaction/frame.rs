//! [`Interaction`]: the frame side. It steps the session against the last
//! committed document, hands commands to the commit thread and brings the
//! [`Scene`] up to date.

use std::sync::mpsc::{self, Receiver, Sender, TryRecvError};
use std::sync::{Arc, Mutex};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use glam::{DMat4, Mat4};
use shapewright::doc::{Document, ObjectId, OpLog, ScriptCommand};
use shapewright::interact::{self, tool_named, Session, Similarity, TraceError};
use shapewright::mesh::TriMesh;
use shapewright_usd::Autosaver;

use super::commit::{
    commit_loop, document_mesh, lock, lock_status, people_of, with_normals, Committed,
    DrawnNormals, Job, LogGuard, ModelBox, Person, Shared, Status,
};
use super::sink::wrap;
use crate::gfx::text::Font;
use crate::gfx::{LineVertex, Scene};
use crate::xr::Haptic;

/// Why an [`Interaction`] could not start.
#[derive(Debug, thiserror::Error)]
pub enum InteractionError {
    /// The tool name is not one the core knows.
    #[error(transparent)]
    Tool(#[from] TraceError),
    /// The operating system refused the commit thread.
    #[error("could not start the commit thread: {0}")]
    Thread(#[from] std::io::Error),
}

/// Counters of an interaction run.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct InteractionStats {
    /// Frames received (each stepped by the tool, at once or once the
    /// commit it waited for landed).
    pub frames: u64,
    /// Commands the tool produced.
    pub commands: u64,
    /// Commands the log refused (the message of each).
    pub rejected: Vec<String>,
    /// Commit times (applying a command and meshing the document), ms.
    pub commit_ms: Vec<f64>,
    /// Saves done (autosave, loss, exit).
    pub saves: usize,
    /// Saves that failed (the message of each).
    pub save_errors: Vec<String>,
    /// Haptic pulses asked for.
    pub haptics: u64,
    /// Saves asked for through the palette.
    pub save_requests: u64,
    /// Documents taken in from others' edits (a shared session).
    pub remote_updates: u64,
    /// The most other participants drawn in one frame (a shared
    /// session's presence).
    pub others_drawn: usize,
}

/// The most held frames one [`Interaction::step`] steps (see there). Each
/// call also adds its own frame, so a backlog shrinks by 7 a frame: at
/// 90 Hz a 160-ms commit's (15 frames) is worked off in 3 frames, a 2-s
/// one's (180) in 26 (0.3 s).
pub(super) const CATCH_UP: usize = 8;

/// A session, the commit thread (log and autosaver) and the scene.
pub struct Interaction {
    pub(super) session: Session,
    /// The last committed document: what the tool sees.
    pub(super) doc: Document,
    pub(super) shared: Arc<Mutex<Shared>>,
    /// The warnings every frame draws (see [`Status`]).
    pub(super) status: Arc<Mutex<Status>>,
    /// A shared session's presence: ours out, others' in.
    pub(super) presence: Option<shapewright_net::PresenceChannel>,
    /// The frame time our presence was last sent.
    pub(super) presence_sent: f64,
    /// A shared session's participants (id, name, colour).
    pub(super) people: Vec<Person>,
    /// Model-space boxes of the drawn objects others selected, for the
    /// scene version they were measured on.
    pub(super) selection_boxes: (u64, Vec<(ObjectId, Option<ModelBox>)>),
    pub(super) jobs: Option<Sender<Job>>,
    pub(super) done: Receiver<Committed>,
    pub(super) worker: Option<JoinHandle<()>>,
    /// Commands handed to the commit thread and not yet reported back,
    /// with the hands that made each.
    pub(super) pending: std::collections::VecDeque<[bool; 2]>,
    /// Input frames that came while a command of ours was being
    /// committed: the tool steps them, in order, once the document that
    /// command made is in (see [`Interaction::step`]).
    pub(super) held: std::collections::VecDeque<interact::InputFrame>,
    /// The newest frame as the head, hands and controllers are drawn from
    /// it ([`Session::display_frame`]): they follow the user while the
    /// tool's frames are held.
    pub(super) drawn: Option<interact::Frame>,
    pub(super) scene: Scene,
    pub(super) stats: InteractionStats,
    pub(super) haptics: Vec<Haptic>,
    /// Whether each ray hit something last frame.
    pub(super) ray_hit: [bool; 2],
    /// The font of the palette and messages.
    pub(super) font: Font,
    /// The last refused edit and the frame time it came back at.
    pub(super) refused: Option<(String, f64)>,
    /// The print line of the HUD (size, bed fit) and the scene version it
    /// was computed for (once per document change, not per frame).
    pub(super) print_status: (u64, Option<shapewright::print::PrintStatus>),
    /// The last preview source mesh and it with normals.
    pub(super) preview_cache: Option<(Arc<TriMesh>, Arc<TriMesh>)>,
}

pub(super) const RAY_COLORS: [[f32; 3]; 2] = [[0.3, 0.6, 1.0], [1.0, 0.5, 0.2]];
pub(super) const HIT_COLOR: [f32; 3] = [0.3, 1.0, 0.4];
pub(super) const SKETCH_COLOR: [f32; 3] = [1.0, 0.9, 0.2];

pub(super) fn to_mat4(s: &Similarity) -> Mat4 {
    affine_to_mat4(s.to_affine())
}

pub(super) fn affine_to_mat4(a: glam::DAffine3) -> Mat4 {
    Mat4::from_cols_array(&DMat4::from(a).to_cols_array().map(|x| x as f32))
}

impl Interaction {
    /// Runs the tool named `tool` alone on `log` (empty, or loaded to
    /// continue its history), the document placed in the stage by `model`.
    pub fn new(
        tool: &str,
        model: Similarity,
        log: OpLog,
        autosave: Option<Autosaver>,
    ) -> Result<Self, InteractionError> {
        let session = Session::new(tool_named(tool).map_err(TraceError::from)?, model);
        Self::with_session(session, log, autosave)
    }

    /// Runs `session` (a modeler session: every tool and the palette) on
    /// `log`.
    pub fn with_session(
        session: Session,
        log: OpLog,
        autosave: Option<Autosaver>,
    ) -> Result<Self, InteractionError> {
        Self::shared(session, log, autosave, None)
    }

    /// Runs `session` on `log`, one person's side of a shared session
    /// when `link` is given (`log` then comes from
    /// [`OpLog::from_shared`]).
    pub fn shared(
        session: Session,
        log: OpLog,
        autosave: Option<Autosaver>,
        link: Option<shapewright_net::Link>,
    ) -> Result<Self, InteractionError> {
        let model = *session.model();
        let doc = log.document().clone();
        let presence = link.as_ref().map(shapewright_net::Link::presence);
        let people = people_of(&log);
        // Kept for the commit thread: a large opened assembly's normals
        // are not computed again on its first commit.
        let mut kept = DrawnNormals::default();
        let drawn = document_mesh(&doc, &mut kept);
        let scene = Scene {
            version: 1,
            document: drawn.mesh,
            document_objects: drawn.objects,
            model_to_world: to_mat4(&model),
            ..Default::default()
        };
        let status = Arc::new(Mutex::new(Status::default()));
        let shared = Arc::new(Mutex::new(Shared {
            log,
            link,
            autosave,
            saves: 0,
            save_errors: Vec::new(),
            status: Arc::clone(&status),
        }));
        let (jobs, jobs_rx) = mpsc::channel();
        let (done_tx, done) = mpsc::channel();
        let s2 = Arc::clone(&shared);
        let worker = std::thread::Builder::new()
            .name("shapewright-commit".into())
            .spawn(move || commit_loop(s2, jobs_rx, done_tx, kept))?;
        Ok(Self {
            session,
            doc,
            shared,
            status,
            presence,
            presence_sent: f64::NEG_INFINITY,
            people,
            selection_boxes: (0, Vec::new()),
            jobs: Some(jobs),
            done,
            worker: Some(worker),
            pending: Default::default(),
            held: Default::default(),
            drawn: None,
            scene,
            stats: InteractionStats::default(),
            haptics: Vec::new(),
            ray_hit: [false; 2],
            font: Font::bundled(),
            refused: None,
            print_status: (u64::MAX, None),
            preview_cache: None,
        })
    }

    /// The hands that hold a button in the session's last frame (both
    /// when none does, or when no controller is there).
    pub(super) fn acting_hands(&self) -> [bool; 2] {
        let held = |h: usize| {
            self.session
                .last_frame()
                .and_then(|f| f.controllers[h].as_ref())
                .and_then(|c| c.buttons)
                .is_some_and(|b| {
                    b.select > 0.5 || b.grab > 0.5 || b.primary || b.secondary || b.menu
                })
        };
        let hands = [held(0), held(1)];
        if hands == [false, false] {
            [true, true]
        } else {
            hands
        }
    }

    /// One frame: take in finished commits, step the session against the
    /// last committed document, hand its command (if any) to the commit
    /// thread, update the scene. Returns the command made in this call
    /// (by this frame, or by a held one stepped now; commands of frames
    /// stepped by [`Interaction::flush`] are counted in the stats only).
    ///
    /// The tool never steps against a document older than the commands it
    /// produced: while one of ours is being committed, frames are held and
    /// stepped, in order, once its document is in (up to `CATCH_UP`, 8, a
    /// call, so a long commit's backlog is worked off over a few frames,
    /// not in one). The scene keeps being drawn meanwhile, the head, hands
    /// and controllers from the newest frame; the tool's own feedback
    /// (its rays, previews, palette) waits for the commit. So the tool
    /// sees exactly what the core's [`shapewright::interact::replay`] of
    /// the same input shows it, however long a commit takes. Before (2026-11-30), frames were
    /// stepped against the last committed document: on a loaded machine
    /// a grab 20 frames after a duplicate picked the original, because
    /// the copy (on top of it) was not committed yet, and the session's
    /// own recording replayed to another model.
    pub fn step(&mut self, frame: &interact::InputFrame) -> Option<ScriptCommand> {
        self.stats.frames += 1;
        loop {
            match self.done.try_recv() {
                Ok(c) => self.take(c),
                Err(TryRecvError::Empty) => break,
                Err(TryRecvError::Disconnected) => {
                    self.commit_thread_gone();
                    break;
                }
            }
        }
        if let Some(f) = self.session.display_frame(frame) {
            self.drawn = Some(f);
        }
        self.held.push_back(frame.clone());
        let cmd = self.step_held(CATCH_UP);
        self.send_presence();
        self.update_preview();
        // A tick when a ray starts pointing at something.
        let hits = self
            .session
            .preview()
            .rays
            .map(|r| r.is_some_and(|r| r.hit));
        for (h, (&now, was)) in hits.iter().zip(&mut self.ray_hit).enumerate() {
            if now && !*was {
                self.haptics.push(Haptic {
                    hand: h,
                    amplitude: 0.2,
                    millis: 10,
                });
            }
            *was = now;
        }
        cmd
    }

    /// Steps held frames in order while no command of ours is pending, at
    /// most `max` of them; returns the command the last one produced (the
    /// next frames wait for its commit).
    fn step_held(&mut self, max: usize) -> Option<ScriptCommand> {
        for _ in 0..max {
            if !self.pending.is_empty() {
                break;
            }
            let f = self.held.pop_front()?;
            let cmd = self.session.step(&f, &self.doc);
            if let Some(c) = &cmd {
                self.stats.commands += 1;
                let hands = self.acting_hands();
                if self.send(Job::Apply(c.clone())) {
                    self.pending.push_back(hands);
                }
            }
            // The palette's Save: after every command so far, off the
            // frame (the result shows in the stats and, if it fails, in
            // the headset).
            for _ in 0..self.session.take_save_requests() {
                let (tx, _ignored) = mpsc::channel();
                self.send(Job::Save(tx));
                self.stats.save_requests += 1;
            }
            if cmd.is_some() {
                return cmd;
            }
        }
        None
    }

    /// The commit thread ended (it panicked): the commands it did not
    /// report back are lost, the tool goes on against the last document
    /// (nothing more can be committed), and the headset says so.
    fn commit_thread_gone(&mut self) {
        if self.pending.is_empty() {
            return;
        }
        self.pending.clear();
        let e = "the commit thread stopped; the last edits were not applied".to_string();
        let now = self.drawn.as_ref().map_or(0.0, |f| f.time);
        self.refused = Some((e.clone(), now));
        self.stats.rejected.push(e);
    }

    /// Hands `job` to the commit thread; false if it is gone.
    pub(super) fn send(&mut self, job: Job) -> bool {
        let sent = self.jobs.as_ref().is_some_and(|j| j.send(job).is_ok());
        if !sent {
            // The commit thread is gone (it panicked): nothing more can be
            // committed, and the stats say so.
            self.stats
                .rejected
                .push("the commit thread stopped; the command was not applied".into());
        }
        sent
    }

    pub(super) fn take(&mut self, c: Committed) {
        if c.remote {
            // Others' edits: the new document, and this person's notices
            // (an edit of theirs refused or skipped) shown like a refusal.
            if let Some(e) = c.error {
                let now = self.session.last_frame().map_or(0.0, |f| f.time);
                self.refused = Some((e, now));
            }
            self.doc = c.doc;
            self.scene.document = c.mesh.mesh;
            self.scene.document_objects = c.mesh.objects;
            self.scene.version += 1;
            self.stats.remote_updates += 1;
            self.people = c.people;
            return;
        }
        let hands = self.pending.pop_front().unwrap_or([true, true]);
        self.stats.commit_ms.push(c.ms);
        match c.error {
            Some(e) => {
                let now = self.session.last_frame().map_or(0.0, |f| f.time);
                self.refused = Some((e.clone(), now));
                self.stats.rejected.push(e);
            }
            None => {
                self.doc = c.doc;
                self.scene.document = c.mesh.mesh;
                self.scene.document_objects = c.mesh.objects;
                self.scene.version += 1;
                for (h, _) in hands.iter().enumerate().filter(|(_, &on)| on) {
                    self.haptics.push(Haptic {
                        hand: h,
                        amplitude: 0.6,
                        millis: 30,
                    });
                }
            }
        }
    }

    /// Waits until every frame so far is stepped and every command they
    /// produced is applied, and takes in the results.
    pub fn flush(&mut self) {
        let stepped = !self.held.is_empty();
        loop {
            if !self.pending.is_empty() {
                let (tx, rx) = mpsc::channel();
                self.send(Job::Flush(tx));
                let _ = rx.recv();
                while let Ok(c) = self.done.try_recv() {
                    self.take(c);
                }
                if !self.pending.is_empty() {
                    // The commit thread is gone: nothing will come back.
                    self.commit_thread_gone();
                }
            }
            if self.held.is_empty() {
                break;
            }
            self.step_held(usize::MAX);
        }
        // The scene shows what the frames stepped here left (a save on
        // session loss, the last frames at exit).
        if stepped {
            self.update_preview();
        }
    }

    /// In a shared session: waits until every edit of ours is confirmed
    /// and nothing new arrived for `quiet` (others are done too), taking
    /// in the documents that came meanwhile. False if `limit` passed
    /// first. Returns at once outside a shared session.
    pub fn settle_shared(&mut self, quiet: Duration, limit: Duration) -> bool {
        let t = Instant::now();
        let mut last = (u64::MAX, usize::MAX);
        let mut since = Instant::now();
        loop {
            self.flush();
            while let Ok(c) = self.done.try_recv() {
                self.take(c);
            }
            let state = {
                let s = lock(&self.shared);
                match s.log.shared() {
                    Some(l) => (l.confirmed().last_seq(), l.pending_count()),
                    None => return true,
                }
            };
            if state != last {
                last = state;
                since = Instant::now();
            }
            if state.1 == 0 && since.elapsed() >= quiet {
                // The frame thread's document is the log's.
                let doc = lock(&self.shared).log.document().clone();
                if doc.content_hash() != self.doc.content_hash() {
                    let drawn = document_mesh(&doc, &mut DrawnNormals::default());
                    self.doc = doc;
                    self.scene.document = drawn.mesh;
                    self.scene.document_objects = drawn.objects;
                    self.scene.version += 1;
                }
                return true;
            }
            if t.elapsed() > limit {
                return false;
            }
            std::thread::sleep(Duration::from_millis(5));
        }
    }

    /// Saves now, after every command produced so far, if there is an
    /// autosaver and anything is unsaved (or the file was never written).
    /// Returns whether it saved.
    pub fn save_now(&mut self) -> bool {
        // The frames held for a commit first: their commands were made
        // before the save was asked for.
        self.flush();
        let (tx, rx) = mpsc::channel();
        self.send(Job::Save(tx));
        let saved = rx.recv().unwrap_or(false);
        self.flush();
        saved
    }

    pub(super) fn update_preview(&mut self) {
        let p = self.session.preview();
        // While an object is dragged, the document is drawn without it.
        self.scene.hidden = p.moving.as_ref().map(|m| m.id);
        // The dragged object where it would land (its own mesh, moved by
        // the renderer), or the GC part as the gesture would leave it.
        let (source, motion) = match p.preview_motion(&self.doc) {
            Some((m, a)) => (Some(m), affine_to_mat4(a)),
            None => (p.gc().and_then(|g| g.mesh.clone()), Mat4::IDENTITY),
        };
        let preview = source.map(|m| with_normals(&mut self.preview_cache, m));
        let same = match (&preview, &self.scene.preview) {
            (Some(a), Some(b)) => Arc::ptr_eq(a, b),
            (None, None) => true,
            _ => false,
        };
        if !same {
            self.scene.preview_version += 1;
        }
        self.scene.preview = preview;
        self.scene.preview_motion = motion;
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
        crate::ui::tool_marks(&self.session, lines);
        crate::ui::hands_and_controllers(self.drawn.as_ref(), lines);
        let now = self.drawn.as_ref().map_or(0.0, |f| f.time);
        let message = self
            .refused
            .as_ref()
            .map(|(m, t)| (m.as_str(), now - t))
            .filter(|(_, age)| *age < crate::ui::MESSAGE_SECS);
        let wrapped = message.map(|(m, age)| (wrap(m, 56), age));
        let message = wrapped.as_ref().map(|(m, age)| (m.as_str(), *age));
        if self.print_status.0 != self.scene.version {
            self.print_status = (
                self.scene.version,
                shapewright::doc::print_status(&self.doc),
            );
        }
        crate::ui::overlay(
            &mut self.font,
            &self.session,
            self.drawn.as_ref(),
            message,
            self.print_status.1.as_ref(),
            &mut self.scene.ui,
        );
        let others = self.avatars();
        self.stats.others_drawn = self.stats.others_drawn.max(others.len());
        let viewer = self.drawn.as_ref().and_then(|f| f.head);
        crate::ui::avatars(
            &mut self.font,
            &others,
            viewer,
            &mut self.scene.lines,
            &mut self.scene.ui,
        );
    }
}

impl Interaction {
    /// Changes not yet on disk (0 without an autosaver), once every
    /// pending command is applied.
    pub fn unsaved_changes(&mut self) -> usize {
        self.flush();
        lock(&self.shared)
            .autosave
            .as_ref()
            .map_or(0, Autosaver::unsaved_changes)
    }

    /// The log, once every pending command is applied.
    pub fn log(&mut self) -> LogGuard<'_> {
        self.flush();
        LogGuard(lock(&self.shared))
    }

    /// The last committed document (what the tool sees).
    pub fn document(&self) -> &Document {
        &self.doc
    }

    /// The scene to draw.
    pub fn scene(&self) -> &Scene {
        &self.scene
    }

    /// The counters (save counts as of now).
    pub fn stats(&self) -> InteractionStats {
        let s = lock(&self.shared);
        InteractionStats {
            saves: s.saves,
            save_errors: s.save_errors.clone(),
            ..self.stats.clone()
        }
    }

    /// The error of the last save, if it failed (cleared by a good save).
    pub fn save_failing(&self) -> Option<String> {
        lock_status(&self.status).failing.clone()
    }

    /// The session (preview, gestures).
    pub fn session(&self) -> &Session {
        &self.session
    }
}

impl Drop for Interaction {
    fn drop(&mut self) {
        // Closing the queue ends the commit thread once it has applied
        // what is queued.
        self.jobs = None;
        if let Some(w) = self.worker.take() {
            let _ = w.join();
        }
    }
}
