//! The line the app prints on exit: frames, frame times, and resident memory (peak, at frame
//! 100, at the last frame), which the soak test reads to catch leaks; and, while anything
//! moved, the moving frames' times (the interval between them, and the frame budget's own
//! measure), median and 95th percentile.

use std::time::Instant;

use leakless_measure::csv_table::CsvTable;

/// Resident set size and its peak, in bytes (Linux `/proc/self/status`; `None` elsewhere).
pub fn rss() -> Option<(u64, u64)> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let field = |name: &str| {
        status
            .lines()
            .find(|l| l.starts_with(name))
            .and_then(|l| l.split_whitespace().nth(1).and_then(|kb| kb.parse::<u64>().ok()).map(|kb| kb * 1024))
    };
    Some((field("VmRSS:")?, field("VmHWM:")?))
}

#[derive(Default)]
pub struct Summary {
    frames: u64,
    total_ms: f64,
    max_ms: f64,
    last: Option<Instant>,
    rss_at_100: Option<u64>,
    /// At the last frame shown (before the window and device are torn down).
    rss_last: Option<u64>,
    /// Host intervals ending at a frame that started an accumulation (a moving frame).
    moving_ms: Vec<f64>,
    /// The frame budget's measure of the frames whose paths it chose (its first, which
    /// compiled the pipelines, left out).
    budgeted_ms: Vec<f64>,
    /// Every budgeted frame's report and render size (`view --frame-log`).
    budget_frames: Vec<(leakless::renderer::BudgetReport, (u32, u32))>,
}

impl Summary {
    /// Counts a frame that was shown (the time since the previous one); `moving`: it started
    /// an accumulation.
    pub fn frame(&mut self, moving: bool) {
        let now = Instant::now();
        if let Some(last) = self.last {
            let ms = (now - last).as_secs_f64() * 1e3;
            self.total_ms += ms;
            self.max_ms = self.max_ms.max(ms);
            if moving {
                self.moving_ms.push(ms);
            }
        }
        self.last = Some(now);
        self.frames += 1;
        self.rss_last = rss().map(|(now, _)| now);
        if self.frames == 100 {
            self.rss_at_100 = self.rss_last;
        }
    }

    /// A budgeted frame of render size `size` completed.
    pub fn budgeted(&mut self, report: leakless::renderer::BudgetReport, size: (u32, u32)) {
        if !report.warm_up {
            self.budgeted_ms.push(report.measured_ms);
        }
        self.budget_frames.push((report, size));
    }

    /// The budgeted frames, one row each.
    pub fn budget_log(&self) -> anyhow::Result<CsvTable> {
        let mut table = CsvTable::new(&[
            "frame",
            "measured_ms",
            "target_ms",
            "paths",
            "next_paths",
            "width",
            "height",
            "over_budget",
            "warm_up",
            "photon_share",
            "fixed_ms",
            "split_only",
        ]);
        for (i, (b, (w, h))) in self.budget_frames.iter().enumerate() {
            let row = [
                i.to_string(),
                format!("{:.3}", b.measured_ms),
                b.target_ms.to_string(),
                b.paths.to_string(),
                b.next_paths.to_string(),
                w.to_string(),
                h.to_string(),
                b.over_budget.to_string(),
                b.warm_up.to_string(),
                b.photon_share.map_or(String::new(), |s| format!("{s:.3}")),
                format!("{:.3}", b.fixed_ms),
                b.split_only.to_string(),
            ];
            table.row(row)?;
        }
        Ok(table)
    }

    pub fn frames(&self) -> u64 {
        self.frames
    }

    /// Mean ms per frame so far.
    pub fn mean_ms(&self) -> f64 {
        if self.frames > 1 {
            self.total_ms / (self.frames - 1) as f64
        } else {
            0.0
        }
    }

    pub fn line(&self) -> String {
        let mib = |b: Option<u64>| b.map_or("n/a".to_string(), |b| format!("{:.1} MiB", b as f64 / 1048576.0));
        let peak = rss().map(|(_, peak)| peak);
        format!(
            "frames {}, mean {:.1} ms, max {:.1} ms, peak RSS {}, RSS at frame 100 {}, RSS at end {}",
            self.frames,
            self.mean_ms(),
            self.max_ms,
            mib(peak),
            mib(self.rss_at_100),
            mib(self.rss_last)
        ) + &moving_line("moving frames", &self.moving_ms)
            + &moving_line("budgeted frames (the budget's measure)", &self.budgeted_ms)
    }
}

/// "; NAME N: median X ms, p95 Y ms" (the 95th percentile by the nearest rank), or nothing.
fn moving_line(name: &str, ms: &[f64]) -> String {
    if ms.is_empty() {
        return String::new();
    }
    let mut v = ms.to_vec();
    v.sort_by(f64::total_cmp);
    let p95 = v[((0.95 * v.len() as f64).ceil() as usize).clamp(1, v.len()) - 1];
    format!("; {name} {}: median {:.1} ms, p95 {:.1} ms", v.len(), v[v.len() / 2], p95)
}
