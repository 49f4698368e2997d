//! The interaction step both frame loops (headset, headless) and `replay`
//! run: one raw [`interact::InputFrame`] in, a
//! [`shapewright::interact::Session`] stepped against the latest document,
//! and the [`Scene`] (document mesh, drag preview, rays and sketch)
//! brought up to date for the renderer.
//!
//! **Commits run off the frame.** A command the tool produces is handed
//! to a commit thread that owns the [`OpLog`]: applying an op re-evaluates
//! its object (a generalized-cylinder assembly re-unites all its parts,
//! 70 to 160 ms for the teapot), which would drop several 90 Hz frames.
//! The frame keeps stepping against the last committed document and
//! picks up the new one (and its mesh) when the commit reports back;
//! commands are applied strictly in the order they were produced.
//! [`Interaction::flush`] waits for every pending commit: `replay` calls it
//! after each frame, so the tool sees exactly what the core's
//! [`interact::replay`] shows it, and the result is bit-identical.
//!
//! Persistence: an optional [`Autosaver`] on the commit thread saves the
//! log as USD (with its history, so `run --open` continues it and undo
//! works) every N changes or T seconds, and [`Interaction::save_now`] is
//! called on session loss, instance loss and exit; it saves after every
//! command produced before it, so no acknowledged op is lost. A failed
//! save is reported (stderr, [`InteractionStats::save_errors`], and a red
//! message in the headset until a save succeeds) and retried at the next
//! trigger; it never stops the session, and the file on disk keeps the
//! last good save (the autosaver replaces it atomically), so a failure
//! loses at most the ops since then.
//!
//! Shared sessions (`run --join`): the commit thread also owns the
//! session's [`shapewright_net::Link`]. It pumps it every few milliseconds
//! (others' entries in, this person's appends out) and hands the frame a
//! new document when others' edits arrived, exactly as after a local
//! commit; the headset says when the server is out of reach and shows the
//! refusals the session sends this person.
//!
//! Haptics: a short pulse on the hand(s) that made a command when its
//! commit lands (the hands holding a button in the frame that produced
//! it, else both), and a tick when a ray starts pointing at something.
//!
//! Tools come from [`interact::tool_named`], so every tool the core
//! registers is available to `--tool` without a list here.

use std::ops::{Deref, Range};
use std::sync::mpsc::{self, Receiver, RecvTimeoutError, Sender};
use std::sync::{Arc, Mutex, MutexGuard};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use glam::{DMat4, Mat4};
use shapewright::doc::shared::{
    colour_for, Presence, PresencePose, PRESENCE_HZ, PRESENCE_STALE_SECS,
};
use shapewright::doc::{Document, ObjectId, OpLog, ScriptCommand};
use shapewright::interact::{
    self, apply_command, tool_named, SanitizerStats, Session, Similarity, TraceError,
};
use shapewright::mesh::TriMesh;
use shapewright_usd::Autosaver;

use crate::gfx::text::Font;
use crate::gfx::{LineVertex, Scene};
use crate::xr::{FrameSink, Haptic, LifecycleEvent, Notice};

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
    /// Frames stepped.
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

/// The state the commit thread owns (the frame thread locks it only to
/// read the log or the save counters, never once per frame: the commit
/// thread holds it while an op applies, up to a quarter second for a GC
/// edit, which a frame cannot wait for).
struct Shared {
    log: OpLog,
    /// The shared session's connection (`run --join`).
    link: Option<shapewright_net::Link>,
    autosave: Option<Autosaver>,
    saves: usize,
    save_errors: Vec<String>,
    /// What every frame shows (its own lock, held only to copy it).
    status: Arc<Mutex<Status>>,
}

/// The warnings every frame draws, kept apart from the log so reading
/// them never waits for a commit.
#[derive(Default)]
struct Status {
    /// The last save failed with this (cleared by the next good save).
    failing: Option<String>,
    /// The shared session's server is out of reach.
    offline: bool,
    /// The shared session's server refused our edits (a viewer).
    view_only: bool,
}

fn lock_status(m: &Mutex<Status>) -> MutexGuard<'_, Status> {
    m.lock().unwrap_or_else(|e| e.into_inner())
}

impl Shared {
    fn note_save(&mut self, r: Result<usize, shapewright_usd::SaveError>) {
        match r {
            Ok(n) => {
                self.saves += n;
                if n > 0 {
                    lock_status(&self.status).failing = None;
                }
            }
            Err(e) => {
                let unsaved = self.autosave.as_ref().map_or(0, Autosaver::unsaved_changes);
                eprintln!(
                    "shapewright-xr: autosave failed (will retry; {unsaved} changes since the last good save are not on disk yet): {e}"
                );
                self.save_errors.push(e.to_string());
                lock_status(&self.status).failing = Some(e.to_string());
            }
        }
    }

    /// Saves if there is an autosaver and anything is unsaved (or the file
    /// was never written). Returns whether it saved.
    fn save_now(&mut self) -> bool {
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
}

fn lock(m: &Mutex<Shared>) -> MutexGuard<'_, Shared> {
    // A panic on the commit thread leaves the log as the last completed
    // op left it (ops apply to a copy): keep using it.
    m.lock().unwrap_or_else(|e| e.into_inner())
}

enum Job {
    Apply(ScriptCommand),
    Save(Sender<bool>),
    Flush(Sender<()>),
}

/// A commit's result, sent back to the frame thread.
struct Committed {
    /// The document after the command (unchanged when it was refused).
    doc: Document,
    /// Its combined mesh (None: empty document) and each object's
    /// triangles in it.
    mesh: DrawnDocument,
    error: Option<String>,
    ms: f64,
    /// Others' edits (a shared session), not a command of ours.
    remote: bool,
    /// A shared session's participants (id, name, colour), sent with
    /// others' edits (a join is one).
    people: Vec<Person>,
}

/// An axis-aligned box in model space: its low and high corners.
type ModelBox = [glam::DVec3; 2];

/// A participant: id, name, colour.
type Person = (String, String, [f32; 3]);

/// The participants of `log`'s shared session (none outside one).
fn people_of(log: &OpLog) -> Vec<Person> {
    log.shared().map_or_else(Vec::new, |s| {
        s.confirmed()
            .participants()
            .iter()
            .map(|p| (p.id.clone(), p.name.clone(), p.colour))
            .collect()
    })
}

/// The document as drawn: every object in one mesh (None: empty
/// document), and each object's range of triangles in it, so the
/// renderer can leave the dragged object out without new mesh work.
#[derive(Default)]
struct DrawnDocument {
    mesh: Option<Arc<TriMesh>>,
    objects: Vec<(ObjectId, Range<u32>)>,
}

fn document_mesh(doc: &Document) -> DrawnDocument {
    if doc.is_empty() {
        return DrawnDocument::default();
    }
    let mut m = TriMesh::default();
    let mut objects = Vec::with_capacity(doc.len());
    for (id, o) in doc.objects() {
        let first = m.triangles.len() as u32;
        m.append(&o.mesh);
        objects.push((id, first..m.triangles.len() as u32));
    }
    m.compute_normals();
    DrawnDocument {
        mesh: Some(Arc::new(m)),
        objects,
    }
}

/// `mesh` with normals (for the renderer's smooth shading), computed once
/// per mesh: `cache` keeps the last source and its result.
fn with_normals(
    cache: &mut Option<(Arc<TriMesh>, Arc<TriMesh>)>,
    mesh: Arc<TriMesh>,
) -> Arc<TriMesh> {
    if let Some((src, out)) = cache {
        if Arc::ptr_eq(src, &mesh) {
            return Arc::clone(out);
        }
    }
    let mut m = (*mesh).clone();
    m.compute_normals();
    let out = Arc::new(m);
    *cache = Some((mesh, Arc::clone(&out)));
    out
}

/// How often the commit thread checks the autosave timer when idle.
const TICK: Duration = Duration::from_millis(200);

/// How often it pumps a shared session's link when idle.
const NET_TICK: Duration = Duration::from_millis(4);

/// Pumps the shared session's link: others' entries in, our next append
/// out. Returns the new document when others' edits changed it, with the
/// session's messages for this person.
fn pump_link(s: &mut Shared) -> Option<(Document, Vec<String>)> {
    let report = s.link.as_mut()?.pump_log(&mut s.log)?;
    let (was_offline, was_view_only) = {
        let mut status = lock_status(&s.status);
        (
            std::mem::replace(&mut status.offline, !report.online),
            std::mem::replace(&mut status.view_only, report.view_only),
        )
    };
    if report.view_only && !was_view_only {
        eprintln!("shapewright-xr: shared session: the server lets you view this document but not edit it");
    }
    if was_offline == report.online {
        eprintln!(
            "shapewright-xr: shared session {}",
            if report.online {
                "back online; sending what was edited meanwhile"
            } else {
                "offline: edits are kept and sent on reconnect"
            }
        );
    }
    for e in &report.errors {
        eprintln!("shapewright-xr: shared session: {e}");
    }
    if !report.changed() {
        return None;
    }
    let messages = report.notices;
    if let Some(a) = &mut s.autosave {
        let r = a.changed(&s.log).map(usize::from);
        s.note_save(r);
    }
    Some((s.log.document().clone(), messages))
}

fn commit_loop(shared: Arc<Mutex<Shared>>, jobs: Receiver<Job>, done: Sender<Committed>) {
    let tick = if lock(&shared).link.is_some() {
        NET_TICK
    } else {
        TICK
    };
    loop {
        match jobs.recv_timeout(tick) {
            Ok(Job::Apply(cmd)) => {
                let t0 = Instant::now();
                let mut guard = lock(&shared);
                let s = &mut *guard;
                let (doc, mesh, error) = match apply_command(&mut s.log, &cmd) {
                    Ok(()) => {
                        if let Some(a) = &mut s.autosave {
                            let r = a.changed(&s.log).map(usize::from);
                            s.note_save(r);
                        }
                        let doc = s.log.document().clone();
                        let mesh = document_mesh(&doc);
                        (doc, mesh, None)
                    }
                    Err(e) => (
                        s.log.document().clone(),
                        DrawnDocument::default(),
                        Some(e.to_string()),
                    ),
                };
                // A shared session sends the edit at once.
                if let Some(l) = &mut s.link {
                    s.log.with_shared(|log| l.pump(log));
                }
                drop(guard);
                let ms = t0.elapsed().as_secs_f64() * 1e3;
                if done
                    .send(Committed {
                        doc,
                        mesh,
                        error,
                        ms,
                        remote: false,
                        people: Vec::new(),
                    })
                    .is_err()
                {
                    return;
                }
            }
            Ok(Job::Save(reply)) => {
                let saved = lock(&shared).save_now();
                let _ = reply.send(saved);
            }
            Ok(Job::Flush(reply)) => {
                let _ = reply.send(());
            }
            Err(RecvTimeoutError::Timeout) => {
                let t0 = Instant::now();
                let mut guard = lock(&shared);
                let s = &mut *guard;
                if let Some(a) = &mut s.autosave {
                    let r = a.tick(&s.log).map(usize::from);
                    s.note_save(r);
                }
                if let Some((doc, messages)) = pump_link(s) {
                    let people = people_of(&s.log);
                    drop(guard);
                    let mesh = document_mesh(&doc);
                    let c = Committed {
                        doc,
                        mesh,
                        error: messages.last().cloned(),
                        ms: t0.elapsed().as_secs_f64() * 1e3,
                        remote: true,
                        people,
                    };
                    if done.send(c).is_err() {
                        return;
                    }
                }
            }
            Err(RecvTimeoutError::Disconnected) => return,
        }
    }
}

/// The log, read after every pending commit finished (see
/// [`Interaction::log`]).
pub struct LogGuard<'a>(MutexGuard<'a, Shared>);

impl Deref for LogGuard<'_> {
    type Target = OpLog;
    fn deref(&self) -> &OpLog {
        &self.0.log
    }
}

/// A session, the commit thread (log and autosaver) and the scene.
pub struct Interaction {
    session: Session,
    /// The last committed document: what the tool sees.
    doc: Document,
    shared: Arc<Mutex<Shared>>,
    /// The warnings every frame draws (see [`Status`]).
    status: Arc<Mutex<Status>>,
    /// A shared session's presence: ours out, others' in.
    presence: Option<shapewright_net::PresenceChannel>,
    /// The frame time our presence was last sent.
    presence_sent: f64,
    /// A shared session's participants (id, name, colour).
    people: Vec<Person>,
    /// Model-space boxes of the drawn objects others selected, for the
    /// scene version they were measured on.
    selection_boxes: (u64, Vec<(ObjectId, Option<ModelBox>)>),
    jobs: Option<Sender<Job>>,
    done: Receiver<Committed>,
    worker: Option<JoinHandle<()>>,
    /// Commands handed to the commit thread and not yet reported back,
    /// with the hands that made each.
    pending: std::collections::VecDeque<[bool; 2]>,
    scene: Scene,
    stats: InteractionStats,
    haptics: Vec<Haptic>,
    /// Whether each ray hit something last frame.
    ray_hit: [bool; 2],
    /// The font of the palette and messages.
    font: Font,
    /// The last refused edit and the frame time it came back at.
    refused: Option<(String, f64)>,
    /// The print line of the HUD (size, bed fit) and the scene version it
    /// was computed for (once per document change, not per frame).
    print_status: (u64, Option<shapewright::print::PrintStatus>),
    /// The last preview source mesh and it with normals.
    preview_cache: Option<(Arc<TriMesh>, Arc<TriMesh>)>,
}

const RAY_COLORS: [[f32; 3]; 2] = [[0.3, 0.6, 1.0], [1.0, 0.5, 0.2]];
const HIT_COLOR: [f32; 3] = [0.3, 1.0, 0.4];
const SKETCH_COLOR: [f32; 3] = [1.0, 0.9, 0.2];

fn to_mat4(s: &Similarity) -> Mat4 {
    affine_to_mat4(s.to_affine())
}

fn affine_to_mat4(a: glam::DAffine3) -> Mat4 {
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
        let drawn = document_mesh(&doc);
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
            .spawn(move || commit_loop(s2, jobs_rx, done_tx))?;
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
    fn acting_hands(&self) -> [bool; 2] {
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
    /// thread, update the scene. Returns the command.
    pub fn step(&mut self, frame: &interact::InputFrame) -> Option<ScriptCommand> {
        self.stats.frames += 1;
        while let Ok(c) = self.done.try_recv() {
            self.take(c);
        }
        let cmd = self.session.step(frame, &self.doc);
        if let Some(c) = &cmd {
            self.stats.commands += 1;
            self.send(Job::Apply(c.clone()));
            let hands = self.acting_hands();
            self.pending.push_back(hands);
        }
        // The palette's Save: after every command so far, off the frame
        // (the result shows in the stats and, if it fails, in the headset).
        for _ in 0..self.session.take_save_requests() {
            let (tx, _ignored) = mpsc::channel();
            self.send(Job::Save(tx));
            self.stats.save_requests += 1;
        }
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

    fn send(&mut self, job: Job) {
        let sent = self.jobs.as_ref().is_some_and(|j| j.send(job).is_ok());
        if !sent {
            // The commit thread is gone (it panicked): nothing more can be
            // committed, and the stats say so.
            self.stats
                .rejected
                .push("the commit thread stopped; the command was not applied".into());
        }
    }

    fn take(&mut self, c: Committed) {
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

    /// Waits until every command produced so far is applied, and takes in
    /// the results.
    pub fn flush(&mut self) {
        if self.pending.is_empty() {
            return;
        }
        let (tx, rx) = mpsc::channel();
        self.send(Job::Flush(tx));
        let _ = rx.recv();
        while let Ok(c) = self.done.try_recv() {
            self.take(c);
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
                    let drawn = document_mesh(&doc);
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
        let (tx, rx) = mpsc::channel();
        self.send(Job::Save(tx));
        let saved = rx.recv().unwrap_or(false);
        self.flush();
        saved
    }

    fn update_preview(&mut self) {
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
        crate::ui::hands_and_controllers(&self.session, lines);
        let now = self.session.last_frame().map_or(0.0, |f| f.time);
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
            message,
            self.print_status.1.as_ref(),
            &mut self.scene.ui,
        );
        let others = self.avatars();
        self.stats.others_drawn = self.stats.others_drawn.max(others.len());
        let viewer = self.session.last_frame().and_then(|f| f.head);
        crate::ui::avatars(
            &mut self.font,
            &others,
            viewer,
            &mut self.scene.lines,
            &mut self.scene.ui,
        );
    }

    /// Sends where this person's head and hands are and what they have
    /// selected, in model space, at most [`PRESENCE_HZ`] times a second
    /// (a shared session only).
    fn send_presence(&mut self) {
        let Some(channel) = &self.presence else {
            return;
        };
        let Some(f) = self.session.last_frame() else {
            return;
        };
        if f.time - self.presence_sent < 1.0 / PRESENCE_HZ {
            return;
        }
        self.presence_sent = f.time;
        let to_model = self.session.model().inverse();
        let pose = |p: &interact::Pose| PresencePose {
            p: to_model.apply(p.position).as_vec3().to_array(),
            q: (to_model.rotate * p.orientation)
                .normalize()
                .as_quat()
                .to_array(),
        };
        let hand = |h: interact::Hand| {
            f.controller(h)
                .and_then(|c| c.grip)
                .or_else(|| f.hand(h).and_then(|j| j.pose(interact::Joint::Palm)))
                .map(|p| pose(&p))
        };
        channel.send(&Presence {
            head: f.head.as_ref().map(pose),
            hands: [hand(interact::Hand::Left), hand(interact::Hand::Right)],
            selected: self.session.preview().selected.map(|id| id.0),
            ..Presence::empty()
        });
    }

    /// The other participants heard from lately, placed in this person's
    /// world (each sees the model where they put it).
    fn avatars(&mut self) -> Vec<crate::ui::Avatar> {
        let Some(channel) = &self.presence else {
            return Vec::new();
        };
        let others = channel.others(Duration::from_secs_f64(PRESENCE_STALE_SECS));
        if others.is_empty() {
            return Vec::new();
        }
        let model = *self.session.model();
        let world = |p: [f32; 3]| model.apply(glam::Vec3::from(p).as_dvec3()).as_vec3();
        if self.selection_boxes.0 != self.scene.version {
            self.selection_boxes = (self.scene.version, Vec::new());
        }
        let mut out = Vec::with_capacity(others.len());
        for (who, p) in others {
            let (name, colour) = self
                .people
                .iter()
                .find(|(id, _, _)| *id == who)
                .map_or_else(
                    || (who.clone(), colour_for(&who)),
                    |(_, n, c)| (n.clone(), *c),
                );
            let selected = p.selected.and_then(|id| {
                let [lo, hi] = self.object_box(ObjectId(id))?;
                Some(std::array::from_fn(|i| {
                    let pick = |bit: usize, a: f64, b: f64| if i & bit == 0 { a } else { b };
                    let c = glam::DVec3::new(
                        pick(1, lo.x, hi.x),
                        pick(2, lo.y, hi.y),
                        pick(4, lo.z, hi.z),
                    );
                    model.apply(c).as_vec3()
                }))
            });
            out.push(crate::ui::Avatar {
                name,
                colour,
                head: p.head.map(|h| {
                    let q = model.rotate * glam::Quat::from_array(h.q).as_dquat();
                    (world(h.p), q.normalize().as_quat())
                }),
                hands: p.hands.map(|h| h.map(|h| world(h.p))),
                selected,
            });
        }
        out
    }

    /// The model-space box of object `id` as drawn (None: not drawn),
    /// measured once per scene version.
    fn object_box(&mut self, id: ObjectId) -> Option<ModelBox> {
        if let Some((_, b)) = self.selection_boxes.1.iter().find(|(o, _)| *o == id) {
            return *b;
        }
        let b = (|| {
            let mesh = self.scene.document.as_ref()?;
            let (_, r) = self.scene.document_objects.iter().find(|(o, _)| *o == id)?;
            let mut lo = glam::DVec3::splat(f64::INFINITY);
            let mut hi = -lo;
            for t in &mesh.triangles[r.start as usize..r.end as usize] {
                for &v in t {
                    let p = glam::DVec3::from_array(mesh.positions[v as usize]);
                    lo = lo.min(p);
                    hi = hi.max(p);
                }
            }
            (lo.x <= hi.x).then_some([lo, hi])
        })();
        self.selection_boxes.1.push((id, b));
        b
    }

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

impl FrameSink for Interaction {
    fn frame(&mut self, frame: &interact::InputFrame) {
        self.step(frame);
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

    fn take_haptics(&mut self) -> Vec<Haptic> {
        self.stats.haptics += self.haptics.len() as u64;
        std::mem::take(&mut self.haptics)
    }

    fn notices(&self) -> Vec<Notice> {
        let (offline, view_only) = {
            let s = lock_status(&self.status);
            (s.offline, s.view_only)
        };
        let view_only = view_only.then(|| Notice {
            text: "VIEW ONLY: THE SESSION'S SERVER LETS YOU LOOK\nBUT NOT EDIT THIS DOCUMENT"
                .into(),
            warning: true,
        });
        let offline = offline.then(|| Notice {
            text: "OFFLINE: THE SHARED SESSION'S SERVER IS OUT OF REACH.\nYOUR EDITS ARE KEPT AND SENT ON RECONNECT".into(),
            warning: true,
        });
        self.save_failing()
            .map(|e| Notice {
                text: format!("AUTOSAVE FAILED, RETRYING:\n{}", wrap(&e, 48)),
                warning: true,
            })
            .into_iter()
            .chain(offline)
            .chain(view_only)
            .collect()
    }

    fn input_stats(&self) -> Option<SanitizerStats> {
        Some(self.session.input_stats())
    }

    fn settle(&mut self) {
        self.flush();
    }

    fn progress(&self) -> (u64, u64) {
        (lock(&self.shared).log.len() as u64, self.stats.commands)
    }
}

/// `text` broken into lines of at most `width` characters, at spaces where
/// possible (at most four lines; the rest is cut with "...").
fn wrap(text: &str, width: usize) -> String {
    let mut lines: Vec<String> = Vec::new();
    let mut cur = String::new();
    for word in text.split_whitespace() {
        let mut word = word.to_string();
        while word.chars().count() > width {
            let head: String = word.chars().take(width).collect();
            word = word.chars().skip(width).collect();
            if !cur.is_empty() {
                lines.push(std::mem::take(&mut cur));
            }
            lines.push(head);
        }
        if !cur.is_empty() && cur.chars().count() + 1 + word.chars().count() > width {
            lines.push(std::mem::take(&mut cur));
        }
        if !cur.is_empty() {
            cur.push(' ');
        }
        cur.push_str(&word);
    }
    if !cur.is_empty() {
        lines.push(cur);
    }
    if lines.len() > 4 {
        lines.truncate(4);
        lines[3].push_str(" ...");
    }
    lines.join("\n")
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
            it.flush();
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
    fn commits_in_the_background_apply_every_command_in_order() {
        // Without a flush per frame the tool may see a document a commit
        // behind; every command it produced is still applied, in order,
        // and the scene catches up.
        let trace = fixture();
        let model = trace.header.model.similarity().unwrap();
        let mut it = Interaction::new(&trace.header.tool, model, OpLog::new(), None).unwrap();
        let mut produced = Vec::new();
        for f in &trace.frames {
            if let Some(c) = it.step(f) {
                produced.push(c);
            }
        }
        assert!(produced.len() >= 3, "{}", produced.len());
        let mut expected = OpLog::new();
        let mut refused = 0;
        for c in &produced {
            refused += usize::from(apply_command(&mut expected, c).is_err());
        }
        let hash = it.log().document().content_hash();
        assert_eq!(hash, expected.document().content_hash());
        assert_eq!(it.stats().rejected.len(), refused);
        assert_eq!(it.stats().commit_ms.len(), produced.len());
        assert_eq!(it.document().content_hash(), hash);
        let doc = it.scene().document.as_ref().unwrap();
        assert_eq!(
            doc.triangle_count(),
            expected.document().combined_mesh().triangle_count()
        );
    }

    #[test]
    fn unknown_tools_are_typed_errors() {
        let e = Interaction::new("nope", Similarity::IDENTITY, OpLog::new(), None).err();
        assert!(
            matches!(e, Some(InteractionError::Tool(TraceError::UnknownTool(t))) if t.0 == "nope")
        );
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

    #[test]
    fn commits_pulse_the_hands_that_made_them() {
        let trace = fixture();
        let model = trace.header.model.similarity().unwrap();
        let mut it = Interaction::new(&trace.header.tool, model, OpLog::new(), None).unwrap();
        let mut pulses = Vec::new();
        for f in &trace.frames {
            it.step(f);
            it.flush();
            pulses.extend(it.take_haptics());
        }
        let commits = it.stats().commands as usize - it.stats().rejected.len();
        let strong: Vec<_> = pulses.iter().filter(|p| p.amplitude > 0.5).collect();
        assert!(commits >= 3, "{commits}");
        // At least one pulse per landed commit, on a real hand.
        assert!(strong.len() >= commits, "{} < {commits}", strong.len());
        assert!(strong.iter().all(|p| p.hand < 2 && p.millis > 0));
        // Ticks when a ray starts pointing at something.
        assert!(pulses.iter().any(|p| p.amplitude < 0.5));
        assert_eq!(it.stats().haptics as usize, pulses.len());
    }

    #[test]
    fn a_failing_save_shows_in_the_headset_until_a_save_succeeds() {
        let dir = std::env::temp_dir().join(format!("sw_xr_notice_{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("s.usda");
        // A directory where the file should be: the atomic save's final
        // rename fails (whatever its temporary file is called).
        let blocker = path.clone();
        std::fs::create_dir(&blocker).unwrap();
        let trace = fixture();
        let model = trace.header.model.similarity().unwrap();
        let saver = Autosaver::new(&path, AutosaveSettings::default(), SaveOptions::default());
        let mut it = Interaction::new("object", model, OpLog::new(), Some(saver)).unwrap();
        let mut k = 0;
        while it.log().is_empty() {
            it.step(&trace.frames[k]);
            k += 1;
        }
        assert!(!it.save_now());
        let notes = it.notices();
        assert_eq!(notes.len(), 1);
        assert!(notes[0].warning && notes[0].text.starts_with("AUTOSAVE FAILED"));
        assert!(!it.stats().save_errors.is_empty());
        std::fs::remove_dir(&blocker).unwrap();
        assert!(it.save_now());
        assert!(it.notices().is_empty());
        let loaded = load_file(&path, LoadOptions::default()).unwrap();
        assert_eq!(loaded.log.len(), it.log().len());
        let _ = std::fs::remove_dir_all(&dir);
    }

    #[test]
    fn a_frame_reads_its_notices_while_a_commit_holds_the_log() {
        // The commit thread holds the log while an op applies (a quarter
        // second for a GC edit); the frame's notices must not wait for it.
        let trace = fixture();
        let model = trace.header.model.similarity().unwrap();
        let it = Interaction::new("object", model, OpLog::new(), None).unwrap();
        let held = Arc::clone(&it.shared);
        let (locked_tx, locked) = mpsc::channel();
        let (release, release_rx) = mpsc::channel::<()>();
        let holder = std::thread::spawn(move || {
            let _guard = lock(&held);
            locked_tx.send(()).unwrap();
            let _ = release_rx.recv_timeout(Duration::from_secs(10));
        });
        locked.recv().unwrap();
        let t0 = Instant::now();
        let notes = it.notices();
        let waited = t0.elapsed();
        release.send(()).unwrap();
        holder.join().unwrap();
        assert!(notes.is_empty());
        assert!(
            waited < Duration::from_secs(5),
            "notices() waited {waited:?} for the log"
        );
    }

    #[test]
    fn wrapped_messages_fit_the_width() {
        let w = wrap(
            "cannot author the USD layer: object #1: patch 4 has 6 sides and more words",
            20,
        );
        assert!(w.lines().all(|l| l.chars().count() <= 20), "{w}");
        assert!(w.starts_with("cannot author the"));
        assert_eq!(wrap(&"x".repeat(50), 20).lines().count(), 3);
        assert!(wrap(&"word ".repeat(100), 10).ends_with("..."));
    }
}
