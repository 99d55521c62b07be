//! The report as Markdown (for people and docs/gpu.md) and JSON (everything, for tools).

use std::fmt::Write as _;
use std::path::Path;

use anyhow::Context;

use super::timing::{find, FrameRow, SHOWN_GROUPS};
use super::Report;

pub fn write(report: &Report, dir: &Path) -> anyhow::Result<()> {
    let json = serde_json::to_string_pretty(report)?;
    std::fs::write(dir.join("gpu-report.json"), json).with_context(|| format!("writing into {}", dir.display()))?;
    std::fs::write(dir.join("gpu-report.md"), markdown(report)?)
        .with_context(|| format!("writing into {}", dir.display()))?;
    Ok(())
}

fn markdown(r: &Report) -> anyhow::Result<String> {
    let mut md = String::new();
    let mode = if r.quick { " (--quick: small sizes, for the test suite)" } else { "" };
    writeln!(md, "# GPU report{mode}\n")?;
    writeln!(md, "Made by `tools/gpu-report` in {:.0} s. The device, as `leakless info` prints it:\n", r.seconds)?;
    writeln!(md, "```\n{}```\n", r.info)?;
    if let Some(line) = summary(r) {
        writeln!(md, "**{line}**\n")?;
    }
    if !r.failures.is_empty() {
        writeln!(md, "## Sections that failed\n")?;
        for f in &r.failures {
            writeln!(md, "* {f}")?;
        }
        writeln!(md)?;
    }
    correctness(&mut md, r)?;
    if !r.frames.is_empty() {
        writeln!(md, "## Frames\n")?;
        writeln!(
            md,
            "Second frame of each, {}; times in ms; `rest` is the frame's time outside the groups shown.\n",
            timing(r)
        )?;
        frame_table(&mut md, &r.frames, false)?;
    }
    if !r.rays.is_empty() {
        writeln!(md, "## Rays\n")?;
        writeln!(
            md,
            "Hits are written to device memory and copied after the timed pass. Nodes and triangles per ray: the compute traversal's work, counted by a pass of its own.\n"
        )?;
        writeln!(
            md,
            "| scene | backend | rays | query | Mrays/s | nodes/ray | triangles/ray |\n|---|---|---|---|---|---|---|"
        )?;
        let per_ray = |v: Option<f64>| v.map_or("–".to_string(), |v| format!("{v:.1}"));
        for x in &r.rays {
            writeln!(
                md,
                "| {} | {} | {} ({}) | {} | {:.1} | {} | {} |",
                x.scene,
                x.backend,
                x.set,
                x.rays,
                x.query,
                x.mrays_per_s,
                per_ray(x.nodes_per_ray),
                per_ray(x.triangles_per_ray)
            )?;
        }
        writeln!(md)?;
    }
    for (title, rows) in [
        ("Branching factor", &r.branching),
        ("View samples rasterised or by rays (`--primary`)", &r.primary),
        ("The device tuning's choices, one at a time", &r.tuning_sweep),
    ] {
        if !rows.is_empty() {
            writeln!(md, "## {title}\n")?;
            frame_table(&mut md, rows, true)?;
        }
    }
    Ok(md)
}

fn timing(r: &Report) -> &'static str {
    let timing = r.tuning.as_ref().map_or(leakless_graph::Timing::PerPassSubmit, |t| t.timing);
    leakless_measure::bench::timing_words(timing)
}

/// The line the README quotes: the 1080p leakless frame against splat and Moreau et al.
fn summary(r: &Report) -> Option<String> {
    let scene = r.frames.first()?.scene.clone();
    let (size, paths) = ((1920, 1080), 200_000);
    let leakless = find(&r.frames, &scene, size, "leakless", paths)?;
    let splat = find(&r.frames, &scene, size, "splat", paths)?;
    Some(format!(
        "1920×1080, {paths} paths, {scene}: leakless {:.1} ms, splat {:.1} ms ({:.2}×); Moreau et al. 2016 \
         (Titan X, 200k photons, 1080p, no leak removal): splat 14–17 ms, frame 33–48 ms",
        leakless.frame_ms,
        splat.frame_ms,
        leakless.frame_ms / splat.frame_ms
    ))
}

fn correctness(md: &mut String, r: &Report) -> anyhow::Result<()> {
    if r.correctness.is_empty() {
        return Ok(());
    }
    let validation = if r.validation { "on" } else { "requested, but the layers are not installed" };
    writeln!(md, "## Correctness\n")?;
    writeln!(
        md,
        "`leakless` at 64×48, 10k paths, seed 0, validation {validation}, against the same render on lavapipe's \
         compute backend (`tests/fixtures/gpu-report/`). A render matches when its relMSE without the worst 0.5% of \
         the pixels (primary rays that graze an edge may land on the other surface) is at most half another seed's, \
         and its mean is within 2%. `off`: pixels more than 5% off.\n"
    )?;
    writeln!(md, "| scene | backend | relMSE | all pixels | off | another seed's | mean ratio | verdict |\n|---|---|---|---|---|---|---|---|")?;
    for c in &r.correctness {
        let mark = if c.passed { "" } else { "**FAILED**: " };
        writeln!(
            md,
            "| {} | {} | {} | {} | {} | {} | {} | {mark}{} |",
            c.scene,
            c.backend,
            number(c.rel_mse, |x| format!("{x:.2e}")),
            number(c.rel_mse_all, |x| format!("{x:.2e}")),
            c.pixels_off,
            number(c.other_seed_rel_mse, |x| format!("{x:.2e}")),
            number(c.mean_ratio, |x| format!("{x:.4}")),
            c.verdict
        )?;
    }
    writeln!(md)?;
    Ok(())
}

/// `x` formatted, or a dash where it is undefined (the relMSE of a black image).
fn number(x: f64, f: impl Fn(f64) -> String) -> String {
    if x.is_finite() {
        f(x)
    } else {
        "–".into()
    }
}

fn frame_table(md: &mut String, rows: &[FrameRow], sweep: bool) -> anyhow::Result<()> {
    let first = if sweep { "variant" } else { "scene | size | method | paths" };
    write!(md, "| {first} | frame |")?;
    for g in SHOWN_GROUPS {
        write!(md, " {g} |")?;
    }
    writeln!(md, " rest | photons | list entries | candidates | most a sample | vis. rays | proven clear |")?;
    let columns = first.matches('|').count() + 1 + 1 + SHOWN_GROUPS.len() + 7;
    writeln!(md, "|{}", "---|".repeat(columns))?;
    for x in rows {
        if sweep {
            write!(md, "| {} ", x.variant)?;
        } else {
            write!(md, "| {} | {}×{} | {} | {} ", x.scene, x.width, x.height, x.method, x.paths)?;
        }
        write!(md, "| {:.2} |", x.frame_ms)?;
        let mut shown = 0.0;
        for g in SHOWN_GROUPS {
            let ms = x.groups.iter().find(|(name, _)| name == g).map_or(0.0, |(_, ms)| *ms);
            shown += ms;
            write!(md, " {ms:.2} |")?;
        }
        writeln!(
            md,
            " {:.2} | {} | {} | {} | {} | {} | {} |",
            (x.frame_ms - shown).max(0.0),
            x.photons_stored,
            x.list_entries,
            x.candidate_tests,
            x.candidates_most,
            x.visibility_rays,
            x.proven_clear
        )?;
    }
    writeln!(md)?;
    Ok(())
}
