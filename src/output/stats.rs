//! `--stats FILE.json`: what the frame cost and what it counted.

use std::path::Path;

use serde::Serialize;

use crate::error::{RenderError, Result};

#[derive(Clone, Debug, Serialize)]
pub struct PassTime {
    pub pass: String,
    /// GPU timestamp difference around the pass.
    pub gpu_ms: f64,
    /// Host time of the pass's own submission (`--timing per-pass` only).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub wall_ms: Option<f64>,
}

#[derive(Clone, Debug, Serialize)]
pub struct Stats {
    pub scene: String,
    pub device: String,
    pub driver: String,
    pub backend: String,
    pub width: u32,
    pub height: u32,
    pub triangles: usize,
    pub lights: usize,
    pub passes: Vec<PassTime>,
    pub frame_gpu_ms: f64,
    /// Host wall-clock time of the whole frame (submission to completion).
    pub frame_wall_ms: f64,
}

pub fn write(path: &Path, stats: &Stats) -> Result<()> {
    let json = serde_json::to_string_pretty(stats).expect("stats serialise");
    std::fs::write(path, json + "\n").map_err(|e| RenderError::Output {
        path: path.display().to_string(),
        message: e.to_string(),
    })
}
