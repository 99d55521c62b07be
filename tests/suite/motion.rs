//! In motion (temporal reuse, docs/architecture.md §1 "Motion"): a render from scratch is the
//! same with reuse on or off, sealed rooms stay exactly black in every frame of a walk, a shut
//! door is black at once, a light that jumps is followed at once and one that moves slowly
//! without lag, and reuse steadies the frames of a moving camera.

use crate::common;

use leakless::{BackendChoice, Method, RenderSettings, RenderedFrame, Renderer, Scene};
use leakless_scene::Camera;

/// A renderer doing what the app does between frames.
fn app(scene: &Scene, settings: RenderSettings) -> Renderer {
    let gpu = common::gpu_with(settings.backend.wants_ray_queries()).expect("checked by common::choices()");
    let mut r = Renderer::new(gpu, scene, settings).expect("renderer");
    r.set_progressive(true);
    r.set_advance_seed(true);
    r
}

fn settings(backend: BackendChoice, paths: u32, radius: f32, reuse: bool) -> RenderSettings {
    RenderSettings { reuse, ..common::photon_settings(Method::LeakLess, backend, paths, radius) }
}

/// `camera` turned by `yaw` radians about +Y and moved `forward` metres along its view.
fn turned(camera: &Camera, yaw: f32, forward: f32) -> Camera {
    let eye = camera.position() + forward * camera.forward();
    let dir = glam::Quat::from_rotation_y(yaw) * camera.forward();
    Camera::look_at(eye, eye + dir, camera.up(), camera.yfov, camera).expect("a valid view")
}

fn lit(frame: &RenderedFrame) -> usize {
    frame.radiance.iter().filter(|p| p.iter().any(|&c| c != 0.0)).count()
}

/// A render has no frames before it: one frame and an accumulation of four are bit for bit the
/// same with reuse on or off, also from a renderer whose camera moved with reuse first.
#[test]
fn a_render_from_scratch_is_the_same_with_reuse_on_or_off() {
    let scene = common::scene("scenes/cornell-box.gltf");
    let Some(&backend) = common::choices().first() else { return };
    for frames in [1, 4] {
        let image = |reuse| {
            let mut r = app(&scene, RenderSettings { frames, ..settings(backend, 5_000, 0.1, reuse) });
            // One seed throughout (reuse gives moving frames fresh photons when seeds advance).
            r.set_advance_seed(false);
            let camera = r.camera().clone();
            for k in 1..=3 {
                r.set_camera(turned(&camera, 0.02 * k as f32, 0.0));
                r.capture_frame().expect("a moving frame");
            }
            r.set_camera(camera);
            r.set_progressive(false);
            let frame = r.render().expect("render");
            r.gpu().check_validation().expect("validation clean");
            frame
        };
        let (on, off) = (image(true), image(false));
        assert!(
            on.radiance == off.radiance && on.indirect == off.indirect,
            "--frames {frames}: reuse changed a render"
        );
    }
}

/// The camera walks and turns inside room B of the sealed two rooms (lit by a point light, and
/// by an emissive panel), one photon frame per step with temporal and spatial reuse: every
/// frame is exactly black on both backends.
#[test]
fn sealed_rooms_stay_black_in_every_frame_of_a_walk() {
    for (path, backend) in ["scenes/two-rooms.gltf", "scenes/stress/sealed-panel.gltf"]
        .into_iter()
        .flat_map(|p| common::choices().into_iter().map(move |b| (p, b)))
    {
        let scene = common::scene(path);
        let mut r = app(&scene, settings(backend, 20_000, 0.3, true));
        let start = r.camera().clone();
        for k in 0..8 {
            r.set_camera(turned(&start, 0.03 * k as f32, 0.02 * k as f32));
            let frame = r.capture_frame().expect("a walking frame");
            assert_eq!(lit(&frame), 0, "{path} {backend:?}: frame {k} of the walk has light in the sealed room");
        }
        // And still: the accumulation with the history weighed in (two frames: a third would
        // trace 8 batches, more than the walk).
        for k in 0..2 {
            let frame = r.capture_frame().expect("a still frame");
            assert_eq!(lit(&frame), 0, "{path} {backend:?}: still frame {k} has light in the sealed room");
        }
        r.gpu().check_validation().expect("validation clean");
    }
}

/// The same walk through the sealed two rooms with a frame budget of 1 ms, which no frame
/// meets: the budget lowers each moving frame's paths from 20 000 to its fewest (the first frame,
/// which compiles the pipelines, unmeasured), the still frames after it continue from the
/// budgeted first frame's paths, and every frame stays exactly black on both backends.
#[test]
fn sealed_rooms_stay_black_under_a_frame_budget() {
    let scene = common::scene("scenes/two-rooms.gltf");
    for backend in common::choices() {
        let mut r = app(&scene, settings(backend, 20_000, 0.3, true));
        r.set_frame_budget(Some(1.0)).expect("a budget");
        let start = r.camera().clone();
        let mut paths = Vec::new();
        for k in 0..8 {
            r.set_camera(turned(&start, 0.03 * k as f32, 0.02 * k as f32));
            let frame = r.capture_frame().expect("a walking frame");
            assert_eq!(lit(&frame), 0, "{backend:?}: frame {k} of the budgeted walk has light in the sealed room");
            let report = r.last_report().expect("a report");
            let budget = report.budget.expect("the budget chose the moving frame's paths");
            assert_eq!(Some(budget.paths), frame.splat.as_ref().map(|s| s.paths), "{backend:?}: frame {k}");
            assert_eq!(budget.target_ms, 1.0);
            if k == 0 {
                // It compiled the pipelines: not measured, so neither over budget nor cut.
                assert!(!budget.over_budget && budget.next_paths == budget.paths, "{backend:?}: {budget:?}");
            }
            paths.push(budget.paths);
        }
        assert!(paths[0] > paths[7], "{backend:?}: the budget lowered the paths: {paths:?}");
        assert_eq!(paths[7], leakless::frame_budget::MIN_BUDGET_PATHS, "{backend:?}: {paths:?}");
        assert!(r.frame_budget().expect("set").over_budget(), "no frame meets 1 ms");
        for k in 0..2 {
            let frame = r.capture_frame().expect("a still frame");
            assert_eq!(lit(&frame), 0, "{backend:?}: still frame {k} has light in the sealed room");
        }
        r.gpu().check_validation().expect("validation clean");
    }
}

/// scenes/door.gltf played frame by frame with reuse, the camera in room B: the frames before
/// the door shuts are lit through the closing gap, and the first frame at the closed time is
/// exactly black on both backends, history notwithstanding.
#[test]
fn a_shut_door_is_black_at_once_with_reuse() {
    let scene = common::scene("scenes/door.gltf");
    let (open, closed) = (common::extra(&scene, "open_time"), common::extra(&scene, "closed_time"));
    for backend in common::choices() {
        let mut r = app(&scene, settings(backend, 20_000, 0.2, true));
        let mut before = 0;
        for step in 0..5 {
            r.set_time(open + (closed - open) * step as f32 / 5.0).expect("a time");
            before = lit(&r.capture_frame().expect("a frame of the swing"));
        }
        assert!(before > 100, "{backend:?}: the nearly shut door lets light in ({before} lit pixels)");
        r.set_time(closed).expect("a time");
        let shut = r.capture_frame().expect("the shut frame");
        eprintln!("{backend:?}: {before} lit pixels just before the door shuts, {} the frame it does", lit(&shut));
        assert_eq!(lit(&shut), 0, "{backend:?}: the shut door's first frame is not black");
        r.gpu().check_validation().expect("validation clean");
    }
}

/// The camera swings between two views of the Cornell box every frame, so every frame is a
/// moving one: against each view's mean of 32 single frames (the expectation of one frame,
/// whose error here is its noise), the frames after the first eight have at most half the
/// relative MSE with reuse that they have without, and their mean stays within 3% of it. The
/// spatial filter cuts the change between two frames of the same view by a third at least, and
/// costs little accuracy (its bias is divided out).
#[test]
fn reuse_halves_the_error_of_a_moving_camera() {
    let scene = common::scene("scenes/cornell-box.gltf");
    let Some(&backend) = common::choices().first() else { return };
    let start = {
        let r = app(&scene, settings(backend, 5_000, 0.1, true));
        r.camera().clone()
    };
    let views = [start.clone(), turned(&start, 0.01, 0.0)];
    let truth: Vec<RenderedFrame> = views
        .iter()
        .map(|v| {
            let mut r = app(&scene, settings(backend, 5_000, 0.1, false));
            r.set_progressive(false);
            r.set_camera(v.clone());
            let mut mean = r.capture_frame().expect("a single frame");
            for k in 1..32 {
                let next = r.capture_frame().expect("a single frame");
                for (m, p) in mean.radiance.iter_mut().zip(&next.radiance) {
                    for c in 0..3 {
                        m[c] += (p[c] - m[c]) / (k + 1) as f32;
                    }
                }
            }
            mean
        })
        .collect();
    let eps = leakless_measure::metrics::epsilon(&truth[0].radiance);
    // (relMSE, mean ratio, change): means over frames 8..24; the change is |ΔY| between a frame
    // and the one two before it, of the same view, over the mean Y: the image's own unrest.
    let run = |reuse, filter| {
        let mut r = app(&scene, settings(backend, 5_000, 0.1, reuse));
        r.set_spatial_reuse(filter);
        let (mut error, mut ratio, mut change) = (0.0, 0.0, 0.0);
        let mut luminance: Vec<Vec<f64>> = Vec::new();
        for k in 0..24 {
            r.set_camera(views[k % 2].clone());
            let frame = r.capture_frame().expect("a moving frame");
            luminance.push(frame.radiance.iter().map(leakless_measure::metrics::luminance).collect());
            if k >= 8 {
                let t = &truth[k % 2].radiance;
                error += leakless_measure::metrics::rel_mse(&frame.radiance, t, None, eps).expect("pixels") / 16.0;
                ratio += leakless_measure::metrics::mean_value(&frame.radiance)
                    / leakless_measure::metrics::mean_value(t)
                    / 16.0;
                let (now, before) = (&luminance[k], &luminance[k - 2]);
                let diff: f64 = now.iter().zip(before).map(|(a, b)| (a - b).abs()).sum();
                change += diff / now.iter().sum::<f64>() / 16.0;
            }
        }
        r.gpu().check_validation().expect("validation clean");
        (error, ratio, change)
    };
    let ((on, mean_on, change_on), (off, mean_off, _)) = (run(true, true), run(false, true));
    let (unfiltered, mean_unfiltered, change_unfiltered) = run(true, false);
    eprintln!(
        "moving camera, relMSE against the mean single frame: reuse {on:.5}, without {off:.5} ({:.2}×), reuse without its spatial filter {unfiltered:.5}; mean ratios {mean_on:.4} / {mean_off:.4} / {mean_unfiltered:.4}",
        on / off
    );
    eprintln!(
        "change between frames of the same view: reuse {change_on:.5}, without its spatial filter {change_unfiltered:.5} ({:.2}×)",
        change_on / change_unfiltered
    );
    assert!(on <= 0.5 * off, "reuse: relMSE {on}, without {off}");
    assert!((mean_on - 1.0).abs() < 0.03, "reuse moved the mean by {}", mean_on - 1.0);
    // The filter steadies the frames, and reaching no further than the kernel (a few pixels
    // here) it adds no error: 0.91× that of reuse without it when written. The change was
    // 0.62× when written, 0.66× since single frames' visible-disk masses are smoothed over
    // each surface (disk_smooth.comp), which takes out part of the grain the filter removed.
    assert!(
        change_on <= 0.7 * change_unfiltered,
        "the filter left a change of {change_on} (without {change_unfiltered})"
    );
    assert!(on <= 1.25 * unfiltered, "the filter made the error {on} (without {unfiltered})");
}

/// Once the camera stops, the accumulation takes over: the history weighs in less with every
/// frame, so after 16 still frames the image is closer to the accumulation without reuse than
/// after 2.
#[test]
fn a_still_view_after_motion_converges_to_the_accumulation() {
    let scene = common::scene("scenes/cornell-box.gltf");
    let Some(&backend) = common::choices().first() else { return };
    let frames = |reuse| {
        let mut r = app(&scene, settings(backend, 5_000, 0.1, reuse));
        let start = r.camera().clone();
        for k in 0..8 {
            r.set_camera(turned(&start, 0.002 * (8 - k) as f32, 0.0));
            r.capture_frame().expect("a moving frame");
        }
        r.set_camera(start);
        let images: Vec<RenderedFrame> = (0..16).map(|_| r.capture_frame().expect("a still frame")).collect();
        r.gpu().check_validation().expect("validation clean");
        images
    };
    let (on, off) = (frames(true), frames(false));
    let early = common::relative_rms(&on[1].radiance, &off[1].radiance);
    let late = common::relative_rms(&on[15].radiance, &off[15].radiance);
    eprintln!("still after motion, reuse against none: relative RMS {early:.4} after 2 frames, {late:.4} after 16");
    assert!(late < 0.5 * early, "the history does not fade: {early} then {late}");
}

/// A light that jumps is followed at once: after 12 frames of the moving light all but at rest
/// (1e-4 s a frame, so that each is a moving frame and builds the history), the light jumps to
/// where it is 3 s on (from room A to the doorway's far side), and the first frame there has,
/// with reuse, the indirect light's mean of a frame without within 5% (0.97× at 64×48). A
/// history that takes the new level only within the clamp's margin, over its frames
/// (`LAG_SIGMAS` infinite in temporal.comp), reads 0.76×.
#[test]
fn a_light_that_jumps_is_followed_at_once() {
    let scene = common::scene("scenes/moving-light.gltf");
    let Some(&backend) = common::choices().first() else { return };
    let jumped = |reuse| {
        let mut r = app(&scene, settings(backend, 10_000, 0.2, reuse));
        for k in 0..12 {
            r.set_time(k as f32 * 1e-4).expect("a time");
            r.capture_frame().expect("a frame before the jump");
        }
        r.set_time(3.0).expect("a time");
        let mean =
            leakless_measure::metrics::mean_value(&r.capture_frame().expect("the frame after the jump").indirect);
        r.gpu().check_validation().expect("validation clean");
        mean
    };
    let (on, off) = (jumped(true), jumped(false));
    eprintln!(
        "moving light, the frame after the jump: indirect mean with reuse {on:.5}, without {off:.5} ({:.4}x)",
        on / off
    );
    assert!((on / off - 1.0).abs() < 0.05, "reuse's indirect light is {:.4}x the baseline's after the jump", on / off);
}

/// A light that moves slowly is followed too: the moving light's first 24 frames at 30 fps,
/// whose indirect light grows by about 1% a frame, less than any neighbourhood tells from a
/// frame's noise. A history of a second's frames lags such a ramp by about as many; the image's
/// lighting level (lighting_level.comp) measures that lag over the whole image and scales the
/// history shown. Over frames 8–23 reuse's mean indirect light must be within 5% of the
/// baseline's, whose every frame is fresh (128×72: 0.955×, the level following the growing lag
/// a few frames late; with half a second's history 0.958×, and 0.922× without the level).
#[test]
fn a_light_that_moves_slowly_is_followed() {
    let scene = common::scene("scenes/moving-light.gltf");
    let Some(&backend) = common::choices().first() else { return };
    let mean = |reuse| {
        let settings = RenderSettings { width: 128, height: 72, ..settings(backend, 10_000, 0.2, reuse) };
        let mut r = app(&scene, settings);
        r.set_reuse_history_rate(30.0);
        let mut sum = 0.0;
        for k in 0..24 {
            r.set_time(k as f32 / 30.0).expect("a time");
            let frame = r.capture_frame().expect("a frame");
            if k >= 8 {
                sum += leakless_measure::metrics::mean_value(&frame.indirect) / 16.0;
            }
        }
        r.gpu().check_validation().expect("validation clean");
        sum
    };
    let (on, off) = (mean(true), mean(false));
    eprintln!("moving light, frames 8-23: indirect mean with reuse {on:.5}, without {off:.5} ({:.4}x)", on / off);
    assert!((on / off - 1.0).abs() < 0.05, "reuse's indirect light is {:.4}x the baseline's", on / off);
}
