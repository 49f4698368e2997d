//! `run [--headless] [--model FILE]`: the OpenXR session (headset:
//! Vulkan, stereo, the model and aim rays; headless: input only). Until `core::interact` lands the
//! frames go to a recording sink (`--record FILE.jsonl`: one JSON line per
//! input frame or lifecycle event) that other engineers can replace with
//! the interaction core.

use std::io::{BufWriter, Write};
use std::path::PathBuf;
use std::time::Duration;

use anyhow::{bail, Context, Result};
use serde::Serialize;
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

impl FrameSink for RecordSink {
    fn frame(&mut self, frame: &InputFrame) {
        self.write(&Line::Frame(frame));
    }
    fn lifecycle(&mut self, event: &LifecycleEvent) {
        self.write(&Line::Lifecycle(event));
    }
}

/// Runs the session and prints a summary.
pub fn run(args: &RunArgs) -> Result<()> {
    let max_duration = match args.seconds {
        Some(s) if !(s.is_finite() && s > 0.0) => {
            bail!("--seconds must be a positive number, got {s}")
        }
        Some(s) => Some(Duration::from_secs_f64(s)),
        None => None,
    };
    let cfg = RunConfig {
        max_frames: args.frames,
        max_duration,
        recreate_lost_sessions: !args.no_recreate,
        ..Default::default()
    };
    let out = match &args.record {
        Some(p) => Some(BufWriter::new(
            std::fs::File::create(p).with_context(|| format!("creating {}", p.display()))?,
        )),
        None => None,
    };
    let mut sink = RecordSink { out, error: None };
    let report = if args.headless {
        run_headless(&cfg, &mut sink)?
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
        run_headset(&cfg, model.as_ref(), &mut sink)?
    };
    if let Some(e) = sink.error.take() {
        bail!("writing the record: {e}");
    }
    if let Some(mut out) = sink.out.take() {
        out.flush().context("writing the record")?;
    }
    if let Some(p) = &args.report {
        std::fs::write(p, serde_json::to_string_pretty(&report)?)
            .with_context(|| format!("writing {}", p.display()))?;
    }
    print_summary(&report);
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
        println!("input step CPU time: p50 {p50:.1} us, p99 {p99:.1} us");
    }
}
