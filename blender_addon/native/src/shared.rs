//! Shared sessions (`shapewright-net`): joining, pumping the connection,
//! and presence as a typed value ([`Presence`]: head, hands, selection,
//! in model space) instead of JSON text.

use std::sync::Mutex;
use std::time::Duration;

use pyo3::prelude::*;
use pyo3::types::PyDict;
use shapewright::doc::shared::{Presence as CorePresence, PresencePose, PRESENCE_STALE_SECS};
use shapewright::doc::OpLog;
use shapewright_net::{LinkOptions, SessionUrl};

use crate::doc::Session;
use crate::error::{ParseError, SessionError};
use crate::placement::Pose;

/// One person's presence: where their head and hands are (model space,
/// metres) and what they have selected.
#[pyclass(module = "shapewright._native", frozen, eq, from_py_object)]
#[derive(Clone, Debug, PartialEq)]
#[repr(transparent)]
pub struct Presence(pub(crate) CorePresence);

fn to_core(p: &Pose) -> PresencePose {
    PresencePose::from_pose(&p.0)
}

fn from_core(p: &PresencePose) -> Pose {
    let c = |x: f32| f64::from(x);
    Pose(shapewright::interact::Pose {
        position: shapewright::math::DVec3::new(c(p.p[0]), c(p.p[1]), c(p.p[2])),
        orientation: shapewright::math::DQuat::from_xyzw(
            c(p.q[0]),
            c(p.q[1]),
            c(p.q[2]),
            c(p.q[3]),
        ),
    })
}

#[pymethods]
impl Presence {
    /// A presence; refuses one others could not draw (a non-finite pose,
    /// an orientation that is not a rotation).
    #[new]
    #[pyo3(signature = (head=None, hands=(None, None), selected=None))]
    fn new(
        head: Option<Pose>,
        hands: (Option<Pose>, Option<Pose>),
        selected: Option<u32>,
    ) -> PyResult<Self> {
        let p = CorePresence {
            head: head.as_ref().map(to_core),
            hands: [hands.0.as_ref().map(to_core), hands.1.as_ref().map(to_core)],
            selected,
            ..CorePresence::empty()
        };
        // The receivers' check, here, so a bad pose is refused at the sender.
        CorePresence::decode(&p.to_bytes()).map_err(|e| ParseError::new_err(e.to_string()))?;
        Ok(Self(p))
    }

    /// The head's pose, when tracked.
    #[getter]
    fn head(&self) -> Option<Pose> {
        self.0.head.as_ref().map(from_core)
    }

    /// The left and right hands' poses, when tracked.
    #[getter]
    fn hands(&self) -> (Option<Pose>, Option<Pose>) {
        let [l, r] = &self.0.hands;
        (l.as_ref().map(from_core), r.as_ref().map(from_core))
    }

    /// The selected object's id, if any.
    #[getter]
    fn selected(&self) -> Option<u32> {
        self.0.selected
    }

    fn __repr__(&self) -> String {
        format!("Presence({:?})", self.0)
    }
}

/// See `Session.join`.
pub(crate) fn join(
    py: Python<'_>,
    url: &str,
    name: &str,
    me: Option<String>,
    replicas: usize,
    opened: OpLog,
) -> PyResult<(Session, Vec<String>)> {
    let url = SessionUrl::parse(url).map_err(|e| SessionError::new_err(e.to_string()))?;
    let me = me.unwrap_or_else(|| shapewright_net::join::participant_id(name));
    let options = LinkOptions {
        replicas: replicas.max(1),
        ..Default::default()
    };
    let (log, link, messages) = py
        .detach(|| shapewright_net::join::join(&url, name, &me, options, &opened))
        .map_err(|e| SessionError::new_err(e.to_string()))?;
    let mut s = Session::from_log(log);
    s.link = Some(Mutex::new(link));
    Ok((s, messages))
}

/// See `Session.pump`.
pub(crate) fn pump<'py>(s: &mut Session, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
    let report = match &s.link {
        Some(link) => {
            // On the caller's thread (Blender's timer): applying a big
            // edit of someone else's takes what applying it takes.
            let mut link = link.lock().unwrap_or_else(|e| e.into_inner());
            link.pump_log(&mut s.log).unwrap_or_default()
        }
        None => Default::default(),
    };
    if report.changed() {
        s.changed(0);
    }
    let d = PyDict::new(py);
    d.set_item("changed", report.changed())?;
    d.set_item("messages", report.notices)?;
    d.set_item("errors", report.errors)?;
    d.set_item("online", report.online || s.link.is_none())?;
    d.set_item("view_only", report.view_only)?;
    Ok(d)
}

/// See `Session.shared_url`.
pub(crate) fn url(s: &Session) -> Option<String> {
    let link = s.link.as_ref()?.lock().unwrap_or_else(|e| e.into_inner());
    Some(link.url().to_string())
}

/// See `Session.participants`.
pub(crate) fn participants(s: &Session) -> Vec<(String, String, (f32, f32, f32))> {
    s.log.shared().map_or_else(Vec::new, |sh| {
        sh.confirmed()
            .participants()
            .iter()
            .map(|p| (p.id.clone(), p.name.clone(), p.colour.into()))
            .collect()
    })
}

/// See `Session.send_presence`.
pub(crate) fn send_presence(s: &Session, p: &Presence) {
    if let Some(link) = &s.link {
        let link = link.lock().unwrap_or_else(|e| e.into_inner());
        link.presence().send(&p.0);
    }
}

/// See `Session.others`.
pub(crate) fn others(s: &Session) -> Vec<(String, Presence)> {
    let Some(link) = &s.link else {
        return Vec::new();
    };
    let link = link.lock().unwrap_or_else(|e| e.into_inner());
    link.presence()
        .others(Duration::from_secs_f64(PRESENCE_STALE_SECS))
        .into_iter()
        .map(|(who, p)| (who, Presence(p)))
        .collect()
}
