//! Running and checking one case: the verdict on a load, the runner, the fuzz test's settings.

use std::path::{Path, PathBuf};
use std::sync::mpsc;
use std::time::{Duration, Instant};

use leakless_scene::{Scene, SceneError};

use crate::budget::{ALLOC_CAP, METER, OVER_CAP_NOTE};
use crate::corpus::{failures_dir, repo, Case};

pub(crate) enum Verdict {
    /// Loaded, or refused with a proper error; the label names which (for the
    /// statistics).
    Clean(&'static str, String),
    Failed(String),
}

/// The promises of `Scene::load` about a loaded scene.
pub(crate) fn check_scene(s: &Scene) -> Result<(), String> {
    let finite = |xs: &[f32]| xs.iter().all(|x| x.is_finite());
    if s.vertices.is_empty() || s.vertices.len() % 3 != 0 {
        return Err(format!("{} vertices: not a non-empty triangle list", s.vertices.len()));
    }
    for (i, v) in s.vertices.iter().enumerate() {
        if !finite(&v.position) || !finite(&v.normal) || !finite(&v.uv) {
            return Err(format!("vertex {i} is not finite: {v:?}"));
        }
        let len = glam::Vec3::from(v.normal).length();
        if (len - 1.0).abs() > 1e-3 {
            return Err(format!("vertex {i} normal has length {len}"));
        }
    }
    if s.triangle_material.len() != s.triangle_count() {
        return Err(format!("{} triangle materials for {} triangles", s.triangle_material.len(), s.triangle_count()));
    }
    if s.materials.is_empty() {
        return Err("no materials".into());
    }
    if let Some(&m) = s.triangle_material.iter().find(|&&m| m as usize >= s.materials.len()) {
        return Err(format!("triangle material {m} out of {}", s.materials.len()));
    }
    for (i, m) in s.materials.iter().enumerate() {
        if !m.base_color.is_finite() {
            return Err(format!("material {i} has a non-finite base colour {}", m.base_color));
        }
        if m.alpha_cutoff.is_some_and(f32::is_nan) {
            return Err(format!("material {i} has a NaN alpha cutoff {:?}", m.alpha_cutoff));
        }
        if m.texture.is_some_and(|t| t as usize >= s.textures.len()) {
            return Err(format!("material {i} texture {:?} out of {}", m.texture, s.textures.len()));
        }
        if !(m.emission.is_finite() && m.emission.min_element() >= 0.0) {
            return Err(format!("material {i} has emission {}", m.emission));
        }
        if m.emission_texture.is_some_and(|t| t as usize >= s.textures.len()) {
            return Err(format!("material {i} emissive texture {:?} out of {}", m.emission_texture, s.textures.len()));
        }
    }
    for (i, t) in s.textures.iter().enumerate() {
        if t.texels.len() as u64 != u64::from(t.width) * u64::from(t.height) || t.texels.is_empty() {
            return Err(format!("texture {i}: {} texels for {}x{}", t.texels.len(), t.width, t.height));
        }
    }
    if s.lights.is_empty() && !s.triangle_material.iter().any(|&m| s.materials[m as usize].emits()) {
        return Err("no lights".into());
    }
    for l in &s.lights {
        let ok = l.position.is_finite()
            && l.direction.is_finite()
            && (l.direction.length() - 1.0).abs() < 1e-3
            && l.color.is_finite()
            && l.intensity.is_finite()
            && l.range.is_none_or(f32::is_finite);
        if !ok {
            return Err(format!("light is not finite: {l:?}"));
        }
    }
    if let Some(c) = &s.camera {
        if !(c.world_from_camera.is_finite()
            && c.yfov.is_finite()
            && c.yfov > 0.0
            && c.znear.is_finite()
            && c.znear > 0.0)
        {
            return Err(format!("camera is not usable: {c:?}"));
        }
    }
    for w in &s.warnings {
        if w.is_empty() || w.contains(['\n', '\r']) {
            return Err(format!("warning is not one line: {w:?}"));
        }
    }
    Ok(())
}

/// An animated scene posed at its start, middle and end, and at times outside its
/// range, keeps the same promises (the poses are what a renderer draws).
fn check_animation(s: &Scene) -> Result<(), String> {
    if !s.is_animated() {
        return Ok(());
    }
    let d = s.duration();
    if !(d.is_finite() && d >= 0.0) {
        return Err(format!("animation duration {d}"));
    }
    for t in [0.0, 0.5 * d, d, -1.0, d + 1.0, 1e30] {
        let posed = s.frozen_at(t);
        check_scene(&posed).map_err(|e| format!("posed at t = {t}: {e}"))?;
        if posed.triangle_count() != s.triangle_count() {
            return Err(format!(
                "posed at t = {t}: {} triangles, {} at load",
                posed.triangle_count(),
                s.triangle_count()
            ));
        }
    }
    Ok(())
}

pub(crate) fn verdict(r: std::thread::Result<Result<Scene, SceneError>>) -> Verdict {
    match r {
        Err(payload) => {
            let msg = payload
                .downcast_ref::<&str>()
                .map(|s| s.to_string())
                .or_else(|| payload.downcast_ref::<String>().cloned())
                .unwrap_or_else(|| "(non-string payload)".into());
            Verdict::Failed(format!("panic: {msg}"))
        }
        Ok(Ok(scene)) => match check_scene(&scene).and_then(|()| check_animation(&scene)) {
            Ok(()) => Verdict::Clean("loaded", String::new()),
            Err(e) => Verdict::Failed(format!("loaded a bad scene: {e}")),
        },
        Ok(Err(e)) => {
            let s = e.to_string();
            if s.is_empty() || s.contains(['\n', '\r']) {
                return Verdict::Failed(format!("error is not one line: {s:?}"));
            }
            // The variant's name, for the statistics.
            let debug = format!("{e:?}");
            let name = debug.split([' ', '{', '(']).next().unwrap_or("");
            let kind = match name {
                "NotFound" => "NotFound",
                "Read" => "Read",
                "Malformed" => "Malformed",
                "Unsupported" => "Unsupported",
                "Buffer" => "Buffer",
                "Image" => "Image",
                "NoLight" => "NoLight",
                "NoTriangles" => "NoTriangles",
                "NonFinitePosition" => "NonFinitePosition",
                _ => "other error",
            };
            Verdict::Clean(kind, s)
        }
    }
}

pub(crate) struct Outcome {
    pub(crate) verdict: Verdict,
    pub(crate) elapsed: Duration,
    pub(crate) peak: usize,
}

/// Where a case runs: its own directory, in a per-process directory under
/// `target/fuzz-failures` so that a case that kills the process (an allocation
/// refused over the cap, a stack overflow) leaves its input where failures go.
pub(crate) struct Runner {
    pub(crate) work: PathBuf,
    pub(crate) seed: u64,
    pub(crate) limit: Duration,
}

/// A case that did not return in time: the thread is left running, so fuzzing
/// stops.
pub(crate) struct Hung;

impl Runner {
    fn case_dir(&self, id: u64) -> PathBuf {
        self.work.join(format!("case-{id}"))
    }

    pub(crate) fn run(&self, case: &Case) -> Result<Outcome, Hung> {
        let dir = self.case_dir(case.id);
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).expect("create case directory");
        for (name, bytes) in &case.files {
            std::fs::write(dir.join(name), bytes).expect("write case file");
        }
        *OVER_CAP_NOTE.lock().unwrap() =
            format!("Case {} (seed {}): {}. Its input is left in {}.", case.id, self.seed, case.recipe, dir.display());
        let path = dir.join(&case.files[0].0);
        let (tx, rx) = mpsc::channel();
        let start = Instant::now();
        std::thread::Builder::new()
            .name(format!("fuzz case {}", case.id))
            .spawn(move || {
                METER.with(|m| {
                    m.live.set(0);
                    m.peak.set(0);
                    m.refused.set(0);
                    m.armed.set(true);
                });
                let r = std::panic::catch_unwind(|| Scene::load(&path));
                let mut v = verdict(r);
                let (peak, refused) = METER.with(|m| {
                    m.armed.set(false);
                    (m.peak.get(), m.refused.get())
                });
                if refused > 0 {
                    v = Verdict::Failed(format!("asked for {refused} bytes over the {ALLOC_CAP}-byte cap"));
                }
                let _ = tx.send((v, peak));
            })
            .expect("spawn case thread");
        match rx.recv_timeout(self.limit) {
            Ok((verdict, peak)) => {
                let elapsed = start.elapsed();
                let verdict = match verdict {
                    Verdict::Clean(..) if elapsed > self.limit => Verdict::Failed(format!(
                        "took {:.2} s (limit {:.0} s)",
                        elapsed.as_secs_f64(),
                        self.limit.as_secs_f64()
                    )),
                    v => v,
                };
                let _ = std::fs::remove_dir_all(&dir);
                Ok(Outcome { verdict, elapsed, peak })
            }
            Err(_) => Err(Hung),
        }
    }

    /// Reports a failure: saves the case ([`Runner::save`]), says so on stderr and returns the
    /// line the test's verdict lists.
    pub(crate) fn report(&self, case: &Case, why: &str) -> String {
        let saved = self.save(case, why);
        eprintln!("fuzz: FAILURE {why}\n      input saved to {}\n      recipe: {}", saved.display(), case.recipe);
        format!("{why} ({})", saved.display())
    }

    /// Copies case `id`'s directory to `target/fuzz-failures/seed<S>-case<N>` with
    /// a note of what happened, and returns that path.
    fn save(&self, case: &Case, why: &str) -> PathBuf {
        let out = failures_dir().join(format!("seed{}-case{}", self.seed, case.id));
        let _ = std::fs::remove_dir_all(&out);
        let _ = std::fs::create_dir_all(&out);
        for (name, bytes) in &case.files {
            let _ = std::fs::write(out.join(name), bytes);
        }
        let note = format!(
            "{why}\ninput: {}\nrecipe: {}\nreplay: LEAKLESS_FUZZ_REPLAY={} cargo test -p leakless-scene --test fuzz -- --nocapture\n",
            case.files[0].0,
            case.recipe,
            out.display()
        );
        let _ = std::fs::write(out.join("WHY.txt"), note);
        out
    }
}

pub(crate) fn env_u64(name: &str) -> Option<u64> {
    let v = std::env::var(name).ok()?;
    Some(v.trim().parse().unwrap_or_else(|_| panic!("{name}={v:?} is not a non-negative integer")))
}

/// Per-case wall-time limit: a few milliseconds is typical and the slowest case (a mutated
/// basilica, 210k triangles) about 1.3 s in a debug build (the test prints it), so only a hang
/// or a run-away load (super-linear in the file's size) reaches it, not a busy machine: the
/// test must pass beside another job.
/// Unoptimized builds (the CI's `cargo test`) get more room.
pub(crate) fn case_limit() -> Duration {
    let default = if cfg!(debug_assertions) { 30 } else { 10 };
    Duration::from_secs(env_u64("LEAKLESS_FUZZ_CASE_SECONDS").unwrap_or(default))
}

/// The scene file of a saved failure (a directory) or the file itself.
pub(crate) fn replay_target(p: &Path) -> PathBuf {
    // `cargo test` runs in the crate's directory; a path may be relative to the
    // workspace instead.
    let joined = repo().join(p);
    let p = if p.exists() || !joined.exists() { p } else { joined.as_path() };
    if p.is_dir() {
        for name in ["scene.gltf", "scene.glb"] {
            if p.join(name).exists() {
                return p.join(name);
            }
        }
    }
    p.to_path_buf()
}
