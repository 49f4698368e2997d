//! `run [--headless] [--tool NAME] [--open FILE.usda] [--save FILE.usda]`:
//! the OpenXR session (headset: Vulkan, stereo, the document, previews and
//! rays; headless: input only). Every input frame steps the interaction
//! core ([`Interaction`]: session, tool, op log, autosave); `--record`
//! also writes each frame and lifecycle event as a JSON line, `--trace`
//! the frames as a trace that `replay` plays back.

use std::io::{BufWriter, Write};
use std::path::PathBuf;
use std::time::Duration;

use anyhow::{bail, Context, Result};
use serde::Serialize;
use shapewright::doc::OpLog;
use shapewright::interact::{ModelPlacement, Trace, TraceHeader, TRACE_FORMAT, TRACE_VERSION};
use shapewright_usd::{load_file, AutosaveSettings, Autosaver, LoadOptions, SaveOptions};
use shapewright_xr::interaction::{Interaction, Scene};
use shapewright_xr::xr::{
    run_headless, run_headset, FrameSink, InputFrame, LifecycleEvent, RunConfig, RunReport,
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
    /// The tool the session runs (any name the core's tool registry knows).
    #[arg(long, default_value = "object")]
    pub tool: String,
    /// Continue a Shapewright USD file: its history is loaded (undo works)
    /// and, unless --save says otherwise, autosaves go back to it.
    #[arg(long)]
    pub open: Option<PathBuf>,
    /// Autosave the document with its op log here (.usda; default: the
    /// --open file, else shapewright-session.usda).
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
        let raw = frame.to_interact();
        self.interaction.step(&raw);
        if let Some(t) = &mut self.trace {
            t.frames.push(raw);
        }
    }
    fn lifecycle(&mut self, event: &LifecycleEvent) {
        self.record.write(&Line::Lifecycle(event));
        self.interaction.lifecycle(event);
    }
    fn scene(&self) -> Option<&Scene> {
        Some(self.interaction.scene())
    }
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
    let cfg = RunConfig {
        max_frames: args.frames,
        max_duration,
        frame_period,
        recreate_lost_sessions: !args.no_recreate,
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
    let save_path = args
        .save
        .clone()
        .or_else(|| args.open.clone())
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
    let interaction = Interaction::new(&args.tool, model, log, Some(saver))?;
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
            fps: 1.0 / frame_period.as_secs_f64(),
            model: placement,
            tool: args.tool.clone(),
            note: "recorded by shapewright-xr run".into(),
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
                if m.normals.len() != m.positions.len() {
                    m.compute_normals();
                }
                Some(m)
            }
            None => None,
        };
        run_headset(&cfg, model.as_ref(), &mut sink)
    };
    // Save on exit, also when the run failed: no acknowledged op is lost;
    // the record and trace are written either way too.
    sink.interaction.save_now();
    if let Some(e) = sink.record.error.take() {
        bail!("writing the record: {e}");
    }
    if let Some(mut out) = sink.record.out.take() {
        out.flush().context("writing the record")?;
    }
    if let (Some(p), Some(t)) = (&args.trace, &sink.trace) {
        shapewright_xr::files::write_text(p, &t.to_jsonl())?;
    }
    let report = result?;
    if let Some(p) = &args.report {
        shapewright_xr::files::write_text(p, &serde_json::to_string_pretty(&report)?)?;
    }
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
