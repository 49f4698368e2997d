//! [`Session`]: the per-frame driver both hosts run — sanitizer, one
//! gesture classifier per hand, and the active tool. For a tool that reads
//! hands, an untracked hand with a controller is made from the controller
//! ([`crate::interact::gesture::controller_hand`]).

use crate::doc::{Document, ScriptCommand};

use crate::interact::gesture::controller_hand::controller_hand;
use crate::interact::gesture::similarity::Similarity;
use crate::interact::gesture::{GestureClassifier, GestureState};
use crate::interact::input::{Frame, Hand, InputFrame, Sanitizer};
use crate::interact::tools::{Preview, Tool, ToolContext};

/// Raw frames in, at most one command per frame out.
pub struct Session {
    sanitizer: Sanitizer,
    classifiers: [GestureClassifier; 2],
    gestures: [GestureState; 2],
    model: Similarity,
    tool: Box<dyn Tool>,
    last_frame: Option<Frame>,
}

impl Session {
    /// A session running `tool`, with the document placed in the world by
    /// `model` (model to stage space).
    pub fn new(tool: Box<dyn Tool>, model: Similarity) -> Self {
        let classifiers = [GestureClassifier::default(), GestureClassifier::default()];
        let gestures = [classifiers[0].state(), classifiers[1].state()];
        Self {
            sanitizer: Sanitizer::default(),
            classifiers,
            gestures,
            model,
            tool,
            last_frame: None,
        }
    }

    /// Feeds one raw frame. A frame the sanitizer rejects changes nothing
    /// and returns `None`.
    pub fn step(&mut self, raw: &InputFrame, doc: &Document) -> Option<ScriptCommand> {
        let mut frame = self.sanitizer.accept(raw)?;
        if self.tool.uses_hands() {
            for hand in Hand::BOTH {
                let i = hand.index();
                if frame.hands[i].is_none() {
                    frame.hands[i] = frame.controllers[i]
                        .as_ref()
                        .and_then(|c| controller_hand(c, hand));
                }
            }
        }
        for (i, c) in self.classifiers.iter_mut().enumerate() {
            self.gestures[i] = c.update(frame.time, frame.hands[i].as_ref(), frame.head.as_ref());
        }
        let cx = ToolContext {
            frame: &frame,
            gestures: &self.gestures,
            doc,
            model: &self.model,
        };
        let out = self.tool.update(&cx);
        self.last_frame = Some(frame);
        out
    }

    /// Switches to another tool, cancelling any gesture of the old one.
    pub fn set_tool(&mut self, tool: Box<dyn Tool>) {
        self.tool.cancel();
        self.tool = tool;
    }

    /// The active tool's preview.
    pub fn preview(&self) -> &Preview {
        self.tool.preview()
    }

    /// The gestures of the left and right hand.
    pub fn gestures(&self) -> &[GestureState; 2] {
        &self.gestures
    }

    /// The last accepted frame.
    pub fn last_frame(&self) -> Option<&Frame> {
        self.last_frame.as_ref()
    }

    /// What the input sanitizer accepted and dropped so far.
    pub fn input_stats(&self) -> crate::interact::input::SanitizerStats {
        self.sanitizer.stats()
    }

    /// The model placement.
    pub fn model(&self) -> &Similarity {
        &self.model
    }
}
