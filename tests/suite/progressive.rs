//! Progressive accumulation of photon frames (`--frames N`): it converges to the closed form
//! on the sphere, its error against the reference falls with N, and a reset gives the single
//! frame back bit for bit.

use crate::common;

use std::f64::consts::PI;

use leakless::{Method, RenderSettings, RenderedFrame, Renderer, SplatSettings};
use leakless_measure::metrics;

fn settings(width: u32, height: u32, paths: u32, radius: f32, max_bounces: u32, frames: u32) -> RenderSettings {
    RenderSettings {
        width,
        height,
        method: Method::LeakLess,
        max_bounces,
        seed: 2,
        frames,
        splat: SplatSettings { paths, radius: Some(radius), ..Default::default() },
        ..Default::default()
    }
}

fn renderer(path: &str, s: RenderSettings) -> Option<Renderer> {
    let gpu = common::gpu_with(s.backend.wants_ray_queries())?;
    Some(Renderer::new(gpu, &common::scene(path), s).expect("renderer"))
}

/// Closed sphere, ρ = 0.5, 4 bounces: the indirect radiance is ρ/π · Σ ρʲ everywhere. One
/// frame of 1000 paths misses it by several percent; 64 accumulated frames (of growing
/// batches, the default) are within 1%.
#[test]
fn accumulation_converges_to_the_closed_form_on_the_sphere() {
    let (rho, k) = (0.5f64, 4);
    let expected = rho / PI * (1..=k).map(|j| rho.powi(j)).sum::<f64>();
    let Some(mut r) = renderer("scenes/sphere.gltf", settings(24, 24, 1000, 0.2, k as u32, 1)) else { return };
    let error = |frame: &RenderedFrame| {
        let mean = common::mean(&frame.indirect);
        mean.iter().map(|c| (c - expected).abs() / expected).fold(0.0, f64::max)
    };
    let one = error(&r.render().expect("one frame"));
    r.update(|s| s.frames = 64).expect("settings");
    let frame = r.render().expect("64 frames");
    r.gpu().check_validation().expect("validation clean");
    assert_eq!(frame.accumulated, 64);
    let many = error(&frame);
    let radius = frame.splat.as_ref().unwrap().radius;
    eprintln!("sphere: mean indirect off the closed form by {one:.4} after 1 frame, {many:.4} after 64 (radius 0.2 -> {radius:.4})");
    assert!(many < 0.01, "64 frames: {many} from the closed form");
    // Frames of 1, 2, 4, then 8 batches: the last frame's radius is its first batch's.
    assert_eq!(frame.batches, 1 + 2 + 4 + 8 * 61);
    let last_first_batch = frame.batches - 8;
    let expected_radius = leakless::splatting::progressive_radius(0.2, last_first_batch);
    assert!((radius - expected_radius).abs() < 1e-7, "last frame's radius {radius}, not {expected_radius}");
}

/// The reference's frames grow as photon frames do, in batches of `spp` samples (1, 2, 4, then
/// 8), each weighted by its samples: 8 frames of 1 sample per batch hold 1 + 2 + 4 + 8·5 = 47
/// samples, and their mean on the closed sphere is the closed form (within 1%: 27k paths).
///
/// The weighting shows in the noise: every pixel of the sphere has the same expectation, so
/// the spread over pixels is the per-pixel noise, and 47 samples in growing frames must be as
/// quiet as 47 in one frame. Frames weighted equally would leave 1.75× its variance
/// ((1 + 1/2 + 1/4 + 5/8) / 64 against 1/47); 576 pixels measure a variance to about 6%.
#[test]
fn reference_frames_grow_in_batches_of_samples() {
    let (rho, k) = (0.5f64, 4);
    let expected = rho / PI * (1..=k).map(|j| rho.powi(j)).sum::<f64>();
    let s = RenderSettings { method: Method::Reference, spp: 1, ..settings(24, 24, 1000, 0.2, k as u32, 8) };
    let Some(mut r) = renderer("scenes/sphere.gltf", s) else { return };
    let frame = r.render().expect("8 frames");
    assert_eq!((frame.accumulated, frame.batches), (8, 1 + 2 + 4 + 8 * 5));
    let mean = common::mean(&frame.indirect);
    let error = mean.iter().map(|c| (c - expected).abs() / expected).fold(0.0, f64::max);
    r.update(|s| (s.frames, s.spp) = (1, 47)).expect("settings");
    let single = r.render().expect("one frame of 47 samples");
    r.gpu().check_validation().expect("validation clean");
    let variance = |layer: &[[f32; 3]]| {
        let m = common::mean(layer)[0];
        layer.iter().map(|p| (p[0] as f64 - m).powi(2)).sum::<f64>() / (layer.len() - 1) as f64
    };
    let ratio = variance(&frame.indirect) / variance(&single.indirect);
    eprintln!(
        "sphere reference, 47 samples in 8 frames: mean indirect off the closed form by {error:.4}; \
         pixel variance {ratio:.3}× that of one frame of 47 samples"
    );
    assert!(error < 0.01, "{error} from the closed form");
    assert!((0.75..1.3).contains(&ratio), "growing frames are not weighted by their samples: variance ratio {ratio}");
}

/// The app's reference while the view is still (progressive, frames of batches of one sample)
/// is `render --method reference --frames N` bit for bit, jittered: four frames of 1, 2, 2, 2
/// samples. One frame of the same 7 samples at the pixel centres is not that image (the Cornell
/// box's edges are antialiased by the jitter).
#[test]
fn the_still_views_reference_is_the_rendered_progressive_reference() {
    let s = RenderSettings { method: Method::Reference, spp: 1, max_batches: 2, ..settings(32, 24, 1000, 0.2, 4, 1) };
    let Some(mut app) = renderer("scenes/cornell-box.gltf", s.clone()) else { return };
    app.set_progressive(true);
    for _ in 0..3 {
        app.render_frame(None).expect("a still frame");
    }
    let still = app.capture_frame().expect("the fourth frame");
    app.gpu().check_validation().expect("validation clean");
    drop(app);
    let Some(mut cli) = renderer("scenes/cornell-box.gltf", RenderSettings { frames: 4, ..s.clone() }) else { return };
    let rendered = cli.render().expect("4 frames");
    assert_eq!((still.accumulated, still.batches), (4, 1 + 2 + 2 + 2));
    assert_eq!((rendered.accumulated, rendered.batches), (4, 7));
    assert!(still.direct == rendered.direct && still.indirect == rendered.indirect, "the still view is not the render");
    cli.update(|c| (c.frames, c.spp) = (1, 7)).expect("settings");
    let centres = cli.render().expect("7 samples at the pixel centres");
    cli.gpu().check_validation().expect("validation clean");
    let differing = centres.direct.iter().zip(&still.direct).filter(|(a, b)| a != b).count();
    eprintln!("still reference: {differing} of {} direct pixels differ from the unjittered image", still.direct.len());
    assert!(differing > 0, "the still view's reference is not jittered");
}

/// Cornell box, 1000 paths per frame: the indirect layer's relMSE against the reference falls
/// at least 4× from 1 to 64 frames, and keeps falling on the way. The reference integrates
/// the same 64 pixel jitters (64 frames of 64 samples), so antialiasing is not counted as error.
#[test]
fn error_against_the_reference_falls_with_frames() {
    let Some(reference) = common::jittered_reference("scenes/cornell-box.gltf", (64, 48), 64, 64, 1) else { return };
    let Some(mut r) = renderer("scenes/cornell-box.gltf", settings(64, 48, 1000, 0.05, 8, 1)) else { return };
    let eps = metrics::epsilon(&reference.indirect);
    let mut errors = Vec::new();
    for frames in [1u32, 4, 16, 64] {
        r.update(|s| s.frames = frames).expect("settings");
        let frame = r.render().expect("render");
        let e = metrics::rel_mse(&frame.indirect, &reference.indirect, None, eps).expect("pixels");
        eprintln!("Cornell, {frames} frames of 1000 paths: relMSE of the indirect layer {e:.5}");
        errors.push(e);
    }
    r.gpu().check_validation().expect("validation clean");
    assert!(errors.windows(2).all(|w| w[1] < w[0]), "relMSE does not fall: {errors:?}");
    assert!(errors[3] * 4.0 <= errors[0], "1 -> 64 frames: {errors:?}");
}

/// Accumulating and then resetting gives the single frame back, bit for bit in every layer;
/// the same accumulation twice is the same image.
#[test]
fn a_reset_gives_the_single_frame_bit_for_bit() {
    for backend in common::choices() {
        let s = RenderSettings { backend, ..settings(40, 30, 2000, 0.05, 4, 1) };
        let Some(mut r) = renderer("scenes/cornell-box.gltf", s) else { return };
        let single = r.render().expect("one frame");
        r.update(|s| s.frames = 6).expect("settings");
        let six = r.render().expect("six frames");
        let again = r.render().expect("six frames again");
        r.update(|s| s.frames = 1).expect("settings");
        let reset = r.render().expect("one frame again");
        r.gpu().check_validation().expect("validation clean");
        let bits = |f: &RenderedFrame| {
            [&f.radiance, &f.direct, &f.indirect, &f.leaked]
                .iter()
                .flat_map(|l| l.iter().flat_map(|p| p.map(f32::to_bits)))
                .collect::<Vec<u32>>()
        };
        assert_eq!(bits(&reset), bits(&single), "{backend:?}: the frame after a reset differs");
        assert_eq!(bits(&again), bits(&six), "{backend:?}: an accumulation is not reproducible");
        assert_ne!(bits(&six), bits(&single), "{backend:?}: six frames equal one");
        assert_eq!((single.accumulated, six.accumulated, reset.accumulated), (1, 6, 1));
    }
}

/// Flicker (a still view, fresh photons every frame, default paths and radius): `leakless`
/// flickers no more than 1.1× `splat` on the leak scenes; and each frame of an accumulation
/// changes the image less than the frames before it did (mean change over frames 2–4, 5–8,
/// 9–16, 17–32).
#[test]
fn leakless_flickers_no_more_than_splat_and_accumulation_settles() {
    use leakless_measure::flicker::{accumulation_changes, flicker, FLICKER_FRAMES};
    for path in ["scenes/doorway.gltf", "scenes/two-rooms.gltf", "scenes/atrium.gltf"] {
        // The default paths and radius, as `bench flicker` measures it (the kernel, not the
        // resolution, sets a pixel's noise).
        let s = |method| {
            let mut s = RenderSettings { method, ..settings(48, 36, 10_000, 1.0, 8, 1) };
            s.splat.radius = None;
            s
        };
        let Some(mut r) = renderer(path, s(Method::Splat)) else { return };
        let splat = flicker(&mut r, FLICKER_FRAMES).expect("splat");
        r.set_settings(s(Method::LeakLess)).expect("settings");
        let ours = flicker(&mut r, FLICKER_FRAMES).expect("leakless");
        eprintln!("{path}: flicker splat {splat:.4}, leakless {ours:.4}");
        assert!(ours <= 1.1 * splat, "{path}: leakless flickers {ours} against splat's {splat}");
        if path == "scenes/doorway.gltf" {
            // One batch a frame: frames that grow only make the fall steeper, and they took
            // two thirds of this test's time (38 of 58 s in release).
            r.update(|s| s.max_batches = 1).expect("settings");
            let changes = accumulation_changes(&mut r, 32).expect("accumulation");
            let window = |a: usize, b: usize| changes[a - 2..b - 1].iter().sum::<f64>() / (b - a + 1) as f64;
            let means = [window(2, 4), window(5, 8), window(9, 16), window(17, 32)];
            eprintln!("{path}: mean change per frame of an accumulation, frames 2-4, 5-8, 9-16, 17-32: {means:.4?}");
            assert!(means.windows(2).all(|w| w[1] < w[0]), "{path}: {means:?}");
        }
        r.gpu().check_validation().expect("validation clean");
    }
}

/// An accumulation's frames double their batches up to `--max-batches`, but hold no more than
/// the node lists can take: they cannot grow past the device's largest buffer
/// (`limits::max_list_entries`), and a frame of more batches would drop photons from them. Here
/// a batch's lists are 512k entries (2000 paths of up to 16 bounces, 16 entries a photon);
/// lavapipe's 128 MiB buffers hold 32 such batches, so the seventh frame holds 32, not 64, and
/// nothing is dropped.
#[test]
fn frames_hold_no_more_batches_than_the_lists_take() {
    let (paths, bounces, frames, max_batches) = (2000, 16, 7, 64);
    let s = RenderSettings {
        max_batches,
        splat: SplatSettings { paths, ..Default::default() },
        ..settings(32, 24, paths, 1.0, bounces, frames)
    };
    let Some(mut r) = renderer("scenes/cornell-box.gltf", s) else { return };
    let limits = r.gpu().report().limits;
    let max_entries = leakless::limits::max_list_entries(&limits);
    let per_batch = leakless::splatting::default_list_capacity(paths * bounces, 32 * 24).min(max_entries);
    let lists_hold = (max_entries / per_batch).max(1);
    let fits = (leakless::limits::max_frame_paths(&limits, bounces) / paths as u64).max(1) as u32;
    let expected: Vec<u32> = (0..frames).map(|k| (1u32 << k).min(max_batches).min(fits).min(lists_hold)).collect();
    eprintln!(
        "{max_entries} list entries at most, {per_batch} a batch: the lists hold {lists_hold} batches, the photon buffer {fits}; frames of {expected:?} batches"
    );
    let frame = r.render().expect("render");
    r.gpu().check_validation().expect("validation clean");
    let stats = frame.splat.expect("a photon frame");
    assert_eq!(frame.batches, expected.iter().sum::<u32>(), "batches accumulated");
    assert_eq!(stats.paths, expected[frames as usize - 1] * paths, "the last frame's paths");
    assert_eq!((stats.list_entries_dropped, stats.photons_dropped), (0, 0), "{stats:?}");
    // On lavapipe the lists are what stops the doubling (a GPU's 4 GiB buffers hold 256).
    if r.gpu().report().device_type == leakless_device::DeviceType::Cpu {
        assert!(lists_hold < 64 && lists_hold < fits, "the lists hold {lists_hold} batches here");
    }
}

/// Paused after an accumulation (and so also once it is full: the same frame that renders
/// nothing), the view keeps showing the accumulation's mean, bit for bit, not its last frame.
#[test]
fn a_paused_view_shows_the_accumulated_mean() {
    // Lists large enough from the start: a frame whose lists grow restarts the accumulation.
    let mut s = settings(32, 24, 1000, 0.2, 4, 1);
    s.splat.list_capacity = Some(1 << 20);
    let Some(mut app) = renderer("scenes/cornell-panel.gltf", s) else { return };
    app.set_progressive(true);
    for _ in 0..3 {
        app.render_frame(None).expect("a still frame");
    }
    let still = app.capture_frame().expect("the fourth frame");
    app.set_paused(true);
    let paused = app.capture_frame().expect("a paused frame");
    app.gpu().check_validation().expect("validation clean");
    assert_eq!((still.accumulated, paused.accumulated), (4, 4));
    for (name, a, b) in [
        ("radiance", &still.radiance, &paused.radiance),
        ("direct", &still.direct, &paused.direct),
        ("indirect", &still.indirect, &paused.indirect),
        ("leaked", &still.leaked, &paused.leaked),
    ] {
        let differing = a.iter().zip(b).filter(|(x, y)| x != y).count();
        assert_eq!(differing, 0, "paused, {differing} pixels of the {name} layer are not the accumulation's");
    }
    assert!(still.display == paused.display, "the shown image changed when paused");
}
