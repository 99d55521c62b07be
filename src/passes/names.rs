//! Every pass of a frame by name, and the part of the frame its time counts under: the graph
//! labels passes with these, and the benchmarks, the stats and the app's panel sum their times
//! by the same groups (`FrameReport::timings`, `bench::Measured::group_ms`).

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
    pub const GATHER: &str = "gather";
    pub const REFERENCE: &str = "reference";
    /// Direct + indirect, and the running mean of an accumulation.
    pub const COMPOSE: &str = "compose";
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
pub const DIRECT: PassName = PassName::new("direct", group::DIRECT);

pub const PHOTON_COUNTERS: PassName = PassName::new("photon counters", group::PHOTONS);
pub const EMISSION_CELLS_CLEAR: PassName = PassName::new("emission cells clear", group::PHOTONS);
pub const EMISSION_CELLS: PassName = PassName::new("emission cells", group::PHOTONS);
pub const EMISSION_CELL_STARTS: PassName = PassName::new("emission cell starts", group::PHOTONS);
pub const EMISSION_ORDER: PassName = PassName::new("emission order", group::PHOTONS);
pub const PHOTONS: PassName = PassName::new("photons", group::PHOTONS);
pub const PHOTON_DISPATCH: PassName = PassName::new("photon dispatch", group::PHOTONS);

pub const PHOTON_CELLS_CLEAR: PassName = PassName::new("photon cells clear", group::PHOTON_ORDER);
pub const PHOTON_CELLS: PassName = PassName::new("photon cells", group::PHOTON_ORDER);
pub const PHOTON_CELL_STARTS: PassName = PassName::new("photon cell starts", group::PHOTON_ORDER);
pub const PHOTON_ORDER: PassName = PassName::new("photon order", group::PHOTON_ORDER);

pub const VISIBLE_DISK: PassName = PassName::new("visible disk", group::VISIBLE_DISK);

pub const SAMPLE_BOUNDS_CLEAR: PassName = PassName::new("sample bounds clear", group::HIERARCHY);
pub const SAMPLE_BOUNDS: PassName = PassName::new("sample bounds", group::HIERARCHY);
pub const MORTON: PassName = PassName::new("morton", group::HIERARCHY);
/// Numbered by digit.
pub const SORT_HISTOGRAM: PassName = PassName::new("sort histogram", group::HIERARCHY);
/// Numbered by digit.
pub const SORT_SCAN: PassName = PassName::new("sort scan", group::HIERARCHY);
/// Numbered by digit.
pub const SORT_SCATTER: PassName = PassName::new("sort scatter", group::HIERARCHY);
pub const SORT_COPY: PassName = PassName::new("sort copy", group::HIERARCHY);
/// Numbered by level.
pub const HIERARCHY_LEVEL: PassName = PassName::new("hierarchy level", group::HIERARCHY);

pub const SPLAT_CLEAR: PassName = PassName::new("splat clear", group::SPLAT);
pub const SPLAT: PassName = PassName::new("splat", group::SPLAT);
pub const PHOTON_CLEARANCE: PassName = PassName::new("photon clearance", group::CLEARANCE);
pub const GATHER_CLEAR: PassName = PassName::new("gather clear", group::GATHER);
pub const GATHER: PassName = PassName::new("gather", group::GATHER);

pub const REFERENCE: PassName = PassName::new("reference", group::REFERENCE);
pub const COMPOSE: PassName = PassName::new("compose", group::COMPOSE);
pub const ACCUMULATE: PassName = PassName::new("accumulate", group::COMPOSE);
pub const LUMINANCE_TILES: PassName = PassName::new("luminance tiles", group::LUMINANCE);
pub const LUMINANCE_TOTAL: PassName = PassName::new("luminance total", group::LUMINANCE);

pub const TONEMAP: PassName = PassName::new("tonemap", group::DISPLAY);
pub const OVERLAY: PassName = PassName::new("overlay", group::DISPLAY);
pub const PRESENT: PassName = PassName::new("present", group::DISPLAY);

pub const READBACK: PassName = PassName::new("readback", group::COPIES);
pub const TO_HOST: PassName = PassName::new("to host", group::COPIES);
pub const FRAME_COUNTERS: PassName = PassName::new("frame counters", group::COPIES);
pub const STATS_TO_HOST: PassName = PassName::new("stats to host", group::COPIES);
pub const CAPTURE_COPY: PassName = PassName::new("capture copy", group::COPIES);
pub const CAPTURE_TO_HOST: PassName = PassName::new("capture to host", group::COPIES);

pub const RAYCAST: PassName = PassName::new("raycast", group::TOOLS);
/// Fault injection's spin (passes/hang.rs), recorded inside the pass it stalls.
pub const HANG: PassName = PassName::new("hang", group::TOOLS);
