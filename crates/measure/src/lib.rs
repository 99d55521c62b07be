//! What the benchmarks, charts, the stability report and the tests measure, and how the charts
//! draw it: image metrics and flicker, rays to trace and their tracer, a stand-alone photon
//! tracer, the scenes' measuring extras, and the measuring side of `bench`, `chart` and
//! `stability`. Kept out of the renderer library (`leakless`): it renders, this crate judges
//! what it renders.

pub mod bench;
pub mod chart;
pub mod csv_table;
pub mod extras;
pub mod flicker;
pub mod metrics;
pub mod motion;
pub mod photon_tracer;
pub mod raycast;
pub mod raygen;
pub mod stability;
