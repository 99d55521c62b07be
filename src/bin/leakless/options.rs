//! The render options `render` and `view` share: what to render and how, as flags.

use std::path::PathBuf;

use anyhow::Context;
use glam::Vec3;
use leakless::{BackendChoice, Method, Primary, RenderSettings, Scene, SplatSettings};
use leakless_scene::Camera;

#[derive(clap::Args, Clone, Debug)]
pub struct RenderOptions {
    /// The scene (.gltf or .glb).
    pub scene: PathBuf,
    /// Output size, WIDTHxHEIGHT (`view`: the window's starting size).
    #[arg(long, value_parser = crate::parse_size)]
    pub size: Option<(u32, u32)>,
    /// `leakless` (ours: splatting with a visibility ray to every photon), `leakless-capped`
    /// (the thesis: no trivial accept, at most --cap photons per pixel), `splat` (Moreau et
    /// al., leaks), `reference` (path-traced indirect light) or `direct` (direct light only).
    #[arg(long, default_value = "leakless")]
    pub method: Method,
    /// Photons gathered per pixel at most by `leakless-capped` (the thesis used 25).
    #[arg(long)]
    pub cap: Option<u32>,
    /// Light paths traced per frame by the photon methods.
    #[arg(long, default_value_t = 10_000)]
    pub paths: u32,
    /// Photon gather radius in scene units (default: the radius at which a kernel holds
    /// --kernel-photons photons, from the view's photon density).
    #[arg(long)]
    pub radius: Option<f32>,
    /// Photons a gather kernel holds on average where --radius is not given: the radius
    /// follows the photon count (more paths, a smaller radius).
    #[arg(long, default_value_t = leakless::splatting::DEFAULT_KERNEL_PHOTONS)]
    pub kernel_photons: f32,
    /// Branching factor of the view-sample hierarchy (default: the device tuning's; `leakless
    /// info` prints it).
    #[arg(long)]
    pub branching: Option<u32>,
    /// Walk to the leaves instead of listing photons on enveloped nodes (same image).
    #[arg(long)]
    pub no_trivial_accept: bool,
    /// Trace a visibility ray for every gathered pair instead of skipping the ones the photons'
    /// clearance proves clear (same image, slower: for measuring what the proofs save).
    #[arg(long)]
    pub trace_every_pair: bool,
    /// `leakless`: divide by the kernel's whole disk, not its visible part, and count photons
    /// on every surface within the radius (the estimator before the corner fix, which darkens
    /// near occluders and in corners).
    #[arg(long)]
    pub whole_disk: bool,
    /// `leakless`: keep every sample's radius where its visible disk is partial, instead of
    /// growing it in a single frame (noisier edges) and shrinking it as frames accumulate
    /// (edges that converge more slowly).
    #[arg(long)]
    pub no_partial_disk_radius: bool,
    /// Node-list entries per frame (default: 16 per photon, grown as frames need);
    /// more are dropped and reported.
    #[arg(long)]
    pub list_capacity: Option<u32>,
    /// Trace backend: ray queries, the compute-shader BVH, or `auto` (the compute BVH on CPU
    /// devices, ray queries on GPUs that have them).
    #[arg(long, default_value = "auto")]
    pub backend: BackendChoice,
    /// Device tuning: the device's own (`auto`), or the `cpu` or `gpu` preset (`leakless info`
    /// prints what each sets; `gpu` on lavapipe runs the GPU's code paths).
    #[arg(long, default_value = "auto")]
    pub tuning: leakless::TuningChoice,
    /// How view samples are found: `raster` (the G-buffer rasterised), `rays` (a closest-hit ray
    /// per pixel on the trace backend, whose cost follows the pixels, not the triangles), or
    /// `auto` (rays on a CPU device where the scene has more triangles than the image pixels;
    /// `leakless info` says). Default: `auto`, so that `render` finds a frame's samples as the
    /// app does
    #[arg(long)]
    pub primary: Option<leakless::Primary>,
    /// Photon frames to average (progressive photon mapping: fresh photons further along one
    /// sequence, a shrinking radius, jittered pixels); `reference`: jittered frames of --spp
    /// samples per batch.
    #[arg(long, default_value_t = 1)]
    pub frames: u32,
    /// Photon batches of --paths paths a frame of an accumulation traces at most: frame k
    /// traces min(2^k, this) (fewer when the node lists cannot hold them), so the per-frame
    /// work is shared by more photons as the image converges (1: every frame traces --paths
    /// paths). A reference frame grows alike, in batches of --spp samples.
    #[arg(long, default_value_t = leakless::settings::DEFAULT_MAX_BATCHES)]
    pub max_batches: u32,
    /// Samples per pixel of the reference path tracer (`view`: while the view is still it
    /// accumulates frames of batches of one sample per pixel instead).
    #[arg(long, default_value_t = 64)]
    pub spp: u32,
    /// Indirect bounces after the first surface.
    #[arg(long, default_value_t = 8)]
    pub max_bounces: u32,
    /// Shadow rays toward emissive triangles per pixel and frame (direct light).
    #[arg(long, default_value_t = leakless::settings::DEFAULT_LIGHT_SAMPLES)]
    pub light_samples: u32,
    /// Candidate emitter points each of those shadow rays is resampled from, by the light each
    /// would bring (1: plain next-event estimation by power).
    #[arg(long, default_value_t = leakless::settings::DEFAULT_LIGHT_CANDIDATES)]
    pub light_candidates: u32,
    /// Seed of every random sequence (a fixed seed gives an identical frame).
    #[arg(long, default_value_t = 0)]
    pub seed: u32,
    /// Temporal reuse of the indirect light: frames after a change start from the frames
    /// before, reprojected (`render --sequence`, the app). `off` renders every frame afresh.
    /// A single image is the same either way.
    #[arg(long, default_value = "on", value_parser = ["on", "off"])]
    pub reuse: String,
    /// The view, instead of the scene's camera: EYE,TARGET,UP,YFOV as ten numbers
    /// `ex,ey,ez,tx,ty,tz,ux,uy,uz,yfov_degrees` (the app's captures write it).
    #[arg(long, value_parser = parse_camera)]
    pub camera: Option<CameraSpec>,
    /// Moves the scene's first light to X,Y,Z (the app's captures write it when the light was
    /// moved).
    #[arg(long, value_parser = parse_vec3)]
    pub light_position: Option<Vec3>,
    /// Seconds on the scene's animation clock: animated objects, lights and the camera are
    /// placed as they are at that time (every animation of the file plays at once; before the
    /// first key and after the last, a channel holds its end value).
    #[arg(long, default_value_t = 0.0, value_parser = parse_time)]
    pub time: f32,
    /// PNG and window exposure multiplier (default: automatic).
    #[arg(long, value_parser = parse_exposure)]
    pub exposure: Option<f32>,
}

/// `--camera`: the view as the app's fly camera holds it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CameraSpec {
    pub eye: Vec3,
    pub target: Vec3,
    pub up: Vec3,
    pub yfov_degrees: f32,
}

impl CameraSpec {
    /// The camera, with the clip distances of the scene's own view.
    pub fn camera(&self, scene: &Scene) -> anyhow::Result<Camera> {
        Camera::look_at(self.eye, self.target, self.up, self.yfov_degrees.to_radians(), &scene.camera_or_framing())
            .context("--camera: eye and target coincide, up is parallel to the view, or yfov is not within (0, 180)")
    }

    /// The flag value that gives back exactly this view (f32's shortest round-trip form).
    pub fn flag(&self) -> String {
        let v = [
            self.eye.x,
            self.eye.y,
            self.eye.z,
            self.target.x,
            self.target.y,
            self.target.z,
            self.up.x,
            self.up.y,
            self.up.z,
            self.yfov_degrees,
        ];
        v.iter().map(|x| x.to_string()).collect::<Vec<_>>().join(",")
    }
}

fn numbers(s: &str, n: usize, what: &str) -> Result<Vec<f32>, String> {
    let v: Vec<f32> = s
        .split(',')
        .map(|x| x.trim().parse::<f32>().map_err(|_| format!("{x:?} is not a number")))
        .collect::<Result<_, _>>()?;
    if v.len() != n || v.iter().any(|x| !x.is_finite()) {
        return Err(format!("{s:?} is not {n} finite numbers ({what})"));
    }
    Ok(v)
}

fn parse_camera(s: &str) -> Result<CameraSpec, String> {
    let v = numbers(s, 10, "ex,ey,ez,tx,ty,tz,ux,uy,uz,yfov_degrees")?;
    Ok(CameraSpec {
        eye: Vec3::new(v[0], v[1], v[2]),
        target: Vec3::new(v[3], v[4], v[5]),
        up: Vec3::new(v[6], v[7], v[8]),
        yfov_degrees: v[9],
    })
}

fn parse_time(s: &str) -> Result<f32, String> {
    let t: f32 = s.trim().parse().map_err(|_| format!("'{s}' is not a number of seconds"))?;
    if t.is_finite() {
        Ok(t)
    } else {
        Err(format!("'{s}' is not a finite number of seconds"))
    }
}

fn parse_exposure(s: &str) -> Result<f32, String> {
    let e: f32 = s.trim().parse().map_err(|_| format!("'{s}' is not a number"))?;
    if e.is_finite() && e > 0.0 {
        Ok(e)
    } else {
        Err(format!("'{s}': an exposure multiplies the image, so it must be a positive number"))
    }
}

fn parse_vec3(s: &str) -> Result<Vec3, String> {
    let v = numbers(s, 3, "x,y,z")?;
    Ok(Vec3::new(v[0], v[1], v[2]))
}

impl RenderOptions {
    /// The settings these flags ask for, at `default_size` when `--size` is not given.
    pub fn settings(&self, default_size: (u32, u32)) -> RenderSettings {
        let (width, height) = self.size.unwrap_or(default_size);
        RenderSettings {
            width,
            height,
            backend: self.backend,
            tuning: self.tuning,
            method: self.method,
            spp: self.spp,
            max_bounces: self.max_bounces,
            light_samples: self.light_samples,
            light_candidates: self.light_candidates,
            seed: self.seed,
            reuse: self.reuse == "on",
            primary: self.primary.unwrap_or(Primary::Auto),
            frames: self.frames,
            max_batches: self.max_batches,
            splat: SplatSettings {
                paths: self.paths,
                radius: self.radius,
                kernel_photons: self.kernel_photons,
                branching: self.branching,
                trivial_accept: !self.no_trivial_accept,
                list_capacity: self.list_capacity,
                // Both follow from the method (RenderSettings::photon_settings).
                visibility: false,
                cap: self.cap,
                prove_clear: !self.trace_every_pair,
                visible_disk: !self.whole_disk,
                partial_disk_radius: !self.no_partial_disk_radius,
                walk_faces: true,
                node_radius: true,
                order_photons: true,
            },
        }
    }

    /// Loads the scene, printing its warnings.
    pub fn load_scene(&self) -> anyhow::Result<Scene> {
        let scene = Scene::load(&self.scene).with_context(|| format!("loading {}", self.scene.display()))?;
        for w in &scene.warnings {
            eprintln!("warning: {}: {w}", self.scene.display());
        }
        Ok(scene)
    }

    /// Applies `--time`, then `--camera` and `--light-position` (which win over the
    /// animation's) to a renderer.
    pub fn apply_view(&self, renderer: &mut leakless::Renderer, scene: &Scene) -> anyhow::Result<()> {
        renderer.set_time(self.time)?;
        if let Some(spec) = &self.camera {
            renderer.set_camera(spec.camera(scene)?);
        }
        if let Some(p) = self.light_position {
            let Some(light) = renderer.lights().first() else {
                anyhow::bail!("--light-position: scene {} has no punctual light to move", scene.name);
            };
            let mut light = light.clone();
            light.position = p;
            renderer.set_light(0, light)?;
        }
        renderer.set_exposure(self.exposure);
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn camera_flag_round_trips_bit_for_bit() {
        let spec = CameraSpec {
            eye: Vec3::new(0.1, -2.000_000_2, 1e-7),
            target: Vec3::new(std::f32::consts::PI, 0.3, -0.7),
            up: Vec3::Y,
            yfov_degrees: 39.597_75,
        };
        let back = parse_camera(&spec.flag()).unwrap();
        assert_eq!(back, spec);
        assert!(parse_camera("1,2,3").is_err());
        assert!(parse_camera("1,2,3,4,5,6,7,8,9,NaN").is_err());
    }
}

/// Where a benchmark also writes its figures.
#[derive(clap::Args)]
pub struct FigureFiles {
    /// Also write the figures to this CSV.
    #[arg(long)]
    pub csv: Option<std::path::PathBuf>,
    /// Also chart them: this SVG and a PNG beside it.
    #[arg(long)]
    pub chart: Option<std::path::PathBuf>,
}

/// Which radius a benchmark gathers at where it sets none.
#[derive(clap::Args, Clone, Copy, Debug, Default)]
pub struct FixedRadius {
    /// Gather at each scene's fixed radius, 5% of its bounding radius, instead of the one at
    /// which a kernel holds --kernel-photons' default (the figures docs/results.md gives "at the
    /// fixed radius" are measured so).
    #[arg(long)]
    pub fixed_radius: bool,
}

impl FixedRadius {
    /// The radius for `scene`: `None` (the photon count's) unless fixed.
    pub fn radius(self, scene: &Scene) -> Option<f32> {
        self.fixed_radius.then(|| leakless::splatting::auto_radius(scene))
    }
}
