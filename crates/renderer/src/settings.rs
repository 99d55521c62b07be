//! What to render and how: the settings every front end (CLI, tests, benchmarks, the app)
//! fills in and the renderer validates.

use crate::error::{RenderError, Result};
pub use crate::splatting::SplatSettings;
use crate::trace::BackendChoice;
use crate::tuning::TuningChoice;

/// What to render and how.
#[derive(Clone, Debug, PartialEq)]
pub struct RenderSettings {
    pub width: u32,
    pub height: u32,
    pub backend: BackendChoice,
    pub method: Method,
    /// Samples per view sample of the reference path tracer.
    pub spp: u32,
    /// Indirect bounces after the view sample (the reference's path depth).
    pub max_bounces: u32,
    /// Seeds every random sequence: a fixed seed gives a bit-identical frame.
    pub seed: u32,
    /// The photon methods' parameters.
    pub splat: SplatSettings,
    /// Photon frames averaged into the image (`--frames`): each traces fresh photons further
    /// along one low-discrepancy sequence, with a gather radius that shrinks as in progressive
    /// photon mapping, and jittered pixel positions. 1: a single frame.
    pub frames: u32,
    /// Photon batches (of `splat.paths` paths each) a frame of an accumulation traces at most:
    /// frame k traces min(2^k, this) of them (`--max-batches`; fewer when the node lists cannot
    /// hold them), so a still view's frames grow and the per-frame work (view samples,
    /// hierarchy, visible disk, direct light) is shared by more photons. 1: every frame traces
    /// `paths` paths.
    pub max_batches: u32,
    /// Which device tuning (`--tuning`): the device's own, or the CPU's or the GPU's preset.
    pub tuning: TuningChoice,
    /// Shadow rays toward emissive triangles per pixel and frame (`--light-samples`).
    pub light_samples: u32,
    /// Candidate emitter points each of those rays is resampled from (`--light-candidates`;
    /// 1: plain next-event estimation by power).
    pub light_candidates: u32,
    /// Temporal reuse of the indirect light (`--reuse`): frames after a change of camera,
    /// light or object start from the frames before, reprojected (docs/architecture.md §1,
    /// "Motion"). A render from scratch has no frames before, so a single image is the same
    /// either way.
    pub reuse: bool,
    /// How the view samples are found (`--primary`): rasterised, or one ray per pixel.
    pub primary: Primary,
}

/// How a frame finds its view samples, the G-buffer (docs/architecture.md §1.1).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Primary {
    /// Rasterised (gbuffer.vert + gbuffer.frag): what a GPU with graphics hardware does fastest.
    #[default]
    Raster,
    /// One closest-hit ray per pixel through its centre (primary_rays.comp), on the frame's
    /// trace backend: its cost follows the pixels, not the triangles, which a CPU driver's
    /// rasteriser pays for whatever the image size.
    Rays,
    /// Rays where the device tuning says they cost less: on a CPU device, a scene of more
    /// triangles than the image has pixels; on a GPU without ray queries, every scene
    /// ([`DeviceTuning::primary_auto`](crate::DeviceTuning)).
    Auto,
}

impl Primary {
    pub const ALL: [Primary; 3] = [Primary::Raster, Primary::Rays, Primary::Auto];

    /// What `--primary` calls it.
    pub fn name(self) -> &'static str {
        match self {
            Primary::Raster => "raster",
            Primary::Rays => "rays",
            Primary::Auto => "auto",
        }
    }
}

crate::value_enum!(Primary);

/// What computes the indirect light (docs/architecture.md §2).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Method {
    /// Direct light only: no indirect layer.
    Direct,
    /// Moreau et al.: hierarchy splat with trivial accept, no visibility (the baseline that
    /// leaks).
    Splat,
    /// The thesis as presented: visibility to every gathered photon, trivial accept off, at
    /// most `cap` photons gathered per pixel.
    LeakLessCapped,
    /// Ours: trivial accept kept, every candidate photon's visibility tested, no cap.
    #[default]
    LeakLess,
    /// Progressive path tracer of the same light transport, `spp` samples.
    Reference,
}

impl Method {
    pub const ALL: [Method; 5] =
        [Method::Direct, Method::Splat, Method::LeakLessCapped, Method::LeakLess, Method::Reference];

    /// What `--method` calls it.
    pub fn name(self) -> &'static str {
        match self {
            Method::Direct => "direct",
            Method::Splat => "splat",
            Method::LeakLessCapped => "leakless-capped",
            Method::LeakLess => "leakless",
            Method::Reference => "reference",
        }
    }

    /// Whether the method traces photons and splats them.
    pub fn splats(self) -> bool {
        matches!(self, Method::Splat | Method::LeakLessCapped | Method::LeakLess)
    }
}

crate::value_enum!(Method);

impl Default for RenderSettings {
    fn default() -> Self {
        RenderSettings {
            width: 640,
            height: 480,
            backend: BackendChoice::Auto,
            method: Method::LeakLess,
            spp: 64,
            max_bounces: 8,
            seed: 0,
            splat: SplatSettings::default(),
            frames: 1,
            max_batches: DEFAULT_MAX_BATCHES,
            tuning: TuningChoice::Auto,
            light_samples: DEFAULT_LIGHT_SAMPLES,
            light_candidates: DEFAULT_LIGHT_CANDIDATES,
            reuse: true,
            primary: Primary::Raster,
        }
    }
}

/// The thesis' per-pixel photon cap.
pub const DEFAULT_CAP: u32 = 25;

/// Emitter sampling of the direct pass: 2 shadow rays a pixel, each resampled from 8 candidate
/// points (arithmetic only, no rays).
pub const DEFAULT_LIGHT_SAMPLES: u32 = 2;
pub const DEFAULT_LIGHT_CANDIDATES: u32 = 8;
pub const MAX_LIGHT_SAMPLES: u32 = 64;
pub const MAX_LIGHT_CANDIDATES: u32 = 256;

/// Upper bounds that keep a typo from asking for hours or gigabytes.
pub const MAX_SPP: u32 = 1 << 20;
pub const MAX_BOUNCES: u32 = 64;
pub const MAX_FRAMES: u32 = 1 << 16;
pub const MAX_BATCHES: u32 = 64;

/// Frames of an accumulation grow to 8 batches: the per-frame work is then under a tenth of a
/// frame on lavapipe (docs/architecture.md §1), and a frame stays a few of the first frame's
/// length, so the view still answers input while it converges.
pub const DEFAULT_MAX_BATCHES: u32 = 8;

/// Most photons a kernel may be asked to hold (`--kernel-photons`): the gather's work per
/// sample grows with it.
pub const MAX_KERNEL_PHOTONS: f32 = 4096.0;

/// Largest image side accepted: bounds memory (a 16k² frame of this renderer's layers would
/// need tens of GiB).
pub const MAX_SIDE: u32 = 8192;

impl RenderSettings {
    pub fn validate(&self) -> Result<()> {
        let bad = |m: String| Err(RenderError::Settings(m));
        if self.width == 0 || self.height == 0 || self.width > MAX_SIDE || self.height > MAX_SIDE {
            return bad(format!("size {}x{} must be within 1..={MAX_SIDE} per side", self.width, self.height));
        }
        if self.spp == 0 || self.spp > MAX_SPP {
            return bad(format!("--spp {} must be within 1..={MAX_SPP}", self.spp));
        }
        if self.light_samples == 0 || self.light_samples > MAX_LIGHT_SAMPLES {
            return bad(format!("--light-samples {} must be within 1..={MAX_LIGHT_SAMPLES}", self.light_samples));
        }
        if self.light_candidates == 0 || self.light_candidates > MAX_LIGHT_CANDIDATES {
            return bad(format!(
                "--light-candidates {} must be within 1..={MAX_LIGHT_CANDIDATES}",
                self.light_candidates
            ));
        }
        if self.splat.paths == 0 {
            // Each photon carries the light's power over the paths traced: none would divide by 0.
            return bad("--paths 0: a photon frame must trace at least one light path".into());
        }
        let k = self.splat.kernel_photons;
        if !(k.is_finite() && (1.0..=MAX_KERNEL_PHOTONS).contains(&k)) {
            return bad(format!("--kernel-photons {k} must be within 1..={MAX_KERNEL_PHOTONS}"));
        }
        if self.splat.cap == Some(0) {
            return bad("--cap 0: a cap must let at least one photon through (omit --cap for the thesis' 25)".into());
        }
        if self.frames == 0 || self.frames > MAX_FRAMES {
            return bad(format!("--frames {} must be within 1..={MAX_FRAMES}", self.frames));
        }
        if self.max_batches == 0 || self.max_batches > MAX_BATCHES {
            return bad(format!("--max-batches {} must be within 1..={MAX_BATCHES}", self.max_batches));
        }
        if self.max_bounces > MAX_BOUNCES {
            return bad(format!("--max-bounces {} must be at most {MAX_BOUNCES}", self.max_bounces));
        }
        Ok(())
    }

    /// What the photon part of the frame does for this method (`None` for methods without
    /// photons): the method fixes visibility, the cap and (for the thesis) trivial accept.
    pub fn photon_settings(&self) -> Option<SplatSettings> {
        let mut s = self.splat.clone();
        match self.method {
            Method::Splat => {
                s.visibility = false;
                s.cap = None;
                s.visible_disk = false;
            }
            Method::LeakLess => {
                s.visibility = true;
                s.cap = None;
            }
            Method::LeakLessCapped => {
                s.visibility = true;
                s.trivial_accept = false;
                s.cap = Some(self.splat.cap.unwrap_or(DEFAULT_CAP));
                s.visible_disk = false; // the thesis' estimator
            }
            Method::Direct | Method::Reference => return None,
        }
        Some(s)
    }

    /// `name=value` pairs for EXR headers and stats.
    pub fn describe(&self) -> String {
        let mut s = format!("size={}x{} method={}", self.width, self.height, self.method.name());
        match self.method {
            Method::Reference => {
                s += &format!(" spp={} max_bounces={} seed={}", self.spp, self.max_bounces, self.seed);
                // A reference of several frames holds `spp` × its batches samples.
                if self.frames > 1 {
                    s += &format!(" frames={} max_batches={}", self.frames, self.max_batches);
                }
            }
            Method::Splat | Method::LeakLessCapped | Method::LeakLess => {
                let p = self.photon_settings().expect("a photon method");
                let radius = p.radius.map_or(format!("auto kernel_photons={}", p.kernel_photons), |r| r.to_string());
                let branching = p.branching.map_or("auto".to_string(), |b| b.to_string());
                s += &format!(
                    " paths={} radius={radius} branching={branching} trivial_accept={} visibility={} max_bounces={} seed={}",
                    p.paths, p.trivial_accept, p.visibility, self.max_bounces, self.seed
                );
                if let Some(cap) = p.cap {
                    s += &format!(" cap={cap}");
                }
                if self.frames > 1 {
                    s += &format!(" frames={} max_batches={}", self.frames, self.max_batches);
                }
            }
            Method::Direct => {}
        }
        // Only where they differ from the defaults, so that existing descriptions stay as they were.
        if (self.light_samples, self.light_candidates) != (DEFAULT_LIGHT_SAMPLES, DEFAULT_LIGHT_CANDIDATES) {
            s += &format!(" light_samples={} light_candidates={}", self.light_samples, self.light_candidates);
        }
        if !self.reuse {
            s += " reuse=off";
        }
        s
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_description_names_what_sets_the_samples_of_an_accumulation() {
        let reference = RenderSettings { method: Method::Reference, spp: 2, ..Default::default() };
        assert!(!reference.describe().contains("frames="), "{}", reference.describe());
        let frames = RenderSettings { frames: 4, max_batches: 2, ..reference };
        assert!(
            frames.describe().ends_with(" spp=2 max_bounces=8 seed=0 frames=4 max_batches=2"),
            "{}",
            frames.describe()
        );
        let photons = RenderSettings { method: Method::LeakLess, frames: 4, ..Default::default() };
        assert!(photons.describe().ends_with(" frames=4 max_batches=8"), "{}", photons.describe());
    }
}
