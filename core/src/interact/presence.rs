//! This person's presence in a shared session, built once for both hosts:
//! [`Presence::from_frame`] (head and hands of a sanitized frame, in model
//! space, and the selection), `Session::presence` (the same from an input
//! session's last frame and model placement) and
//! [`PresencePose::from_pose`] (one model-space pose as presence carries
//! it). The presence message itself
//! is [`crate::doc::shared`]'s; building it from input lives here, above
//! both (the document never names `interact`).

use crate::doc::shared::{Presence, PresencePose};
use crate::interact::gesture::similarity::Similarity;
use crate::interact::input::{Frame, Hand, Joint, Pose};

impl PresencePose {
    /// A model-space pose as presence carries it (single precision).
    pub fn from_pose(p: &Pose) -> Self {
        Self {
            p: p.position.as_vec3().to_array(),
            q: p.orientation.as_quat().to_array(),
        }
    }
}

impl Presence {
    /// The presence of the person whose sanitized frame is `f`: the head,
    /// each hand (controller grip, else the tracked palm), both taken to
    /// model space by `to_model` (world to model: the inverse of the
    /// model's placement), and the selected object.
    pub fn from_frame(f: &Frame, to_model: &Similarity, selected: Option<u32>) -> Self {
        let pose = |p: &Pose| {
            PresencePose::from_pose(&Pose {
                position: to_model.apply(p.position),
                orientation: (to_model.rotate * p.orientation).normalize(),
            })
        };
        let hand = |h: Hand| {
            f.controller(h)
                .and_then(|c| c.grip)
                .or_else(|| f.hand(h).and_then(|j| j.pose(Joint::Palm)))
                .map(|p| pose(&p))
        };
        Presence {
            head: f.head.as_ref().map(pose),
            hands: [hand(Hand::Left), hand(Hand::Right)],
            selected,
            ..Presence::empty()
        }
    }
}

impl crate::interact::Session {
    /// This person's presence from the last frame the session accepted
    /// ([`Presence::from_frame`], through the inverse of the model's
    /// placement), with the host's selection; `None` before the first
    /// frame. Both hosts send it (the headset host at [`PRESENCE_HZ`],
    /// Blender's VR session when it runs the core's input session).
    ///
    /// [`PRESENCE_HZ`]: crate::doc::shared::PRESENCE_HZ
    pub fn presence(&self, selected: Option<u32>) -> Option<Presence> {
        Some(self.presence_at(self.last_frame()?, selected))
    }

    /// This person's presence from sanitized frame `f` (a host that draws
    /// newer frames than its tool has stepped sends the newest,
    /// [`crate::interact::Session::display_frame`]), through the inverse
    /// of the model's placement, with the host's selection.
    pub fn presence_at(&self, f: &Frame, selected: Option<u32>) -> Presence {
        Presence::from_frame(f, &self.model().inverse(), selected)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::interact::input::{Controller, HandJoints, JOINT_COUNT};
    use crate::math::{DQuat, DVec3};

    #[test]
    fn a_frame_becomes_presence_in_model_space() {
        // The model sits 1 m forward (-z) and twice as large: a world
        // point maps to model space through the inverse.
        let model = Similarity {
            translate: DVec3::new(0.0, 0.0, -1.0),
            rotate: DQuat::IDENTITY,
            scale: 2.0,
        };
        let grip = Pose::new(DVec3::new(0.2, 1.0, -1.0), DQuat::IDENTITY);
        let mut joints = [None; JOINT_COUNT];
        joints[Joint::Palm as usize] =
            Some(Pose::new(DVec3::new(-0.2, 1.0, -1.0), DQuat::IDENTITY));
        let f = Frame {
            time: 1.0,
            dt: 0.011,
            head: Some(Pose::new(DVec3::new(0.0, 1.6, 0.0), DQuat::IDENTITY)),
            hands: [None, Some(HandJoints { joints })],
            controllers: [
                Some(Controller {
                    grip: Some(grip),
                    aim: None,
                    buttons: None,
                    teleported: false,
                }),
                None,
            ],
        };
        let p = Presence::from_frame(&f, &model.inverse(), Some(7));
        assert_eq!(p.head.unwrap().p, [0.0, 0.8, 0.5]);
        // Left: the controller's grip; right: no controller, the palm.
        assert_eq!(p.hands[0].unwrap().p, [0.1, 0.5, 0.0]);
        assert_eq!(p.hands[1].unwrap().p, [-0.1, 0.5, 0.0]);
        assert_eq!(p.hands[0].unwrap().q, [0.0, 0.0, 0.0, 1.0]);
        assert_eq!(p.selected, Some(7));
        // What receivers accept.
        assert_eq!(Presence::decode(&p.to_bytes()).unwrap(), p);
        // Nothing tracked: nothing sent but the selection.
        let empty = Frame {
            head: None,
            hands: [None, None],
            controllers: [None, None],
            ..f
        };
        let q = Presence::from_frame(&empty, &Similarity::IDENTITY, None);
        assert_eq!(q, Presence::empty());
    }
}

#[cfg(test)]
mod session_tests {
    use crate::doc::Document;
    use crate::interact::gesture::similarity::Similarity;
    use crate::interact::input::{InputFrame, Pose};
    use crate::interact::{tool_named, Session};
    use crate::math::{DQuat, DVec3};

    #[test]
    fn a_session_sends_its_last_frame_in_model_space() {
        let model = Similarity {
            translate: DVec3::new(0.0, 0.0, -1.0),
            rotate: DQuat::IDENTITY,
            scale: 2.0,
        };
        let mut s = Session::new(tool_named("object").unwrap(), model);
        assert_eq!(s.presence(None), None, "no frame yet: nothing to send");
        let doc = Document::default();
        for k in 0..3 {
            let frame = InputFrame {
                time: f64::from(k) / 72.0,
                head: Some(Pose::new(DVec3::new(0.0, 1.6, 0.0), DQuat::IDENTITY)),
                hands: [None, None],
                controllers: [None, None],
            };
            s.step(&frame, &doc);
        }
        let p = s.presence(Some(3)).unwrap();
        assert_eq!(p.head.unwrap().p, [0.0, 0.8, 0.5]);
        assert_eq!(p.selected, Some(3));
    }
}
