//! `run [--headless] [--tool NAME] [--open FILE.usda] [--save FILE.usda]`:
//! the OpenXR session (headset: Vulkan, stereo, the document, previews and
//! rays; headless: input only). Every input frame steps the interaction
//! core ([`Interaction`]: session, tool, op log, autosave); `--record`
//! also writes each frame and lifecycle event as a JSON line, `--trace`
//! the frames as a trace that `replay` plays back (its fps is the rate the
//! input really came at).
//!
//! **A clean end, always.** SIGINT and SIGTERM set a flag the frame loop
//! reads: it calls xrRequestExitSession and runs the normal STOPPING /
//! EXITING path, then this command saves, flushes `--record` and writes
//! `--trace` and `--report`, and exits 0. A second signal exits at once
//! (status 130 / 143) without running destructors; the autosave file then
//! holds the last completed save (saves replace the file atomically).

use std::io::{BufWriter, Write};
use std::path::PathBuf;
use std::sync::atomic::AtomicBool;
use std::sync::Arc;
use std::time::Duration;

use anyhow::{bail, Context, Result};
use serde::Serialize;
use shapewright::doc::OpLog;
use shapewright::interact::{
    Hand, InputFrame, ModelPlacement, SanitizerStats, Session, Trace, TraceHeader, TRACE_FORMAT,
    TRACE_VERSION,
};
use shapewright_usd::{load_file, AutosaveSettings, Autosaver, LoadOptions, SaveOptions};
use shapewright_xr::gfx::Scene;
use shapewright_xr::interaction::Interaction;
use shapewright_xr::xr::{
    run_headless, run_headset, FrameSink, Haptic, LifecycleEvent, Notice, RunConfig, RunReport,
};

/// Arguments of `run`.
#[derive(clap::Args, Debug)]
pub struct RunArgs {
    /// Input only, no graphics (needs a runtime with XR_MND_headless).
    #[arg(long)]
    pub headless: bool,
    /// Stop after this many input frames.
    #[arg(long)]
    pub frames: Option<u64>,
    /// Stop after this many seconds.
    #[arg(long)]
    pub seconds: Option<f64>,
    /// Write every input frame and lifecycle event as JSON lines.
    #[arg(long)]
    pub record: Option<PathBuf>,
    /// Write the run report as JSON.
    #[arg(long)]
    pub report: Option<PathBuf>,
    /// A mesh (.stl, .obj) to show in the headset.
    #[arg(long)]
    pub model: Option<PathBuf>,
    /// Stop instead of recreating the session after LOSS_PENDING.
    #[arg(long)]
    pub no_recreate: bool,
    /// The tool active at the start (any name the core's tool registry
    /// knows); every tool is in the session, switched with the off hand's
    /// palette.
    #[arg(long, default_value = "object")]
    pub tool: String,
    /// Continue a Shapewright USD file: its history is loaded (undo works)
    /// and, unless --save says otherwise, autosaves go back to it.
    #[arg(long)]
    pub open: Option<PathBuf>,
    /// Join a shared session (with --open, an empty session starts from
    /// that file).
    #[command(flatten)]
    pub join: crate::join::JoinArgs,
    /// Autosave the document with its op log here (.usda; default: the
    /// --open file, else shapewright-session.usda, or
    /// shapewright-DOC.usda in a shared session).
    #[arg(long)]
    pub save: Option<PathBuf>,
    /// Autosave after this many changes (ops applied, undone or redone).
    #[arg(long, default_value_t = 1)]
    pub autosave_ops: usize,
    /// Autosave this many seconds after an unsaved change.
    #[arg(long, default_value_t = 30.0)]
    pub autosave_secs: f64,
    /// Headless tick period in milliseconds (default 90 Hz).
    #[arg(long, default_value_t = 11.111)]
    pub period_ms: f64,
    /// Write the input frames as a trace (.trace.jsonl) for `replay`.
    #[arg(long)]
    pub trace: Option<PathBuf>,
    /// Pace the run by a client listening at this loopback address
    /// (127.0.0.1:PORT): one tool step per request, at the request's time,
    /// through the runtime's input (for deterministic runs against a real
    /// runtime; see `xr::pace`).
    #[arg(long)]
    pub pace: Option<std::net::SocketAddr>,
    /// Behave as an OpenXR 1.0 application: API 1.0 and only the mode's
    /// extensions plus hand tracking (for validation layers built for 1.0,
    /// such as Debian 12's openxr-layer-corevalidation).
    #[arg(long)]
    pub openxr_1_0: bool,
}

#[derive(Serialize)]
#[serde(rename_all = "snake_case")]
enum Line<'a> {
    Frame(&'a InputFrame),
    Lifecycle(&'a LifecycleEvent),
}

struct RecordSink {
    out: Option<BufWriter<std::fs::File>>,
    error: Option<std::io::Error>,
}

impl RecordSink {
    fn write(&mut self, line: &Line<'_>) {
        if let (Some(out), None) = (&mut self.out, &self.error) {
            let r = serde_json::to_writer(&mut *out, line)
                .map_err(std::io::Error::other)
                .and_then(|_| out.write_all(b"\n"));
            if let Err(e) = r {
                self.error = Some(e);
            }
        }
    }
}

/// Records, steps the interaction, and keeps the trace.
struct RunSink {
    record: RecordSink,
    interaction: Interaction,
    trace: Option<Trace>,
}

impl FrameSink for RunSink {
    fn frame(&mut self, frame: &InputFrame) {
        self.record.write(&Line::Frame(frame));
        self.interaction.step(frame);
        if let Some(t) = &mut self.trace {
            t.frames.push(frame.clone());
        }
    }
    fn lifecycle(&mut self, event: &LifecycleEvent) {
        self.record.write(&Line::Lifecycle(event));
        match event {
            LifecycleEvent::ProfileBound { hand, profile } => println!(
                "profile bound: {hand} -> {}",
                profile.as_deref().unwrap_or("nothing")
            ),
            LifecycleEvent::ExitRequested(why) => {
                println!("ending the session: {why}")
            }
            _ => {}
        }
        self.interaction.lifecycle(event);
    }
    fn scene(&self) -> Option<&Scene> {
        Some(self.interaction.scene())
    }
    fn take_haptics(&mut self) -> Vec<Haptic> {
        self.interaction.take_haptics()
    }
    fn notices(&self) -> Vec<Notice> {
        self.interaction.notices()
    }
    fn input_stats(&self) -> Option<SanitizerStats> {
        self.interaction.input_stats()
    }
    fn settle(&mut self) {
        self.interaction.settle();
    }
    fn progress(&self) -> (u64, u64) {
        self.interaction.progress()
    }
}

/// The rate input really came at: 1 / the median step between frame
/// times (None with fewer than two increasing times).
fn input_fps(frames: &[InputFrame]) -> Option<f64> {
    let mut dts: Vec<f64> = frames
        .windows(2)
        .map(|w| w[1].time - w[0].time)
        .filter(|d| d.is_finite() && *d > 0.0)
        .collect();
    dts.sort_by(f64::total_cmp);
    let m = *dts.get(dts.len() / 2)?;
    Some(1.0 / m)
}

/// SIGINT / SIGTERM: the first sets `stop`, a second exits at once.
fn install_signals(stop: &Arc<AtomicBool>) -> Result<()> {
    use signal_hook::consts::{SIGINT, SIGTERM};
    for sig in [SIGINT, SIGTERM] {
        // Registered first, so it sees the flag as it was before this
        // signal: set means a second signal, which exits with 128 + sig.
        signal_hook::flag::register_conditional_shutdown(sig, 128 + sig, Arc::clone(stop))
            .context("installing the signal handlers")?;
        signal_hook::flag::register(sig, Arc::clone(stop))
            .context("installing the signal handlers")?;
    }
    Ok(())
}

/// `v` units of `unit` seconds, if `v` is a positive number.
fn positive(name: &str, v: f64, unit: f64) -> Result<Duration> {
    if !(v.is_finite() && v > 0.0) {
        bail!("--{name} must be a positive number, got {v}");
    }
    Ok(Duration::from_secs_f64(v * unit))
}

/// Runs the session and prints a summary.
pub fn run(args: &RunArgs) -> Result<()> {
    let max_duration = args
        .seconds
        .map(|s| positive("seconds", s, 1.0))
        .transpose()?;
    let autosave_every = positive("autosave-secs", args.autosave_secs, 1.0)?;
    let frame_period = positive("period-ms", args.period_ms, 1e-3)?;
    if args.autosave_ops == 0 {
        bail!("--autosave-ops must be at least 1");
    }
    let stop = Arc::new(AtomicBool::new(false));
    install_signals(&stop)?;
    let cfg = RunConfig {
        max_frames: args.frames,
        max_duration,
        frame_period,
        recreate_lost_sessions: !args.no_recreate,
        stop: Some(stop),
        pace: args.pace,
        openxr_1_0: args.openxr_1_0,
        ..Default::default()
    };
    let log = match &args.open {
        Some(p) => {
            let loaded = load_file(p, LoadOptions::default())
                .with_context(|| format!("opening {}", p.display()))?;
            if !loaded.report.is_consistent() {
                eprintln!(
                    "warning: {}: stored geometry disagrees with the log; continuing from the log:\n{}",
                    p.display(),
                    loaded.report
                );
            }
            loaded.log
        }
        None => OpLog::new(),
    };
    let (log, link) = crate::join::join(&args.join, log)?;
    let save_path = args
        .save
        .clone()
        .or_else(|| args.open.clone())
        .or_else(|| {
            let doc = link.as_ref()?.url().doc.clone();
            Some(PathBuf::from(format!("shapewright-{doc}.usda")))
        })
        .unwrap_or_else(|| PathBuf::from("shapewright-session.usda"));
    let saver = Autosaver::new(
        &save_path,
        AutosaveSettings {
            every_ops: args.autosave_ops,
            every: autosave_every,
        },
        SaveOptions::default(),
    );
    let placement = ModelPlacement::desk();
    let model = placement
        .similarity()
        .context("the default model placement is invalid")?;
    let session = Session::modeler(&args.tool, Hand::Right, model)?;
    let interaction = Interaction::shared(session, log, Some(saver), link)?;
    let out = match &args.record {
        Some(p) => Some(BufWriter::new(
            std::fs::File::create(p).with_context(|| format!("creating {}", p.display()))?,
        )),
        None => None,
    };
    let trace = args.trace.as_ref().map(|_| {
        Trace::new(TraceHeader {
            format: TRACE_FORMAT.into(),
            version: TRACE_VERSION,
            // Replaced by the measured input rate when the trace is written.
            fps: 1.0 / frame_period.as_secs_f64(),
            model: placement,
            tool: args.tool.clone(),
            note: "recorded by shapewright-xr run".into(),
            modeler: true,
        })
    });
    let mut sink = RunSink {
        record: RecordSink { out, error: None },
        interaction,
        trace,
    };
    let result = if args.headless {
        run_headless(&cfg, &mut sink)
    } else {
        let model = match &args.model {
            Some(p) => {
                let mut m = crate::cmd::read_mesh(p)?;
                m.ensure_normals();
                Some(m)
            }
            None => None,
        };
        run_headset(&cfg, model.as_ref(), &mut sink)
    };
    // Save on exit, also when the run failed: no acknowledged op is lost;
    // the record and trace are written either way too. A run that failed
    // with nothing to save (no runtime, no headset) writes no file.
    if result.is_ok() || sink.interaction.unsaved_changes() > 0 {
        sink.interaction.save_now();
    }
    if let Some(e) = sink.record.error.take() {
        bail!("writing the record: {e}");
    }
    if let Some(mut out) = sink.record.out.take() {
        out.flush().context("writing the record")?;
    }
    if let (Some(p), Some(t)) = (&args.trace, &mut sink.trace) {
        if let Some(fps) = input_fps(&t.frames) {
            t.header.fps = fps;
        }
        shapewright_xr::files::write_text(p, &t.to_jsonl())?;
    }
    let report = result?;
    if let Some(p) = &args.report {
        shapewright_xr::files::write_text(p, &serde_json::to_string_pretty(&report)?)?;
    }
    print_runtime(&report);
    print_summary(&report);
    let unsaved = sink.interaction.unsaved_changes();
    let st = sink.interaction.stats();
    let log = sink.interaction.log();
    println!(
        "tool {} | commands {} (refused {}) | ops {} (cursor {}) | objects {} | saved {} times to {}{}",
        args.tool,
        st.commands,
        st.rejected.len(),
        log.len(),
        log.cursor(),
        log.document().len(),
        st.saves,
        save_path.display(),
        if st.save_errors.is_empty() {
            String::new()
        } else {
            format!(" ({} failed saves)", st.save_errors.len())
        }
    );
    drop(log);
    if unsaved > 0 {
        let e = st.save_errors.last().map_or("", String::as_str);
        bail!("changes are not saved to {}: {e}", save_path.display());
    }
    Ok(())
}

/// What the runtime is: name and version, system, spaces, bound profiles,
/// hands, input devices.
fn print_runtime(r: &RunReport) {
    let rt = &r.runtime;
    println!(
        "runtime: {} {} (OpenXR {}) | system: {}",
        rt.name, rt.version, rt.api_version, rt.system
    );
    println!(
        "spaces: base {} (LOCAL lowered by {:.3} m{}); offered {}",
        if r.spaces.base.is_empty() {
            "not established"
        } else {
            &r.spaces.base
        },
        r.spaces.floor_offset_m,
        if r.spaces.base == "local_floor" {
            ": the runtime's LOCAL_FLOOR, not lowered"
        } else {
            ""
        },
        r.spaces.offered.join(", ")
    );
    let bound = |p: &Option<String>| p.clone().unwrap_or_else(|| "nothing".into());
    println!(
        "profiles bound: left {} | right {} (suggested for {} profiles)",
        bound(&r.profiles_bound[0]),
        bound(&r.profiles_bound[1]),
        r.profiles.len()
    );
    let hand = |h: &Option<String>| h.clone().unwrap_or_else(|| "not tracked".into());
    println!(
        "hands: XR_EXT_hand_tracking {}, system {} track hands{} | left {} | right {}",
        if rt.hand_tracking_offered {
            "offered"
        } else {
            "not offered"
        },
        if rt.hand_tracking_supported {
            "can"
        } else {
            "cannot"
        },
        if rt.hand_data_source && rt.hand_tracking_supported {
            ", data source reported"
        } else {
            ""
        },
        hand(&r.hands_tracked[0]),
        hand(&r.hands_tracked[1])
    );
    if !r.input_device {
        println!(
            "input: no input device (no controller, no tracked hand): no tool could be driven"
        );
    }
    for f in &r.fallbacks {
        println!("fallback: {f}");
    }
    println!(
        "rates: input {:.1} Hz, display {:.1} Hz ({} frames submitted){}",
        r.input_hz,
        r.display_hz,
        r.display_frames,
        if r.pace_steps > 0 {
            format!(
                " | paced: {} steps, {} frames waited for the runtime",
                r.pace_steps, r.pace_waits
            )
        } else {
            String::new()
        }
    );
}

fn print_summary(r: &RunReport) {
    println!(
        "frames {} | dropped poses {} joints {} | instances {} (lost {}, retries {}) | sessions {} (lost {}) | focused {} | exit: {}",
        r.frames,
        r.poses_dropped,
        r.joints_dropped,
        r.instances_created,
        r.instance_losses,
        r.instance_retries,
        r.sessions_created,
        r.session_losses,
        r.reached_focused,
        r.exit_reason
    );
    if let (Some(p50), Some(p99)) = (r.frame_cpu_quantile(0.5), r.frame_cpu_quantile(0.99)) {
        println!(
            "frame CPU time (input + interaction + preview): p50 {:.3} ms, p99 {:.3} ms (budget 11.1 ms)",
            p50 * 1e-3,
            p99 * 1e-3
        );
    }
}
