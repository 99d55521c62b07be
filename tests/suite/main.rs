//! The GPU and CLI tests, one module per concern, in one test binary: one link instead of
//! twenty, and one scheduler that keeps both test threads busy to the end (separate binaries
//! each left a thread idle behind their longest test). `cargo test --test suite progressive`
//! runs one module.

mod common;

mod animation;
mod bindings;
mod chart;
mod cli;
mod corner_bias;
mod device;
mod direct_light;
mod docs;
mod identity;
mod leak;
mod leak_scenes;
mod output;
mod photons;
mod progressive;
mod reference;
mod sort;
mod splat;
mod stress;
mod trace;
mod view;
mod visibility;
