//! How every op of the document is reached from the headset (issue 19:
//! "every SPEC op reachable with hands or controllers"): one row per op of
//! [`crate::doc::OP_NAMES`], saying which tool emits it and with what
//! gesture or palette entry, or which op does its job in the headset, or
//! why it is left to the desktop. The README's "In the headset" table
//! says the same for a user. The test below keeps this table complete and
//! true: for each row a tool emits, and each row another op reaches, it
//! runs the test the row names (which makes the row's gesture with a
//! puppet) and checks that the row's op (or the op, or the kind of part
//! edit, that does its job) got into the log through the tool, not by the
//! test's own hand.

/// A test that drives a row's gesture: its path under `crate::interact`,
/// and the test itself (made by [`t!`]).
pub type Driver = (&'static str, fn());

/// The [`Driver`] of the test at `path` under `crate::interact`.
macro_rules! t {
    ($($path:ident)::+) => {
        (stringify!($($path)::+), crate::interact::$($path)::+)
    };
}

/// How one op is reached.
#[derive(Clone, Copy, Debug)]
pub enum How {
    /// A tool of the modeler session emits it.
    Emitted {
        /// The tool ([`crate::interact::TOOL_NAMES`]).
        tool: &'static str,
        /// The gesture or palette entry.
        gesture: &'static str,
        /// The test that drives it; the table's own test runs it and
        /// checks the op reached the log.
        test: Driver,
    },
    /// Another op, emitted in the headset, does its job there.
    Via {
        /// That op.
        op: &'static str,
        /// How.
        note: &'static str,
        /// What the test must get into the log: the op's name, or for a
        /// part edit its kind (`gc_edit_part:bend`).
        emits: &'static str,
        /// The test that drives the gesture `note` describes; the table's
        /// own test runs it and checks `emits` reached the log.
        test: Driver,
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
#[derive(Clone, Copy, Debug)]
pub struct Reach {
    /// The op's name.
    pub op: &'static str,
    /// How.
    pub how: How,
}

const fn tool(op: &'static str, tool: &'static str, gesture: &'static str, test: Driver) -> Reach {
    Reach {
        op,
        how: How::Emitted {
            tool,
            gesture,
            test,
        },
    }
}

const fn via(
    op: &'static str,
    by: &'static str,
    note: &'static str,
    emits: &'static str,
    test: Driver,
) -> Reach {
    Reach {
        op,
        how: How::Via {
            op: by,
            note,
            emits,
            test,
        },
    }
}

/// Every op, in the op table's order.
pub const HEADSET_REACH: &[Reach] = &[
    tool("add_solid", "object", "A with nothing selected places the palette's Shape at the controller", t!(tools::tool_tests::select_copy_delete_undo_redo)),
    via("edit_solid", "set_transform", "a solid's sizes change by scaling it (two hands, per axis from the palette's Scale)", "set_transform", t!(modeler_op_tests::a_two_hand_grab_scales_along_the_chosen_axis)),
    tool("set_transform", "object", "squeeze drags (one hand moves and turns, two hands scale)", t!(tools::tool_tests::grab_move_rotate_emits_one_op_per_release)),
    via("transform_by", "set_transform", "a drag records the absolute placement", "set_transform", t!(tools::tool_tests::grab_move_rotate_emits_one_op_per_release)),
    tool("duplicate", "object", "trigger selects, A copies the selection", t!(tools::tool_tests::select_copy_delete_undo_redo)),
    tool("delete", "object", "trigger selects, B deletes the selection", t!(tools::tool_tests::select_copy_delete_undo_redo)),
    tool("gc_create", "gc", "POINT (trigger) in empty space sketches a section, a second POINT stroke the spine", t!(tools::gc_tool::drawn_tests::a_section_then_a_spine_in_empty_space_make_a_new_assembly)),
    via("gc_bend", "gc_edit_part", "FIST (squeeze) on a key point and drag (PartEdit::Bend)", "gc_edit_part:bend", t!(tools::gc_tool::tests::fist_on_a_key_point_bends_within_the_spine_plane)),
    tool("gc_replace_spine", "gc", "POINT (trigger) on a key point, then sketch the new spine", t!(tools::gc_tool::tests::point_on_a_key_point_replaces_the_spine_by_a_sketch)),
    via("gc_resize", "gc_edit_part", "FIST (squeeze) on a section ring, drag across the spine (PartEdit::Resize)", "gc_edit_part:resize", t!(tools::gc_tool::tests::fist_on_a_section_resizes_shifts_or_twists_by_the_motion_component)),
    via("gc_shift", "gc_edit_part", "FIST (squeeze) on a section ring, drag along the spine (PartEdit::Shift)", "gc_edit_part:shift", t!(tools::gc_tool::tests::fist_on_a_section_resizes_shifts_or_twists_by_the_motion_component)),
    via("gc_twist", "gc_edit_part", "FIST (squeeze) on a section ring, turn about the spine (PartEdit::Twist)", "gc_edit_part:twist", t!(tools::gc_tool::tests::fist_on_a_section_resizes_shifts_or_twists_by_the_motion_component)),
    tool("gc_replace_section", "gc", "POINT (trigger) on a section ring, then sketch the new section", t!(tools::gc_tool::tests::point_on_a_section_replaces_it_by_a_sketch)),
    tool("gc_delete_section", "gc", "OPEN (no button) held 3 s on a section ring", t!(tools::gc_tool::tests::an_open_hold_on_a_section_deletes_it)),
    tool("gc_insert_section", "gc", "OPEN (no button) held 3 s on a part's surface between sections", t!(tools::gc_tool::tests::an_open_hold_on_the_surface_inserts_a_section_once)),
    tool("gc_set_shape", "gc", "PINCH (A, the trigger closes it) on an end section, then open: open or closed end", t!(tools::gc_tool::tests::pinch_on_an_end_section_sets_the_shape_type)),
    tool(
        "gc_set_resolution",
        "gc",
        "palette Resolution coarse/normal/fine (every part of the assembly)",
        t!(modeler_op_tests::gc_relations_are_released_and_resolution_set_from_the_palette),
    ),
    tool("sculpt_create", "sculpt", "A with no sculpt: a sphere to sculpt", t!(tools::ctl_tool_tests::a_with_no_sculpt_creates_a_sphere)),
    tool(
        "sculpt_stroke",
        "sculpt",
        "trigger held: the palette's Brush (drag, whittle, explode, collapse) or Brush from (any other object) at its Size",
        t!(modeler_op_tests::explode_and_collapse_presets_grow_and_shrink_the_sculpt),
    ),
    tool("sdf_create", "csg", "A with no volume: a new volume (a second A places the component)", t!(tools::ctl_tool_tests::a_with_no_volume_creates_one_then_places_the_component)),
    tool("sdf_add_operand", "csg", "A places the palette's Component with the Operation (stick up/down)", t!(modeler_op_tests::any_object_becomes_the_active_csg_component)),
    tool("sdf_set_operand_transform", "csg", "squeeze drags an operand", t!(tools::ctl_tool_tests::csg_drag_is_one_op_with_nan_frames_ignored)),
    tool("sdf_scale_two_hand", "csg", "both squeezes scale an operand (right stick quadrant: axis)", t!(tools::ctl_tool_tests::csg_two_hand_scale_is_clamped_and_per_axis)),
    tool("sdf_cancel_operand", "csg", "trigger double click on an operand", t!(tools::ctl_tool_tests::csg_select_copy_delete_update_and_undo)),
    tool("sdf_copy_operand", "csg", "trigger selects an operand, B copies it", t!(tools::ctl_tool_tests::csg_select_copy_delete_update_and_undo)),
    tool("sdf_update", "csg", "B with nothing selected fuses the pending operands", t!(tools::ctl_tool_tests::csg_select_copy_delete_update_and_undo)),
    Reach {
        op: "sdf_import_component",
        how: How::Desktop {
            why: "reads a mesh file: `shapewright-xr import --as component` or Blender's panel; in the headset, sdf_component_from_object makes a component of any model",
        },
    },
    tool("sdf_set_step", "csg", "palette Grid step", t!(modeler_tests::the_palette_reaches_every_tool_and_every_choice)),
    tool(
        "sdf_move_fused",
        "csg",
        "palette Grab moves: fused result, then squeeze and drag",
        t!(modeler_op_tests::a_grab_moves_the_fused_result_as_such),
    ),
    tool("sdf_copy_fused", "csg", "palette Fused result: copy", t!(modeler_tests::the_fused_result_is_copied_from_the_palette)),
    tool(
        "sdf_component_from_object",
        "csg",
        "palette Component from: any other object (it becomes the active component)",
        t!(modeler_op_tests::any_object_becomes_the_active_csg_component),
    ),
    tool("curve_network_create", "curve", "the first stroke with no network", t!(tools::curve_tool_tests::held_tools_emit_one_op_with_their_path)),
    tool("curve_draw", "curve", "trigger held: draw (left squeeze: on a plane; left trigger: mirrored)", t!(tools::curve_tool_tests::symmetry_plane_mirrors_the_stroke_and_drawing_plane_flattens_it)),
    tool("curve_draw_in_frame", "curve", "palette Draw in: left hand, then draw", t!(modeler_tests::strokes_drawn_in_the_left_hands_frame_move_with_it)),
    tool("curve_smooth", "curve", "trigger held 2-4 cm along a curve (Table 1), or palette Trigger: smooth", t!(tools::curve_tool_tests::held_tools_emit_one_op_with_their_path)),
    tool("curve_sharpen", "curve", "trigger held 2-4 cm across a curve (Table 1), or palette Trigger: sharpen", t!(tools::curve_tool_tests::held_tools_emit_one_op_with_their_path)),
    tool("curve_pull", "curve", "trigger held under 2 cm across a curve (Table 1), or palette Trigger: pull", t!(tools::curve_tool_tests::held_tools_emit_one_op_with_their_path)),
    tool("curve_attract", "curve", "palette Trigger: attract; trigger held on a curve draws it to the left hand's point (its trigger: line, its squeeze: plane)", t!(tools::curve_tool_tests::attract_draws_the_pointed_curve_towards_the_left_hands_point)),
    tool("curve_delete", "curve", "B on a curve", t!(tools::curve_tool_tests::fill_delete_undo_redo)),
    tool("curve_fill_loop", "curve", "palette A fills: pointed loop, then A over the loop", t!(tools::curve_tool_tests::a_pointed_loop_is_filled_alone)),
    tool("curve_fill_auto", "curve", "A (every loop)", t!(tools::curve_tool_tests::curve_network_trace_replays_to_a_closed_styled_model)),
    tool("surface_smooth", "curve", "palette Trigger: smooth, trigger held over a patch", t!(tools::curve_tool_tests::forced_tools_pull_smooth_and_sharpen_the_pointed_surface)),
    tool("surface_sharpen", "curve", "palette Trigger: sharpen, trigger held over a patch", t!(tools::curve_tool_tests::forced_tools_pull_smooth_and_sharpen_the_pointed_surface)),
    tool("surface_pull", "curve", "palette Trigger: pull, trigger held on a patch and dragged", t!(tools::curve_tool_tests::forced_tools_pull_smooth_and_sharpen_the_pointed_surface)),
    tool("gc_add_child", "gc", "POINT (trigger) on a part's surface sketches the child's section, then its spine", t!(tools::gc_tool::tests::point_on_the_surface_sketches_a_child_section_and_spine)),
    tool("gc_copy", "gc", "FIST (squeeze) held still 3 s on a part (palette Instance: copy or mirror), then drag the copy", t!(tools::gc_tool::tests::a_static_fist_for_three_seconds_instances_the_part_then_moves_the_copy)),
    tool("gc_transform_part", "gc", "FIST (squeeze) on a child part, drag, open", t!(tools::gc_tool::tests::a_static_fist_for_three_seconds_instances_the_part_then_moves_the_copy)),
    tool("gc_edit_part", "gc", "FIST (squeeze) on a key point (bend) or a section ring (resize, shift, twist), drag, open", t!(tools::gc_tool::tests::fist_on_a_section_resizes_shifts_or_twists_by_the_motion_component)),
    tool(
        "gc_release",
        "gc",
        "palette Release coplanar/concentric/symmetric, on the part last aimed at",
        t!(modeler_op_tests::gc_relations_are_released_and_resolution_set_from_the_palette),
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
        t!(modeler_op_tests::print_settings_are_set_from_the_palette),
    ),
    tool(
        "set_self_intersection_policy",
        "object",
        "palette Overlaps refuse/flag (a document setting)",
        t!(modeler_op_tests::print_settings_are_set_from_the_palette),
    ),
    tool(
        "set_printer",
        "object",
        "palette Printer: a preset (a document setting; a custom size is typed on the desktop)",
        t!(modeler_op_tests::print_settings_are_set_from_the_palette),
    ),
    Reach {
        op: "reserve_ids",
        how: How::Automatic {
            by: "a shared session, before each person's op that creates objects (their own id range)",
        },
    },
];

#[cfg(test)]
mod tests {
    use super::*;
    use crate::doc::applied;
    use crate::doc::OP_NAMES;
    use crate::interact::TOOL_NAMES;

    #[test]
    fn every_op_has_exactly_one_row_in_table_order() {
        let rows: Vec<&str> = HEADSET_REACH.iter().map(|r| r.op).collect();
        assert_eq!(rows, OP_NAMES, "one row per op, in the op table's order");
    }

    /// Runs `test` (once: `ran` keeps what each test got into the log)
    /// and says what is wrong unless `want` was among the ops it got
    /// into the log through `OpLog::apply_command` (`row`: the row's op).
    fn drive_and_check(
        ran: &mut Vec<(&'static str, Vec<&'static str>)>,
        test: Driver,
        want: &str,
        row: &str,
    ) -> Option<String> {
        let (test, drive) = test;
        if !ran.iter().any(|(t, _)| *t == test) {
            applied::take();
            drive();
            ran.push((test, applied::take()));
        }
        let ops = &ran.iter().find(|(t, _)| *t == test).unwrap().1;
        // stringify! spaces (and may break) the path at its `::`.
        let name: String = test.split_whitespace().collect();
        (!ops.contains(&want))
            .then(|| format!("{row}: {name} got {ops:?} into the log, not {want}"))
    }

    /// Each row a tool emits, and each row reached through another op, is
    /// run: the test it names drives the row's gesture through a session
    /// or the tool, and the row's op (for a row reached through another
    /// op, that op, or for a part edit its kind: a bend for `gc_bend`)
    /// must be among those that reached the log through
    /// `OpLog::apply_command`, which the tools and sessions apply through
    /// (an op a test sets up with `OpLog::apply` does not count; one it
    /// built and passed to `apply_command` itself would, so the drivers
    /// do not).
    #[test]
    fn each_row_s_test_gets_its_op_into_the_log_through_the_tool() {
        let mut ran: Vec<(&str, Vec<&'static str>)> = Vec::new();
        let mut failures = Vec::new();
        for r in HEADSET_REACH {
            match r.how {
                How::Emitted {
                    tool,
                    gesture,
                    test,
                } => {
                    assert!(TOOL_NAMES.contains(&tool), "{}: no tool {tool}", r.op);
                    assert!(!gesture.is_empty());
                    if let Some(f) = drive_and_check(&mut ran, test, r.op, r.op) {
                        failures.push(f);
                    }
                }
                How::Via {
                    op,
                    note,
                    emits,
                    test,
                } => {
                    assert!(!note.is_empty());
                    // A part edit's kind is the row's own (`gc_bend`:
                    // `gc_edit_part:bend`).
                    let kind = format!("{op}:{}", r.op.trim_start_matches("gc_"));
                    assert!(
                        emits == op || emits == kind,
                        "{}: {emits} is neither {op} nor {kind}",
                        r.op
                    );
                    if let Some(f) = drive_and_check(&mut ran, test, emits, r.op) {
                        failures.push(f);
                    }
                    let by = HEADSET_REACH.iter().find(|b| b.op == op);
                    assert!(
                        matches!(by.map(|b| b.how), Some(How::Emitted { .. })),
                        "{} is reached via {op}, which the headset must emit",
                        r.op
                    );
                }
                How::Desktop { why } => assert!(!why.is_empty()),
                How::Automatic { by } => assert!(!by.is_empty()),
            }
        }
        assert!(failures.is_empty(), "{failures:#?}");
        // The ops left to the desktop (each a row above, with its reason)
        // stay the two that need text entry or a file dialog.
        let desktop = HEADSET_REACH
            .iter()
            .filter(|r| matches!(r.how, How::Desktop { .. }))
            .count();
        assert!(desktop <= 2, "{desktop} ops left to the desktop");
    }
}
