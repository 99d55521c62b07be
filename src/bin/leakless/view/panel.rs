//! What the overlay shows: the scene, device and backend, the frame's cost pass by pass, the
//! photon counts, sliders for radius, paths and cap, and the key map.

use egui::{Color32, RichText};
use leakless::{FrameReport, Method, ViewLayer};

use super::keys;

/// What the panel reports on this frame.
pub struct PanelInfo<'a> {
    pub scene: &'a str,
    pub device: &'a str,
    pub backend: &'a str,
    pub backend_why: &'a str,
    /// Why the last change was not made (`refusal`).
    pub refusal: Option<&'a str>,
    pub width: u32,
    pub height: u32,
    pub method: Method,
    /// How the frame found its view samples (`--primary`, resolved).
    pub primary: leakless::Primary,
    pub layer: ViewLayer,
    /// Host time between shown frames.
    pub frame_ms: f64,
    pub report: Option<&'a FrameReport>,
    /// Per-pass times of the newest frame that measured them.
    pub timings: Option<&'a [leakless_graph::PassTiming]>,
    /// How per-pass times are measured on this device.
    pub timing_note: &'a str,
    pub paused: bool,
    pub seed_frozen: bool,
    /// Frames accumulate (`Renderer::accumulating`).
    pub accumulating: bool,
    /// The accumulation holds all it may (`Renderer::accumulation_full`).
    pub accumulation_full: bool,
    pub trivial_accept: bool,
    /// Temporal reuse is on (U).
    pub reuse: bool,
    pub light_moved: bool,
    /// The scene's animation plays.
    pub playing: bool,
    /// Host time of the last instance update (transforms, vertices, top level).
    pub pose_update_ms: f64,
    /// What the frame budget did for the newest frame whose paths it chose.
    pub budget: Option<&'a leakless::renderer::BudgetReport>,
    /// Dynamic resolution's share of the render scale along each axis (1: none).
    pub dynamic_scale: f32,
}

/// The sliders' values; the app applies what changed.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sliders {
    pub radius: f32,
    pub radius_range: (f32, f32),
    pub paths: u32,
    /// Photon batches a still view's frames grow to.
    pub max_batches: u32,
    pub cap: u32,
    /// The scene's clock, and its animation's length (`None`: nothing moves).
    pub time: f32,
    pub duration: Option<f32>,
}

pub fn show(ctx: &egui::Context, info: &PanelInfo<'_>, sliders: &mut Sliders, help: &mut bool) {
    // A small window (the default on CPU devices is 640×480) is shorter than the panel: it
    // scrolls within the screen rather than cutting off the sliders (a scrolling egui window
    // is as tall as its default height, 400 points unless set).
    let height = (ctx.content_rect().height() - 24.0).max(100.0);
    egui::Window::new("leakless")
        .default_pos([8.0, 8.0])
        .resizable(false)
        .collapsible(true)
        .vscroll(true)
        .default_height(height)
        .max_height(height)
        .show(ctx, |ui| contents(ui, info, sliders));
    if *help {
        egui::Window::new("keys").anchor(egui::Align2::RIGHT_TOP, [-8.0, 8.0]).open(help).show(ctx, |ui| {
            egui::Grid::new("keymap").striped(true).show(ui, |ui| {
                ui.label("W A S D");
                ui.label("fly; Q / E down / up; drag to look; wheel: speed");
                ui.end_row();
                for (_, _, key, what) in keys::ACTIONS {
                    ui.label(*key);
                    ui.label(*what);
                    ui.end_row();
                }
            });
        });
    }
}

/// The panel's labels, per-pass bars and sliders.
fn contents(ui: &mut egui::Ui, info: &PanelInfo<'_>, sliders: &mut Sliders) {
    ui.label(RichText::new(info.scene).strong());
    ui.label(format!("{} — {} ({})", info.device, info.backend, info.backend_why));
    let samples = match info.primary {
        leakless::Primary::Rays => "view samples by rays",
        _ => "view samples rasterised",
    };
    ui.label(format!(
        "{}×{}   {}   layer: {}   {samples}",
        info.width,
        info.height,
        info.method.name(),
        info.layer.name()
    ));
    let fps = if info.frame_ms > 0.0 { 1000.0 / info.frame_ms } else { 0.0 };
    let mut flags = Vec::new();
    if info.paused {
        flags.push("paused");
    }
    if info.seed_frozen {
        flags.push("seed frozen");
    }
    if info.accumulation_full {
        flags.push("accumulation full");
    }
    if !info.trivial_accept {
        flags.push("trivial accept off");
    }
    if !info.reuse {
        flags.push("reuse off");
    }
    if info.light_moved {
        flags.push("light moved");
    }
    if info.playing {
        flags.push("playing");
    }
    ui.label(format!("{:.1} ms/frame, {:.1} fps   {}", info.frame_ms, fps, flags.join(", ")));
    if let Some(b) = info.budget {
        let radius =
            info.report.and_then(|r| r.splat.as_ref()).map_or(String::new(), |s| format!(", radius {:.4}", s.radius));
        let warm_up = if b.warm_up { " (a pass ran for the first time: not counted)" } else { "" };
        ui.label(format!(
            "budget {:.1} ms: moving frame {:.1} ms{warm_up} with {} paths{radius}; next {} paths",
            b.target_ms, b.measured_ms, b.paths, b.next_paths
        ));
        if info.dynamic_scale < 1.0 {
            ui.label(format!(
                "dynamic resolution: {:.0}% of the render scale along each axis",
                100.0 * info.dynamic_scale
            ));
        }
        if b.over_budget {
            // The estimate, not the last frame: one frame may come in under the target.
            let text = format!(
                "over budget: {} paths take {:.1} ms by the last frames' mean, against {:.1} ms",
                leakless::frame_budget::MIN_BUDGET_PATHS,
                b.fewest_paths_ms,
                b.target_ms
            );
            ui.label(RichText::new(text).color(Color32::from_rgb(255, 170, 60)));
        }
    }
    if let Some(why) = info.refusal {
        ui.label(RichText::new(format!("not applied: {why}")).color(Color32::from_rgb(255, 170, 60)));
    }
    if let Some(report) = info.report {
        if report.method == Method::Reference && !info.accumulating {
            // Not accumulating frames: samples add to one image at the pixel centres.
            ui.label(format!("reference: {} spp accumulated", report.accumulated));
        } else if report.method == Method::Reference {
            // Jittered frames of batches of one sample per pixel (the app's reference).
            let (frames, samples) = (report.accumulated, report.batches);
            ui.label(format!("reference: {frames} frames accumulated ({samples} spp)"));
        } else if let Some(s) = &report.splat {
            let (frames, batches) = (report.accumulated, report.batches);
            ui.label(format!("{frames} photon frames accumulated ({batches} batches), radius now {:.4}", s.radius));
        }
        if let Some(timings) = info.timings {
            ui.separator();
            pass_bars(ui, timings, info.timing_note);
        }
        if let Some(s) = &report.splat {
            ui.separator();
            ui.label(format!(
                "photons stored {}   paths {}   radius {:.4} ({:.1} photons a kernel)",
                s.photons_stored, s.paths, s.radius, s.photons_per_kernel
            ));
            let proven = 100.0 * s.proven_clear as f64 / s.visibility_tests.max(1) as f64;
            ui.label(format!(
                "visibility tests {} ({proven:.0}% proven clear)   rays {}   leaks culled {}",
                s.visibility_tests, s.visibility_rays, s.leaks_culled
            ));
            ui.label(format!("leaked energy {:.2}%", 100.0 * s.leaked_energy_fraction));
            let drops = s.photons_dropped as u64 + s.list_entries_dropped as u64;
            let text = format!("drops: photons {}, list entries {}", s.photons_dropped, s.list_entries_dropped);
            ui.label(if drops > 0 { RichText::new(text).color(Color32::LIGHT_RED) } else { RichText::new(text) });
        }
    }
    ui.separator();
    let (lo, hi) = sliders.radius_range;
    ui.add(egui::Slider::new(&mut sliders.radius, lo..=hi).logarithmic(true).text("radius"));
    // The range holds the value given on the command line: egui clamps a value outside it.
    let paths_range = sliders.paths.min(1_000)..=sliders.paths.max(1_000_000);
    ui.add(egui::Slider::new(&mut sliders.paths, paths_range).logarithmic(true).text("paths"));
    let most = leakless::settings::MAX_BATCHES;
    ui.add(egui::Slider::new(&mut sliders.max_batches, 1..=most).logarithmic(true).text("batches when still"));
    ui.add(egui::Slider::new(&mut sliders.cap, 1..=200).text("cap"));
    if let Some(duration) = sliders.duration {
        ui.add(egui::Slider::new(&mut sliders.time, 0.0..=duration).text("time (s)"));
        ui.label(format!("M: play / stop   instance update {:.2} ms (host)", info.pose_update_ms));
    }
    ui.label("H / F1: keys   Tab: hide");
}

fn pass_bars(ui: &mut egui::Ui, timings: &[leakless_graph::PassTiming], note: &str) {
    let mut groups: Vec<(&str, f64)> = Vec::new();
    for t in timings {
        let ms = t.wall_ms.unwrap_or(t.ms);
        match groups.iter_mut().find(|(g, _)| *g == t.group) {
            Some((_, total)) => *total += ms,
            None => groups.push((t.group, ms)),
        }
    }
    let total: f64 = groups.iter().map(|(_, ms)| ms).sum();
    // Passes under 2% of the frame share one bar; reuse always has its own (its cost is what
    // the U key trades).
    let own_bar = |(g, ms): &(&str, f64)| *ms >= 0.02 * total || *g == leakless::passes::names::group::REUSE;
    let small: f64 = groups.iter().filter(|g| !own_bar(g)).map(|(_, ms)| ms).sum();
    groups.retain(own_bar);
    if small > 0.0 {
        groups.push(("other passes", small));
    }
    let max = groups.iter().map(|(_, ms)| *ms).fold(1e-3, f64::max);
    ui.label(format!("GPU {total:.1} ms per frame ({note})"));
    for (name, ms) in groups {
        ui.add(egui::ProgressBar::new((ms / max) as f32).desired_width(260.0).text(format!("{name} {ms:.1} ms")));
    }
}
