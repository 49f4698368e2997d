//! `replay TRACE [--out FILE] [--stl X.stl] [--png X.png]`: plays a
//! recorded input trace through the same interaction step as `run` (no
//! OpenXR runtime), writes any subset of outputs (`--out` by extension:
//! .usda/.usdz with the op log, or .stl/.3mf/.obj/.ply; the PNG from the host's own
//! Vulkan renderer, lavapipe without a GPU), and prints a one-screen
//! summary with the per-frame CPU time of interaction + preview update.

use std::path::PathBuf;
use std::time::Instant;

use anyhow::{Context, Result};
use shapewright::doc::print_document;
use shapewright::doc::OpLog;
use shapewright::interact::Trace;
use shapewright::mesh::MeshFormat;
use shapewright::print::PrintSettings;
use shapewright_xr::interaction::Interaction;
use shapewright_xr::render::{render_mesh_png, RenderSettings};
use shapewright_xr::xr::quantile;

/// Outputs of `replay`.
#[derive(clap::Args, Debug)]
pub struct ReplayArgs {
    /// The trace: a header line, then one input frame per line.
    pub trace: PathBuf,
    /// Output file; the format follows the extension (.usda or .usdz
    /// keeps the op log; .stl or .3mf (millimetres, for slicers), .obj or
    /// .ply (metres) the printable union).
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Write the printable union here too: binary STL in millimetres (or
    /// 3MF, OBJ, PLY by the extension).
    #[arg(long)]
    pub stl: Option<PathBuf>,
    /// Render the model to this PNG with the host's Vulkan renderer.
    #[arg(long)]
    pub png: Option<PathBuf>,
    /// Run this tool alone instead of the session the trace header
    /// describes.
    #[arg(long)]
    pub tool: Option<String>,
    /// Render the headset view (from the recorded head, with the palette
    /// and text as the headset shows them) at this trace time (seconds;
    /// default: the last frame) to this PNG.
    #[arg(long)]
    pub view_png: Option<PathBuf>,
    /// The trace time of `--view-png` (seconds from the first frame).
    #[arg(long)]
    pub view_at: Option<f64>,
    /// Play the trace as one person of a shared session (several replays
    /// at once: a session of several people); at the end, wait until the
    /// session is quiet this long before writing the outputs.
    #[command(flatten)]
    pub join: crate::join::JoinArgs,
    /// With --join: seconds without news from the session that count as
    /// quiet at the end.
    #[arg(long, default_value_t = 1.5)]
    pub quiet_secs: f64,
}

/// `replay`: open the trace, play its frames, write the outputs, say what
/// happened.
pub fn replay(args: &ReplayArgs) -> Result<()> {
    for out in [&args.out, &args.stl].into_iter().flatten() {
        crate::cmd::check_out(out)?;
    }
    let (trace, mut it, shared) = open(args)?;
    let mut played = play(args, &trace, &mut it, shared)?;
    let stats = it.stats();
    for e in &stats.rejected {
        eprintln!("shapewright-xr: a command was refused: {e}");
    }
    let log = it.log();
    let log = &*log;
    let doc = log.document();
    // The printable model (one path for every exit: union, open surfaces
    // thickened, checked at float32 in mm), needed for mesh outputs and the
    // summary; an unprintable document fails a mesh output with the reason
    // but still renders (the objects as they are) and saves its USD.
    let printed = print_document(doc, &PrintSettings::default());
    let written = write_outputs(args, log, &printed, played.view.take())?;
    let tool = args.tool.as_deref().unwrap_or(&trace.header.tool);
    println!(
        "trace      {} ({} frames at {} fps, tool {tool})",
        args.trace.display(),
        trace.frames.len(),
        trace.header.fps
    );
    println!(
        "commands   {} ({} refused): {}",
        played.names.len(),
        stats.rejected.len(),
        summarize(&played.names)
    );
    println!("ops        {} (cursor {})", log.len(), log.cursor());
    println!("objects    {}", doc.len());
    println!("content    {:016x}", doc.content_hash());
    if shared {
        println!(
            "people     {} other(s) drawn at most in one frame",
            stats.others_drawn
        );
    }
    match &printed {
        Ok(p) => {
            println!("mesh       {}", crate::cmd::print_summary(p));
            println!("{}", crate::cmd::fit_line(doc, p));
        }
        Err(e) => println!("mesh       NOT printable: {e}"),
    }
    print_times(&played, &stats.commit_ms);
    println!(
        "written    {}",
        if written.is_empty() {
            "nothing (give --out, --stl or --png)".to_string()
        } else {
            written.join(", ")
        }
    );
    Ok(())
}

/// Reads the trace and makes the interaction that plays it (its own tool
/// and model placement, or `--tool`; joined to a shared session with
/// `--join`). Also says whether the session is shared.
fn open(args: &ReplayArgs) -> Result<(Trace, Interaction, bool)> {
    let path = &args.trace;
    let text =
        std::fs::read_to_string(path).with_context(|| format!("reading {}", path.display()))?;
    let trace = Trace::from_jsonl(&text).with_context(|| format!("in {}", path.display()))?;
    let model = trace.header.model.similarity().with_context(|| {
        format!(
            "in {}: model placement must be finite with a positive scale",
            path.display()
        )
    })?;
    let (log, link) = crate::join::join(&args.join, OpLog::new())?;
    let shared = link.is_some();
    let session = match args.tool.as_deref() {
        Some(tool) => {
            let tool = shapewright::interact::tool_named(tool)
                .with_context(|| format!("in {}", path.display()))?;
            shapewright::interact::Session::new(tool, model)
        }
        None => trace
            .header
            .session()
            .with_context(|| format!("in {}", path.display()))?,
    };
    let it = Interaction::shared(session, log, None, link)?;
    Ok((trace, it, shared))
}

/// What playing the frames gave.
struct Played {
    /// CPU time of each frame's step (ms).
    frame_ms: Vec<f64>,
    /// The same for frames with the palette open and a drag in progress
    /// (issue 19's frame-time case).
    busy_ms: Vec<f64>,
    /// The commands, in order.
    names: Vec<&'static str>,
    /// The scene and head for `--view-png`.
    view: Option<(shapewright_xr::gfx::Scene, shapewright::interact::Pose)>,
}

/// Steps every frame of the trace, waiting for each commit, then (shared)
/// for the session to go quiet.
fn play(args: &ReplayArgs, trace: &Trace, it: &mut Interaction, shared: bool) -> Result<Played> {
    let mut played = Played {
        frame_ms: Vec::with_capacity(trace.frames.len()),
        busy_ms: Vec::new(),
        names: Vec::new(),
        view: None,
    };
    let t_first = trace.frames.first().map_or(0.0, |f| f.time);
    let view_at = args.view_at.map(|t| t_first + t);
    for f in &trace.frames {
        let t0 = Instant::now();
        let cmd = it.step(f);
        let ms = t0.elapsed().as_secs_f64() * 1e3;
        played.frame_ms.push(ms);
        if it.session().palette().is_some() && it.session().preview().moving.is_some() {
            played.busy_ms.push(ms);
        }
        if args.view_png.is_some() && view_at.is_none_or(|t| f.time <= t) {
            let head = it.session().last_frame().and_then(|f| f.head);
            played.view = head.map(|h| (it.scene().clone(), h));
        }
        // The headset loop lets commits finish in the background; a replay
        // waits for each, so the tool sees what the core's replay shows it.
        it.flush();
        if let Some(c) = cmd {
            played.names.push(c.name());
        }
    }
    if shared {
        let quiet = std::time::Duration::from_secs_f64(args.quiet_secs.max(0.0));
        if !it.settle_shared(quiet, std::time::Duration::from_secs(120)) {
            anyhow::bail!("the shared session did not settle in 120 s");
        }
    }
    Ok(played)
}

/// Writes `--out`, `--stl`, `--view-png` and `--png`; returns what it wrote.
fn write_outputs(
    args: &ReplayArgs,
    log: &OpLog,
    printed: &Result<shapewright::print::Printable, shapewright::print::PrintError>,
    view: Option<(shapewright_xr::gfx::Scene, shapewright::interact::Pose)>,
) -> Result<Vec<String>> {
    let doc = log.document();
    let mut written: Vec<String> = Vec::new();
    if let Some(out) = &args.out {
        if crate::usd_cmd::is_usd(out) {
            shapewright_usd::save_file(out, log, &shapewright_usd::SaveOptions::default())
                .with_context(|| format!("saving {}", out.display()))?;
            written.push(out.display().to_string());
        }
    }
    for path in [args.out.as_ref(), args.stl.as_ref()].into_iter().flatten() {
        if crate::usd_cmd::is_usd(path) {
            continue;
        }
        // STL and 3MF are float32 millimetres, as `printed` was checked;
        // OBJ and PLY are metres and are checked for their own.
        let same = MeshFormat::from_path(path).is_some_and(|f| {
            let s = PrintSettings::for_format(f);
            let d = PrintSettings::default();
            (s.precision, s.unit) == (d.precision, d.unit)
        });
        match printed {
            Ok(p) if same => crate::cmd::write_printed(doc, p, path)?,
            _ => crate::cmd::write_printed(doc, &crate::cmd::print_for(doc, path)?, path)?,
        }
        written.push(path.display().to_string());
    }
    if let (Some(png), Some((scene, head))) = (&args.view_png, view) {
        let ctx = std::sync::Arc::new(shapewright_xr::gfx::GpuContext::new_offscreen()?);
        let pose = (
            head.position.as_vec3(),
            head.orientation.as_quat().normalize(),
        );
        let image = shapewright_xr::render::render_scene(&ctx, &scene, pose, 1280, 800, 70.0)?;
        shapewright_xr::render::write_png(&image, png)?;
        written.push(png.display().to_string());
    }
    if let Some(png) = &args.png {
        let m = match printed {
            Ok(p) => p.mesh.clone(),
            Err(_) => doc.combined_mesh(),
        };
        render_mesh_png(&m, png, &RenderSettings::default())
            .with_context(|| format!("rendering {}", png.display()))?;
        written.push(png.display().to_string());
    }
    Ok(written)
}

/// The frame and commit time lines of the summary.
fn print_times(played: &Played, commit_ms: &[f64]) {
    let p50 = quantile(&played.frame_ms, 0.5).unwrap_or(f64::NAN);
    let p99 = quantile(&played.frame_ms, 0.99).unwrap_or(f64::NAN);
    let commit_max = commit_ms.iter().copied().fold(0.0, f64::max);
    let commit_p50 = quantile(commit_ms, 0.5).unwrap_or(0.0);
    println!("frame time {p50:.3} ms p50, {p99:.3} ms p99 (input + interaction + preview; budget 11.1 ms)");
    if !played.busy_ms.is_empty() {
        let q = |p| quantile(&played.busy_ms, p).unwrap_or(f64::NAN);
        println!(
            "           {:.3} ms p50, {:.3} ms p99 over the {} frames with the palette open and a drag in progress",
            q(0.5),
            q(0.99),
            played.busy_ms.len()
        );
    }
    println!(
        "commits    {commit_p50:.1} ms p50, {commit_max:.1} ms max (op + document mesh, off the frame thread)"
    );
}

/// `a, b x3, c`: runs of equal names collapsed.
fn summarize(names: &[&str]) -> String {
    let mut out: Vec<String> = Vec::new();
    let mut i = 0;
    while i < names.len() {
        let n = names[i..].iter().take_while(|x| **x == names[i]).count();
        out.push(if n > 1 {
            format!("{} x{n}", names[i])
        } else {
            names[i].to_string()
        });
        i += n;
    }
    out.join(", ")
}
