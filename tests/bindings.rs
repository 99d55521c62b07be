//! Every pass's declared bindings agree with its shaders' reflection (no GPU needed).

use leakless::passes::{direct, gbuffer};
use leakless::shaders;
use leakless_device::check_bindings;

#[test]
fn every_pass_matches_its_shader() {
    check_bindings(&shaders::DIRECT_COMP, "direct", direct::BINDINGS).unwrap();
    // The G-buffer's bindings are split over two stages: each stage's subset must match.
    for shader in [&shaders::GBUFFER_VERT, &shaders::GBUFFER_FRAG] {
        let reflected = shader.reflection.expect("naga parses raster modules");
        let used: Vec<_> = gbuffer::BINDINGS
            .iter()
            .copied()
            .filter(|d| reflected.iter().any(|r| r.name == d.name))
            .collect();
        check_bindings(shader, "gbuffer", &used).unwrap();
    }
}

#[test]
fn every_module_is_reflected_or_says_why_not() {
    for s in shaders::ALL {
        match s.reflection {
            Ok(_) => {}
            Err(why) => assert!(
                !why.is_empty(),
                "{} has no reflection and no reason",
                s.name
            ),
        }
        assert_eq!(
            s.spirv.first(),
            Some(&0x0723_0203),
            "{} is not SPIR-V",
            s.name
        );
    }
}
