//! A client for Monado's `remote` driver: the project's own test client,
//! which plays recorded input through a real OpenXR runtime. Test-only
//! (issue 36): it lives with the tests that use it (`tests/monado.rs`),
//! not in the shipped host.
//!
//! Monado's remote driver (`src/xrt/drivers/remote/`) is an HMD and two
//! Valve Index controllers fed over TCP (port 4242 by default, open once
//! the application has created its system). The client sends fixed-size
//! packets, `struct r_remote_data` of `r_interface.h` (header `mndrmt3`,
//! 376 bytes, little-endian, C layout); the hub keeps the latest. On
//! connect the hub first writes two packets (its reset state and its
//! latest), which [`RemoteClient::connect`] reads as the handshake.
//!
//! What the runtime makes of a packet: the head centre is the HEAD pose;
//! with `per_view_data_valid` the two views' poses and fields of view come
//! from the packet as they are (the pacing tag rides on the left eye's
//! `angle_up`, see `shapewright_xr::xr::pace`); each controller's one pose is both
//! its grip and its aim pose; `active` false makes every input of that
//! controller inactive and its poses invalid; the finger curls drive
//! simulated, controller-derived hand joints when `hand_tracking_active`.
//!
//! [`Packet::from_frame`] turns one trace frame into a packet for the
//! Index bindings of [`shapewright::interact::ActionMap::default_map`]
//! (select = trigger, grab = squeeze force, primary = A, secondary = B,
//! menu = thumbstick click, stick = thumbstick), and [`expected_frame`]
//! says what a host must read back: the same frame with every number
//! rounded to f32 (the runtime's precision), aim = grip, and every
//! orientation renormalized the way Monado does it
//! ([`monado_normalize`]).

use std::io::{Read, Write};
use std::net::{SocketAddr, TcpStream};
use std::time::{Duration, Instant};

use shapewright::interact::{ControllerSample, InputFrame, Pose};
use shapewright::math::{DQuat, DVec3};

use shapewright_xr::xr::pace::tag_angle;

/// `R_HEADER_VALUE`: the bytes "mndrmt3\0" as a little-endian u64.
pub const HEADER: [u8; 8] = *b"mndrmt3\0";
/// `sizeof(struct r_remote_data)`.
pub const PACKET_SIZE: usize = 376;

/// What went wrong talking to the hub.
#[derive(Debug, thiserror::Error)]
pub enum RemoteError {
    /// Nothing listened within the timeout (is the host's system created,
    /// and `P_OVERRIDE_ACTIVE_CONFIG=remote` set?).
    #[error("Monado's remote hub at {addr} did not answer within {secs} s: {source}")]
    Connect {
        /// The address tried.
        addr: SocketAddr,
        /// The timeout.
        secs: u64,
        /// The last error.
        source: std::io::Error,
    },
    /// A read or write failed.
    #[error("remote hub: {0}")]
    Io(#[from] std::io::Error),
    /// The hub's greeting was not a packet of this layout.
    #[error("remote hub sent a packet with header {0:?}, expected \"mndrmt3\" (another Monado version?)")]
    Header([u8; 8]),
}

/// A rigid pose in f32, as the runtime keeps it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RPose {
    /// Position, metres.
    pub position: [f32; 3],
    /// Orientation `[x, y, z, w]`.
    pub orientation: [f32; 4],
}

impl RPose {
    /// At `position`, unrotated.
    pub const fn at(position: [f32; 3]) -> Self {
        Self {
            position,
            orientation: [0.0, 0.0, 0.0, 1.0],
        }
    }

    /// A core pose rounded to f32.
    pub fn from_pose(p: &Pose) -> Self {
        Self {
            position: p.position.to_array().map(|x| x as f32),
            orientation: p.orientation.to_array().map(|x| x as f32),
        }
    }

    /// Widened exactly to the core's f64 pose.
    pub fn to_pose(self) -> Pose {
        Pose::new(
            DVec3::from_array(self.position.map(f64::from)),
            DQuat::from_array(self.orientation.map(f64::from)),
        )
    }
}

/// One eye's view (`views[i]` of `struct r_head_data`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RView {
    /// `angle_left, angle_right, angle_up, angle_down`, radians.
    pub fov: [f32; 4],
    /// Pose relative to the head centre.
    pub pose: RPose,
}

/// The head (`struct r_head_data`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RHead {
    /// The head centre (OpenXR's VIEW space).
    pub center: RPose,
    /// Per-view data (`per_view_data_valid` when Some).
    pub views: Option<[RView; 2]>,
}

/// One controller (`struct r_remote_controller_data`).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct RController {
    /// Grip and aim pose.
    pub pose: RPose,
    /// Linear velocity, m/s.
    pub linear_velocity: [f32; 3],
    /// Angular velocity, rad/s (body space).
    pub angular_velocity: [f32; 3],
    /// Finger curls 0..1: little, ring, middle, index, thumb.
    pub hand_curl: [f32; 5],
    /// Trigger 0..1.
    pub trigger_value: f32,
    /// Squeeze 0..1.
    pub squeeze_value: f32,
    /// Squeeze force 0..1.
    pub squeeze_force: f32,
    /// Thumbstick x, y.
    pub thumbstick: [f32; 2],
    /// Trackpad force.
    pub trackpad_force: f32,
    /// Trackpad x, y.
    pub trackpad: [f32; 2],
    /// Controller-derived hand joints are reported.
    pub hand_tracking_active: bool,
    /// The controller is on (else every input is inactive, poses invalid).
    pub active: bool,
    /// Buttons, in the struct's order.
    pub system_click: bool,
    /// See above.
    pub system_touch: bool,
    /// A.
    pub a_click: bool,
    /// A touched.
    pub a_touch: bool,
    /// B.
    pub b_click: bool,
    /// B touched.
    pub b_touch: bool,
    /// Trigger clicked.
    pub trigger_click: bool,
    /// Trigger touched.
    pub trigger_touch: bool,
    /// Thumbstick clicked.
    pub thumbstick_click: bool,
    /// Thumbstick touched.
    pub thumbstick_touch: bool,
    /// Trackpad touched.
    pub trackpad_touch: bool,
}

impl Default for RPose {
    fn default() -> Self {
        Self::at([0.0; 3])
    }
}

/// A whole packet.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Packet {
    /// The head.
    pub head: RHead,
    /// Left controller.
    pub left: RController,
    /// Right controller.
    pub right: RController,
}

/// Half the distance between the eyes.
const HALF_IPD: f32 = 0.0315;
/// Half of a 90-degree field of view.
const HALF_FOV: f32 = std::f32::consts::FRAC_PI_4;

struct W(Vec<u8>);

impl W {
    fn f(&mut self, x: f32) {
        self.0.extend_from_slice(&x.to_le_bytes());
    }
    fn fs(&mut self, xs: &[f32]) {
        xs.iter().for_each(|&x| self.f(x));
    }
    fn b(&mut self, x: bool) {
        self.0.push(u8::from(x));
    }
    fn pose(&mut self, p: &RPose) {
        // struct xrt_pose { xrt_quat orientation; xrt_vec3 position; }
        self.fs(&p.orientation);
        self.fs(&p.position);
    }
}

struct R<'a>(&'a [u8], usize);

impl R<'_> {
    fn f(&mut self) -> f32 {
        let mut b = [0u8; 4];
        b.copy_from_slice(&self.0[self.1..self.1 + 4]);
        self.1 += 4;
        f32::from_le_bytes(b)
    }
    fn fs<const N: usize>(&mut self) -> [f32; N] {
        std::array::from_fn(|_| self.f())
    }
    fn b(&mut self) -> bool {
        self.1 += 1;
        self.0[self.1 - 1] != 0
    }
    fn skip(&mut self, n: usize) {
        self.1 += n;
    }
    fn pose(&mut self) -> RPose {
        let orientation = self.fs();
        let position = self.fs();
        RPose {
            position,
            orientation,
        }
    }
}

impl RController {
    fn write(&self, w: &mut W) {
        w.pose(&self.pose);
        w.fs(&self.linear_velocity);
        w.fs(&self.angular_velocity);
        w.fs(&self.hand_curl);
        w.f(self.trigger_value);
        w.f(self.squeeze_value);
        w.f(self.squeeze_force);
        w.fs(&self.thumbstick);
        w.f(self.trackpad_force);
        w.fs(&self.trackpad);
        for b in [
            self.hand_tracking_active,
            self.active,
            self.system_click,
            self.system_touch,
            self.a_click,
            self.a_touch,
            self.b_click,
            self.b_touch,
            self.trigger_click,
            self.trigger_touch,
            self.thumbstick_click,
            self.thumbstick_touch,
            self.trackpad_touch,
            false,
            false,
            false,
        ] {
            w.b(b);
        }
    }

    fn read(r: &mut R<'_>) -> Self {
        let mut c = RController {
            pose: r.pose(),
            linear_velocity: r.fs(),
            angular_velocity: r.fs(),
            hand_curl: r.fs(),
            trigger_value: r.f(),
            squeeze_value: r.f(),
            squeeze_force: r.f(),
            thumbstick: r.fs(),
            trackpad_force: r.f(),
            trackpad: r.fs(),
            ..Default::default()
        };
        for b in [
            &mut c.hand_tracking_active,
            &mut c.active,
            &mut c.system_click,
            &mut c.system_touch,
            &mut c.a_click,
            &mut c.a_touch,
            &mut c.b_click,
            &mut c.b_touch,
            &mut c.trigger_click,
            &mut c.trigger_touch,
            &mut c.thumbstick_click,
            &mut c.thumbstick_touch,
            &mut c.trackpad_touch,
        ] {
            *b = r.b();
        }
        r.skip(3);
        c
    }
}

impl Packet {
    /// The layout's bytes.
    pub fn to_bytes(self) -> [u8; PACKET_SIZE] {
        let mut w = W(Vec::with_capacity(PACKET_SIZE));
        w.0.extend_from_slice(&HEADER);
        let views = self.head.views.unwrap_or(
            [RView {
                fov: [0.0; 4],
                pose: RPose::default(),
            }; 2],
        );
        for v in &views {
            w.fs(&v.fov);
            w.pose(&v.pose);
            w.0.extend_from_slice(&[0; 4]);
        }
        w.pose(&self.head.center);
        w.b(self.head.views.is_some());
        w.0.extend_from_slice(&[0; 3]);
        self.left.write(&mut w);
        self.right.write(&mut w);
        let mut out = [0u8; PACKET_SIZE];
        out.copy_from_slice(&w.0);
        out
    }

    /// A packet from its bytes (the header is checked).
    pub fn from_bytes(b: &[u8; PACKET_SIZE]) -> Result<Self, RemoteError> {
        let mut header = [0u8; 8];
        header.copy_from_slice(&b[..8]);
        if header != HEADER {
            return Err(RemoteError::Header(header));
        }
        let mut r = R(b, 8);
        let mut views = [RView {
            fov: [0.0; 4],
            pose: RPose::default(),
        }; 2];
        for v in &mut views {
            v.fov = r.fs();
            v.pose = r.pose();
            r.skip(4);
        }
        let center = r.pose();
        let per_view = r.b();
        r.skip(3);
        let left = RController::read(&mut r);
        let right = RController::read(&mut r);
        Ok(Packet {
            head: RHead {
                center,
                views: per_view.then_some(views),
            },
            left,
            right,
        })
    }

    /// The packet for trace frame `frame`, stamped with pacing `tag` (see
    /// the module doc for the button mapping). A missing head stands at
    /// the origin at 1.6 m.
    pub fn from_frame(frame: &InputFrame, tag: u32) -> Packet {
        let center = frame
            .head
            .as_ref()
            .map_or(RPose::at([0.0, 1.6, 0.0]), RPose::from_pose);
        let view = |dx: f32, up: f32| RView {
            fov: [-HALF_FOV, HALF_FOV, up, -HALF_FOV],
            pose: RPose::at([dx, 0.0, 0.0]),
        };
        let controller = |c: &Option<ControllerSample>| match c {
            None => RController::default(),
            Some(c) => {
                let b = c.buttons;
                let (select, grab) = (b.select as f32, b.grab as f32);
                RController {
                    pose: RPose::from_pose(&c.grip),
                    hand_curl: [grab, grab, grab, select, if b.primary { 1.0 } else { 0.0 }],
                    trigger_value: select,
                    squeeze_value: grab,
                    squeeze_force: grab,
                    thumbstick: b.stick.map(|x| x as f32),
                    hand_tracking_active: true,
                    active: true,
                    a_click: b.primary,
                    a_touch: b.primary,
                    b_click: b.secondary,
                    b_touch: b.secondary,
                    trigger_click: select >= 0.5,
                    trigger_touch: select > 0.0,
                    thumbstick_click: b.menu,
                    thumbstick_touch: b.menu || b.stick != [0.0; 2],
                    ..Default::default()
                }
            }
        };
        Packet {
            head: RHead {
                center,
                views: Some([view(-HALF_IPD, tag_angle(tag)), view(HALF_IPD, HALF_FOV)]),
            },
            left: controller(&frame.controllers[0]),
            right: controller(&frame.controllers[1]),
        }
    }
}

/// Monado's renormalization of every located orientation
/// (`m_relation_chain_resolve` ends with `math_quat_normalize`, Eigen's
/// `normalize()` on four floats): the squared norm summed as
/// `(x² + z²) + (y² + w²)` (Eigen's SSE reduction of a 4-float packet),
/// its square root, each component divided by it, all in f32. Checked bit
/// for bit against what the host read over the 1114 frames of the teapot
/// controller trace.
pub fn monado_normalize(q: [f32; 4]) -> [f32; 4] {
    let [x, y, z, w] = q;
    let n = (x * x + z * z) + (y * y + w * w);
    if n > 0.0 {
        let s = n.sqrt();
        [x / s, y / s, z / s, w / s]
    } else {
        q
    }
}

/// Why a trace frame cannot pass through the remote driver unchanged.
pub fn unrepresentable(frame: &InputFrame) -> Option<String> {
    for (h, c) in frame.controllers.iter().enumerate() {
        let Some(c) = c else { continue };
        if !(c.grip_valid && c.aim_valid && c.buttons_valid) {
            return Some(format!(
                "hand {h}: a controller with some parts invalid (the driver has one `active` flag)"
            ));
        }
        if c.aim != c.grip {
            return Some(format!(
                "hand {h}: aim differs from grip (the driver has one pose)"
            ));
        }
    }
    frame
        .hands
        .iter()
        .any(Option::is_some)
        .then(|| "optical hand joints (the driver makes joints from controllers)".into())
}

/// What a host reads back for `frame` through the remote driver: every
/// number rounded to f32, aim = grip, and no hand joints (the driver's
/// controller-derived joints are set aside by the core's sanitizer while
/// the buttons are valid).
pub fn expected_frame(frame: &InputFrame) -> InputFrame {
    let q = |p: &Pose| {
        let mut r = RPose::from_pose(p);
        r.orientation = monado_normalize(r.orientation);
        r.to_pose()
    };
    let f = |x: f64| f64::from(x as f32);
    InputFrame {
        time: frame.time,
        head: Some(
            frame
                .head
                .as_ref()
                .map_or(Pose::new(DVec3::new(0.0, f(1.6), 0.0), DQuat::IDENTITY), q),
        ),
        hands: [None, None],
        controllers: frame.controllers.map(|c| {
            c.map(|c| {
                let mut b = c.buttons;
                b.select = f(b.select);
                b.grab = f(b.grab);
                b.stick = b.stick.map(f);
                ControllerSample {
                    grip: q(&c.grip),
                    aim: q(&c.grip),
                    buttons: b,
                    ..c
                }
            })
        }),
    }
}

/// A connection to the remote hub.
pub struct RemoteClient {
    stream: TcpStream,
    /// Packets sent.
    pub sent: u64,
}

impl RemoteClient {
    /// Connects to the hub at `addr`, retrying until `timeout` (the hub
    /// listens only once the application created its system), and reads
    /// its two greeting packets.
    pub fn connect(addr: SocketAddr, timeout: Duration) -> Result<Self, RemoteError> {
        let start = Instant::now();
        let mut stream = loop {
            match TcpStream::connect_timeout(&addr, Duration::from_millis(500)) {
                Ok(s) => break s,
                Err(e) if start.elapsed() >= timeout => {
                    return Err(RemoteError::Connect {
                        addr,
                        secs: timeout.as_secs(),
                        source: e,
                    })
                }
                Err(_) => std::thread::sleep(Duration::from_millis(50)),
            }
        };
        stream.set_nodelay(true)?;
        stream.set_read_timeout(Some(timeout))?;
        let mut buf = [0u8; PACKET_SIZE];
        stream.read_exact(&mut buf)?;
        // The hub's reset state, then its latest: read as the handshake.
        Packet::from_bytes(&buf)?;
        stream.read_exact(&mut buf)?;
        Packet::from_bytes(&buf)?;
        Ok(Self { stream, sent: 0 })
    }

    /// Sends one packet.
    pub fn send(&mut self, p: &Packet) -> Result<(), RemoteError> {
        self.stream.write_all(&p.to_bytes())?;
        self.sent += 1;
        Ok(())
    }

    /// Sends trace frame `frame` paced as step `seq` (see `shapewright_xr::xr::pace`):
    /// twice, tagged `2 seq + 1` and `2 seq + 2`.
    pub fn send_paced(&mut self, frame: &InputFrame, seq: u32) -> Result<(), RemoteError> {
        self.send(&Packet::from_frame(frame, 2 * seq + 1))?;
        self.send(&Packet::from_frame(frame, 2 * seq + 2))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use shapewright::interact::ControllerButtons;
    use shapewright_xr::xr::pace::angle_tag;

    fn frame() -> InputFrame {
        let grip = Pose::new(
            DVec3::new(0.15, 1.15, -0.25),
            DQuat::from_xyzw(-0.229753, 0.0, 0.0, 0.973249),
        );
        InputFrame {
            time: 0.04,
            head: Some(Pose::new(DVec3::new(0.0, 1.6, 0.0), DQuat::IDENTITY)),
            hands: [None, None],
            controllers: [
                None,
                Some(ControllerSample {
                    grip,
                    grip_valid: true,
                    aim: grip,
                    aim_valid: true,
                    buttons: ControllerButtons {
                        select: 1.0,
                        grab: 0.3,
                        primary: true,
                        menu: true,
                        stick: [0.5, -0.25],
                        ..Default::default()
                    },
                    buttons_valid: true,
                }),
            ],
        }
    }

    #[test]
    fn the_layout_matches_r_interface_h() {
        // Offsets from `struct r_remote_data` (checked with offsetof on the
        // vendored header): head at 8, its center at 8 + 96, per-view flag
        // at 8 + 124, left at 136, right at 256; in a controller the
        // trigger at 72, the thumbstick at 84, the active flag at 105, A at
        // 108, the thumbstick click at 114.
        let p = Packet::from_frame(&frame(), 5);
        let b = p.to_bytes();
        assert_eq!(b.len(), 376);
        assert_eq!(&b[..8], b"mndrmt3\0");
        let f = |o: usize| f32::from_le_bytes(b[o..o + 4].try_into().unwrap());
        // Left view's angle_up carries the tag.
        assert_eq!(angle_tag(f(8 + 8)), Some(5));
        // Head centre position y (after the 16-byte quaternion).
        assert_eq!(f(8 + 96 + 16 + 4), 1.6);
        assert_eq!(b[8 + 124], 1);
        let right = 256;
        assert_eq!(f(right + 16), 0.15);
        assert_eq!(f(right + 72), 1.0);
        assert_eq!(f(right + 80), 0.3);
        assert_eq!((f(right + 84), f(right + 88)), (0.5, -0.25));
        assert_eq!((b[right + 104], b[right + 105]), (1, 1));
        assert_eq!((b[right + 108], b[right + 110], b[right + 114]), (1, 0, 1));
        assert_eq!(b[136 + 105], 0, "the absent left controller is off");
        assert_eq!(Packet::from_bytes(&b).unwrap(), p);
        let mut bad = b;
        bad[0] = b'x';
        assert!(matches!(
            Packet::from_bytes(&bad),
            Err(RemoteError::Header(_))
        ));
    }

    #[test]
    fn expected_frames_are_the_trace_in_f32() {
        let f = frame();
        assert_eq!(unrepresentable(&f), None);
        let e = expected_frame(&f);
        let c = e.controllers[1].unwrap();
        assert_eq!(c.grip.position.x, f64::from(0.15f32));
        assert_eq!(c.buttons.grab, f64::from(0.3f32));
        assert_eq!(c.aim, c.grip);
        assert_eq!(e.time, f.time);
        let mut g = f.clone();
        g.controllers[1].as_mut().unwrap().aim_valid = false;
        assert!(unrepresentable(&g).is_some());
    }
}
