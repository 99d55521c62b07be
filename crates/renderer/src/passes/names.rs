//! The parts of a frame a pass's time counts under, and the names of the passes that are no
//! compute pass's own (the raster, display and copy passes several files add). A compute pass
//! names itself in its `ComputePassDef` (`PassName::new(label, group::…)`); the benchmarks,
//! the stats and the app's panel sum times by these groups (`PassTiming::group`).

use leakless_graph::PassName;

/// The parts of a frame, in frame order.
pub mod group {
    /// Rasterising the view samples.
    pub const VIEW: &str = "gbuffer";
    /// Moving animated instances (vertices, the TLAS).
    pub const SCENE: &str = "scene";
    pub const DIRECT: &str = "direct";
    /// Tracing the photons, with the passes that order their paths and count them.
    pub const PHOTONS: &str = "photons";
    /// Copying the photons in the order of a grid's cells.
    pub const PHOTON_ORDER: &str = "photon order";
    /// Each sample's visible share of its gather disk.
    pub const VISIBLE_DISK: &str = "visible disk";
    /// Rebuilding the view-sample hierarchy: bounds, Morton codes, the sort, the levels.
    pub const HIERARCHY: &str = "hierarchy";
    pub const SPLAT: &str = "splat";
    /// The distance each photon is clear of geometry.
    pub const CLEARANCE: &str = "photon clearance";
    /// The distance each view sample is clear of geometry.
    pub const SAMPLE_CLEARANCE: &str = "sample clearance";
    pub const GATHER: &str = "gather";
    pub const REFERENCE: &str = "reference";
    /// Direct + indirect, and the running mean of an accumulation.
    pub const COMPOSE: &str = "compose";
    /// Temporal and spatial reuse of the indirect light across frames and pixels.
    pub const REUSE: &str = "reuse";
    pub const LUMINANCE: &str = "luminance";
    /// The tonemap, the app's overlay and the hand-over to the window.
    pub const DISPLAY: &str = "display";
    /// Copies for the host: layers, counters, captures.
    pub const COPIES: &str = "copies";
    /// Passes of tools and tests (`bench rays`, fault injection).
    pub const TOOLS: &str = "tools";
}

pub const GBUFFER: PassName = PassName::new("gbuffer", group::VIEW);
pub const INSTANCE_VERTICES: PassName = PassName::new("instance vertices", group::SCENE);

pub const TONEMAP: PassName = PassName::new("tonemap", group::DISPLAY);
pub const OVERLAY: PassName = PassName::new("overlay", group::DISPLAY);
pub const PRESENT: PassName = PassName::new("present", group::DISPLAY);

pub const READBACK: PassName = PassName::new("readback", group::COPIES);
pub const TO_HOST: PassName = PassName::new("to host", group::COPIES);
pub const FRAME_COUNTERS: PassName = PassName::new("frame counters", group::COPIES);
pub const STATS_TO_HOST: PassName = PassName::new("stats to host", group::COPIES);
pub const CAPTURE_COPY: PassName = PassName::new("capture copy", group::COPIES);
pub const CAPTURE_TO_HOST: PassName = PassName::new("capture to host", group::COPIES);
