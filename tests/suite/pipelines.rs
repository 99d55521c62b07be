//! The large passes that only some methods run (the gather's three estimators, the path tracer,
//! primary rays) have their pipelines made by the first frame that runs them, not with the
//! renderer (lavapipe takes about 0.1 s for each of the first four).

use leakless::passes::FRAME_PASSES;
use leakless::{BackendChoice, Method, Primary, RenderSettings, Renderer, SplatSettings};

use crate::common;

const ON_DEMAND: [&str; 5] = ["gather", "gather traced", "gather visible disk", "reference", "primary rays"];

/// The on-demand pipelines `r` has made, in `ON_DEMAND`'s order.
fn made(r: &Renderer) -> Vec<&'static str> {
    ON_DEMAND.into_iter().filter(|label| r.has_pipeline(label)).collect()
}

/// The passes marked on demand are these five: a pass marked later says here which frames make
/// it (the test below), or it would go unchecked.
#[test]
fn the_on_demand_passes_are_the_ones_this_file_checks() {
    let mut marked: Vec<&str> = FRAME_PASSES.iter().filter(|d| d.on_demand).map(|d| d.name.label).collect();
    marked.sort_unstable();
    let mut checked = ON_DEMAND.to_vec();
    checked.sort_unstable();
    assert_eq!(marked, checked);
}

/// A renderer made for `direct` makes none of them; a `leakless` frame makes its estimator's
/// and the splat gather its radius probe runs, `leakless-capped` the traced one, `reference`
/// the path tracer, and a frame whose view samples are rays the primary rays'; each frame
/// after a switch renders, with validation clean.
#[test]
fn each_method_makes_its_passes_pipelines_when_it_first_runs() {
    let Some(gpu) = common::gpu_with(false) else { return };
    let settings = |method| RenderSettings {
        width: 32,
        height: 24,
        method,
        backend: BackendChoice::Compute,
        primary: Primary::Raster,
        splat: SplatSettings { paths: 2000, ..Default::default() },
        ..Default::default()
    };
    let mut r =
        Renderer::new(gpu, &common::scene("scenes/cornell-box.gltf"), settings(Method::Direct)).expect("renderer");
    assert!(made(&r).is_empty(), "made with the renderer: {:?}", made(&r));
    r.render().expect("render");
    assert!(made(&r).is_empty(), "made by a direct frame: {:?}", made(&r));
    let expect = |r: &mut Renderer, settings: RenderSettings, labels: &[&str]| {
        r.set_settings(settings).expect("settings");
        r.render().expect("render");
        assert_eq!(made(r), labels);
    };
    expect(&mut r, settings(Method::LeakLess), &["gather", "gather visible disk"]);
    expect(&mut r, settings(Method::LeakLessCapped), &["gather", "gather traced", "gather visible disk"]);
    expect(&mut r, settings(Method::Reference), &["gather", "gather traced", "gather visible disk", "reference"]);
    expect(&mut r, RenderSettings { primary: Primary::Rays, ..settings(Method::Direct) }, &ON_DEMAND);
    r.gpu().check_validation().expect("validation clean");
}
