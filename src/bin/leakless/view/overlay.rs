//! The overlay: egui, fed by egui-winit, drawn by egui-ash-renderer into the swapchain image
//! after the tonemap, as a pass of the frame's graph (so captures, which read the layers
//! back, never contain it). egui-ash-renderer drives Vulkan itself: it gets the device's raw
//! handles, an allocator of its own, and a command pool for its texture uploads.

use std::cell::RefCell;
use std::sync::{Arc, Mutex};

use ash::vk;
use egui_ash_renderer::{DynamicRendering, Options, RenderMode};
use leakless::Gpu;
use leakless_graph::{Access, Graph, ImageHandle};
use winit::window::Window;

type EguiRenderer = egui_ash_renderer::Renderer<egui_ash_renderer::allocator::GpuAllocator>;

pub struct Overlay {
    pub ctx: egui::Context,
    state: egui_winit::State,
    renderer: RefCell<EguiRenderer>,
    device: ash::Device,
    queue: vk::Queue,
    command_pool: vk::CommandPool,
    format: vk::Format,
    primitives: Vec<egui::ClippedPrimitive>,
    pixels_per_point: f32,
    /// Textures egui freed, with the frame after which no frame in flight can use them.
    to_free: Vec<(u64, Vec<egui::TextureId>)>,
}

fn is_srgb(format: vk::Format) -> bool {
    matches!(format, vk::Format::B8G8R8A8_SRGB | vk::Format::R8G8B8A8_SRGB)
}

impl Overlay {
    pub fn new(gpu: &Gpu, window: &Window, format: vk::Format, frames_in_flight: usize) -> anyhow::Result<Overlay> {
        let raw = gpu.raw();
        let allocator = Arc::new(Mutex::new(gpu.new_allocator()?));
        let mode = RenderMode::DynamicRendering(DynamicRendering {
            color_attachment_format: format,
            depth_attachment_format: None,
            stencil_attachment_format: None,
        });
        let options = Options {
            in_flight_frames: frames_in_flight,
            enable_depth_test: false,
            enable_depth_write: false,
            srgb_framebuffer: is_srgb(format),
        };
        let renderer = EguiRenderer::with_gpu_allocator(allocator, raw.device.clone(), mode, options)
            .map_err(|e| anyhow::anyhow!("creating the overlay's renderer: {e}"))?;
        let info = vk::CommandPoolCreateInfo::default()
            .queue_family_index(raw.queue_family)
            .flags(vk::CommandPoolCreateFlags::TRANSIENT);
        // SAFETY: a valid device and create info; the pool is destroyed in Drop, before the
        // Gpu (the app drops the overlay first).
        let command_pool = unsafe { raw.device.create_command_pool(&info, None) }?;
        let ctx = egui::Context::default();
        let state = egui_winit::State::new(ctx.clone(), egui::ViewportId::ROOT, window, None, None, None);
        Ok(Overlay {
            ctx,
            state,
            renderer: RefCell::new(renderer),
            device: raw.device.clone(),
            queue: raw.queue,
            command_pool,
            format,
            primitives: Vec::new(),
            pixels_per_point: 1.0,
            to_free: Vec::new(),
        })
    }

    /// Gives egui a window event; true when egui used it (the pointer is over the overlay).
    pub fn on_event(&mut self, window: &Window, event: &winit::event::WindowEvent) -> bool {
        self.state.on_window_event(window, event).consumed
    }

    /// Whether egui wants the pointer or keyboard (a slider being dragged).
    pub fn wants_input(&self) -> bool {
        self.ctx.egui_wants_pointer_input() || self.ctx.egui_is_using_pointer()
    }

    /// Runs the UI for this frame, uploads the textures it changed, and keeps its triangles
    /// for the frame's overlay pass. `frame` numbers frames, to free textures safely.
    pub fn run(&mut self, window: &Window, frame: u64, mut ui: impl FnMut(&egui::Context)) -> anyhow::Result<()> {
        // Small windows (a CPU device's default) get smaller text, so the overlay leaves room
        // for the image.
        let height = window.inner_size().height as f32;
        self.ctx.set_zoom_factor(if height < 600.0 { 0.8 } else { 1.0 });
        let input = self.state.take_egui_input(window);
        let mut output = self.ctx.run_ui(input, |root| ui(root.ctx()));
        self.state.handle_platform_output(window, output.platform_output);
        let mut renderer = self.renderer.borrow_mut();
        for (id, deltas) in &output.textures_delta.set {
            for delta in deltas {
                // Uploads with its own submission and waits for the queue: rare (font atlas).
                renderer
                    .set_texture(self.queue, self.command_pool, *id, delta)
                    .map_err(|e| anyhow::anyhow!("overlay texture: {e}"))?;
            }
        }
        if !output.textures_delta.free.is_empty() {
            self.to_free.push((frame + 2, output.textures_delta.free.drain().collect()));
        }
        output.textures_delta.set.clear();
        let (ready, later): (Vec<_>, Vec<_>) = self.to_free.drain(..).partition(|(after, _)| *after <= frame);
        self.to_free = later;
        for id in ready.into_iter().flat_map(|(_, ids)| ids) {
            renderer.free_texture(id).map_err(|e| anyhow::anyhow!("overlay texture: {e}"))?;
        }
        self.pixels_per_point = output.pixels_per_point;
        self.primitives = self.ctx.tessellate(output.shapes, output.pixels_per_point);
        Ok(())
    }

    /// Drops the UI's triangles: the next frame shows no overlay (Tab).
    pub fn clear(&mut self) {
        self.primitives.clear();
    }

    /// After a swapchain recreation, in case the format changed.
    pub fn set_format(&mut self, format: vk::Format) -> anyhow::Result<()> {
        if format != self.format {
            let mode = RenderMode::DynamicRendering(DynamicRendering {
                color_attachment_format: format,
                depth_attachment_format: None,
                stencil_attachment_format: None,
            });
            self.renderer.borrow_mut().set_render_mode(mode).map_err(|e| anyhow::anyhow!("overlay: {e}"))?;
            self.format = format;
        }
        Ok(())
    }
}

impl leakless::Overlay for Overlay {
    fn add<'r>(&'r self, graph: &mut Graph<'r>, target: &mut ImageHandle) -> leakless::Result<()> {
        if self.primitives.is_empty() {
            return Ok(());
        }
        let extent = target.extent();
        let mut pass = graph.pass(leakless::passes::names::OVERLAY);
        let out = pass.write(target, Access::ColorAttachmentWrite);
        pass.record(move |ctx| {
            let image = ctx.image(out);
            ctx.cmd.draw_over(image, |raw| {
                self.renderer
                    .borrow_mut()
                    .cmd_draw(raw, extent, self.pixels_per_point, &self.primitives)
                    .map_err(|e| leakless_device::DeviceError::Unsupported(format!("overlay: {e}")))
            })
        });
        Ok(())
    }
}

impl Drop for Overlay {
    fn drop(&mut self) {
        // SAFETY: the app waits for the device to be idle before dropping the overlay; the pool
        // was made from this device.
        unsafe { self.device.destroy_command_pool(self.command_pool, None) };
    }
}
