//! `leakless view`: the native app. A winit window presenting through an ash swapchain, a fly
//! camera, keyboard toggles for every setting, an egui overlay, captures to EXR, and scripted
//! runs for tests. It drives the same `Renderer` as `render`: one frame in flight while the
//! next is recorded, nothing read back except on capture.

mod batches;
mod camera;
mod capture;
mod keys;
mod overlay;
mod panel;
mod press;
mod refusal;
mod script;
mod summary;
mod tick;

use std::collections::HashSet;
use std::path::PathBuf;
use std::sync::Arc;
use std::time::Instant;

use anyhow::{bail, Context};
use leakless::{RenderSettings, Renderer, Scene};
use leakless_device::{PresentMode, Swapchain};
use raw_window_handle::{HasDisplayHandle, HasWindowHandle};
use winit::application::ApplicationHandler;
use winit::event::{ElementState, MouseButton, MouseScrollDelta, WindowEvent};
use winit::event_loop::{ActiveEventLoop, ControlFlow, EventLoop};
use winit::keyboard::{KeyCode, PhysicalKey};
use winit::window::{Window, WindowId};

use crate::options::RenderOptions;
use camera::FlyCamera;
use overlay::Overlay;
use script::Script;
use summary::Summary;

#[derive(clap::Args)]
pub struct ViewArgs {
    #[command(flatten)]
    options: RenderOptions,
    /// Presentation: `fifo` (vsync, never tears), `mailbox` or `immediate`.
    #[arg(long, default_value = "fifo", value_parser = ["fifo", "mailbox", "immediate"])]
    present: String,
    /// Replays events from FILE at frame numbers with a fixed time step (see `view/script.rs`).
    #[arg(long)]
    script: Option<PathBuf>,
    /// Stops after N frames (then prints the summary line).
    #[arg(long)]
    exit_after: Option<u64>,
    /// Rendered pixels per window pixel along each axis (default: 0.5 on CPU devices, 1 on
    /// GPUs). `--size` is the rendered size; the window is `--size` / this.
    #[arg(long)]
    render_scale: Option<f32>,
    /// Frame-time budget in ms, or `off`: while anything moves, each frame traces the light
    /// paths that keep it within T (a still view's frames grow their batches within T).
    /// Default: the device tuning's (16.7 on GPUs, 150 on CPU devices; `leakless info`).
    #[arg(long, value_name = "T|off", value_parser = parse_frame_ms)]
    frame_ms: Option<FrameMs>,
    /// With a frame budget: where even the fewest light paths miss it, render fewer pixels
    /// (each step about 30% fewer, down to a sixteenth), and more again once there is room.
    #[arg(long, default_value = "on", value_parser = ["on", "off"])]
    dynamic_resolution: String,
    /// On exit, writes each frame whose paths the budget chose to this CSV: its time by the
    /// budget's measure, its paths and the next frame's, its render size, whether it was over
    /// budget, and whether it was the first (which compiles the pipelines and is not counted).
    #[arg(long)]
    frame_log: Option<PathBuf>,
}

/// `--frame-ms`: a budget, or none.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum FrameMs {
    Off,
    Target(f64),
}

pub fn parse_frame_ms(s: &str) -> Result<FrameMs, String> {
    if s == "off" {
        return Ok(FrameMs::Off);
    }
    let t: f64 = s.trim().parse().map_err(|_| format!("{s:?} is neither a time in ms nor `off`"))?;
    let most = leakless::renderer::MAX_FRAME_MS;
    if !(t.is_finite() && t > 0.0 && t <= most) {
        return Err(format!("{s}: the frame budget must be within (0, {most}] ms"));
    }
    Ok(FrameMs::Target(t))
}

/// The window size showing a `size` render at `scale`.
fn window_size(size: (u32, u32), scale: f32) -> (u32, u32) {
    let up = |v: u32| ((v as f32 / scale).round() as u32).max(1);
    (up(size.0), up(size.1))
}

/// Whether there is a display to open a window on.
pub fn display_available() -> bool {
    ["DISPLAY", "WAYLAND_DISPLAY"].iter().any(|v| std::env::var_os(v).is_some_and(|s| !s.is_empty()))
}

pub fn run(args: ViewArgs) -> anyhow::Result<()> {
    if !display_available() {
        bail!("no display: $DISPLAY and $WAYLAND_DISPLAY are unset (`leakless render` writes EXR + PNG instead)");
    }
    let present = PresentMode::parse(&args.present).expect("clap checked the value");
    if let Some(scale) = args.render_scale {
        if !(scale.is_finite() && scale > 0.0 && scale <= 4.0) {
            bail!("--render-scale {scale} must be within (0, 4]");
        }
    }
    let scene = args.options.load_scene()?;
    args.options.settings((1, 1)).validate()?;
    let script = args.script.as_deref().map(Script::load).transpose()?;
    let event_loop = EventLoop::new().context("connecting to the display")?;
    event_loop.set_control_flow(ControlFlow::Poll);
    let mut app = App { args, present, scene, script, running: None, error: None, summary: Summary::default() };
    event_loop.run_app(&mut app).context("running the window's event loop")?;
    if app.running.is_some() {
        // Closed by the event loop ending: tear down in order.
        app.running = None;
    }
    if let Some(e) = app.error {
        return Err(e);
    }
    println!("{}", app.summary.line());
    if let Some(path) = &app.args.frame_log {
        app.summary.budget_log()?.write(path).with_context(|| format!("writing {}", path.display()))?;
    }
    Ok(())
}

struct App {
    args: ViewArgs,
    present: PresentMode,
    scene: Scene,
    script: Option<Script>,
    running: Option<Running>,
    error: Option<anyhow::Error>,
    summary: Summary,
}

/// The app once its window is open. Fields drop in order: the overlay and swapchain before the
/// renderer (which owns the device), the window last.
struct Running {
    overlay: Overlay,
    swapchain: Option<Swapchain>,
    renderer: Renderer,
    window: Arc<Window>,
    camera: FlyCamera,
    /// Movement keys held down, and those tapped by a script this frame.
    held: HashSet<KeyCode>,
    tapped: Vec<KeyCode>,
    dragging: bool,
    cursor: Option<(f64, f64)>,
    /// Drag pixels since the last frame.
    drag: (f32, f32),
    /// The window's size (the swapchain's), and rendered pixels per window pixel.
    size: (u32, u32),
    render_scale: f32,
    /// Dynamic resolution's share of `render_scale` along each axis (1: none), and whether it
    /// may change (`--dynamic-resolution`).
    dynamic: leakless::frame_budget::DynamicResolution,
    minimized: bool,
    recreate: bool,
    /// Loop iterations so far (script frame numbers).
    frame: u64,
    show_overlay: bool,
    show_help: bool,
    seed_frozen: bool,
    light_moved: bool,
    /// The scene's animation plays (M), on a clock that loops with a second's hold at the end.
    playing: bool,
    animation_clock: f32,
    last_shown: Option<Instant>,
    frame_ms: f64,
    /// Photon batches a still view's frames may grow to (`--max-batches`, the slider); each
    /// accumulation grows to fewer when that would take a frame past `STILL_FRAME_BUDGET_MS`.
    batch_limit: u32,
    /// A measured frame has fitted the batches (until then, frames stay at one batch).
    batches_fitted: bool,
    /// On CPU devices, per-pass times come from a frame every this many whose passes are each
    /// submitted alone (timestamps there do not bracket compute work); 0: every frame, from
    /// timestamps.
    profile_every: u64,
    /// Why the last change of settings (a key, a slider, the window's size) was not made, or
    /// was made smaller (`refusal`).
    refusal: Option<String>,
    /// Per-pass times of the newest frame that measured them (see `profile_every`).
    timings: Option<Vec<leakless_graph::PassTiming>>,
    /// What the frame budget did for the newest frame whose paths it chose.
    budget: Option<leakless::renderer::BudgetReport>,
    quit: bool,
}

impl Drop for Running {
    fn drop(&mut self) {
        // Frames in flight use the swapchain and the overlay's buffers, and presents its
        // semaphores.
        let _ = self.renderer.wait_idle();
        let _ = self.renderer.gpu().wait_idle();
    }
}

impl App {
    fn start(&mut self, event_loop: &ActiveEventLoop) -> anyhow::Result<Running> {
        let options = &self.args.options;
        let title = format!("leakless — {}", self.scene.name);
        // The size is the device tuning's; the window comes first (the device must present to
        // it), so it opens at the CPU preset's size and grows if the device is a GPU.
        let cpu = leakless::DeviceTuning::cpu();
        let (w, h) =
            window_size(options.size.unwrap_or(cpu.view_size), self.args.render_scale.unwrap_or(cpu.view_render_scale));
        let attributes =
            Window::default_attributes().with_title(title).with_inner_size(winit::dpi::PhysicalSize::new(w, h));
        let window = Arc::new(event_loop.create_window(attributes).context("opening the window")?);
        let handles = leakless_device::WindowHandles {
            display: window.display_handle().context("the window's display handle")?.as_raw(),
            window: window.window_handle().context("the window's handle")?.as_raw(),
        };
        let gpu_options = leakless::GpuOptions {
            validation: None,
            ray_tracing: options.backend.wants_ray_queries(),
            window: Some(handles),
        };
        let gpu = leakless::Gpu::new(&gpu_options).context("opening a Vulkan device that presents to the window")?;
        let tuning = leakless::DeviceTuning::choose(gpu.report(), options.tuning);
        let render_scale = self.args.render_scale.unwrap_or(tuning.view_render_scale);
        let render_size = options.size.unwrap_or(tuning.view_size);
        let size = window_size(render_size, render_scale);
        if size != (w, h) {
            let _ = window.request_inner_size(winit::dpi::PhysicalSize::new(size.0, size.1));
        }
        // The reference accumulates while the view is still, as photon frames do, in batches
        // of one sample per pixel: its frames start short and grow as the batch fit allows.
        let settings = RenderSettings { spp: 1, ..options.settings(render_size) };
        let mut renderer = Renderer::new(gpu, &self.scene, settings).context("setting up the renderer")?;
        options.apply_view(&mut renderer, &self.scene)?;
        renderer.set_frame_budget(match self.args.frame_ms {
            Some(FrameMs::Off) => None,
            Some(FrameMs::Target(t)) => Some(t),
            None => Some(tuning.frame_ms),
        })?;
        // Frames accumulate while nothing changes (P freezes the photons instead).
        renderer.set_advance_seed(true);
        renderer.set_progressive(true);
        let camera = FlyCamera::new(&self.scene, renderer.camera());
        let swapchain = Swapchain::new(
            renderer.gpu(),
            ash::vk::Extent2D { width: size.0, height: size.1 },
            self.present,
            leakless::renderer::FRAMES_IN_FLIGHT,
            None,
        )
        .context("creating the swapchain")?;
        renderer.prepare_display(swapchain.format())?;
        let overlay = Overlay::new(renderer.gpu(), &window, swapchain.format(), leakless::renderer::FRAMES_IN_FLIGHT)?;
        Ok(Running {
            overlay,
            swapchain: Some(swapchain),
            renderer,
            window,
            camera,
            held: HashSet::new(),
            tapped: Vec::new(),
            dragging: false,
            cursor: None,
            drag: (0.0, 0.0),
            size,
            render_scale,
            dynamic: leakless::frame_budget::DynamicResolution::new(self.args.dynamic_resolution == "on"),
            minimized: false,
            recreate: true,
            frame: 0,
            show_overlay: true,
            show_help: false,
            seed_frozen: false,
            light_moved: false,
            playing: self.scene.is_animated(),
            animation_clock: options.time,
            last_shown: None,
            frame_ms: 0.0,
            batch_limit: options.max_batches,
            batches_fitted: false,
            profile_every: tuning.view_profile_every as u64,
            refusal: None,
            timings: None,
            budget: None,
            quit: false,
        })
    }

    fn fail(&mut self, event_loop: &ActiveEventLoop, e: anyhow::Error) {
        if self.error.is_none() {
            self.error = Some(e);
        }
        self.running = None;
        event_loop.exit();
    }
}

impl ApplicationHandler for App {
    fn resumed(&mut self, event_loop: &ActiveEventLoop) {
        if self.running.is_some() || self.error.is_some() {
            return;
        }
        match self.start(event_loop) {
            Ok(running) => self.running = Some(running),
            Err(e) => self.fail(event_loop, e),
        }
    }

    fn window_event(&mut self, event_loop: &ActiveEventLoop, _id: WindowId, event: WindowEvent) {
        let Some(r) = &mut self.running else { return };
        let consumed = r.overlay.on_event(&r.window, &event);
        match event {
            WindowEvent::CloseRequested => {
                self.running = None;
                event_loop.exit();
            }
            WindowEvent::Resized(size) => r.resize(size.width, size.height),
            WindowEvent::KeyboardInput { event, .. } if !consumed => {
                let PhysicalKey::Code(code) = event.physical_key else { return };
                match event.state {
                    ElementState::Pressed => {
                        if keys::motion(code).is_some() {
                            r.held.insert(code);
                        } else if !event.repeat {
                            if let Err(e) = r.key(code, &self.scene) {
                                self.fail(event_loop, e);
                            }
                        }
                    }
                    ElementState::Released => {
                        r.held.remove(&code);
                    }
                }
            }
            WindowEvent::MouseInput { state, button: MouseButton::Left, .. } => {
                r.dragging = state == ElementState::Pressed && !r.overlay.wants_input();
            }
            WindowEvent::CursorMoved { position, .. } => {
                if let (true, Some((x, y))) = (r.dragging, r.cursor) {
                    r.drag.0 += (position.x - x) as f32;
                    r.drag.1 += (position.y - y) as f32;
                }
                r.cursor = Some((position.x, position.y));
            }
            WindowEvent::MouseWheel { delta, .. } if !consumed => {
                let notches = match delta {
                    MouseScrollDelta::LineDelta(_, y) => y,
                    MouseScrollDelta::PixelDelta(p) => (p.y / 40.0) as f32,
                };
                r.camera.scale_speed(notches);
            }
            _ => {}
        }
    }

    fn about_to_wait(&mut self, event_loop: &ActiveEventLoop) {
        let Some(r) = &mut self.running else { return };
        let result = r.tick(&self.scene, self.script.as_mut(), &mut self.summary, &self.args);
        match result {
            Err(e) => self.fail(event_loop, e),
            Ok(()) if r.quit => {
                self.running = None;
                event_loop.exit();
            }
            Ok(()) => {}
        }
    }
}
