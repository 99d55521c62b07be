//! The stages of a frame after its G-buffer, in the order `frame.rs` records them: direct
//! light, indirect light (photons or path-traced samples), compose, accumulation. Each is a
//! function over the frame's graph whose inputs and outputs are in its signature; temporal
//! reuse is its state's own (`reuse.rs`), the display and readback `frame.rs`'s end.

use leakless_graph::{BufferHandle, Graph, ImageHandle};

use super::frame::layer;
use super::plan::FramePlan;
use crate::error::Result;
use crate::passes::accumulate::{self, Accumulated, FrameLayers, Means, Sums};
use crate::passes::compose::{self, ComposeImages, ComposeParams};
use crate::passes::direct::{self, DirectParams};
use crate::passes::gather::{self, GatherOutputs};
use crate::passes::reference::{self, ReferenceParams};
use crate::passes::ViewInputs;
use crate::photon_lights::LightHandles;
use crate::settings::{Method, RenderSettings};
use crate::splatting::{self, SplatCounterHandles, SplatFrame};

/// The layers of the image a frame shows and reads back.
pub(super) struct Layers {
    pub direct: ImageHandle,
    pub indirect: ImageHandle,
    pub leaked: ImageHandle,
    pub radiance: ImageHandle,
}

/// What is fixed for all the stages of one frame.
pub(super) struct FrameStage<'a> {
    pub plan: &'a FramePlan,
    pub settings: &'a RenderSettings,
    pub method: Method,
    pub seed: u32,
    pub extent: ash::vk::Extent2D,
}

impl FrameStage<'_> {
    /// The reference's first sample this frame: progressive, frame `index` restarts the sum
    /// and continues the sequence.
    fn first_sample(&self, accumulated_before: u32) -> u32 {
        let p = self.plan;
        if p.progressive {
            p.first_batch.wrapping_mul(self.settings.spp)
        } else if p.first {
            0
        } else {
            accumulated_before
        }
    }
}

/// Direct light into `direct`. The emitters' direct light grows with the frame's work as the
/// indirect light does: `light_samples` per photon batch, or per REFERENCE_SAMPLES_PER_DIRECT
/// samples of a progressive reference frame, continuing one sequence. A reference outside an
/// accumulation adds samples to one image over many frames while its direct layer is each
/// frame's own: a frame that is `seen` (shown or read back) estimates it anew for all the
/// image's samples, and one that is not skips it.
pub(super) fn direct_light<'r>(
    g: &mut Graph<'r>,
    s: &FrameStage<'_>,
    accumulated_before: u32,
    seen: bool,
    view: &ViewInputs<'_>,
    direct: &mut ImageHandle,
) {
    let p = s.plan;
    let per = direct::REFERENCE_SAMPLES_PER_DIRECT;
    let (direct_first, direct_units, direct_needed) = match s.method {
        Method::Reference if p.progressive => {
            (s.first_sample(accumulated_before).div_ceil(per), p.samples.div_ceil(per), true)
        }
        Method::Reference => (0, p.accumulated.div_ceil(per), seen),
        _ => (p.first_batch, p.frame_batches, true),
    };
    let light_samples = s.settings.light_samples;
    let params = DirectParams {
        first_sample: direct_first.wrapping_mul(light_samples),
        samples: direct_units.max(1).saturating_mul(light_samples).min(direct::MAX_SAMPLES),
        candidates: s.settings.light_candidates,
        seed: s.seed,
    };
    if p.render && direct_needed {
        direct::add(g, params, view, direct);
    }
}

/// The indirect light's layers before compose.
pub(super) struct IndirectSums {
    pub indirect_sum: ImageHandle,
    pub reference_sum: ImageHandle,
    pub leaked: ImageHandle,
    pub gather_counts: ImageHandle,
}

/// The counters of the indirect light that the frame copies out.
pub(super) struct IndirectCounters {
    pub gather: BufferHandle,
    /// The photon pass's and the lists' counters, when photons were traced.
    pub splat: Option<SplatCounterHandles>,
}

/// Indirect light: photons splatted and gathered (`splat`), or path-traced samples
/// accumulated (the reference).
pub(super) fn indirect_light<'r>(
    g: &mut Graph<'r>,
    s: &FrameStage<'_>,
    accumulated_before: u32,
    splat: Option<&SplatFrame>,
    view: &ViewInputs<'_>,
    lights: &LightHandles,
) -> Result<(IndirectSums, IndirectCounters)> {
    let mut sums = IndirectSums {
        indirect_sum: layer(g, s.extent, "indirect sum")?,
        reference_sum: layer(g, s.extent, "reference sum")?,
        leaked: layer(g, s.extent, "leaked")?,
        gather_counts: layer(g, s.extent, "gather counts")?,
    };
    let mut counters = IndirectCounters { gather: gather::counters(g)?, splat: None };
    if let Some(splat) = splat {
        let out = GatherOutputs {
            indirect_sum: &mut sums.indirect_sum,
            leaked: &mut sums.leaked,
            counts: &mut sums.gather_counts,
            counters: &mut counters.gather,
        };
        counters.splat = Some(splatting::add(g, splat, view, lights, out)?);
    }
    let p = s.plan;
    if p.render && s.method == Method::Reference {
        let params = ReferenceParams {
            first_sample: s.first_sample(accumulated_before),
            // Progressive frames are whole images; a single reference starts over at its first.
            restart: (p.progressive || p.first) as u32,
            sample_count: p.samples,
            max_bounces: s.settings.max_bounces,
            // The frame's seed, which a capture records (the settings' own outside the app).
            seed: s.seed,
            roulette_start: 3,
            ..Default::default()
        };
        reference::add(g, params, view, &mut sums.reference_sum);
    }
    Ok((sums, counters))
}

/// The layers: radiance = direct + indirect, the indirect sum scaled as the method says
/// (`gathered`: a gather wrote the leaked and count layers). Also gives back the gather's
/// counts, which the candidates' views show.
pub(super) fn compose_layers<'r>(
    g: &mut Graph<'r>,
    s: &FrameStage<'_>,
    frame: &BufferHandle,
    direct: ImageHandle,
    mut sums: IndirectSums,
    gathered: bool,
) -> Result<(Layers, ImageHandle)> {
    let p = s.plan;
    let mut indirect = layer(g, s.extent, "indirect")?;
    let mut radiance = layer(g, s.extent, "radiance")?;
    let (sum, indirect_scale) = match s.method {
        Method::Reference if p.progressive => (&sums.reference_sum, 1.0 / p.samples as f32),
        Method::Reference => (&sums.reference_sum, 1.0 / p.accumulated as f32),
        Method::Splat | Method::LeakLessCapped | Method::LeakLess => (&sums.indirect_sum, 1.0),
        Method::Direct => (&sums.indirect_sum, 0.0),
    };
    let params = ComposeParams { indirect_scale, gathered: gathered as u32, ..Default::default() };
    let images = ComposeImages {
        direct: &direct,
        indirect_sum: sum,
        indirect: &mut indirect,
        radiance: &mut radiance,
        leaked: &mut sums.leaked,
        gather_counts: &mut sums.gather_counts,
    };
    if p.render {
        compose::add(g, params, frame, images);
    }
    Ok((Layers { direct, indirect, leaked: sums.leaked, radiance }, sums.gather_counts))
}

/// Accumulating: the image becomes the mean of the frames so far (kept in the pool by name).
/// A frame that renders nothing new while the image is such a mean (`image_is_mean`) shows
/// that mean again.
pub(super) fn accumulate_layers<'r>(
    g: &mut Graph<'r>,
    s: &FrameStage<'_>,
    frame: &BufferHandle,
    layers: Layers,
    image_is_mean: bool,
) -> Result<Layers> {
    let p = s.plan;
    let mean = |g: &mut Graph<'r>| -> Result<Layers> {
        Ok(Layers {
            direct: layer(g, s.extent, "mean direct")?,
            indirect: layer(g, s.extent, "mean indirect")?,
            leaked: layer(g, s.extent, "mean leaked")?,
            radiance: layer(g, s.extent, "mean radiance")?,
        })
    };
    if p.progressive {
        let mut sum_direct = layer(g, s.extent, "accumulated direct")?;
        let mut sum_indirect = layer(g, s.extent, "accumulated indirect")?;
        let mut sum_leaked = layer(g, s.extent, "accumulated leaked")?;
        let mut means = mean(g)?;
        accumulate::add(
            g,
            Accumulated { frames: p.accumulated, batches: p.batches, frame_batches: p.frame_batches },
            frame,
            FrameLayers { direct: &layers.direct, indirect: &layers.indirect, leaked: &layers.leaked },
            Sums { direct: &mut sum_direct, indirect: &mut sum_indirect, leaked: &mut sum_leaked },
            Means {
                direct: &mut means.direct,
                indirect: &mut means.indirect,
                leaked: &mut means.leaked,
                radiance: &mut means.radiance,
            },
        );
        Ok(means)
    } else if !p.render && image_is_mean {
        mean(g)
    } else {
        Ok(layers)
    }
}
