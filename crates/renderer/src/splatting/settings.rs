//! The photon method's settings: what `--paths`, `--radius` and the method's switches set.

/// The photon method's parameters (`--paths`, `--radius`, …).
#[derive(Clone, Debug, PartialEq)]
pub struct SplatSettings {
    /// Light paths traced per frame.
    pub paths: u32,
    /// Gather radius in scene units; `None`: the radius at which a kernel holds about
    /// `kernel_photons` photons ([`KernelDensity`](super::KernelDensity)).
    pub radius: Option<f32>,
    /// K, photons a kernel holds where `radius` is `None` (`--kernel-photons`).
    pub kernel_photons: f32,
    /// Branching factor B of the hierarchy; `None`: the device tuning's
    /// ([`DeviceTuning::branching`](crate::tuning::DeviceTuning::branching)).
    pub branching: Option<u32>,
    /// List a photon on an enveloped, facing node instead of descending (Moreau et al.).
    pub trivial_accept: bool,
    /// Node-list entries per frame; more are counted as dropped, never written.
    pub list_capacity: Option<u32>,
    /// Trace a visibility segment from each sample to each photon (leakage removal); set by
    /// the method.
    pub visibility: bool,
    /// Gather at most this many photons per pixel (`leakless-capped`; `--cap`).
    pub cap: Option<u32>,
    /// Skip the visibility rays the photons' clearance proves clear (same image; off with
    /// `--trace-every-pair`, to measure what the proofs save and check they change nothing).
    pub prove_clear: bool,
    /// Divide each sample's sum by the kernel's mass over the part of its disk that can be
    /// seen, counting only photons on its own surface (`leakless`; off with `--whole-disk`,
    /// the estimator before the corner fix). Needs `visibility`.
    pub visible_disk: bool,
    /// Gather within r·clamp(m^γ, ½, 1.5) where the visible disk holds a share m < 1 of the
    /// kernel's mass: γ = −1 (grow) in a single frame, then ramping from 1/64 to 1 (shrink) as
    /// batches accumulate ([`partial_radius_exponent`]; visible_disk.comp says why; off with
    /// `--no-partial-disk-radius`). Needs `visible_disk`.
    pub partial_disk_radius: bool,
    /// Find whether the sample's face lies under a visible-disk probe by walking to a coplanar
    /// neighbour of its triangle before tracing a ray down (`Scene::coplanar_neighbours`;
    /// same image, fewer rays; off only to check that).
    pub walk_faces: bool,
    /// Cull each hierarchy node with its own samples' largest gather radius, not the frame's
    /// largest, where a single frame grows partial disks (same image, fewer list entries; off
    /// only to check that).
    pub node_radius: bool,
    /// Copy the photons in the order of a grid's cells before the splat, so that neighbouring
    /// threads walk the same nodes (photon_order.rs; same image, faster; off only to check
    /// that).
    pub order_photons: bool,
}

impl Default for SplatSettings {
    fn default() -> Self {
        SplatSettings {
            paths: 10_000,
            radius: None,
            kernel_photons: super::DEFAULT_KERNEL_PHOTONS,
            branching: None,
            trivial_accept: true,
            list_capacity: None,
            visibility: false,
            cap: None,
            prove_clear: true,
            visible_disk: true,
            partial_disk_radius: true,
            walk_faces: true,
            node_radius: true,
            order_photons: true,
        }
    }
}
