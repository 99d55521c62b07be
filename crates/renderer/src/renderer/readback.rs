//! Reading a frame back, on explicit request: the CLI's render, the tests, the app's capture.
//! The request rides on a frame like any other; the host waits for that frame alone and reads
//! the layers and the tonemapped image from its per-frame buffer.

use ash::vk;
use leakless_graph::PassTiming;

use super::{FrameReport, Renderer};
use crate::error::Result;
use crate::passes::tonemap::ViewLayer;
use crate::settings::Method;
use crate::splatting::SplatStats;

/// The 8-bit image a PNG is saved from: the tonemap writes it, encoding sRGB itself.
pub const DISPLAY_FORMAT: vk::Format = vk::Format::R8G8B8A8_UNORM;

/// The per-frame buffer the layers are read back into.
pub(super) const LAYERS_BUFFER: &str = "layers readback";

/// What a readback also tonemaps (the PNG).
#[derive(Clone, Copy, Debug)]
pub(super) struct ReadbackRequest {
    pub view: ViewLayer,
    pub exposure: Option<f32>,
}

/// The layers of one rendered frame, linear radiance, row-major from the top-left pixel.
#[derive(Clone, Debug)]
pub struct RenderedFrame {
    pub width: u32,
    pub height: u32,
    /// Final radiance: direct + indirect.
    pub radiance: Vec<[f32; 3]>,
    pub direct: Vec<[f32; 3]>,
    pub indirect: Vec<[f32; 3]>,
    /// Indirect light the visibility test removed (zero for methods without it).
    pub leaked: Vec<[f32; 3]>,
    /// The surface each pixel sees in the frame's G-buffer (the last frame's, for an
    /// accumulation): its world position, and in .w its triangle + 1 (0 where it sees none).
    pub surface: Vec<[f32; 4]>,
    /// The final image tonemapped as the window shows it (sRGB, RGBA8): the PNG.
    pub display: Vec<[u8; 4]>,
    /// Per-pass times, summed over the frames that made the image (a reference image
    /// accumulates its samples over several).
    pub timings: Vec<PassTiming>,
    /// The last of those frames' own per-pass times: the frame that `splat` counted, so that
    /// a time and a count of the same frame go together (`timings` holds every frame's).
    pub last_frame_timings: Vec<PassTiming>,
    /// GPU time of the frames that made the image, each from its first pass's start to its
    /// last pass's end, summed: the frame time on a GPU (with `Timing::Timestamps`).
    pub gpu_span_ms: f64,
    /// Host wall-clock time of the whole render.
    pub wall_ms: f64,
    /// What the photon method counted, for methods that splat.
    pub splat: Option<SplatStats>,
    /// Reference samples (or photon frames) in the image.
    pub accumulated: u32,
    /// Photon batches (of `paths` paths) in the image.
    pub batches: u32,
    /// The seed the image's photons were traced with.
    pub seed: u32,
}

impl RenderedFrame {
    pub fn pixel(layer: &[[f32; 3]], width: u32, x: u32, y: u32) -> [f32; 3] {
        layer[(y * width + x) as usize]
    }
}

impl Renderer {
    /// Renders the image the settings ask for, from scratch, and reads its layers back: one
    /// photon frame, or `spp` reference samples (over several frames).
    pub fn render(&mut self) -> Result<RenderedFrame> {
        self.render_with_progress(&mut |_, _| {})
    }

    /// As [`Renderer::render`]; `progress(done, total)` is called as reference samples
    /// accumulate. A splat frame whose node lists overflowed restarts the image with lists
    /// large enough (`collect`), so the frames are rendered again within the same loop, unless
    /// the capacity was fixed by the user or is at its maximum, in which case the drops are
    /// reported in the frame's stats.
    pub fn render_with_progress(&mut self, progress: &mut dyn FnMut(u32, u32)) -> Result<RenderedFrame> {
        let start = std::time::Instant::now();
        self.wait_idle()?;
        self.restart();
        self.forget_history();
        // Nor frames to measure the photon density: the first frame's own photons do.
        self.forget_kernel_density();
        // A reference of several frames renders `spp` samples per frame (`accumulating`).
        let frames = self.settings.frames.max(1);
        let total = if self.settings.method == Method::Reference && frames == 1 { self.settings.spp } else { frames };
        let mut timings = Timings::default();
        let mut gpu_span_ms = 0.0;
        // Reference samples in submissions of about half a second: responsive progress, few
        // submissions, far from the lost-device timeout. Each waits, to measure the next.
        let mut chunk = 1;
        let request = super::readback::ReadbackRequest { view: ViewLayer::Final, exposure: self.exposure };
        while self.accumulation.accumulated < total {
            let t = std::time::Instant::now();
            let last = self.accumulation.accumulated + chunk >= total;
            self.set_samples_per_frame(chunk.min(total - self.accumulation.accumulated));
            self.submit_frame(None, last.then_some(request))?;
            self.wait_idle()?;
            if self.accumulation.accumulated == 0 {
                // The lists grew and the image restarted: its passes' times start again too.
                timings = Timings::default();
                gpu_span_ms = 0.0;
                continue;
            }
            let last = self.last.as_ref().expect("a frame completed");
            timings.add(&last.timings);
            gpu_span_ms += last.gpu_span_ms;
            progress(self.accumulation.accumulated.min(total), total);
            let per_sample = t.elapsed().as_secs_f64() * 1e3 / chunk as f64;
            // Photon frames go one per submission (a frame is one unit of accumulation).
            if self.settings.method == Method::Reference && frames == 1 {
                chunk = ((500.0 / per_sample.max(1e-3)) as u32).clamp(1, 256);
            }
        }
        self.set_samples_per_frame(1);
        let report = self.last.clone().expect("a frame completed");
        let mut frame = self.read_layers(&report)?;
        frame.timings = timings.0;
        frame.gpu_span_ms = gpu_span_ms;
        frame.wall_ms = start.elapsed().as_secs_f64() * 1e3;
        Ok(frame)
    }

    /// Renders the next frame of the current state (accumulation goes on) and reads it back:
    /// what the window shows, as layers (the app's capture).
    pub fn capture_frame(&mut self) -> Result<RenderedFrame> {
        let request = ReadbackRequest { view: ViewLayer::Final, exposure: self.exposure };
        self.submit_frame(None, Some(request))?;
        self.wait_idle()?;
        let report = self.last.clone().expect("a frame completed");
        self.read_layers(&report)
    }

    /// Reads the layers the newest completed frame copied out (it must have been submitted
    /// with a readback request).
    fn read_layers(&self, report: &FrameReport) -> Result<RenderedFrame> {
        let (width, height) = (self.settings.width, self.settings.height);
        let n = (width * height) as usize;
        let buffer = self.runner.pool().frame_buffer(LAYERS_BUFFER, report.slot).ok_or_else(|| {
            crate::RenderError::Settings("reading layers back: the frame was not rendered with a readback".into())
        })?;
        let texels: Vec<[f32; 4]> = buffer.read_vec(5 * n)?;
        let layer =
            |i: usize| -> Vec<[f32; 3]> { texels[i * n..(i + 1) * n].iter().map(|t| [t[0], t[1], t[2]]).collect() };
        let mut display = vec![[0u8; 4]; n];
        buffer.read(5 * n as u64 * 16, bytemuck::cast_slice_mut(&mut display))?;
        Ok(RenderedFrame {
            width,
            height,
            radiance: layer(0),
            direct: layer(1),
            indirect: layer(2),
            leaked: layer(3),
            surface: texels[4 * n..5 * n].to_vec(),
            display,
            timings: report.timings.clone(),
            last_frame_timings: report.timings.clone(),
            gpu_span_ms: report.gpu_span_ms,
            wall_ms: report.wall_ms,
            splat: report.splat.clone(),
            accumulated: report.accumulated,
            batches: report.batches,
            seed: report.seed,
        })
    }
}

/// Per-pass times summed by pass name, in first-run order.
#[derive(Default)]
struct Timings(Vec<PassTiming>);

/// `run` with the passes of one name summed into the first of them.
pub(super) fn merged_by_name(run: &[PassTiming]) -> Vec<PassTiming> {
    let mut timings = Timings::default();
    timings.add(run);
    timings.0
}

impl Timings {
    fn add(&mut self, run: &[PassTiming]) {
        add_timings(&mut self.0, run);
    }
}

impl RenderedFrame {
    /// Adds `later`'s pass times and frame times to this frame's (the totals of a run of
    /// frames: a sequence's stats).
    pub fn add_times(&mut self, later: &RenderedFrame) {
        add_timings(&mut self.timings, &later.timings);
        self.gpu_span_ms += later.gpu_span_ms;
        self.wall_ms += later.wall_ms;
    }
}

/// Adds `run`'s pass times to `sums`, by pass name, in first-run order.
fn add_timings(sums: &mut Vec<PassTiming>, run: &[PassTiming]) {
    for t in run {
        match sums.iter_mut().find(|x| x.name == t.name) {
            Some(x) => {
                x.ms += t.ms;
                x.wall_ms = match (x.wall_ms, t.wall_ms) {
                    (Some(a), Some(b)) => Some(a + b),
                    (a, b) => a.or(b),
                };
            }
            None => sums.push(t.clone()),
        }
    }
}
