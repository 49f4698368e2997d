//! A shared session's presence in the headset: this person's pose and
//! selection sent out, the others' drawn as avatars with their selections.

use std::time::Duration;

use shapewright::doc::shared::{colour_for, Presence, PRESENCE_HZ, PRESENCE_STALE_SECS};
use shapewright::doc::ObjectId;

use super::commit::ModelBox;
use super::frame::Interaction;

impl Interaction {
    /// Sends where this person's head and hands are and what they have
    /// selected, in model space, at most [`PRESENCE_HZ`] times a second
    /// (a shared session only).
    pub(super) fn send_presence(&mut self) {
        if self.presence.is_none() {
            return;
        }
        let Some((time, p)) = self.presence_now() else {
            return;
        };
        if time - self.presence_sent < 1.0 / PRESENCE_HZ {
            return;
        }
        self.presence_sent = time;
        if let Some(channel) = &self.presence {
            channel.send(&p);
        }
    }

    /// This person's presence now and its frame's time: the head and
    /// hands of the newest frame, as they are drawn, not of the last one
    /// the tool stepped (while a commit runs the tool's frames are held,
    /// and the others saw this person's hands stop for its length).
    pub(super) fn presence_now(&self) -> Option<(f64, Presence)> {
        let f = self.drawn.as_ref().or(self.session.last_frame())?;
        let selected = self.session.preview().selected.map(|id| id.0);
        Some((f.time, self.session.presence_at(f, selected)))
    }

    /// The other participants heard from lately, placed in this person's
    /// world (each sees the model where they put it).
    pub(super) fn avatars(&mut self) -> Vec<crate::ui::Avatar> {
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
    pub(super) fn object_box(&mut self, id: ObjectId) -> Option<ModelBox> {
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
}
