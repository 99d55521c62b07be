//! The GPU and CLI tests, one module per concern, in one test binary: one link instead of
//! twenty. `tools/test` runs each test in a process of its own, two at a time (Debian 12's
//! validation layers race when one thread creates a device while another records: see
//! tools/test); `cargo test --test suite progressive -- --test-threads 1` runs one module.

mod common;

mod animation;
mod area_lights;
mod bindings;
mod chart;
mod cli;
mod corner_bias;
mod device;
mod direct_light;
mod docs;
mod game_scale;
mod gpu_report;
mod identity;
mod kernel_radius;
mod leak;
mod leak_scenes;
mod motion;
mod output;
mod photons;
mod pipelines;
mod primary;
mod progressive;
mod reference;
mod sort;
mod splat;
mod stress;
mod trace;
mod tuning;
mod view;
mod visibility;
