//! The files a render leaves: layered EXR with header attributes, PNG, stats.

mod common;

use leakless::output::{exr, png};

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

#[test]
fn tonemap_maps_black_to_black_and_saturates_monotonically() {
    let px = [[0.0, 0.0, 0.0], [0.1, 0.1, 0.1], [1.0, 1.0, 1.0], [100.0, 100.0, 100.0]];
    let out = png::tonemap(&px, 1.0);
    assert_eq!(&out[0..3], &[0, 0, 0]);
    assert!(out[3] < out[6] && out[6] < out[9]);
    assert_eq!(out[9], 255);
}
