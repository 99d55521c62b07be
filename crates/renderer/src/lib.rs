//! leakless: real-time diffuse global illumination by photon splatting, without light leaks.
//!
//! The frame, top to bottom, is `renderer/frame.rs`; docs/architecture.md walks through it.
//! Each pass lives in `passes/`, one file per pass, next to its shader in `shaders-glsl/`.

pub mod device_address;
pub mod emitters;
pub mod error;
pub mod frame_budget;
pub mod frame_set;
pub mod gpu_scene;
pub mod gpu_types;
pub mod limits;
pub mod output;
pub mod passes;
pub mod photon_lights;
pub mod pipelines;
pub mod renderer;
pub mod scene_pose;
pub mod settings;
pub mod shaders;
pub mod splatting;
pub mod stderr_log;
pub mod trace;
pub mod tuning;

pub use error::{RenderError, Result};

/// Lets clap parse, list and complete an option's enum from its `ALL` and `name()`, so the
/// names are written once, in `name()`.
macro_rules! value_enum {
    ($t:ty) => {
        impl clap::ValueEnum for $t {
            fn value_variants<'a>() -> &'a [Self] {
                &Self::ALL
            }
            fn to_possible_value(&self) -> Option<clap::builder::PossibleValue> {
                Some(clap::builder::PossibleValue::new(self.name()))
            }
        }
    };
}
pub use leakless_device::{Gpu, GpuOptions};
pub use leakless_scene::Scene;
pub use passes::tonemap::ViewLayer;
pub use renderer::{Capture, DisplayTarget, FrameReport, Overlay, RenderedFrame, Renderer};
pub use settings::{Method, Primary, RenderSettings, SplatSettings};
pub use trace::{Backend, BackendChoice, ResolvedBackend};
pub use tuning::{DeviceTuning, PrimaryAuto, TuningChoice};
pub(crate) use value_enum;
