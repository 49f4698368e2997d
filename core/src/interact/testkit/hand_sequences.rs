//! Labelled hand-pose sequences for the gesture classifier's test set
//! (the kinematic hand model of [`crate::interact::gesture`] posed, moved
//! and jittered), and the score of a classifier on them.

use crate::math::fm::DetMath as _;
use crate::math::{DQuat, DVec3};

use crate::interact::gesture::handmodel::{hand_pose, HandParams, Rng};
use crate::interact::gesture::{GestureClassifier, GestureLabel, GestureSettings};
use crate::interact::input::{
    Hand, HandSample, InputFrame, JointSample, Pose, Sanitizer, JOINT_COUNT,
};

/// A raw hand sample of `poses`, every joint valid, with Gaussian tracking
/// jitter of `jitter` metres (standard deviation per axis).
pub fn hand_sample(poses: &[Pose; JOINT_COUNT], jitter: f64, rng: &mut Rng) -> HandSample {
    let joints = poses.map(|p| {
        let noise = DVec3::new(rng.normal(), rng.normal(), rng.normal()) * jitter;
        JointSample {
            pose: Pose::new(p.position + noise, p.orientation),
            radius: 0.008,
            valid: true,
        }
    });
    HandSample {
        active: true,
        joints,
        source: Default::default(),
    }
}

/// How a labelled test sequence is generated.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SequenceSettings {
    /// Frames per second.
    pub fps: f64,
    /// Number of held poses.
    pub segments: usize,
    /// Shortest and longest hold, seconds.
    pub hold: (f64, f64),
    /// Shortest and longest transition between holds, seconds.
    pub transition: (f64, f64),
    /// Tracking jitter (standard deviation per axis), metres.
    pub jitter: f64,
    /// Physiological tremor of the curls while holding (amplitude).
    pub tremor: f64,
    /// The generator's seed.
    pub seed: u64,
}

impl Default for SequenceSettings {
    fn default() -> Self {
        Self {
            fps: 90.0,
            segments: 200,
            hold: (0.6, 1.5),
            transition: (0.12, 0.3),
            jitter: 0.0015,
            tremor: 0.03,
            seed: 1,
        }
    }
}

/// One generated frame: the raw input and the pose being held (`None`
/// during a transition).
#[derive(Clone, Debug)]
pub struct LabelledFrame {
    /// The raw input (head and right hand).
    pub frame: InputFrame,
    /// The held pose, or `None` while moving between poses.
    pub label: Option<GestureLabel>,
    /// Index of the hold segment (transitions carry the next one's index).
    pub segment: usize,
}

/// A labelled sequence of held poses joined by transitions, with the wrist
/// moving and turning, the curls trembling and every joint jittering.
pub fn labelled_sequence(settings: &SequenceSettings) -> Vec<LabelledFrame> {
    let mut rng = Rng::new(settings.seed);
    let dt = 1.0 / settings.fps;
    let head = Pose::new(DVec3::new(0.0, 1.6, 0.0), DQuat::IDENTITY);
    let mut out = Vec::new();
    let mut t = 0.0;
    let mut prev: Option<(HandParams, Pose)> = None;
    for seg in 0..settings.segments {
        let label = GestureLabel::ALL[(rng.next_u64() % 5) as usize];
        let params = HandParams::sample(label, &mut rng);
        let wrist = random_wrist(&mut rng);
        if let Some((p0, w0)) = prev {
            let n = (rng.range(settings.transition.0, settings.transition.1) * settings.fps)
                .round()
                .max(1.0) as usize;
            for k in 0..n {
                let a = (k as f64 + 0.5) / n as f64;
                let a = a * a * (3.0 - 2.0 * a);
                let p = p0.lerp(&params, a);
                let w = Pose::new(
                    w0.position.lerp(wrist.position, a),
                    w0.orientation.slerp(wrist.orientation, a),
                );
                out.push(frame_of(
                    t,
                    head,
                    &p,
                    &w,
                    settings.jitter,
                    &mut rng,
                    None,
                    seg,
                ));
                t += dt;
            }
        }
        let n = (rng.range(settings.hold.0, settings.hold.1) * settings.fps).round() as usize;
        let phase = rng.range(0.0, std::f64::consts::TAU);
        for k in 0..n {
            let tt = k as f64 * dt;
            let wob = |i: f64| settings.tremor * (tt * 9.0 + phase + i).fsin();
            let mut p = params;
            for (i, c) in p.curls.iter_mut().enumerate() {
                *c = (*c + wob(i as f64)).clamp(0.0, 1.0);
            }
            p.pinch_gap = (p.pinch_gap + 0.1 * wob(5.0) * p.pinch_gap).max(0.0);
            let drift = DVec3::new((tt * 1.3).fsin(), (tt * 0.7).fcos(), 0.0) * 0.01;
            let w = Pose::new(wrist.position + drift, wrist.orientation);
            out.push(frame_of(
                t,
                head,
                &p,
                &w,
                settings.jitter,
                &mut rng,
                Some(label),
                seg,
            ));
            t += dt;
        }
        prev = Some((params, wrist));
    }
    out
}

fn random_wrist(rng: &mut Rng) -> Pose {
    let pos = DVec3::new(
        rng.range(-0.1, 0.4),
        rng.range(1.1, 1.5),
        rng.range(-0.5, -0.25),
    );
    // Around a neutral pose (palm down, fingers forward), turned up to 60°.
    let turn = DQuat::from_axis_angle(rng.unit_vector(), rng.range(0.0, 1.05));
    Pose::new(pos, turn)
}

#[allow(clippy::too_many_arguments)]
fn frame_of(
    t: f64,
    head: Pose,
    p: &HandParams,
    wrist: &Pose,
    jitter: f64,
    rng: &mut Rng,
    label: Option<GestureLabel>,
    segment: usize,
) -> LabelledFrame {
    let poses = hand_pose(p, Hand::Right, wrist);
    LabelledFrame {
        frame: InputFrame {
            time: t,
            head: Some(head),
            hands: [None, Some(hand_sample(&poses, jitter, rng))],
            controllers: [None, None],
        },
        label,
        segment,
    }
}

/// Accuracy of a classifier on a labelled sequence.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct GestureScore {
    /// Labelled (held-pose) frames.
    pub frames: usize,
    /// Of those, frames whose output matched the label.
    pub correct: usize,
    /// Output changes inside held poses after the output first matched
    /// the label (each is a spurious transition).
    pub spurious: usize,
    /// Held poses whose label was never output.
    pub missed_segments: usize,
}

impl GestureScore {
    /// `correct / frames`.
    pub fn accuracy(&self) -> f64 {
        self.correct as f64 / self.frames.max(1) as f64
    }
}

/// Runs a fresh classifier over `seq` (through the sanitizer) and scores it.
pub fn score_sequence(seq: &[LabelledFrame], settings: GestureSettings) -> GestureScore {
    let mut san = Sanitizer::default();
    let mut clf = GestureClassifier::new(settings);
    let mut score = GestureScore::default();
    // (segment, reached label, last output)
    let mut seg_state: Option<(usize, bool, Option<GestureLabel>)> = None;
    for lf in seq {
        let Some(frame) = san.accept(&lf.frame) else {
            continue;
        };
        let st = clf.update(frame.time, frame.hand(Hand::Right), frame.head.as_ref());
        let out = st.label();
        let Some(label) = lf.label else {
            continue;
        };
        score.frames += 1;
        if out == Some(label) {
            score.correct += 1;
        }
        match &mut seg_state {
            Some((seg, reached, last)) if *seg == lf.segment => {
                if *reached && out != *last {
                    score.spurious += 1;
                }
                *reached |= out == Some(label);
                *last = out;
            }
            _ => {
                if let Some((_, false, _)) = seg_state {
                    score.missed_segments += 1;
                }
                seg_state = Some((lf.segment, out == Some(label), out));
            }
        }
    }
    if let Some((_, false, _)) = seg_state {
        score.missed_segments += 1;
    }
    score
}
