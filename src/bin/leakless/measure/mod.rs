//! What the benchmarks, charts and the stability report measure and how they draw it: the
//! measuring side of the CLI (`bench`, `chart`, `stability`), kept out of the renderer library.

pub mod bench;
pub mod chart;
pub mod csv_table;
pub mod motion;
pub mod stability;
