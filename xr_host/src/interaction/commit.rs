//! The commit thread: it owns the [`OpLog`], the autosaver and a shared
//! session's link, applies the commands the frame hands it in order, and
//! reports each document (and its mesh) back.

use std::collections::HashMap;
use std::ops::{Deref, Range};
use std::sync::mpsc::{Receiver, RecvTimeoutError, Sender};
use std::sync::{Arc, Mutex, MutexGuard};
use std::time::{Duration, Instant};

use shapewright::doc::{Document, ObjectId, OpLog, ScriptCommand};
use shapewright::mesh::TriMesh;
use shapewright_usd::Autosaver;

/// The state the commit thread owns (the frame thread locks it only to
/// read the log or the save counters, never once per frame: the commit
/// thread holds it while an op applies, up to a quarter second for a GC
/// edit, which a frame cannot wait for).
pub(super) struct Shared {
    pub(super) log: OpLog,
    /// The shared session's connection (`run --join`).
    pub(super) link: Option<shapewright_net::Link>,
    pub(super) autosave: Option<Autosaver>,
    pub(super) saves: usize,
    pub(super) save_errors: Vec<String>,
    /// What every frame shows (its own lock, held only to copy it).
    pub(super) status: Arc<Mutex<Status>>,
}

/// The warnings every frame draws, kept apart from the log so reading
/// them never waits for a commit.
#[derive(Default)]
pub(super) struct Status {
    /// The last save failed with this (cleared by the next good save).
    pub(super) failing: Option<String>,
    /// The shared session's server is out of reach.
    pub(super) offline: bool,
    /// The shared session's server refused our edits (a viewer).
    pub(super) view_only: bool,
}

pub(super) fn lock_status(m: &Mutex<Status>) -> MutexGuard<'_, Status> {
    m.lock().unwrap_or_else(|e| e.into_inner())
}

impl Shared {
    pub(super) fn note_save(&mut self, r: Result<usize, shapewright_usd::SaveError>) {
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
    pub(super) fn save_now(&mut self) -> bool {
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

pub(super) fn lock(m: &Mutex<Shared>) -> MutexGuard<'_, Shared> {
    // A panic on the commit thread leaves the log as the last completed
    // op left it (ops apply to a copy): keep using it.
    m.lock().unwrap_or_else(|e| e.into_inner())
}

pub(super) enum Job {
    Apply(ScriptCommand),
    Save(Sender<bool>),
    Flush(Sender<()>),
    /// Tests: every later commit first waits this long (a slow commit,
    /// as a GC edit or a loaded machine makes one).
    #[cfg(test)]
    Slow(std::time::Duration),
}

/// A commit's result, sent back to the frame thread.
pub(super) struct Committed {
    /// The document after the command (unchanged when it was refused).
    pub(super) doc: Document,
    /// Its combined mesh (None: empty document) and each object's
    /// triangles in it.
    pub(super) mesh: DrawnDocument,
    pub(super) error: Option<String>,
    pub(super) ms: f64,
    /// Others' edits (a shared session), not a command of ours.
    pub(super) remote: bool,
    /// A shared session's participants (id, name, colour), sent with
    /// others' edits (a join is one).
    pub(super) people: Vec<Person>,
}

/// An axis-aligned box in model space: its low and high corners.
pub(super) type ModelBox = [glam::DVec3; 2];

/// A participant: id, name, colour.
pub(super) type Person = (String, String, [f32; 3]);

/// The participants of `log`'s shared session (none outside one).
pub(super) fn people_of(log: &OpLog) -> Vec<Person> {
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
pub(super) struct DrawnDocument {
    pub(super) mesh: Option<Arc<TriMesh>>,
    pub(super) objects: Vec<(ObjectId, Range<u32>)>,
}

/// `doc` as drawn, with smooth normals: each object's own when its mesh
/// has one per vertex (as the previews and the `render` command draw
/// it), else computed, or taken from `kept` when its mesh is the one they
/// were computed for (objects gone from `doc` are dropped from `kept`).
pub(super) fn document_mesh(doc: &Document, kept: &mut DrawnNormals) -> DrawnDocument {
    let mut normals = HashMap::with_capacity(doc.len());
    if doc.is_empty() {
        kept.by_object = normals;
        return DrawnDocument::default();
    }
    let (verts, tris) = doc.objects().fold((0, 0), |(v, t), (_, o)| {
        (v + o.mesh.positions.len(), t + o.mesh.triangles.len())
    });
    // Positions and triangles only: the drawn normals are gathered
    // below, and nothing reads the drawn mesh's sources (objects are
    // told apart by their triangle ranges). `TriMesh::append` would copy
    // the first object's normals (into an empty mesh) and every source.
    let mut m = TriMesh::new(Vec::with_capacity(verts), Vec::with_capacity(tris));
    let mut objects = Vec::with_capacity(doc.len());
    let mut drawn_normals = Vec::with_capacity(verts);
    for (id, o) in doc.objects() {
        let (base, first) = (m.positions.len() as u32, m.triangles.len() as u32);
        m.positions.extend_from_slice(&o.mesh.positions);
        m.triangles
            .extend(o.mesh.triangles.iter().map(|t| t.map(|i| i + base)));
        objects.push((id, first..m.triangles.len() as u32));
        if o.mesh.has_vertex_normals() {
            drawn_normals.extend_from_slice(&o.mesh.normals);
            continue;
        }
        let n = match kept.by_object.remove(&id) {
            Some((mesh, n)) if Arc::ptr_eq(&mesh, &o.mesh) => n,
            _ => {
                kept.computed += 1;
                o.mesh.vertex_normals()
            }
        };
        drawn_normals.extend_from_slice(&n);
        normals.insert(id, (Arc::clone(&o.mesh), n));
    }
    m.normals = drawn_normals;
    kept.by_object = normals;
    DrawnDocument {
        mesh: Some(Arc::new(m)),
        objects,
    }
}

/// An object's mesh and its normals.
type KeptNormals = (Arc<TriMesh>, Vec<[f64; 3]>);

/// The normals [`document_mesh`] computed for objects whose mesh has none
/// (a boolean's result, as a GC assembly's union), kept for the next
/// call while the object's mesh is the same (`Arc`). Before, every commit
/// recomputed the normals of the whole combined mesh, those of objects
/// that carry their own included (a sculpt, a solid, an SDF mesh): 262 ms
/// for a 4M-triangle sphere on the 2-core test machine, on every stroke
/// commit of a large sculpt and every edit of a small part beside it.
/// Computed normals are bit for bit the object's part of the combined
/// mesh's ([`TriMesh::vertex_normals`] sums a vertex's triangles in
/// order, and objects share no vertex). Holding an object's mesh keeps
/// its address from being reused while it is a key.
#[derive(Default)]
pub(super) struct DrawnNormals {
    by_object: HashMap<ObjectId, KeptNormals>,
    /// Objects whose normals were computed (for tests).
    pub(super) computed: usize,
}

/// `mesh` with normals (for the renderer's smooth shading): its own when
/// it has one per vertex (as in the drawn document), else computed once
/// per mesh: `cache` keeps the last source and its result.
pub(super) fn with_normals(
    cache: &mut Option<(Arc<TriMesh>, Arc<TriMesh>)>,
    mesh: Arc<TriMesh>,
) -> Arc<TriMesh> {
    if mesh.has_vertex_normals() {
        return mesh;
    }
    if let Some((src, out)) = cache {
        if Arc::ptr_eq(src, &mesh) {
            return Arc::clone(out);
        }
    }
    let out = Arc::new(mesh.with_normals().into_owned());
    *cache = Some((mesh, Arc::clone(&out)));
    out
}

/// How often the commit thread checks the autosave timer when idle.
pub(super) const TICK: Duration = Duration::from_millis(200);

/// How often it pumps a shared session's link when idle.
pub(super) const NET_TICK: Duration = Duration::from_millis(4);

/// Pumps the shared session's link: others' entries in, our next append
/// out. Returns the new document when others' edits changed it, with the
/// session's messages for this person.
pub(super) fn pump_link(s: &mut Shared) -> Option<(Document, Vec<String>)> {
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

/// The commit thread: applies the frame thread's commands to the log,
/// pumps a shared session's link and autosaves, and sends each new
/// document back drawn. `drawn` holds the normals the frame thread
/// computed for the document it started with.
pub(super) fn commit_loop(
    shared: Arc<Mutex<Shared>>,
    jobs: Receiver<Job>,
    done: Sender<Committed>,
    mut drawn: DrawnNormals,
) {
    let tick = if lock(&shared).link.is_some() {
        NET_TICK
    } else {
        TICK
    };
    #[cfg(test)]
    let mut slow = std::time::Duration::ZERO;
    loop {
        match jobs.recv_timeout(tick) {
            #[cfg(test)]
            Ok(Job::Slow(d)) => slow = d,
            Ok(Job::Apply(cmd)) => {
                #[cfg(test)]
                std::thread::sleep(slow);
                let t0 = Instant::now();
                let mut guard = lock(&shared);
                let s = &mut *guard;
                let (doc, error) = match s.log.apply_command(&cmd) {
                    Ok(()) => {
                        if let Some(a) = &mut s.autosave {
                            let r = a.changed(&s.log).map(usize::from);
                            s.note_save(r);
                        }
                        (s.log.document().clone(), None)
                    }
                    Err(e) => (s.log.document().clone(), Some(e.to_string())),
                };
                // A shared session sends the edit at once.
                if let Some(l) = &mut s.link {
                    s.log.with_shared(|log| l.pump(log));
                }
                drop(guard);
                // Meshed for drawing without the lock (the log does not
                // wait on drawing).
                let mesh = match error {
                    None => document_mesh(&doc, &mut drawn),
                    Some(_) => DrawnDocument::default(),
                };
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
                    let mesh = document_mesh(&doc, &mut drawn);
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
/// [`Interaction::log`](super::Interaction::log)).
pub struct LogGuard<'a>(pub(super) MutexGuard<'a, Shared>);

impl Deref for LogGuard<'_> {
    type Target = OpLog;
    fn deref(&self) -> &OpLog {
        &self.0.log
    }
}
