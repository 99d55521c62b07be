//! The files a render leaves: layered EXR with header attributes, PNG, stats.

use crate::common;

use leakless::output::exr;
use leakless_measure::metrics::luminance;

#[test]
fn exr_layers_and_attributes_round_trip() {
    let path = common::tmp_path("roundtrip.exr");
    let w = 5u32;
    let h = 3u32;
    let radiance: Vec<[f32; 3]> = (0..w * h).map(|i| [i as f32, 0.5, -1.0]).collect();
    let direct: Vec<[f32; 3]> = (0..w * h).map(|i| [0.25, i as f32 * 2.0, 1e-3]).collect();
    exr::write(
        &path,
        w,
        h,
        &[exr::ExrLayer { name: "", pixels: &radiance }, exr::ExrLayer { name: "direct", pixels: &direct }],
        &[("leakless.scene", "scenes/x.gltf".into()), ("leakless.method", "direct".into())],
    )
    .unwrap();
    let read = exr::read(&path).unwrap();
    assert_eq!((read.width, read.height), (w, h));
    let mut names: Vec<_> = read.channels.iter().map(|(n, _)| n.as_str()).collect();
    names.sort();
    assert_eq!(names, ["B", "G", "R", "direct.B", "direct.G", "direct.R"]);
    assert_eq!(read.channel("R").unwrap()[7], 7.0);
    assert_eq!(read.channel("direct.G").unwrap()[4], 8.0);
    assert_eq!(read.channel("B").unwrap()[0], -1.0);
    assert_eq!(read.attribute("leakless.scene"), Some("scenes/x.gltf"));
    assert_eq!(read.attribute("leakless.method"), Some("direct"));
}

#[test]
fn exr_rejects_a_layer_of_the_wrong_size() {
    let err =
        exr::write(&common::tmp_path("bad.exr"), 4, 4, &[exr::ExrLayer { name: "", pixels: &[[0.0; 3]; 3] }], &[])
            .unwrap_err();
    assert!(err.to_string().contains("3 pixels"), "{err}");
}

/// The PNG's definition, on the CPU: automatic exposure (log-average luminance of the pixels
/// above 1e-6 to middle grey), Narkowicz's ACES fit, sRGB encoding.
fn cpu_tonemap(pixels: &[[f32; 3]]) -> Vec<[u8; 3]> {
    let logs: Vec<f64> = pixels.iter().map(luminance).filter(|l| *l > 1e-6).map(f64::ln).collect();
    let exposure = if logs.is_empty() { 1.0 } else { 0.18 / (logs.iter().sum::<f64>() / logs.len() as f64).exp() };
    let filmic = |x: f64| ((x * (2.51 * x + 0.03)) / (x * (2.43 * x + 0.59) + 0.14)).clamp(0.0, 1.0);
    let srgb = |x: f64| if x <= 0.0031308 { 12.92 * x } else { 1.055 * x.powf(1.0 / 2.4) - 0.055 };
    pixels.iter().map(|p| p.map(|c| (srgb(filmic(c.max(0.0) as f64 * exposure)) * 255.0).round() as u8)).collect()
}

#[test]
fn gpu_tonemap_is_the_png_definition() {
    let settings = leakless::RenderSettings { width: 64, height: 48, ..Default::default() };
    let Some(frame) = common::render_with("scenes/cornell-box.gltf", settings) else { return };
    let expected = cpu_tonemap(&frame.radiance);
    let mut worst = 0;
    for (gpu, cpu) in frame.display.iter().zip(&expected) {
        for c in 0..3 {
            worst = worst.max((gpu[c] as i32 - cpu[c] as i32).abs());
        }
    }
    // float32 on the GPU against float64 here: at most one step of 255 apart.
    assert!(worst <= 1, "GPU tonemap differs from the PNG's definition by {worst}/255");
    assert!(frame.display.iter().any(|p| p[0] > 200), "a bright pixel exists");
    assert!(frame.display.iter().all(|p| p[3] == 255));
    // The GPU's leaked-energy sums agree with the layers read back.
    let lum = |l: &[[f32; 3]]| l.iter().map(luminance).sum::<f64>();
    let (lost, kept) = (lum(&frame.leaked), lum(&frame.indirect));
    let host = lost / (lost + kept);
    let gpu = frame.splat.as_ref().unwrap().leaked_energy_fraction;
    assert!(host > 0.0 && (gpu - host).abs() <= 1e-4 * host.max(1e-3), "leaked fraction: GPU {gpu}, layers {host}");
}
