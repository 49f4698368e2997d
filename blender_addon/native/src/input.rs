//! One frame of raw input as a typed value: [`Controller`] (grip and aim
//! poses, buttons) and [`InputFrame`] (time, head, controllers), built by
//! a host each frame and handed to `InputSession.step`. Nothing is checked
//! here: a lost pose (NaN) or a jump is the core's sanitizer's to judge,
//! as for the headset host. Recorded trace lines (which may hold tracked
//! hand joints) come in through [`InputFrame::from_dict`].

use pyo3::prelude::*;
use shapewright::interact::{ControllerButtons, ControllerSample, InputFrame as CoreFrame};

use crate::placement::Pose;

/// One controller's state in a frame.
#[pyclass(module = "shapewright._native", frozen, from_py_object)]
#[derive(Clone, Copy, Debug)]
#[repr(transparent)]
pub struct Controller(pub(crate) ControllerSample);

#[pymethods]
impl Controller {
    /// A controller sample: grip and aim poses (stage space, metres),
    /// trigger (`select`) and squeeze (`grab`) in [0, 1], the A/X
    /// (`primary`), B/Y (`secondary`) and menu buttons, the stick.
    #[new]
    #[pyo3(signature = (grip, aim=None, select=0.0, grab=0.0, primary=false, secondary=false, menu=false, stick=[0.0, 0.0]))]
    #[allow(clippy::too_many_arguments)]
    fn new(
        grip: Pose,
        aim: Option<Pose>,
        select: f64,
        grab: f64,
        primary: bool,
        secondary: bool,
        menu: bool,
        stick: [f64; 2],
    ) -> Self {
        Self(ControllerSample {
            grip: grip.0,
            grip_valid: true,
            aim: aim.unwrap_or(grip).0,
            aim_valid: true,
            buttons: ControllerButtons {
                select,
                grab,
                primary,
                secondary,
                menu,
                stick,
            },
            buttons_valid: true,
        })
    }
}

/// Everything a host read in one frame.
#[pyclass(module = "shapewright._native", frozen)]
#[derive(Clone, Debug)]
#[repr(transparent)]
pub struct InputFrame(pub(crate) CoreFrame);

#[pymethods]
impl InputFrame {
    /// A frame at `time` seconds (increasing from frame to frame) with the
    /// head's pose and the left and right controllers, when present.
    #[new]
    #[pyo3(signature = (time, head=None, controllers=(None, None)))]
    fn new(
        time: f64,
        head: Option<Pose>,
        controllers: (Option<Controller>, Option<Controller>),
    ) -> Self {
        Self(CoreFrame {
            time,
            head: head.map(|h| h.0),
            hands: [None, None],
            controllers: [controllers.0.map(|c| c.0), controllers.1.map(|c| c.0)],
        })
    }

    /// A frame as a recorded trace line holds it (a dict with `time`,
    /// `head`, `hands` with their joints, `controllers`).
    #[staticmethod]
    fn from_dict(frame: &Bound<'_, PyAny>) -> PyResult<Self> {
        crate::convert::from_py_lenient(frame, "input frame").map(Self)
    }

    /// The frame's time (seconds).
    #[getter]
    fn time(&self) -> f64 {
        self.0.time
    }
}
