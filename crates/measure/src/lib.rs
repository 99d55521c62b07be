//! What the benchmarks, charts, the stability report and the tests measure, and how the charts
//! draw it: image metrics and flicker, rays to trace and their tracer, the scenes' measuring
//! extras, and the measuring side of `bench`, `chart` and `stability`. Kept out of the renderer
//! library (`leakless`), which renders and measures nothing of its own images.

pub mod bench;
pub mod chart;
pub mod csv_table;
pub mod extras;
pub mod flicker;
pub mod metrics;
pub mod motion;
pub mod raycast;
pub mod raygen;
pub mod stability;
