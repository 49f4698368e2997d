//! [`Interaction`] as the frame loops' [`FrameSink`]: frames, lifecycle
//! events, haptics and the notices the headset shows.

use shapewright::interact::{self, SanitizerStats};

use super::commit::{lock, lock_status};
use super::frame::Interaction;
use crate::gfx::Scene;
use crate::xr::{FrameSink, Haptic, LifecycleEvent, Notice};

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
pub(super) fn wrap(text: &str, width: usize) -> String {
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
