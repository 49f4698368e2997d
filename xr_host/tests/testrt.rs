//! The host driven through the project's scripted OpenXR runtime
//! (`xr_host/testrt`), loaded by the real (static) loader via a runtime
//! manifest in `XR_RUNTIME_JSON`. Each test runs the `shapewright-xr`
//! binary as a child process, so the environment is per test.

#[path = "support/record.rs"]
mod record;

use std::path::{Path, PathBuf};
use std::process::Command;

use shapewright::interact::{self, replay, InputFrame, Trace};
use shapewright_usd::{load_file, LoadOptions};
use shapewright_xr::xr::{LifecycleEvent, RunReport};
use shapewright_xr_testrt::script::{
    Fault, FaultAt, FrameStats, Keyframe, Refusals, Script, ScriptHand, ScriptPose, SENTINEL,
};

fn runtime_lib() -> PathBuf {
    let exe = std::env::current_exe().unwrap();
    let deps = exe.parent().unwrap();
    for dir in [deps, deps.parent().unwrap()] {
        let p = dir.join("libshapewright_xr_testrt.so");
        if p.exists() {
            return p;
        }
    }
    panic!(
        "libshapewright_xr_testrt.so not built next to {}",
        deps.display()
    );
}

fn pose(p: [f32; 3]) -> ScriptPose {
    ScriptPose {
        p,
        q: [0.0, 0.0, 0.0, 1.0],
        valid: true,
        nan: false,
    }
}

struct Run {
    code: Option<i32>,
    stdout: String,
    stderr: String,
    frames: Vec<InputFrame>,
    events: Vec<LifecycleEvent>,
    report: Option<RunReport>,
}

fn run_host(name: &str, script: &Script, args: &[&str]) -> Run {
    run_host_mode(name, script, &["--headless"], args).0
}

/// Runs the host in the given mode; also returns the runtime's frame stats.
fn run_host_mode(
    name: &str,
    script: &Script,
    mode: &[&str],
    args: &[&str],
) -> (Run, Option<FrameStats>) {
    let dir = std::env::temp_dir().join(format!(
        "shapewright_xr_testrt_{name}_{}",
        std::process::id()
    ));
    std::fs::create_dir_all(&dir).unwrap();
    let manifest = dir.join("runtime.json");
    let lib = runtime_lib();
    std::fs::write(
        &manifest,
        serde_json::json!({
            "file_format_version": "1.0.0",
            "runtime": {"name": "shapewright-xr-testrt", "library_path": lib}
        })
        .to_string(),
    )
    .unwrap();
    let script_path = dir.join("script.json");
    let stats_path = dir.join("stats.json");
    let mut script = script.clone();
    script.stats_path = Some(stats_path.to_string_lossy().into_owned());
    if let Some(c) = &script.capture_path {
        script.capture_path = Some(dir.join(c).to_string_lossy().into_owned());
    }
    let capture_path = script.capture_path.clone();
    let model = dir.join("model.stl");
    let mut cube = shapewright::solid::tessellate(
        &shapewright::solid::SolidShape::Box {
            size: [1.0, 1.0, 1.0],
        },
        16,
    )
    .unwrap();
    cube.compute_normals();
    shapewright::mesh::write_stl(&cube, &mut std::fs::File::create(&model).unwrap()).unwrap();
    std::fs::write(&script_path, serde_json::to_string(&script).unwrap()).unwrap();
    let record = dir.join("record.jsonl");
    let report = dir.join("report.json");
    let out = Command::new(env!("CARGO_BIN_EXE_shapewright-xr"))
        // The default autosave file lands in the working directory.
        .current_dir(&dir)
        .arg("run")
        .args(mode)
        .arg("--model")
        .arg(&model)
        .arg("--record")
        .arg(&record)
        .arg("--report")
        .arg(&report)
        .args(args)
        .env("XR_RUNTIME_JSON", &manifest)
        .env("SHAPEWRIGHT_TESTRT_SCRIPT", &script_path)
        .env_remove("XR_LOADER_DEBUG")
        .output()
        .unwrap();
    let (frames, events) = read_record(&record);
    let report = std::fs::read_to_string(&report)
        .ok()
        .map(|t| serde_json::from_str(&t).unwrap());
    let run = Run {
        code: out.status.code(),
        stdout: String::from_utf8_lossy(&out.stdout).into_owned(),
        stderr: String::from_utf8_lossy(&out.stderr).into_owned(),
        frames,
        events,
        report,
    };
    assert!(
        !run.stderr.contains("panicked"),
        "the host panicked:\n{}",
        run.stderr
    );
    let stats = std::fs::read_to_string(&stats_path)
        .ok()
        .map(|t| serde_json::from_str(&t).unwrap());
    if let Some(c) = capture_path {
        let _ = std::fs::copy(
            &c,
            std::env::temp_dir().join(format!("shapewright_xr_{name}_capture.bin")),
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
    (run, stats)
}

fn read_record(p: &Path) -> (Vec<InputFrame>, Vec<LifecycleEvent>) {
    record::parse(&std::fs::read_to_string(p).unwrap_or_default())
}

fn states(r: &Run) -> Vec<String> {
    r.events
        .iter()
        .filter_map(|e| match e {
            LifecycleEvent::State(s) => Some(s.clone()),
            _ => None,
        })
        .collect()
}

/// No scripted sentinel (a pose read without VALID bits) in any pose the
/// host marked valid, and every untracked pose written as the identity:
/// the runtime's undefined contents never reach the core.
fn assert_clean(frames: &[InputFrame]) {
    let mut poses = Vec::new();
    for f in frames {
        poses.extend(f.head);
        for c in f.controllers.iter().flatten() {
            for (p, valid) in [(c.grip, c.grip_valid), (c.aim, c.aim_valid)] {
                if valid {
                    poses.push(p);
                } else {
                    assert_eq!(p, interact::Pose::IDENTITY);
                }
            }
        }
        for h in f.hands.iter().flatten() {
            for j in &h.joints {
                if j.valid {
                    poses.push(j.pose);
                } else {
                    assert_eq!(j.pose, interact::Pose::IDENTITY);
                }
            }
        }
    }
    for p in poses {
        assert!(
            p.position
                .to_array()
                .iter()
                .all(|c| *c as f32 != SENTINEL || !c.is_finite()),
            "{p:?}"
        );
    }
}

/// Frame times strictly increase and are positive.
fn assert_times_increase(frames: &[InputFrame]) {
    assert!(frames
        .windows(2)
        .all(|w| w[1].time > w[0].time && w[0].time > 0.0));
}

fn v3(p: &interact::Pose) -> [f32; 3] {
    p.position.to_array().map(|x| x as f32)
}

fn base_script() -> Script {
    Script {
        keyframes: vec![Keyframe {
            at: 0,
            head: Some(pose([0.0, 1.6, 0.0])),
            left: ScriptHand {
                grip: Some(pose([-0.2, 1.2, -0.3])),
                aim: Some(pose([-0.2, 1.2, -0.35])),
                ..Default::default()
            },
            right: ScriptHand {
                grip: Some(pose([0.2, 1.2, -0.3])),
                aim: Some(pose([0.2, 1.2, -0.35])),
                select: 0.7,
                squeeze: 0.25,
                primary: true,
                joints: Some(pose([0.2, 1.1, -0.3])),
                ..Default::default()
            },
        }],
        ..Default::default()
    }
}

#[test]
fn session_reaches_focused_and_scripted_input_reaches_the_sink() {
    let r = run_host("focused", &base_script(), &["--frames", "12"]);
    assert_eq!(r.code, Some(0), "{}\n{}", r.stdout, r.stderr);
    let rep = r.report.as_ref().unwrap();
    assert!(rep.reached_focused);
    assert_eq!(states(&r), record::HOST_ENDED_RUN);
    assert_eq!(
        rep.exit_reason,
        "exit requested by the host: the frame limit was reached"
    );
    assert_eq!(r.frames.len(), 12);
    assert_eq!(rep.frames, 12);
    assert_eq!(rep.poses_dropped, 0);
    for f in &r.frames {
        // LOCAL_FLOOR: the script's floor-level coordinates, unchanged.
        assert_eq!(v3(&f.head.unwrap()), [0.0, 1.6, 0.0]);
        let [left, right] = &f.controllers;
        let (left, right) = (left.unwrap(), right.unwrap());
        assert_eq!(v3(&left.grip), [-0.2, 1.2, -0.3]);
        assert_eq!(v3(&right.aim), [0.2, 1.2, -0.35]);
        assert_eq!(right.buttons.select, f64::from(0.7f32));
        assert_eq!(right.buttons.grab, 0.25);
        assert!(right.buttons.primary && !right.buttons.menu);
        assert_eq!(left.buttons.select, 0.0);
        // 26 joints laid out 1 cm apart along +X from the wrist.
        let hand = f.hands[1].as_ref().unwrap();
        let j25 = v3(&hand.joints[25].pose);
        assert!((j25[0] - 0.45).abs() < 1e-5 && j25[1] == 1.1);
        assert!(f.hands[0].is_none(), "left hand tracker inactive");
    }
    // Time comes from xrConvertTimespecTimeToTimeKHR: positive, increasing.
    assert_times_increase(&r.frames);
    // All five controller profiles were accepted (hand interaction is not
    // offered, the 1.1 and vendor profiles not available).
    assert_eq!(rep.profiles.len(), 5, "{:?}", rep.profiles);
    let touch = "/interaction_profiles/oculus/touch_controller";
    assert_eq!(rep.profiles_bound, [Some(touch.into()), Some(touch.into())]);
    assert_eq!(rep.spaces.base, "local_floor");
    assert_eq!(rep.runtime.api_version, "1.0", "the 1.1 request fell back");
    assert!(rep.runtime.hand_tracking_supported);
    assert!(
        r.stdout.contains(
            "profile bound: /user/hand/left -> /interaction_profiles/oculus/touch_controller"
        ),
        "{}",
        r.stdout
    );
    assert_clean(&r.frames);
}

#[test]
fn invalid_poses_never_reach_the_sink() {
    let mut s = base_script();
    let mut lost = s.keyframes[0].clone();
    lost.at = 4; // applies from frame index 3 (frame k is synced at step k+1)
    lost.head = Some(ScriptPose {
        valid: false,
        ..pose([0.0, 1.6, 0.0])
    });
    lost.right.grip = Some(ScriptPose {
        nan: true,
        ..pose([0.2, 1.2, -0.3])
    });
    lost.left.aim = Some(ScriptPose {
        q: [0.0, 0.0, 0.0, 0.0],
        ..pose([0.0; 3])
    });
    lost.right.invalid_joints = vec![0, 5, 25];
    let mut back = s.keyframes[0].clone();
    back.at = 8;
    s.keyframes.extend([lost, back]);
    let r = run_host("invalid", &s, &["--frames", "10"]);
    assert_eq!(r.code, Some(0), "{}", r.stderr);
    assert_eq!(r.frames.len(), 10);
    for (k, f) in r.frames.iter().enumerate() {
        let bad = (3..7).contains(&k);
        // The host passes what the runtime said: the head untracked, the
        // NaN grip marked valid (the core's sanitizer drops it), the zero
        // quaternion marked valid, the three joints untracked.
        assert_eq!(f.head.is_none(), bad, "head at {k}");
        let right = f.controllers[1].unwrap();
        assert!(right.grip_valid);
        assert_eq!(right.grip.position.x.is_nan(), bad, "grip at {k}");
        let left = f.controllers[0].unwrap();
        assert_eq!(left.aim.orientation.length() == 0.0, bad, "aim at {k}");
        let hand = f.hands[1].as_ref().unwrap();
        let missing: Vec<usize> = (0..26).filter(|&j| !hand.joints[j].valid).collect();
        assert_eq!(missing, if bad { vec![0, 5, 25] } else { vec![] });
    }
    let rep = r.report.clone().unwrap();
    // 4 frames x (untracked head + NaN grip + zero-quaternion aim), all
    // counted by the one sanitizer; the runtime reports the zero quaternion
    // as valid, the sanitizer still rejects it.
    assert_eq!(rep.poses_dropped, 12);
    let input = rep.input.unwrap();
    assert_eq!((input.poses_untracked, input.poses_rejected), (4, 8));
    assert_clean(&r.frames);
}

#[test]
fn loss_pending_recreates_the_session() {
    let mut s = base_script();
    s.faults = vec![FaultAt {
        at: 6,
        fault: Fault::LossPending,
    }];
    let r = run_host("losspending", &s, &["--frames", "15"]);
    assert_eq!(r.code, Some(0), "{}", r.stderr);
    let rep = r.report.clone().unwrap();
    assert_eq!(rep.session_losses, 1);
    assert_eq!(rep.sessions_created, 2);
    assert_eq!(rep.instances_created, 1);
    assert_eq!(states(&r).iter().filter(|s| *s == "FOCUSED").count(), 2);
    assert!(states(&r).contains(&"LOSS_PENDING".to_string()));
    assert!(r.events.contains(&LifecycleEvent::SessionLost));
    assert_eq!(
        r.events
            .iter()
            .filter(|e| **e == LifecycleEvent::SessionCreated)
            .count(),
        2
    );
    // Frames keep counting across the new session; none are duplicated.
    assert_eq!(r.frames.len(), 15);
    assert_times_increase(&r.frames);
    assert_eq!(
        rep.exit_reason,
        "exit requested by the host: the frame limit was reached"
    );
    assert_clean(&r.frames);
}

#[test]
fn loss_pending_without_recreation_shuts_down_cleanly() {
    let mut s = base_script();
    s.faults = vec![FaultAt {
        at: 3,
        fault: Fault::LossPending,
    }];
    let r = run_host("lossexit", &s, &["--frames", "50", "--no-recreate"]);
    assert_eq!(r.code, Some(0), "{}", r.stderr);
    let rep = r.report.clone().unwrap();
    assert_eq!(rep.sessions_created, 1);
    assert_eq!(rep.session_losses, 1);
    assert_eq!(rep.exit_reason, "session lost");
    assert!(rep.frames >= 2 && rep.frames <= 4, "{}", rep.frames);
}

#[test]
fn instance_loss_is_retried() {
    let mut s = base_script();
    s.faults = vec![FaultAt {
        at: 5,
        fault: Fault::InstanceLoss,
    }];
    s.refuse_creates = 2;
    let r = run_host("instanceloss", &s, &["--frames", "12"]);
    assert_eq!(r.code, Some(0), "{}", r.stderr);
    let rep = r.report.clone().unwrap();
    assert_eq!(rep.instance_losses, 1);
    assert_eq!(
        rep.instance_retries, 2,
        "two refused xrCreateInstance calls"
    );
    assert_eq!(rep.instances_created, 2);
    assert_eq!(rep.sessions_created, 2);
    assert!(r.events.contains(&LifecycleEvent::InstanceLost));
    assert_eq!(r.frames.len(), 12);
    assert_times_increase(&r.frames);
    assert_clean(&r.frames);
}

#[test]
fn runtime_initiated_exit_ends_the_run() {
    let mut s = base_script();
    s.faults = vec![FaultAt {
        at: 4,
        fault: Fault::RuntimeExit,
    }];
    let r = run_host("runtimeexit", &s, &["--frames", "1000"]);
    assert_eq!(r.code, Some(0), "{}", r.stderr);
    let rep = r.report.clone().unwrap();
    assert_eq!(rep.exit_reason, "exit requested by the runtime");
    assert!(rep.frames <= 6, "{}", rep.frames);
    assert_eq!(states(&r).last().map(String::as_str), Some("EXITING"));
}

#[test]
fn without_hand_tracking_controllers_still_work() {
    let mut s = base_script();
    s.hand_tracking = false;
    let r = run_host("nohands", &s, &["--frames", "5"]);
    assert_eq!(r.code, Some(0), "{}", r.stderr);
    assert_eq!(r.frames.len(), 5);
    assert!(r
        .frames
        .iter()
        .all(|f| f.hands[1].is_none() && f.controllers[1].is_some_and(|c| c.grip_valid)));
}

/// Issue 16, item 1: a runtime that offers XR_EXT_hand_tracking on a
/// system that cannot track hands (Monado's `simulated`, most PC
/// headsets). The host asks the system, creates no tracker, and runs on
/// controllers.
#[test]
fn a_system_without_hand_tracking_gets_no_tracker_and_runs() {
    let mut s = base_script();
    s.hands_supported = false;
    let r = run_host("nohandsys", &s, &["--frames", "5"]);
    assert_eq!(r.code, Some(0), "{}", r.stderr);
    let rep = r.report.unwrap();
    assert!(rep.runtime.hand_tracking_offered && !rep.runtime.hand_tracking_supported);
    assert_eq!(rep.hands_tracked, [None, None]);
    assert_eq!(r.frames.len(), 5);
    assert!(r.frames.iter().all(|f| f.hands == [None, None]));
    assert!(
        r.stdout.contains("system cannot track hands"),
        "{}",
        r.stdout
    );
}

/// XR_EXT_hand_tracking_data_source: the host reports where joints come
/// from and passes it to the core, whose sanitizer lets buttons win over
/// controller-derived joints and keeps optical ones.
#[test]
fn hand_data_sources_are_reported_and_passed_on() {
    for (source, overridden) in [("controller", true), ("unobstructed", false)] {
        let mut s = base_script();
        s.hand_source = Some(source.into());
        let r = run_host(&format!("source_{source}"), &s, &["--frames", "5"]);
        assert_eq!(r.code, Some(0), "{}", r.stderr);
        let rep = r.report.unwrap();
        assert!(rep.runtime.hand_data_source);
        let name = if overridden { "controller" } else { "optical" };
        assert_eq!(rep.hands_tracked[1].as_deref(), Some(name));
        let input = rep.input.unwrap();
        assert_eq!(
            input.hands_overridden > 0,
            overridden,
            "{source}: {input:?}"
        );
        let want = if overridden {
            interact::HandSource::Controller
        } else {
            interact::HandSource::Optical
        };
        assert!(r
            .frames
            .iter()
            .all(|f| f.hands[1].as_ref().unwrap().source == want));
    }
}

/// Issue 16, item 2: LOCAL's origin is at eye height on real runtimes.
/// Whatever base space the runtime allows (LOCAL_FLOOR; LOCAL lowered by
/// the height measured in STAGE; LOCAL lowered by an assumed 1.6 m, also
/// when STAGE is offered but cannot locate LOCAL at the start), the tools
/// see floor-level coordinates and build the same model.
#[test]
fn the_model_lands_at_floor_level_whichever_space_the_runtime_gives() {
    let trace = fixture_trace();
    let n = trace.frames.len().to_string();
    let want = replay(&trace).unwrap();
    for (name, local_floor, stage, blind_start, base) in [
        ("sp_floor", true, true, false, "local_floor"),
        ("sp_measured", false, true, false, "local_measured"),
        ("sp_assumed", false, false, false, "local_assumed"),
        ("sp_unmeasured", false, true, true, "local_assumed"),
    ] {
        let mut s = script_from_trace(&trace);
        s.local_floor = local_floor;
        s.stage = stage;
        if blind_start {
            // The head is untracked until the app reads input: LOCAL has
            // no origin yet, so it cannot be measured in STAGE.
            s.keyframes[0].head = Some(script_pose(&interact::Pose::IDENTITY, false));
        }
        let m = run_model(name, &s, &["--frames", &n]);
        assert_eq!(m.run.code, Some(0), "{name}: {}", m.run.stderr);
        let rep = m.run.report.clone().unwrap();
        assert_eq!(rep.spaces.base, base, "{name}");
        let expect_offset = if base == "local_floor" { 0.0 } else { 1.6 };
        assert!(
            (rep.spaces.floor_offset_m - expect_offset).abs() < 1e-6,
            "{rep:?}"
        );
        let saved = m.saved.unwrap();
        let names = |ops: &[shapewright::doc::Op]| ops.iter().map(|o| o.name()).collect::<Vec<_>>();
        assert_eq!(names(saved.log.ops()), names(want.log.ops()), "{name}");
        assert_same_model(saved.log.document(), want.log.document(), 1e-4);
    }
}

/// Every valid pose of `got` (what the host fed its session) within `tol`
/// of `want`'s (the trace the runtime played): the same floor-level
/// coordinates.
fn assert_frames_near(got: &Trace, want: &Trace, tol: f64, name: &str) {
    assert_eq!(got.frames.len(), want.frames.len(), "{name}");
    let near = |a: &interact::Pose, b: &interact::Pose, what: &str, k: usize| {
        let d = (a.position - b.position).length();
        assert!(d < tol, "{name}: frame {k} {what}: {a:?} vs {b:?}");
    };
    for (k, (g, w)) in got.frames.iter().zip(&want.frames).enumerate() {
        if let (Some(a), Some(b)) = (&g.head, &w.head) {
            near(a, b, "head", k);
        }
        for (a, b) in g.controllers.iter().zip(&w.controllers) {
            if let (Some(a), Some(b)) = (a, b) {
                if a.grip_valid && b.grip_valid {
                    near(&a.grip, &b.grip, "grip", k);
                }
            }
        }
    }
}

/// Issue 32: a runtime's (or layer's) refusals fall back, never end the
/// session. Each rung of the base-space chain (LOCAL_FLOOR -> LOCAL
/// measured against STAGE -> LOCAL assumed), refused the way layers and
/// runtimes refuse, gives a full session on the next rung with one
/// fallback line per refusal in the log and the report, the same
/// floor-level input, and the model replay builds from it.
#[test]
fn refused_spaces_fall_back_rung_by_rung_and_keep_floor_level_input() {
    let trace = fixture_trace();
    let n = trace.frames.len().to_string();
    let want = replay(&trace).unwrap();
    let floor = "LOCAL_FLOOR refused (XR_ERROR_VALIDATION_FAILURE): measuring LOCAL against STAGE";
    let stage = "STAGE (with LOCAL) refused (XR_ERROR_RUNTIME_FAILURE): LOCAL at an assumed eye height of 1.6 m";
    let locate = "locating LOCAL in STAGE refused (XR_ERROR_RUNTIME_FAILURE): LOCAL at an assumed eye height of 1.6 m";
    let floor_no_stage =
        "LOCAL_FLOOR refused (XR_ERROR_VALIDATION_FAILURE): LOCAL at an assumed eye height of 1.6 m";
    let none = Refusals::NONE;
    let cases: [(&str, Refusals, bool, &str, &[&str]); 4] = [
        (
            "rf_floor",
            Refusals {
                local_floor: true,
                ..none.clone()
            },
            true,
            "local_measured",
            &[floor],
        ),
        (
            "rf_stage",
            Refusals {
                local_floor: true,
                stage: true,
                ..none.clone()
            },
            true,
            "local_assumed",
            &[floor, stage],
        ),
        (
            "rf_locate",
            Refusals {
                local_floor: true,
                locate_stage: true,
                ..none.clone()
            },
            true,
            "local_assumed",
            &[floor, locate],
        ),
        (
            "rf_nostage",
            Refusals {
                local_floor: true,
                ..none
            },
            false,
            "local_assumed",
            &[floor_no_stage],
        ),
    ];
    for (name, refuse, offer_stage, base, lines) in cases {
        let mut s = script_from_trace(&trace);
        s.refuse = refuse;
        s.stage = offer_stage;
        let m = run_model(name, &s, &["--frames", &n]);
        assert_eq!(m.run.code, Some(0), "{name}: {}", m.run.stderr);
        let rep = m.run.report.clone().unwrap();
        assert_eq!(rep.spaces.base, base, "{name}");
        assert_eq!(rep.fallbacks, lines, "{name}");
        for l in lines {
            assert!(
                m.run.stderr.contains(&format!("fallback: {l}")),
                "{name}: {}",
                m.run.stderr
            );
            assert!(
                m.run.stdout.contains(&format!("fallback: {l}")),
                "{name}: {}",
                m.run.stdout
            );
        }
        assert!(rep.reached_focused, "{name}");
        // The input reached the tools at floor level (the fixture's head
        // is at 1.6 m, so the assumed height is exact here), and replaying
        // what the host recorded builds the fixture's model. (The saved
        // model itself can lag a commit on a loaded machine: commits run
        // off the frame; the paced Monado runs check it op for op.)
        let rec = m.recorded.expect("the host wrote its trace");
        assert_frames_near(&rec, &trace, 1e-5, name);
        let again = replay(&rec).unwrap();
        let names = |ops: &[shapewright::doc::Op]| ops.iter().map(|o| o.name()).collect::<Vec<_>>();
        assert_eq!(names(again.log.ops()), names(want.log.ops()), "{name}");
        assert_same_model(again.log.document(), want.log.document(), 1e-4);
        assert!(
            m.saved.is_some_and(|s| s.log.len() >= 4),
            "{name}: nothing saved"
        );
    }
}

/// Issue 32: refused hand trackers fall back (with the data-source struct
/// -> without -> controllers only), refused bindings of one profile skip
/// that profile; the session runs on, says so in the log and the report,
/// and the controllers keep driving the tools.
#[test]
fn refused_trackers_and_bindings_fall_back_and_controllers_still_work() {
    let touch = "/interaction_profiles/oculus/touch_controller";
    let simple = "/interaction_profiles/khr/simple_controller";
    let cases: [(&str, Refusals, Option<&str>, &[&str]); 3] = [
        (
            "rf_source",
            Refusals { hand_data_source: true, ..Refusals::NONE },
            Some("unknown"),
            &["hand trackers with a data source refused (XR_ERROR_VALIDATION_FAILURE): trying without"],
        ),
        (
            "rf_hands",
            Refusals { hand_trackers: true, ..Refusals::NONE },
            None,
            &[
                "hand trackers with a data source refused (XR_ERROR_RUNTIME_FAILURE): trying without",
                "hand trackers refused (XR_ERROR_RUNTIME_FAILURE): no hand tracking, controllers only",
            ],
        ),
        (
            "rf_profile",
            Refusals { profiles: vec![simple.into()], ..Refusals::NONE },
            Some("controller"),
            &["bindings for /interaction_profiles/khr/simple_controller refused (XR_ERROR_VALIDATION_FAILURE): that profile is skipped"],
        ),
    ];
    for (name, refuse, hands, lines) in cases {
        let mut s = base_script();
        s.hand_source = Some("controller".into());
        s.refuse = refuse;
        let r = run_host(name, &s, &["--frames", "5"]);
        assert_eq!(r.code, Some(0), "{name}: {}", r.stderr);
        let rep = r.report.clone().unwrap();
        assert_eq!(rep.fallbacks, lines, "{name}");
        for l in lines {
            assert!(
                r.stderr.contains(&format!("fallback: {l}")),
                "{name}: {}",
                r.stderr
            );
        }
        assert_eq!(rep.hands_tracked[1].as_deref(), hands, "{name}");
        assert_eq!(r.frames.len(), 5, "{name}");
        assert!(
            r.frames
                .iter()
                .all(|f| f.controllers[1].is_some_and(|c| c.grip_valid)),
            "{name}"
        );
        if hands.is_none() {
            assert!(r.frames.iter().all(|f| f.hands == [None, None]), "{name}");
        }
        assert!(
            rep.profiles.iter().any(|p| p == touch),
            "{name}: {:?}",
            rep.profiles
        );
        assert!(!rep.profiles.iter().any(|p| p == simple) || name != "rf_profile");
    }
}

#[test]
fn missing_runtime_is_a_clean_error() {
    let out = Command::new(env!("CARGO_BIN_EXE_shapewright-xr"))
        .current_dir(std::env::temp_dir())
        .args(["run", "--headless", "--frames", "1"])
        .env("XR_RUNTIME_JSON", "/nonexistent/runtime.json")
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(1));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("no OpenXR runtime available"), "{err}");
    assert!(!err.contains("panicked"));
}

/// Against a real runtime when `XR_RUNTIME_JSON` is set in the test's
/// environment; skipped otherwise. Headless needs XR_MND_headless; a
/// runtime without it must give the typed "lacks" error, not a crash.
#[test]
fn real_runtime_if_configured() {
    let Ok(manifest) = std::env::var("XR_RUNTIME_JSON") else {
        eprintln!("skipped: XR_RUNTIME_JSON is not set");
        return;
    };
    let out = Command::new(env!("CARGO_BIN_EXE_shapewright-xr"))
        .current_dir(std::env::temp_dir())
        .args(["run", "--headless", "--seconds", "2"])
        .env("XR_RUNTIME_JSON", &manifest)
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!err.contains("panicked"), "{err}");
    assert!(
        out.status.success() || err.contains("lacks XR_MND_headless"),
        "{err}"
    );
}

#[test]
fn headset_mode_reports_a_runtime_without_vulkan() {
    let dir = std::env::temp_dir().join(format!(
        "shapewright_xr_testrt_headset_{}",
        std::process::id()
    ));
    std::fs::create_dir_all(&dir).unwrap();
    let manifest = dir.join("runtime.json");
    std::fs::write(
        &manifest,
        serde_json::json!({"file_format_version": "1.0.0", "runtime": {"name": "t", "library_path": runtime_lib()}})
            .to_string(),
    )
    .unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_shapewright-xr"))
        .current_dir(std::env::temp_dir())
        .args(["run", "--frames", "1"])
        .env("XR_RUNTIME_JSON", &manifest)
        .env_remove("SHAPEWRIGHT_TESTRT_SCRIPT")
        .output()
        .unwrap();
    let _ = std::fs::remove_dir_all(&dir);
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1));
    assert!(err.contains("lacks XR_KHR_vulkan_enable2"), "{err}");
    assert!(!err.contains("panicked"));
}

#[test]
fn headset_renders_stereo_frames_on_lavapipe_through_the_runtime() {
    let mut s = base_script();
    s.vulkan = true;
    let (r, stats) = run_host_mode("headset", &s, &[], &["--frames", "8"]);
    assert_eq!(r.code, Some(0), "{}\n{}", r.stdout, r.stderr);
    let rep = r.report.clone().unwrap();
    assert!(rep.reached_focused);
    assert_eq!(rep.frames, 8);
    let stats = stats.expect("the runtime wrote frame stats");
    assert!(stats.graphics);
    // Every input frame came with a frame submission; while VISIBLE or
    // FOCUSED with a tracked head, each one carried a stereo projection
    // layer that passed the runtime's validation (swapchain released,
    // rects inside the image, array index < 2, unit poses).
    assert!(stats.frames_ended >= 8, "{stats:?}");
    assert!(stats.projection_layers >= 8, "{stats:?}");
    assert_clean(&r.frames);
}

#[test]
fn headset_skips_rendering_views_without_valid_poses() {
    let mut s = base_script();
    s.vulkan = true;
    let mut lost = s.keyframes[0].clone();
    lost.at = 3;
    lost.head = Some(ScriptPose {
        valid: false,
        ..pose([0.0, 1.6, 0.0])
    });
    s.keyframes.push(lost);
    let (r, stats) = run_host_mode("headsetlost", &s, &[], &["--frames", "8"]);
    assert_eq!(r.code, Some(0), "{}", r.stderr);
    let stats = stats.unwrap();
    // Frames 0-1 rendered (head tracked); from step 3 on the views are
    // invalid and the host submits empty frames.
    assert!(stats.projection_layers <= 3, "{stats:?}");
    assert!(stats.frames_ended >= 8, "{stats:?}");
    assert!(r.frames.iter().skip(2).all(|f| f.head.is_none()));
}

#[test]
fn headset_recreates_the_session_and_swapchain_after_loss_pending() {
    let mut s = base_script();
    s.vulkan = true;
    s.faults = vec![FaultAt {
        at: 4,
        fault: Fault::LossPending,
    }];
    let (r, stats) = run_host_mode("headsetloss", &s, &[], &["--frames", "10"]);
    assert_eq!(r.code, Some(0), "{}", r.stderr);
    let rep = r.report.clone().unwrap();
    assert_eq!(rep.sessions_created, 2);
    assert_eq!(rep.session_losses, 1);
    assert_eq!(rep.frames, 10);
    // Stats are of the last session: it rendered frames on a new swapchain.
    assert!(stats.unwrap().projection_layers >= 5);
}

#[test]
fn headset_pixels_show_the_model_where_the_eye_sees_it() {
    let mut s = base_script();
    s.vulkan = true;
    s.capture_path = Some("capture.bin".into());
    let (r, _) = run_host_mode("headsetpixels", &s, &[], &["--frames", "4"]);
    assert_eq!(r.code, Some(0), "{}", r.stderr);
    let bytes =
        std::fs::read(std::env::temp_dir().join("shapewright_xr_headsetpixels_capture.bin"))
            .expect("the runtime captured the left eye");
    let w = u32::from_le_bytes(bytes[0..4].try_into().unwrap());
    let h = u32::from_le_bytes(bytes[4..8].try_into().unwrap());
    assert_eq!((w, h), (256, 256));
    let px = |x: u32, y: u32| {
        let i = 8 + ((y * w + x) * 4) as usize;
        [bytes[i], bytes[i + 1], bytes[i + 2], bytes[i + 3]]
    };
    let bg = px(0, h - 1);
    for (x, y) in [(w - 1, h - 1), (w / 2, h / 2), (0, h / 2)] {
        assert_eq!(px(x, y), bg, "({x},{y}) should be background");
    }
    // The model (bounding radius 25 cm) sits 0.7 m ahead of the user, 1.3 m
    // above the floor, so 0.3 m below the 1.6 m eye: with ±45° views its
    // center projects 0.3/0.7 of the half height below the image center,
    // shifted by the half-IPD for the left eye.
    let (cx, cy) = (128.0 + 128.0 * 0.032 / 0.7, 128.0 + 128.0 * 0.3 / 0.7);
    let mut hits = 0;
    for dy in -6..=6 {
        for dx in -6..=6 {
            if px((cx as i32 + dx) as u32, (cy as i32 + dy) as u32) != bg {
                hits += 1;
            }
        }
    }
    assert!(hits > 100, "only {hits} model pixels near ({cx},{cy})");
}

// ---- The interaction core through the runtime --------------------------

fn fixture_trace() -> Trace {
    let p = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../tests/data/primitives_session.trace.jsonl"
    );
    Trace::from_jsonl(&std::fs::read_to_string(p).unwrap()).unwrap()
}

fn script_pose(p: &interact::Pose, valid: bool) -> ScriptPose {
    let f = |x: f64| x as f32;
    let (pos, q) = (p.position, p.orientation);
    let finite = pos.is_finite() && q.is_finite();
    ScriptPose {
        p: if finite {
            [f(pos.x), f(pos.y), f(pos.z)]
        } else {
            [0.0; 3]
        },
        q: if finite {
            [f(q.x), f(q.y), f(q.z), f(q.w)]
        } else {
            [0.0, 0.0, 0.0, 1.0]
        },
        valid,
        nan: !finite,
    }
}

/// The trace as a runtime script: frame k of the trace is what the runtime
/// reports at step k + 1 (the step at which the host's frame k is synced),
/// on a stepped clock at the trace's rate.
fn script_from_trace(trace: &Trace) -> Script {
    let keyframes = trace
        .frames
        .iter()
        .enumerate()
        .map(|(k, f)| {
            let hand = |i: usize| match &f.controllers[i] {
                None => ScriptHand::default(),
                Some(c) => ScriptHand {
                    grip: Some(script_pose(&c.grip, c.grip_valid)),
                    aim: Some(script_pose(&c.aim, c.aim_valid)),
                    select: c.buttons.select as f32,
                    squeeze: c.buttons.grab as f32,
                    menu: c.buttons.menu,
                    primary: c.buttons.primary,
                    secondary: c.buttons.secondary,
                    stick: c.buttons.stick.map(|x| x as f32),
                    ..Default::default()
                },
            };
            Keyframe {
                at: k as u64 + 1,
                head: Some(match &f.head {
                    Some(h) => script_pose(h, true),
                    None => script_pose(&interact::Pose::IDENTITY, false),
                }),
                left: hand(0),
                right: hand(1),
            }
        })
        .collect();
    Script {
        hand_tracking: false,
        // The puppet presses menu on the right hand: Touch has no right
        // menu button in the bindings, Vive wands have menu, trackpad
        // (primary, stick) and squeeze on both hands.
        profile: "/interaction_profiles/htc/vive_controller".into(),
        keyframes,
        step_ns: Some((1e9 / trace.header.fps).round() as i64),
        ..Default::default()
    }
}

struct ModelRun {
    run: Run,
    /// The autosaved USD file, loaded.
    saved: Option<shapewright_usd::Loaded>,
    /// The frames the host fed its session, as it recorded them.
    recorded: Option<Trace>,
}

/// Runs the host headless with the object tool on `script` (1 ms ticks),
/// autosaving to a USD file and recording the trace it stepped.
fn run_model(name: &str, script: &Script, args: &[&str]) -> ModelRun {
    run_tool(name, script, "object", "1", args)
}

/// [`run_model`] with `tool` at a tick of `period_ms`.
fn run_tool(name: &str, script: &Script, tool: &str, period_ms: &str, args: &[&str]) -> ModelRun {
    let dir = std::env::temp_dir().join(format!("sw_xr_model_{name}_{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let usd = dir.join("session.usda");
    let trace = dir.join("run.trace.jsonl");
    let (u, t) = (usd.to_str().unwrap(), trace.to_str().unwrap());
    let mut all = vec![
        "--tool",
        tool,
        "--period-ms",
        period_ms,
        "--save",
        u,
        "--trace",
        t,
    ];
    all.extend_from_slice(args);
    let run = run_host(name, script, &all);
    let saved = usd
        .exists()
        .then(|| load_file(&usd, LoadOptions::default()).unwrap());
    let recorded = std::fs::read_to_string(&trace)
        .ok()
        .map(|t| Trace::from_jsonl(&t).unwrap());
    let _ = std::fs::remove_dir_all(&dir);
    ModelRun {
        run,
        saved,
        recorded,
    }
}

/// Sorted (kind, bbox) of every object, to compare models built from f32
/// (runtime) and f64 (trace) poses.
fn objects(doc: &shapewright::doc::Document) -> Vec<(String, [f64; 6])> {
    doc.objects()
        .map(|(_, o)| {
            let (lo, hi) = o.mesh.bbox().unwrap();
            (
                o.kind.name().to_string(),
                [lo.x, lo.y, lo.z, hi.x, hi.y, hi.z],
            )
        })
        .collect()
}

fn assert_same_model(a: &shapewright::doc::Document, b: &shapewright::doc::Document, tol: f64) {
    let (oa, ob) = (objects(a), objects(b));
    assert_eq!(oa.len(), ob.len(), "{oa:?}\n{ob:?}");
    for ((ka, ba), (kb, bb)) in oa.iter().zip(&ob) {
        assert_eq!(ka, kb);
        for (x, y) in ba.iter().zip(bb) {
            assert!((x - y).abs() < tol, "{ka}: {ba:?} vs {bb:?}");
        }
    }
}

#[test]
fn scripted_controllers_build_the_model_the_trace_replay_builds() {
    let trace = fixture_trace();
    let n = trace.frames.len().to_string();
    let m = run_model("model", &script_from_trace(&trace), &["--frames", &n]);
    assert_eq!(m.run.code, Some(0), "{}\n{}", m.run.stdout, m.run.stderr);
    let want = replay(&trace).unwrap();
    let saved = m.saved.expect("the session was autosaved");
    assert!(saved.report.is_consistent(), "{}", saved.report);
    let names = |ops: &[shapewright::doc::Op]| ops.iter().map(|o| o.name()).collect::<Vec<_>>();
    assert_eq!(names(saved.log.ops()), names(want.log.ops()));
    assert_eq!(saved.log.cursor(), want.log.cursor());
    assert!(saved.log.document().len() >= 4);
    // The host's own recording replays to exactly what it saved.
    let rec = m.recorded.unwrap();
    assert_eq!(rec.frames.len(), trace.frames.len());
    let again = replay(&rec).unwrap();
    assert_eq!(
        again.log.document().content_hash(),
        saved.log.document().content_hash()
    );
    assert!(m.run.stdout.contains("frame CPU time"), "{}", m.run.stdout);
    // Poses went through f32 in the runtime: placements agree to ~1e-6 m.
    assert_same_model(saved.log.document(), want.log.document(), 1e-4);
}

/// The hand-gesture GC tool (paper 1) on a runtime without hand tracking:
/// the host makes hands from the controllers, buttons for gestures. The
/// puppet's mug by controller, played through the real loader at its
/// recorded rate (so commits, which run off the frame, land between
/// gestures as they would in a headset), builds the mug the core's replay
/// of the same input builds.
#[test]
fn the_gc_tool_runs_on_controllers_through_the_loader() {
    let trace = interact::testkit::mug_controller_trace();
    let n = trace.frames.len().to_string();
    let period = format!("{}", 1e3 / trace.header.fps);
    let m = run_tool(
        "gcmug",
        &script_from_trace(&trace),
        "gc",
        &period,
        &["--frames", &n],
    );
    assert_eq!(m.run.code, Some(0), "{}\n{}", m.run.stdout, m.run.stderr);
    let want = replay(&trace).unwrap();
    let saved = m.saved.expect("the session was autosaved");
    let names = |ops: &[shapewright::doc::Op]| ops.iter().map(|o| o.name()).collect::<Vec<_>>();
    assert_eq!(
        names(saved.log.ops()),
        ["gc_create", "gc_edit_part", "gc_set_shape", "gc_add_child"]
    );
    assert_eq!(names(saved.log.ops()), names(want.log.ops()));
    assert!(saved.report.is_consistent(), "{}", saved.report);
    // Poses went through f32 in the runtime: the mug agrees to a fraction
    // of a millimetre.
    assert_same_model(saved.log.document(), want.log.document(), 5e-4);
}

fn ops_of(t: &Trace) -> Vec<shapewright::doc::Op> {
    replay(t).unwrap().log.ops().to_vec()
}

/// The fixture trace with `faults` at fractions of its length, autosaving
/// only on loss and exit (no op or time trigger can fire).
fn run_with_faults(name: &str, faults: &[(f64, Fault)], refuse_creates: u32) -> ModelRun {
    let trace = fixture_trace();
    let n = trace.frames.len();
    let mut s = script_from_trace(&trace);
    s.faults = faults
        .iter()
        .map(|&(at, fault)| FaultAt {
            at: (n as f64 * at) as u64,
            fault,
        })
        .collect();
    s.refuse_creates = refuse_creates;
    let frames = n.to_string();
    let args = [
        "--frames",
        &frames,
        "--autosave-ops",
        "1000000",
        "--autosave-secs",
        "3600",
    ];
    run_model(name, &s, &args)
}

#[test]
fn no_acknowledged_op_is_lost_across_session_and_instance_loss() {
    let faults = [
        (1.0 / 3.0, Fault::LossPending),
        (2.0 / 3.0, Fault::InstanceLoss),
    ];
    let m = run_with_faults("loss", &faults, 1);
    assert_eq!(m.run.code, Some(0), "{}\n{}", m.run.stdout, m.run.stderr);
    let rep = m.run.report.clone().unwrap();
    assert_eq!(rep.session_losses, 1);
    assert_eq!(rep.instance_losses, 1);
    assert_eq!(rep.sessions_created, 3);
    let saved = m.saved.unwrap();
    let recorded = m.recorded.unwrap();
    // Every op the host applied (its recorded input, replayed) is in the file.
    let acknowledged = ops_of(&recorded);
    assert!(acknowledged.len() >= 4, "{}", acknowledged.len());
    assert_eq!(saved.log.ops(), acknowledged.as_slice());
    assert!(saved.report.is_consistent(), "{}", saved.report);
}

#[test]
fn a_run_that_gives_up_after_instance_loss_still_saved_every_op() {
    let m = run_with_faults("giveup", &[(0.5, Fault::InstanceLoss)], 1000);
    assert_eq!(m.run.code, Some(1), "{}\n{}", m.run.stdout, m.run.stderr);
    let saved = m.saved.expect("saved on instance loss");
    let acknowledged = ops_of(&m.recorded.unwrap());
    assert!(acknowledged.len() >= 2, "{}", acknowledged.len());
    assert_eq!(saved.log.ops(), acknowledged.as_slice());
}

#[test]
fn nan_poses_and_tracking_loss_change_nothing() {
    let trace = fixture_trace();
    let n = trace.frames.len();
    let clean = script_from_trace(&trace);
    // A stretch of 40 frames after the first ops with no button held.
    let idle = |f: &interact::InputFrame| {
        f.controllers
            .iter()
            .all(|c| c.is_some_and(|c| c.buttons == Default::default()))
    };
    let start = (200..n - 40)
        .find(|&k| trace.frames[k..k + 40].iter().all(idle))
        .expect("an idle stretch");
    let mut bad = clean.clone();
    for kf in &mut bad.keyframes[start + 10..start + 30] {
        if let Some(g) = &mut kf.right.grip {
            g.nan = true;
        }
        if let Some(a) = &mut kf.left.aim {
            a.valid = false;
        }
        if let Some(h) = &mut kf.head {
            h.valid = false;
        }
    }
    let frames = n.to_string();
    let a = run_model("nanclean", &clean, &["--frames", &frames]);
    let b = run_model("nanbad", &bad, &["--frames", &frames]);
    assert_eq!(b.run.code, Some(0), "{}", b.run.stderr);
    let dropped = |m: &ModelRun| m.run.report.as_ref().unwrap().poses_dropped;
    assert_eq!(
        dropped(&b),
        dropped(&a) + 60,
        "20 frames x (NaN grip, lost aim, lost head)"
    );
    let (sa, sb) = (a.saved.unwrap(), b.saved.unwrap());
    assert_eq!(sa.log.ops(), sb.log.ops());
    assert_eq!(
        sa.log.document().content_hash(),
        sb.log.document().content_hash()
    );
    // The record keeps the raw input (so a replay meets the same faults):
    // the NaN grip, lost aim and lost head are in exactly those 20 frames.
    let rec = b.recorded.unwrap();
    let faulty = |f: &interact::InputFrame| {
        let [l, r] = &f.controllers;
        let nan_grip = r.is_some_and(|r| r.grip_valid && !r.grip.is_finite());
        let lost_aim = l.is_some_and(|l| !l.aim_valid);
        [nan_grip, lost_aim, f.head.is_none()]
    };
    for (k, f) in rec.frames.iter().enumerate() {
        let want = (start + 10..start + 30).contains(&k);
        assert_eq!(faulty(f), [want; 3], "frame {k}");
    }
    // The core's door turns them into absent poses and lets no NaN through.
    let mut door = interact::Sanitizer::default();
    for (k, raw) in rec.frames.iter().enumerate() {
        let f = door.accept(raw).expect("every frame's time is fine");
        let poses = [
            f.head,
            f.controllers[0].and_then(|c| c.aim),
            f.controllers[1].and_then(|c| c.grip),
        ];
        assert!(poses.iter().flatten().all(|p| p.is_finite()), "frame {k}");
        let want = (start + 10..start + 30).contains(&k);
        assert_eq!(poses.map(|p| p.is_none()), [want; 3], "frame {k}");
    }
}
