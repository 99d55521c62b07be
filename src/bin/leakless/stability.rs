//! `leakless stability`: the stress scenes against the reference — a Markdown report with a
//! table and a sentence per scene, a CSV of every row, and the wall-thickness chart.

use std::fmt::Write as _;
use std::path::PathBuf;

use anyhow::Context;
use leakless::{Backend, Method, Scene};
use leakless_measure::chart::thickness::{plot_thickness, ThicknessPoint};
use leakless_measure::csv_table::CsvTable;
use leakless_measure::stability::{measure, SceneStability, StabilityConfig};

#[derive(clap::Args)]
pub struct StabilityArgs {
    /// The scenes (.gltf or .glb), e.g. scenes/stress/*.gltf.
    #[arg(required = true)]
    scenes: Vec<PathBuf>,
    /// Output prefix: writes PREFIX.md, PREFIX.csv and PREFIX-thickness.{svg,png,csv}.
    #[arg(long)]
    out: PathBuf,
    #[arg(long, default_value = "96x72", value_parser = crate::parse_size)]
    size: (u32, u32),
    #[arg(long, default_value_t = 10_000)]
    paths: u32,
    /// Samples per pixel of the reference.
    #[arg(long, default_value_t = 256)]
    spp: u32,
    #[arg(long, default_value_t = 8)]
    max_bounces: u32,
    #[command(flatten)]
    fixed: crate::options::FixedRadius,
}

pub fn run(args: StabilityArgs) -> anyhow::Result<()> {
    if let Some(dir) = args.out.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir).with_context(|| format!("creating {}", dir.display()))?;
    }
    let scenes = args
        .scenes
        .iter()
        .map(|p| Scene::load(p).with_context(|| format!("loading {}", p.display())))
        .collect::<anyhow::Result<Vec<_>>>()?;
    let open = |rt: bool| -> leakless::Result<leakless::Gpu> {
        Ok(leakless::Gpu::new(&leakless::GpuOptions { validation: None, ray_tracing: rt, window: None })?)
    };
    let first = open(true)?;
    let mut backends = vec![Backend::Compute];
    if first.capabilities().ray_query {
        backends.insert(0, Backend::RayQuery);
    }
    let device = first.report().name.clone();
    drop(first);
    let config = StabilityConfig {
        width: args.size.0,
        height: args.size.1,
        paths: args.paths,
        spp: args.spp,
        max_bounces: args.max_bounces,
        backends,
        fixed_radius: args.fixed.fixed_radius,
    };
    let mut measured = Vec::new();
    for scene in &scenes {
        let s = measure(&open, scene, &config, &mut |what| eprintln!("{}: {what}", scene.name))?;
        measured.push(s);
    }
    let out = args.out.display().to_string();
    let md = report(&measured, &config, &device, &out);
    std::fs::write(format!("{out}.md"), md).with_context(|| format!("writing {out}.md"))?;
    csv(&measured)?.write(format!("{out}.csv").as_ref())?;
    println!("wrote {out}.md, {out}.csv");
    let points = thickness_points(&scenes, &measured);
    if !points.is_empty() {
        let caption = format!(
            "partition-*.gltf, compute backend, {}x{}, {} paths, reference {} spp; {device}",
            config.width, config.height, config.paths, config.spp
        );
        let (svg, png) = (format!("{out}-thickness.svg"), format!("{out}-thickness.png"));
        plot_thickness(&points, &caption, svg.as_ref(), png.as_ref(), (900, 450))?;
        let mut c = CsvTable::new(&["thickness_mm", "method", "dark_radiance", "rmse"]);
        for p in &points {
            let (dark, rmse) = (format!("{:.6e}", p.dark_radiance), format!("{:.6e}", p.rmse));
            c.row([p.thickness_mm.to_string(), p.method.name().to_string(), dark, rmse])?;
        }
        c.write(format!("{out}-thickness.csv").as_ref())?;
        println!("wrote {svg}, {png}, {out}-thickness.csv");
    }
    Ok(())
}

fn num(v: Option<f64>, digits: usize) -> String {
    v.filter(|v| v.is_finite()).map_or("–".into(), |v| if v == 0.0 { "0".into() } else { format!("{v:.digits$}") })
}

fn report(scenes: &[SceneStability], c: &StabilityConfig, device: &str, out: &str) -> String {
    let mut md = String::new();
    let _ = writeln!(md, "# Where methods fail: the stress scenes\n");
    let _ = writeln!(
        md,
        "Written by `leakless stability` ({}x{}, {} paths, {} bounces, reference {} spp, {device}). Dark room: mean \
         luminance of the radiance (W·sr⁻¹·m⁻², in the scene's units) over the pixels whose surface lies in the \
         scene's dark box, where the reference is exactly 0. Energy: the image's mean luminance over the \
         reference's. Leaked: share of the gathered indirect energy the visibility test removed. \
         Flicker: per-pixel temporal std / mean over 16 frames with fresh photons. Frame: wall time of the passes, \
         each submitted alone (CPU time on lavapipe). The scenes are described in [scenes.md](scenes.md).\n",
        c.width, c.height, c.paths, c.max_bounces, c.spp
    );
    let name = std::path::Path::new(out).file_name().map(|f| f.to_string_lossy().into_owned()).unwrap_or_default();
    let _ = writeln!(md, "![leaks against thickness]({name}-thickness.png)\n");
    for s in scenes {
        let _ = writeln!(md, "## {}\n", s.scene);
        if let Some(p) = &s.purpose {
            let _ = writeln!(md, "{p}.\n");
        }
        let _ = writeln!(md, "{}\n", sentence(s));
        let _ = writeln!(md, "| method | backend | dark room | energy | leaked | relMSE | RMSE | HDR-FLIP | NaN/Inf | flicker | frame ms |");
        let _ = writeln!(md, "|---|---|---|---|---|---|---|---|---|---|---|");
        for r in &s.rows {
            let _ = writeln!(
                md,
                "| {} | {} | {} | {} | {} | {} | {} | {:.3} | {} | {} | {:.1} |",
                r.method.name(),
                r.backend.name(),
                num(r.dark_radiance, 5),
                num(r.energy, 3),
                num(r.leaked_fraction, 3),
                num(r.relmse, 4),
                num(r.rmse, 4),
                r.flip,
                r.non_finite,
                num(r.flicker, 3),
                r.frame_ms
            );
        }
        md.push('\n');
    }
    md
}

/// What fails in the scene and how, from the compute backend's rows: one sentence, each
/// clause a measured outcome.
fn sentence(s: &SceneStability) -> String {
    let row = |m: Method| s.rows.iter().find(|r| r.method == m && r.backend == Backend::Compute);
    let (Some(splat), Some(ours), Some(capped)) =
        (row(Method::Splat), row(Method::LeakLess), row(Method::LeakLessCapped))
    else {
        return String::new();
    };
    let mut parts = Vec::new();
    let bad: usize = s.rows.iter().map(|r| r.non_finite).sum();
    if bad > 0 {
        parts.push(format!("{bad} NaN/Inf values across the methods"));
    }
    match (splat.dark_radiance, ours.dark_radiance, capped.dark_radiance) {
        (Some(leak), Some(o), Some(c)) if leak > 0.0 && o == 0.0 && c == 0.0 => parts.push(format!(
            "`splat` lights the dark room (mean {leak:.3e}), which `leakless` and the capped method keep exactly black"
        )),
        (Some(leak), Some(o), Some(c)) => {
            parts.push(format!("dark room: `splat` {leak:.3e}, `leakless` {o:.3e}, capped {c:.3e}"))
        }
        _ => {}
    }
    if let (Some(e_ours), Some(e_capped)) = (ours.energy, capped.energy) {
        if e_capped < 0.95 * e_ours {
            parts.push(format!(
                "the capped method keeps {:.0}% of the reference's energy against {:.0}% for `leakless` (photons past its cap are dropped)",
                100.0 * e_capped,
                100.0 * e_ours
            ));
        }
    }
    if let (Some(e), Some(f)) = (ours.energy, splat.energy) {
        if (e - 1.0).abs() > 0.05 || (f - 1.0).abs() > 0.05 {
            parts.push(format!(
                "energy against the reference: `leakless` {:.0}%, `splat` {:.0}%",
                100.0 * e,
                100.0 * f
            ));
        }
    }
    if let (Some(a), Some(b)) = (ours.relmse, splat.relmse) {
        parts.push(format!("relMSE `leakless` {a:.3} against `splat` {b:.3}"));
    }
    if let Some(f) = ours.flicker.filter(|f| *f > 1.0) {
        parts.push(format!(
            "one photon frame is noise-dominated here (flicker {f:.2}: few photons reach what the camera sees)"
        ));
    }
    if parts.is_empty() {
        "Nothing fails here: every method matches the reference (a black image where the camera sees only the dark room).".into()
    } else {
        let mut t = parts.join("; ");
        t.push('.');
        t[..1].to_uppercase() + &t[1..]
    }
}

fn csv(scenes: &[SceneStability]) -> anyhow::Result<CsvTable> {
    let header = [
        "scene",
        "method",
        "backend",
        "dark_radiance",
        "energy",
        "leaked_fraction",
        "relmse",
        "rmse",
        "hdr_flip",
        "non_finite",
        "flicker",
        "frame_ms",
    ];
    let mut c = CsvTable::new(&header);
    let f = |v: Option<f64>| v.map(|v| format!("{v:.6e}")).unwrap_or_default();
    for r in scenes.iter().flat_map(|s| &s.rows) {
        c.row([
            r.scene.clone(),
            r.method.name().to_string(),
            r.backend.name().to_string(),
            f(r.dark_radiance),
            f(r.energy),
            f(r.leaked_fraction),
            f(r.relmse),
            f(r.rmse),
            format!("{:.6e}", r.flip),
            r.non_finite.to_string(),
            f(r.flicker),
            format!("{:.3}", r.frame_ms),
        ])?;
    }
    Ok(c)
}

/// The partition sweep's points: scenes whose extras give `partition_thickness` and a dark box.
fn thickness_points(scenes: &[Scene], measured: &[SceneStability]) -> Vec<ThicknessPoint> {
    let mut points = Vec::new();
    for (scene, m) in scenes.iter().zip(measured) {
        if !scene.name.starts_with("partition-") {
            continue;
        }
        let extras: serde_json::Value =
            scene.extras.as_deref().and_then(|e| serde_json::from_str(e).ok()).unwrap_or_default();
        let Some(t) = extras["partition_thickness"].as_f64() else { continue };
        for r in m.rows.iter().filter(|r| r.backend == Backend::Compute && r.method != Method::Direct) {
            if let (Some(e), Some(rmse)) = (r.dark_radiance, r.rmse) {
                points.push(ThicknessPoint { thickness_mm: t * 1000.0, method: r.method, dark_radiance: e, rmse });
            }
        }
    }
    points
}
