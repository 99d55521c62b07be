//! `leakless render`: one image to a layered EXR, optionally a PNG and stats.

use std::path::PathBuf;

use anyhow::Context;
use leakless::frame_budget::DynamicResolution;
use leakless::output::{self, OutputPaths};
use leakless::{DeviceTuning, Method, Renderer};
use leakless_graph::Timing;

use crate::options::RenderOptions;

#[derive(clap::Args)]
pub struct RenderArgs {
    #[command(flatten)]
    options: RenderOptions,
    /// Output EXR (default: <scene name>.exr in the current directory); with `--sequence`,
    /// the directory the frames go to (default: <scene name>/).
    #[arg(long)]
    out: Option<PathBuf>,
    /// Also write the tonemapped PNG (what the window shows): to PNG, or without a value next
    /// to the EXR (a sequence's DIR/NNNN.png).
    #[arg(long, num_args = 0..=1)]
    png: Option<Option<PathBuf>>,
    /// Renders the animation from T0 to T1 seconds at FPS frames a second, in order, as the
    /// app does between frames: DIR/0000.exr, DIR/0001.exr, … and DIR/sequence.json (each
    /// frame's index, time, camera and frame_ms).
    #[arg(long, value_name = "T0:T1:FPS", value_parser = crate::sequence::parse_sequence)]
    sequence: Option<crate::sequence::Sequence>,
    /// Write per-pass GPU times, build costs and counts as JSON.
    #[arg(long)]
    stats: Option<PathBuf>,
    /// How passes are timed: `timestamps` (one submission, GPU timestamps), `per-pass` (one
    /// waited submission per pass, also timed on the host), or `auto`: the device tuning's
    /// (per-pass on CPU devices such as lavapipe, whose timestamps inside one submission do not
    /// bracket compute work; timestamps on GPUs).
    #[arg(long, default_value = "auto", value_parser = ["auto", "timestamps", "per-pass"])]
    timing: String,
    /// With `--sequence`: a frame-time budget of T ms. Each frame that starts an accumulation
    /// (every frame while anything moves) traces the light paths that keep it within T, chosen
    /// from the frames before, as the app does; `sequence.json` records them per frame.
    /// Without it every frame traces `--paths`.
    #[arg(long, value_name = "T")]
    frame_ms: Option<f64>,
    /// With `--frame-ms`: where even the fewest light paths miss it, render fewer pixels (each
    /// step about 30% fewer, down to a sixteenth) and resample the frame to `--size`, as the
    /// app renders fewer pixels and shows them at its window's size.
    #[arg(long, default_value = "on", value_parser = ["on", "off"])]
    dynamic_resolution: String,
    /// The light paths of an accumulation's first frame, its later batches tracing `--paths`
    /// each: what a capture of the app records when its frame budget chose them.
    #[arg(long, value_name = "N")]
    first_frame_paths: Option<u32>,
    /// The gather radius of an accumulation's first frame, its later batches shrinking from
    /// `--radius`: what a capture of the app records when the two differ.
    #[arg(long, value_name = "R")]
    first_frame_radius: Option<f32>,
    /// Count the compute traversal's work for the gather's visibility rays into `--stats`
    /// (`ray_nodes_visited`, `ray_triangles_tested`), as `bench rays` counts its rays': the
    /// gather then runs with the counts compiled in. Ray queries count nothing.
    #[arg(long)]
    count_work: bool,
}

/// The size `render` renders at without `--size`.
pub const DEFAULT_SIZE: (u32, u32) = (640, 480);

pub fn run(args: RenderArgs) -> anyhow::Result<()> {
    let settings = args.options.settings(DEFAULT_SIZE);
    settings.validate()?;
    let scene = args.options.load_scene()?;
    let gpu = crate::open_gpu(settings.backend)?;
    let mut tuning = DeviceTuning::choose(gpu.report(), settings.tuning);
    tuning.count_work = args.count_work;
    let mut renderer =
        Renderer::with_tuning(gpu, &scene, settings.clone(), tuning).context("setting up the renderer")?;
    args.options.apply_view(&mut renderer, &scene)?;
    renderer.set_timing(match args.timing.as_str() {
        "per-pass" => Timing::PerPassSubmit,
        "timestamps" => Timing::Timestamps,
        _ => renderer.tuning().timing,
    });
    if let Some(paths) = args.first_frame_paths {
        renderer.set_first_frame_paths(paths)?;
    }
    renderer.set_first_frame_radius(args.first_frame_radius)?;
    if args.frame_ms.is_some() && args.sequence.is_none() {
        anyhow::bail!("--frame-ms budgets the frames of a --sequence (or of the app, `leakless view`)");
    }
    renderer.set_frame_budget(args.frame_ms)?;
    if let Some(sequence) = args.sequence {
        let dir = args.out.unwrap_or_else(|| PathBuf::from(&scene.name));
        if matches!(args.png, Some(Some(_))) {
            anyhow::bail!("--png with --sequence takes no path: the frames' PNGs go next to their EXRs");
        }
        let outputs = crate::sequence::Outputs { dir: &dir, png: args.png.is_some(), stats: args.stats.as_deref() };
        let dynamic = DynamicResolution::new(args.frame_ms.is_some() && args.dynamic_resolution == "on");
        return crate::sequence::run(&mut renderer, &args.options.scene, sequence, outputs, dynamic);
    }
    let frame = render_with_bar(&mut renderer, settings.method)?;
    if let Some(s) = &frame.splat {
        if s.photons_dropped > 0 || s.list_entries_dropped > 0 {
            eprintln!(
                "warning: capacity exceeded: {} photons and {} node-list entries dropped (raise --list-capacity); the indirect light is incomplete",
                s.photons_dropped, s.list_entries_dropped
            );
        }
    }
    let exr = args.out.unwrap_or_else(|| PathBuf::from(format!("{}.exr", scene.name)));
    let png = args.png.map(|png| png.unwrap_or_else(|| exr.with_extension("png")));
    let paths = OutputPaths { exr, png, stats: args.stats };
    for path in output::write_render(&paths, &args.options.scene, &renderer, &frame, None)? {
        println!("wrote {}", path.display());
    }
    Ok(())
}

/// Renders, with a progress bar on a terminal while reference samples accumulate.
fn render_with_bar(renderer: &mut Renderer, method: Method) -> anyhow::Result<leakless::RenderedFrame> {
    use std::io::IsTerminal;
    let bar = (method == Method::Reference && std::io::stderr().is_terminal()).then(|| {
        let bar = indicatif::ProgressBar::new(renderer.settings().spp as u64);
        bar.set_style(
            indicatif::ProgressStyle::with_template("{msg} [{bar:40}] {pos}/{len} spp, {elapsed} (eta {eta})")
                .expect("valid template")
                .progress_chars("=> "),
        );
        bar.set_message("reference");
        bar
    });
    let frame = renderer.render_with_progress(&mut |done, _| {
        if let Some(bar) = &bar {
            bar.set_position(done as u64);
        }
    });
    if let Some(bar) = bar {
        bar.finish_and_clear();
    }
    frame.context("rendering")
}
