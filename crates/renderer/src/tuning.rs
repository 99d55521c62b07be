//! Per-device tuning: the choices that make the same frame fast on a CPU driver or on a GPU,
//! picked once from what the device reports and printed by `leakless info` and in `--stats`.
//!
//! Nothing else may depend on the kind of device: a choice that does belongs here, with the
//! reason it differs. (The one older exception is `auto`'s trace backend, `trace.rs`, chosen
//! before a renderer exists and printed with its reason; a chart's axis also says when its
//! times are CPU time.) The CPU preset is what lavapipe was measured and tuned
//! with (8-lane SIMD groups on a few cores, where a workgroup is a loop and local memory is
//! cache); changing it changes lavapipe's images or speed, and the image-hash test guards the
//! first. The GPU preset is the starting point for GPUs (32- or 64-lane subgroups, thousands
//! of threads in flight, registers and local memory scarce, global atomics contended); its
//! values are unmeasured until `tools/gpu-report` has run on one (docs/architecture.md §10).
//! No choice changes an image beyond the order photons are stored in, which the gather's
//! fixed-point sums do not see.

use leakless_device::{DeviceReport, DeviceType, Specialization};
use leakless_graph::Timing;
use serde::Serialize;

use crate::error::{RenderError, Result};
use crate::passes::photon_dispatch::PHOTON_WORKGROUP;

/// Which preset a renderer uses: the device's own (`auto`), or one forced to test the other's
/// code paths (`--tuning gpu` on lavapipe runs the subgroup counters and the GPU's queue and
/// workgroup sizes).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum TuningChoice {
    #[default]
    Auto,
    Cpu,
    Gpu,
}

crate::value_enum!(TuningChoice);

impl TuningChoice {
    pub const ALL: [TuningChoice; 3] = [Self::Auto, Self::Cpu, Self::Gpu];

    /// What `--tuning` calls it.
    pub fn name(self) -> &'static str {
        match self {
            Self::Auto => "auto",
            Self::Cpu => "cpu",
            Self::Gpu => "gpu",
        }
    }
}

/// How `--primary auto` finds a frame's view samples on a device ([`DeviceTuning::primary_auto`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum PrimaryAuto {
    /// The G-buffer raster.
    Raster,
    /// A ray a pixel where the scene has more triangles than the image has pixels, else the
    /// raster.
    RaysOverDenseMeshes,
    /// A ray a pixel.
    Rays,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Preset {
    Cpu,
    Gpu,
}

/// What the renderer tunes to its device.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct DeviceTuning {
    pub preset: Preset,
    /// The device's vendor and subgroup size, as chosen from.
    pub vendor: String,
    pub subgroup_size: u32,
    /// Branching factor B of the view-sample hierarchy, unless `--branching` sets it. On the
    /// CPU, 8 makes one 8-lane SIMD group one leaf (and measured fastest of 4/8/16/32).
    pub branching: u32,
    /// Light paths each photon thread traces. A CPU runs a few hundred threads at a time and
    /// pays for each one's start; a GPU wants one path per thread, many threads in flight.
    pub paths_per_thread: u32,
    /// Threads take paths grouped by emission cell (emission_order.rs): coherent rays, at the
    /// cost of four small passes, one a single-workgroup scan.
    pub emission_order: bool,
    /// Photons copied in cell order before the splat (photon_order.rs).
    pub photon_order: bool,
    /// Visibility segments a gather thread queues before tracing them together
    /// (`RAY_QUEUE`, gather.comp): 4 bytes each, per thread, of local memory, or of shared
    /// memory where the walk is shared (its subgroup then traces its lanes' queues as one pool,
    /// `RAY_POOL`), which bounds it by the device's `maxComputeSharedMemorySize`.
    pub ray_queue: u32,
    /// Workgroup size of the gather (`local_size_x`; one thread per view sample). The passes
    /// over photons keep 64: their indirect dispatches are counted in 64-thread groups.
    pub gather_workgroup: u32,
    /// Counter additions and list-slot reservations combined per subgroup (one atomic per
    /// subgroup instead of one per thread; `SUBGROUP_COUNTERS`). Needs subgroup ballot and
    /// arithmetic in compute shaders.
    pub subgroup_counters: bool,
    /// The lanes of a subgroup walk the gather's node lists together (`SHARED_WALK`,
    /// gather.comp): a subgroup's width of entries read at once, one a lane, and shuffled to
    /// the lanes of its node, which test them. On where the device has subgroup operations in
    /// compute shaders and a subgroup is no wider than a leaf (lavapipe: 8 lanes, branching 8,
    /// where the gather takes 0.53–0.66× the per-lane walk's time, docs/results.md); the GPU
    /// report's sweep measures it on a GPU. The same candidates in the same order either way.
    pub shared_walk: bool,
    /// Where the walk is shared and a subgroup spans several leaves, its lanes walk in aligned
    /// clusters of this many, each its own lists side by side (`WALK_CLUSTER`, gather.comp): a
    /// leaf's width, the largest power of two dividing the branching (an H200's 32 lanes walk
    /// four leaves of 8 at once, where one subgroup-wide walk would take them in turn). 0: the
    /// subgroup is one cluster (lavapipe's 8 lanes, a leaf). The same candidates either way.
    pub walk_cluster: u32,
    /// Where the walk is shared, a subgroup's lanes wait for each other (`subgroupBarrier`)
    /// between writing their ray queues to the pool and tracing it (`POOL_WAIT`, gather.comp):
    /// a GPU's lanes need not run in step. Chosen by the device, not the preset: off on a CPU
    /// device, whose subgroup is one SIMD vector whose lanes cannot be out of step, and where
    /// lavapipe (Mesa 25.0) makes a subgroup's execution barrier a wait for the whole
    /// workgroup: subgroups that traced their pools different numbers of times then lost view
    /// samples (16,752 of 19,200 counted on the atrium at 160×120).
    pub pool_wait: bool,
    /// How `bench` and `render --stats` time passes: each submitted alone and timed on the
    /// host (lavapipe runs dispatches asynchronously to its timestamp writes, so only the host
    /// sees their time), or GPU timestamps inside one submission (on a GPU, a submission per
    /// pass would add a fence wait to each of about 60 passes).
    #[serde(serialize_with = "timing_name")]
    pub timing: Timing,
    /// The app's rendered size and render scale without `--size` / `--render-scale`: on a CPU,
    /// where every pixel costs, 320×240 shown at twice its size; on a GPU 1280×720 at 1:1.
    pub view_size: (u32, u32),
    pub view_render_scale: f32,
    /// The app times a frame pass by pass (each submitted alone) every this many frames, for
    /// its bars, where timestamps in one submission do not bracket the work (0: never).
    pub view_profile_every: u32,
    /// The app's frame-time budget without `--frame-ms` (`frame_budget/`): 60 frames a
    /// second on a GPU; on a CPU about what lavapipe takes for a moving frame of the default
    /// scene (the Cornell box) at the CPU view size with `--paths`' default and `--frame-ms
    /// off` (docs/results.md, "Frame budget").
    pub frame_ms: f64,
    /// Lanes that walk one photon's hierarchy together in the splat (1: a thread a photon;
    /// splat.comp). A power of two, at most the subgroup's width. Where a frame has few
    /// photons, a thread each leaves a GPU nearly idle: on the H200 at 1080p the splat took
    /// 8.7 ms at 10k paths and 3.6 ms at 200k (docs/gpu.md), each photon's walk a chain of
    /// dependent node loads. A cluster tests a node's children side by side, one contiguous read.
    pub splat_lanes: u32,
    /// The splat takes a photon onto a leaf wider than the radius only where one of its
    /// samples can gather it (`LEAF_SAMPLES`, splat.comp): where the Morton order jumps, a
    /// leaf's samples lie far apart and its list met about 40% of all photons, each a
    /// candidate of all 8 samples, a chain a GPU's gather waits for (on the H200 the gather
    /// took as long at 720p as at 1080p, and 14 times longer at twenty times the photons). The
    /// images are the same either way. On lavapipe the tests cost the splat more than the
    /// gather saves (320×240, best of 3: frames 0.67–1.16× as fast, docs/results.md), so the CPU
    /// preset leaves them out.
    pub leaf_samples: bool,
    /// How `--primary auto` finds view samples ([`PrimaryAuto`]). On a CPU, lavapipe's
    /// rasteriser costs about half a microsecond a triangle whatever the image size (the
    /// basilica's 210k triangles: 110 ms at 320×240 and at 160×120), a ray a pixel 0.6 µs (49 ms
    /// at 320×240); the two are even at 640×480 (docs/results.md, "View samples"): rays above a
    /// triangle a pixel. On a GPU without ray queries, a chip without ray-tracing hardware such
    /// as the H200, the compute BVH's ray a pixel: there the G-buffer raster of the atrium's few
    /// thousand triangles took 6.5 ms of a 1080p frame, and the frame by rays 40.6 ms against
    /// 47.1 (docs/gpu.md). On a GPU with ray queries the raster (unmeasured): such a chip has
    /// the graphics hardware that the H200 gives little of its area. A GPU from before ray
    /// tracing (no ray queries, a full rasteriser) is taken for the H200's kind, wrongly:
    /// `--primary raster` asks for its raster.
    pub primary_auto: PrimaryAuto,
    /// The gather counts its visibility rays' traversal work (`TRACE_COUNT_WORK`,
    /// trace_compute.glsl; `render --count-work`): off by default on every device, since the
    /// counts cost two additions a step. Ray queries count nothing.
    pub count_work: bool,
    /// The most workgroups a dispatch over the frame's photons or list records takes before
    /// its threads loop over the rest (the clustered splat, the list scatter; 0: the device's
    /// `maxComputeWorkGroupCount[0]`, on every device). A smaller cap makes those loops run
    /// at the sizes tests render (`tests/suite/tuning.rs`); the images are the same.
    pub dispatch_groups: u32,
}

fn timing_name<S: serde::Serializer>(timing: &Timing, s: S) -> std::result::Result<S::Ok, S::Error> {
    s.serialize_str(match timing {
        Timing::Timestamps => "timestamps",
        Timing::PerPassSubmit => "per-pass-submit",
    })
}

impl DeviceTuning {
    /// The tuning `choice` gives on the device `report` describes.
    pub fn choose(report: &DeviceReport, choice: TuningChoice) -> DeviceTuning {
        let preset = match choice {
            TuningChoice::Cpu => Preset::Cpu,
            TuningChoice::Gpu => Preset::Gpu,
            TuningChoice::Auto if report.device_type == DeviceType::Cpu => Preset::Cpu,
            TuningChoice::Auto => Preset::Gpu,
        };
        let mut tuning = match preset {
            Preset::Cpu => Self::cpu(),
            Preset::Gpu => Self::gpu(report.subgroup_arithmetic),
        };
        tuning.vendor = report.vendor();
        tuning.subgroup_size = report.subgroup_size;
        // A subgroup no wider than a leaf walks one list a level; a wider one would walk its
        // leaves one after the other, where its lanes walked them side by side.
        tuning.shared_walk = report.subgroup_arithmetic && report.subgroup_size <= tuning.branching;
        tuning.walk_cluster = Self::leaf_cluster(report.subgroup_size, tuning.branching);
        tuning.pool_wait = report.device_type != DeviceType::Cpu;
        // A GPU without ray queries (by the device, not the preset: `--tuning gpu` on lavapipe
        // keeps the raster that its images were made with).
        if report.device_type != DeviceType::Cpu && !report.ray_query {
            tuning.primary_auto = PrimaryAuto::Rays;
        }
        // The splat's clusters need subgroups at least as wide, a whole number of them a workgroup.
        if !Self::splat_lanes_fit(tuning.splat_lanes, report) {
            tuning.splat_lanes = 1;
        }
        // Pooled, the queues share the workgroup's shared memory: a preset's length (the GPU's
        // 512 was measured in local memory) shrinks to what the device holds.
        if tuning.shared_walk {
            let fits = report.limits.max_compute_shared_memory_size / (4 * tuning.gather_workgroup);
            tuning.ray_queue = tuning.ray_queue.min(fits.max(1));
        }
        tuning
    }

    /// lavapipe's values (today's images and speed).
    pub fn cpu() -> DeviceTuning {
        DeviceTuning {
            preset: Preset::Cpu,
            vendor: String::new(),
            subgroup_size: 0,
            branching: 8,
            paths_per_thread: 8,
            emission_order: true,
            photon_order: true,
            ray_queue: 64,
            gather_workgroup: 64,
            subgroup_counters: false,
            shared_walk: false,
            walk_cluster: 0,
            splat_lanes: 1,
            leaf_samples: false,
            pool_wait: false,
            timing: Timing::PerPassSubmit,
            view_size: (320, 240),
            view_render_scale: 0.5,
            view_profile_every: 30,
            frame_ms: 150.0,
            primary_auto: PrimaryAuto::RaysOverDenseMeshes,
            count_work: false,
            dispatch_groups: 0,
        }
    }

    /// A GPU's values: one path per thread, counters combined per subgroup where the device
    /// can, passes timed inside one submission, the splat's photons walked by clusters of 8
    /// lanes (unmeasured on a GPU; see `splat_lanes`). The rest is what the GPU report measured
    /// on an H200 (docs/gpu.md): both orders on (photon order off: the 1080p frame 9% slower),
    /// and a 512-entry ray queue (64 to 1024 entries within 1% of each other there). Branching is 8 on
    /// every device, whatever is fastest on one: it decides which photons the capped method
    /// keeps and the hierarchy's counts, which no tuning choice may change
    /// (`tests/suite/tuning.rs`; the branching sweep is in docs/gpu.md).
    pub fn gpu(subgroup_arithmetic: bool) -> DeviceTuning {
        DeviceTuning {
            preset: Preset::Gpu,
            paths_per_thread: 1,
            ray_queue: 512,
            subgroup_counters: subgroup_arithmetic,
            pool_wait: true,
            timing: Timing::Timestamps,
            view_size: (1280, 720),
            view_render_scale: 1.0,
            view_profile_every: 0,
            frame_ms: 16.7,
            primary_auto: PrimaryAuto::Raster,
            splat_lanes: 8,
            leaf_samples: true,
            ..Self::cpu()
        }
    }

    /// One line for `leakless info` and logs.
    pub fn summary(&self) -> String {
        format!(
            "{} preset: branching {}, {} paths/thread, emission order {}, photon order {}, ray queue {}, \
             gather workgroup {}, subgroup counters {}, shared walk {}{} (pooled rays, lanes {}), splat lanes {}, leaf samples tested {}, timing {}, primary auto {}",
            match self.preset {
                Preset::Cpu => "cpu",
                Preset::Gpu => "gpu",
            },
            self.branching,
            self.paths_per_thread,
            on(self.emission_order),
            on(self.photon_order),
            self.ray_queue,
            self.gather_workgroup,
            on(self.subgroup_counters),
            on(self.shared_walk),
            match self.walk_cluster {
                0 => String::new(),
                c => format!(" in clusters of {c}"),
            },
            if self.pool_wait { "waiting for each other" } else { "in step" },
            self.splat_lanes,
            on(self.leaf_samples),
            match self.timing {
                Timing::Timestamps => "GPU timestamps in one submission",
                Timing::PerPassSubmit => "one submission per pass, host-timed",
            },
            match self.primary_auto {
                PrimaryAuto::Raster => "raster",
                PrimaryAuto::RaysOverDenseMeshes => "rays above a triangle a pixel",
                PrimaryAuto::Rays => "rays",
            }
        )
    }

    /// The clusters a shared walk takes on a subgroup of `subgroup_size` lanes over leaves of
    /// `branching` samples: the largest power of two dividing the branching, where that is
    /// narrower than the subgroup (0 where the whole subgroup is one cluster).
    pub fn leaf_cluster(subgroup_size: u32, branching: u32) -> u32 {
        let leaf = 1u32 << branching.max(1).trailing_zeros();
        if leaf < subgroup_size {
            leaf
        } else {
            0
        }
    }

    /// The gather's specialization constants.
    pub fn gather(&self) -> Specialization {
        Specialization::new()
            .with("local_size_x", self.gather_workgroup)
            .with("RAY_QUEUE", self.ray_queue)
            .with("SUBGROUP_COUNTERS", self.subgroup_counters as u32)
            .with("SHARED_WALK", self.shared_walk as u32)
            .with("WALK_CLUSTER", self.walk_cluster)
            .with("RAY_POOL", self.ray_pool_words())
            .with("POOL_WAIT", self.pool_wait as u32)
            .with("TRACE_COUNT_WORK", self.count_work as u32)
    }

    /// The words of shared memory the gather's pooled ray queues take (1, a placeholder, where
    /// the walk is not shared and each lane keeps its queue in local memory).
    pub fn ray_pool_words(&self) -> u32 {
        if self.shared_walk {
            self.ray_queue * self.gather_workgroup
        } else {
            1
        }
    }

    /// The photon pass's, and others' that count with the subgroup counters.
    pub fn counters(&self) -> Specialization {
        Specialization::new().with("SUBGROUP_COUNTERS", self.subgroup_counters as u32)
    }

    /// Whether the splat can walk a photon with `lanes` lanes on the device: one lane, or
    /// subgroup shuffles on subgroups at least that wide, a whole number of them in a workgroup.
    fn splat_lanes_fit(lanes: u32, report: &DeviceReport) -> bool {
        lanes == 1
            || (report.subgroup_arithmetic
                && lanes <= report.subgroup_size
                && PHOTON_WORKGROUP % report.subgroup_size.max(1) == 0)
    }

    /// The splat's.
    pub fn splat(&self) -> Specialization {
        self.counters().with("SPLAT_LANES", self.splat_lanes).with("LEAF_SAMPLES", self.leaf_samples as u32)
    }

    /// The most workgroups a looping dispatch takes on a device whose limit is `device_max`.
    pub fn max_workgroups(&self, device_max: u32) -> u32 {
        match self.dispatch_groups {
            0 => device_max,
            cap => cap.min(device_max),
        }
    }

    /// The hierarchy build's: it writes the sorted samples' positions only for the splat's
    /// test of a wide leaf (`leaf_samples`), which alone reads them.
    pub fn hierarchy_build(&self) -> Specialization {
        Specialization::new().with("LEAF_SAMPLES", self.leaf_samples as u32)
    }

    /// Checks values a user or a test set by hand against each other and the device.
    pub fn validate(&self, report: &DeviceReport) -> Result<()> {
        let bad = |what: &str| Err(RenderError::Settings(format!("tuning: {what}")));
        if self.subgroup_counters && !report.subgroup_arithmetic {
            return bad(&format!("subgroup counters need subgroup ballot and arithmetic, which {} lacks", report.name));
        }
        let lanes = self.splat_lanes;
        if !lanes.is_power_of_two() || lanes > PHOTON_WORKGROUP {
            return bad(&format!("splat lanes {lanes} must be a power of two within 1..={PHOTON_WORKGROUP}"));
        }
        if !Self::splat_lanes_fit(lanes, report) {
            return bad(&format!(
                "splat lanes {lanes} need subgroup shuffles, subgroups of at least {lanes} lanes and a whole number of them in {PHOTON_WORKGROUP} threads: {} has {}-lane subgroups{}",
                report.name,
                report.subgroup_size,
                if report.subgroup_arithmetic { "" } else { " without arithmetic" }
            ));
        }
        if self.shared_walk && !report.subgroup_arithmetic {
            return bad(&format!("a shared walk needs subgroup arithmetic, which {} lacks", report.name));
        }
        if !(1..=1024).contains(&self.ray_queue) {
            return bad(&format!("ray queue {} must be within 1..=1024", self.ray_queue));
        }
        if self.paths_per_thread == 0 {
            return bad("paths per thread must be at least 1");
        }
        let size = self.gather_workgroup;
        if !size.is_power_of_two() || !(8..=1024).contains(&size) {
            return bad(&format!("gather workgroup {size} must be a power of two within 8..=1024"));
        }
        if self.shared_walk {
            // A pooled lane finds its subgroup's queues by subgroup id and lane, which stay
            // within the workgroup only where it is a whole number of subgroups.
            if size % report.subgroup_size.max(1) != 0 {
                return bad(&format!(
                    "a shared walk needs the gather workgroup ({size}) to be a whole number of {}-lane subgroups",
                    report.subgroup_size
                ));
            }
            let c = self.walk_cluster;
            if c != 0 && (!c.is_power_of_two() || c >= report.subgroup_size) {
                return bad(&format!(
                    "walk clusters of {c} lanes must be a power of two narrower than {}'s {}-lane subgroups (0: the whole subgroup)",
                    report.name, report.subgroup_size
                ));
            }
            let bytes = 4 * self.ray_pool_words() as u64;
            let most = report.limits.max_compute_shared_memory_size as u64;
            if bytes > most {
                return bad(&format!(
                    "ray queue {} × gather workgroup {size} × 4 bytes = {bytes} bytes of shared memory, above {}'s maxComputeSharedMemorySize ({most})",
                    self.ray_queue, report.name
                ));
            }
        }
        Ok(())
    }
}

fn on(b: bool) -> &'static str {
    if b {
        "on"
    } else {
        "off"
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The CPU preset is what lavapipe's images and figures were made with.
    #[test]
    fn cpu_preset_keeps_todays_values() {
        let t = DeviceTuning::cpu();
        assert_eq!((t.branching, t.paths_per_thread, t.ray_queue), (8, 8, 64));
        assert_eq!(t.gather_workgroup, 64);
        assert!(t.emission_order && t.photon_order && !t.subgroup_counters);
        assert_eq!(t.timing, Timing::PerPassSubmit);
    }

    #[test]
    fn gpu_preset_uses_subgroups_only_where_the_device_has_them() {
        assert!(DeviceTuning::gpu(true).subgroup_counters);
        assert!(!DeviceTuning::gpu(false).subgroup_counters);
        let g = DeviceTuning::gpu(true);
        assert_eq!((g.paths_per_thread, g.ray_queue, g.timing), (1, 512, Timing::Timestamps));
        assert!(g.pool_wait && !DeviceTuning::cpu().pool_wait);
    }

    /// The pooled queues take the queue's length for every thread of the workgroup where the
    /// walk is shared, and a placeholder word where each lane keeps its own.
    #[test]
    fn the_ray_pool_is_sized_by_the_queue_and_the_workgroup_only_where_the_walk_is_shared() {
        let shared = DeviceTuning { shared_walk: true, ray_queue: 64, gather_workgroup: 128, ..DeviceTuning::cpu() };
        assert_eq!(shared.ray_pool_words(), 64 * 128);
        assert_eq!(DeviceTuning { shared_walk: false, ..shared }.ray_pool_words(), 1);
    }

    /// A subgroup wider than a leaf walks in clusters of a leaf; one no wider is one cluster.
    #[test]
    fn walk_clusters_are_a_leaf_where_the_subgroup_spans_several() {
        assert_eq!(DeviceTuning::leaf_cluster(32, 8), 8);
        assert_eq!(DeviceTuning::leaf_cluster(64, 8), 8);
        assert_eq!(DeviceTuning::leaf_cluster(8, 8), 0);
        assert_eq!(DeviceTuning::leaf_cluster(4, 8), 0);
        assert_eq!(DeviceTuning::leaf_cluster(32, 12), 4);
        assert_eq!(DeviceTuning::leaf_cluster(32, 64), 0);
        assert_eq!(DeviceTuning::leaf_cluster(8, 2), 2);
    }
}
