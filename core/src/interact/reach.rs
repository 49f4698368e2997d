//! How every op of the document is reached from the headset (issue 19:
//! "every SPEC op reachable with hands or controllers"): one row per op of
//! [`crate::doc::OP_NAMES`], saying which tool emits it and with what
//! gesture or palette entry, or which op does its job in the headset, or
//! why it is left to the desktop. The README's "In the headset" table
//! says the same for a user; the tests below keep this table complete and
//! true to the tools' code, and the tools' own tests (named per row) drive
//! each gesture through a modeler session and check its effect.

/// How one op is reached.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum How {
    /// A tool of the modeler session emits it.
    Emitted {
        /// The tool ([`crate::interact::TOOL_NAMES`]).
        tool: &'static str,
        /// The gesture or palette entry.
        gesture: &'static str,
        /// A test that drives it through a session.
        test: &'static str,
    },
    /// Another op, emitted in the headset, does its job there.
    Via {
        /// That op.
        op: &'static str,
        /// How.
        note: &'static str,
    },
    /// Needs a keyboard or a file dialog: Blender's panel or the CLI.
    Desktop {
        /// Why.
        why: &'static str,
    },
    /// No person writes it: the software does, in the headset as on the
    /// desktop.
    Automatic {
        /// What writes it, and why.
        by: &'static str,
    },
}

/// One row: an op and how the headset reaches it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Reach {
    /// The op's name.
    pub op: &'static str,
    /// How.
    pub how: How,
}

const fn tool(
    op: &'static str,
    tool: &'static str,
    gesture: &'static str,
    test: &'static str,
) -> Reach {
    Reach {
        op,
        how: How::Emitted {
            tool,
            gesture,
            test,
        },
    }
}

const fn via(op: &'static str, by: &'static str, note: &'static str) -> Reach {
    Reach {
        op,
        how: How::Via { op: by, note },
    }
}

/// Every op, in the op table's order.
pub const HEADSET_REACH: &[Reach] = &[
    tool("add_solid", "object", "trigger on empty space places the palette's Shape", "tool_tests"),
    via("edit_solid", "set_transform", "a solid's sizes change by scaling it (two hands, per axis from the palette's Scale)"),
    tool("set_transform", "object", "grip drags (one hand moves and turns, two hands scale)", "modeler_tests::undo_redo_save_and_snapping_are_in_the_palette_and_replay_identically"),
    via("transform_by", "set_transform", "a drag records the absolute placement"),
    tool("duplicate", "object", "A on the selection", "tool_tests"),
    tool("delete", "object", "B on the selection", "tool_tests"),
    tool("gc_create", "gc", "draw a stroke (spine) and a section", "gc_tool::tests"),
    via("gc_bend", "gc_edit_part", "grab a key point and drag (PartEdit::Bend)"),
    tool("gc_replace_spine", "gc", "redraw the spine over a selected part", "gc_tool::tests"),
    via("gc_resize", "gc_edit_part", "pinch a section ring and spread (PartEdit::Resize)"),
    via("gc_shift", "gc_edit_part", "grab a section ring and slide it along the spine (PartEdit::Shift)"),
    via("gc_twist", "gc_edit_part", "grab a section ring and turn (PartEdit::Twist)"),
    tool("gc_replace_section", "gc", "draw a new section across a part", "gc_tool::tests"),
    tool("gc_delete_section", "gc", "B on a section ring", "gc_tool::tests"),
    tool("gc_insert_section", "gc", "A on the spine between sections", "gc_tool::tests"),
    tool("gc_set_shape", "gc", "hold on a part: cycle shape (GC kinds)", "gc_tool::tests"),
    tool(
        "gc_set_resolution",
        "gc",
        "palette Resolution coarse/normal/fine (every part of the assembly)",
        "modeler_op_tests::gc_relations_are_released_and_resolution_set_from_the_palette",
    ),
    tool("sculpt_create", "sculpt", "A with no sculpt: a sphere to sculpt", "ctl_tool_tests"),
    tool(
        "sculpt_stroke",
        "sculpt",
        "trigger held: the palette's Brush (drag, whittle, explode, collapse) or Brush from (any other object) at its Size",
        "modeler_op_tests::explode_and_collapse_presets_grow_and_shrink_the_sculpt",
    ),
    tool("sdf_create", "csg", "first operand placed with no volume", "ctl_tool_tests"),
    tool("sdf_add_operand", "csg", "trigger places the palette's Component with its Operation", "ctl_tool_tests"),
    tool("sdf_set_operand_transform", "csg", "grip drags an operand", "ctl_tool_tests"),
    tool("sdf_scale_two_hand", "csg", "two grips scale an operand (palette Scale axis)", "ctl_tool_tests::csg_two_hand_scale_is_clamped_and_per_axis"),
    tool("sdf_cancel_operand", "csg", "B on an operand", "ctl_tool_tests"),
    tool("sdf_copy_operand", "csg", "A on an operand", "ctl_tool_tests"),
    tool("sdf_update", "csg", "release of a drag re-fuses", "ctl_tool_tests"),
    Reach {
        op: "sdf_import_component",
        how: How::Desktop {
            why: "reads a mesh file: `shapewright-xr import --as component` or Blender's panel; in the headset, sdf_component_from_object makes a component of any model",
        },
    },
    tool("sdf_set_step", "csg", "palette Grid step", "modeler_tests::the_palette_reaches_every_tool_and_every_choice"),
    tool(
        "sdf_move_fused",
        "csg",
        "palette Grab moves: fused result, then squeeze and drag",
        "modeler_op_tests::a_grab_moves_the_fused_result_as_such",
    ),
    tool("sdf_copy_fused", "csg", "palette Fused result: copy", "modeler_tests::the_fused_result_is_copied_from_the_palette"),
    tool(
        "sdf_component_from_object",
        "csg",
        "palette Component from: any other object (it becomes the active component)",
        "modeler_op_tests::any_object_becomes_the_active_csg_component",
    ),
    tool("curve_network_create", "curve", "the first stroke with no network", "curve_tool_tests"),
    tool("curve_draw", "curve", "trigger held: draw (left grip: on a plane; left trigger: mirrored)", "curve_tool_tests"),
    tool("curve_draw_in_frame", "curve", "palette Draw in: left hand, then draw", "modeler_tests::strokes_drawn_in_the_left_hands_frame_move_with_it"),
    tool("curve_smooth", "curve", "trigger held 2-4 cm along a curve (Table 1), or palette Trigger: smooth", "curve_tool_tests::held_tools_emit_one_op_with_their_path"),
    tool("curve_sharpen", "curve", "trigger held 2-4 cm across a curve (Table 1), or palette Trigger: sharpen", "curve_tool_tests::held_tools_emit_one_op_with_their_path"),
    tool("curve_pull", "curve", "trigger held under 2 cm across a curve (Table 1), or palette Trigger: pull", "curve_tool_tests::held_tools_emit_one_op_with_their_path"),
    tool("curve_attract", "curve", "palette Trigger: attract; trigger held on a curve draws it to the left hand's point (its trigger: line, its grip: plane)", "curve_tool_tests::attract_draws_the_pointed_curve_towards_the_left_hands_point"),
    tool("curve_delete", "curve", "B on a curve", "curve_tool_tests::fill_delete_undo_redo"),
    tool("curve_fill_loop", "curve", "palette A fills: pointed loop, then A over the loop", "curve_tool_tests::a_pointed_loop_is_filled_alone"),
    tool("curve_fill_auto", "curve", "A (every loop)", "curve_tool_tests::fill_delete_undo_redo"),
    tool("surface_smooth", "curve", "palette Trigger: smooth, trigger held over a patch", "curve_tool_tests::forced_tools_pull_smooth_and_sharpen_the_pointed_surface"),
    tool("surface_sharpen", "curve", "palette Trigger: sharpen, trigger held over a patch", "curve_tool_tests::forced_tools_pull_smooth_and_sharpen_the_pointed_surface"),
    tool("surface_pull", "curve", "palette Trigger: pull, trigger held on a patch and dragged", "curve_tool_tests::forced_tools_pull_smooth_and_sharpen_the_pointed_surface"),
    tool("gc_add_child", "gc", "draw a stroke starting on a part", "gc_tool::tests"),
    tool("gc_copy", "gc", "palette Instance (copy or mirror), then A on a part", "modeler_tests::instancing_a_child_copies_it_unmirrored_unless_mirror_is_chosen"),
    tool("gc_transform_part", "gc", "grip drags a child part", "gc_tool::tests"),
    tool("gc_edit_part", "gc", "key point and section gestures on an assembly part", "gc_tool::tests"),
    tool(
        "gc_release",
        "gc",
        "palette Release coplanar/concentric/symmetric, on the part last aimed at",
        "modeler_op_tests::gc_relations_are_released_and_resolution_set_from_the_palette",
    ),
    Reach {
        op: "rename_object",
        how: How::Desktop {
            why: "needs text entry: Blender's outliner or panel (the headset names objects by kind and number)",
        },
    },
    tool(
        "set_wall_thickness",
        "object",
        "palette Wall 1.2/2/3 mm (a document setting)",
        "modeler_op_tests::print_settings_are_set_from_the_palette",
    ),
    tool(
        "set_self_intersection_policy",
        "object",
        "palette Overlaps refuse/flag (a document setting)",
        "modeler_op_tests::print_settings_are_set_from_the_palette",
    ),
    tool(
        "set_printer",
        "object",
        "palette Printer: a preset (a document setting; a custom size is typed on the desktop)",
        "modeler_op_tests::print_settings_are_set_from_the_palette",
    ),
    Reach {
        op: "reserve_ids",
        how: How::Automatic {
            by: "a shared session, before each person's op that creates objects (their own id range)",
        },
    },
];

/// The source of each tool, to check that it emits what the table says.
#[cfg(test)]
const TOOL_SOURCES: [(&str, &[&str]); 5] = [
    ("object", &[include_str!("tools/object_tool.rs")]),
    (
        "gc",
        &[
            include_str!("tools/gc_tool/create.rs"),
            include_str!("tools/gc_tool/edit.rs"),
            include_str!("tools/gc_tool/state.rs"),
            include_str!("tools/gc_tool/tool.rs"),
        ],
    ),
    (
        "csg",
        &[
            include_str!("tools/csg_tool/settings.rs"),
            include_str!("tools/csg_tool/gestures.rs"),
            include_str!("tools/csg_tool/tool.rs"),
        ],
    ),
    (
        "curve",
        &[
            include_str!("tools/curve_tool/settings.rs"),
            include_str!("tools/curve_tool/modes.rs"),
            include_str!("tools/curve_tool/tool.rs"),
        ],
    ),
    ("sculpt", &[include_str!("tools/brush_tool.rs")]),
];

#[cfg(test)]
mod tests {
    use super::*;
    use crate::doc::OP_NAMES;
    use crate::interact::TOOL_NAMES;

    /// `gc_add_child` -> `GcAddChild`, the op's variant in [`crate::doc::Op`].
    fn variant(op: &str) -> String {
        op.split('_')
            .map(|w| {
                let mut c = w.chars();
                c.next()
                    .map(|f| f.to_ascii_uppercase().to_string() + c.as_str())
                    .unwrap_or_default()
            })
            .collect()
    }

    #[test]
    fn every_op_has_exactly_one_row_in_table_order() {
        let rows: Vec<&str> = HEADSET_REACH.iter().map(|r| r.op).collect();
        assert_eq!(rows, OP_NAMES, "one row per op, in the op table's order");
    }

    #[test]
    fn each_tool_emits_the_ops_its_rows_name() {
        let mut emitted = 0;
        let mut automatic = 0;
        let mut missing = Vec::new();
        for r in HEADSET_REACH {
            match r.how {
                How::Emitted { tool, gesture, .. } => {
                    assert!(TOOL_NAMES.contains(&tool), "{}: no tool {tool}", r.op);
                    assert!(!gesture.is_empty());
                    let src = TOOL_SOURCES.iter().find(|(t, _)| *t == tool).unwrap().1;
                    let needle = format!("Op::{}(", variant(r.op));
                    if !src.iter().any(|s| s.contains(&needle)) {
                        missing.push(format!("{}: the {tool} tool never makes {needle}", r.op));
                    }
                    emitted += 1;
                }
                How::Via { op, note } => {
                    assert!(!note.is_empty());
                    let by = HEADSET_REACH.iter().find(|b| b.op == op);
                    assert!(
                        matches!(by.map(|b| b.how), Some(How::Emitted { .. })),
                        "{} is reached via {op}, which the headset must emit",
                        r.op
                    );
                }
                How::Desktop { why } => assert!(!why.is_empty()),
                How::Automatic { by } => {
                    assert!(!by.is_empty());
                    automatic += 1;
                }
            }
        }
        assert!(missing.is_empty(), "{missing:#?}");
        // All but a handful of those a person writes: the exceptions are
        // listed, with reasons.
        assert!(
            emitted + automatic + 8 >= OP_NAMES.len(),
            "{emitted} of {}",
            OP_NAMES.len()
        );
    }
}
