//! What a render asks of the device, checked against the device's limits before anything is
//! allocated: each failure is one line naming the limit, its value and what exceeded it.
//! (Anything a pass dispatches is checked once more by the device layer at record time.)

use leakless_accel::BvhTriangle;
use leakless_device::DeviceLimits;
use leakless_scene::Scene;

use crate::error::{RenderError, Result};
use crate::gpu_scene::MAX_TRIANGLES;
use crate::passes::photons::Photon;
use crate::passes::splat::{PhotonPosition, SplatRecord};
use crate::settings::RenderSettings;
use crate::splatting::default_list_capacity;
use crate::trace::Backend;

/// Bytes per pixel of the images a frame keeps (G-buffer, layers, sums, counts: about two
/// dozen RGBA32F images) and of the readback (four layers and the display image).
const IMAGE_BYTES_PER_PIXEL: u64 = 24 * 16;
const READBACK_BYTES_PER_PIXEL: u64 = 4 * 16 + 4;
/// Bytes per triangle of the scene's buffers and trace structures (vertices, BVH, BLAS).
const SCENE_BYTES_PER_TRIANGLE: u64 = 512;

fn limit(message: String) -> RenderError {
    RenderError::Limit(message)
}

fn gib(bytes: u64) -> String {
    format!("{:.2} GiB", bytes as f64 / (1u64 << 30) as f64)
}

/// The most node-list entries one buffer of the device can hold (and the splat address): the
/// splat's records, the largest of the list buffers per entry.
pub fn max_list_entries(limits: &DeviceLimits) -> u32 {
    let per_entry = std::mem::size_of::<SplatRecord>() as u64;
    (limits.max_storage_buffer_range as u64 / per_entry).min(crate::splatting::MAX_LIST_CAPACITY as u64) as u32
}

/// What bounds the light paths of one frame with `max_bounces` on a device with `limits`: its
/// photon buffer within maxStorageBufferRange, its path and photon dispatches (64 threads a
/// group) within maxComputeWorkGroupCount.
struct FramePathLimits {
    by_buffer: u64,
    by_workgroups: u64,
}

fn frame_path_limits(limits: &DeviceLimits, max_bounces: u32) -> FramePathLimits {
    let bounces = max_bounces.max(1) as u64;
    let threads = limits.max_compute_work_group_count[0] as u64 * 64;
    FramePathLimits {
        by_buffer: limits.max_storage_buffer_range as u64 / (bounces * std::mem::size_of::<Photon>() as u64),
        // One thread a path, and one a photon stored (up to `bounces` a path).
        by_workgroups: threads / bounces,
    }
}

/// The most light paths one frame may trace with `max_bounces` on a device with `limits`.
/// [`check`] holds `--paths` to it; the frames of an accumulation grow to at most this many
/// paths (their batches are clamped to it).
pub fn max_frame_paths(limits: &DeviceLimits, max_bounces: u32) -> u64 {
    let bounds = frame_path_limits(limits, max_bounces);
    bounds.by_buffer.min(bounds.by_workgroups)
}

/// Checks `settings` on `scene` with the trace `backend` against `limits`.
pub fn check(settings: &RenderSettings, scene: &Scene, backend: Backend, limits: &DeviceLimits) -> Result<()> {
    let (w, h) = (settings.width, settings.height);
    let side = w.max(h);
    if side > limits.max_image_dimension_2d {
        return Err(limit(format!(
            "--size {w}x{h}: {side} pixels exceed the device's maxImageDimension2D ({})",
            limits.max_image_dimension_2d
        )));
    }
    let pixels = w as u64 * h as u64;
    let groups = |threads: u64, per_group: u64| threads.div_ceil(per_group);
    let max_groups = limits.max_compute_work_group_count[0] as u64;
    // The hierarchy, sort and gather run one thread per view sample along one axis.
    if settings.method.splats() && groups(pixels, 64) > max_groups {
        return Err(limit(format!(
            "--size {w}x{h}: {pixels} view samples need {} workgroups, above the device's maxComputeWorkGroupCount ({max_groups})",
            groups(pixels, 64)
        )));
    }
    let readback = pixels * READBACK_BYTES_PER_PIXEL;
    if readback > limits.max_buffer_size {
        return Err(limit(format!(
            "--size {w}x{h}: the layers read back need {} bytes, above the device's maxBufferSize ({})",
            readback, limits.max_buffer_size
        )));
    }

    let triangles = scene.triangle_count() as u64;
    // Checked first: a BLAS that cannot hold the scene is the limit a user can act on by
    // choosing the other backend. We fail rather than split the scene into several BLASes:
    // the per-triangle storage buffers below bind the whole scene at once and bound it far
    // earlier on most devices (lavapipe: 3.3 M triangles against 16.7 M primitives).
    // The static triangles share one BLAS; each animated instance has its own.
    let largest_blas = (scene.instances.iter().map(|i| i.triangle_count as u64))
        .chain([scene.static_triangle_count() as u64])
        .max()
        .unwrap_or(0);
    if backend == Backend::RayQuery && largest_blas > limits.max_primitive_count {
        let what = match (scene.instances.is_empty(), largest_blas == scene.static_triangle_count() as u64) {
            (true, _) => format!("the scene's {largest_blas} triangles"),
            (false, true) => format!("the scene's {largest_blas} static triangles"),
            (false, false) => format!("one animated instance's {largest_blas} triangles"),
        };
        return Err(limit(format!(
            "{what} exceed the device's maxPrimitiveCount ({}) for one BLAS; --backend compute has no such limit",
            limits.max_primitive_count
        )));
    }
    if triangles > MAX_TRIANGLES as u64 {
        return Err(limit(format!(
            "the scene's {triangles} triangles exceed the {MAX_TRIANGLES} the G-buffer's triangle ids can tell apart"
        )));
    }
    // The largest per-triangle storage buffer is the compute BVH's triangles (40 B a triangle,
    // against the vertex positions' or normals' 36 B), so it bounds them: 3.3M triangles on
    // 128 MiB. The BVH's nodes, 64 B for each interior node, are 32–40 B a triangle in the
    // shipped scenes (one triangle a leaf would make them 64), so `SceneBvh::build` checks
    // them once built.
    let range = limits.max_storage_buffer_range as u64;
    let triangle_bytes = triangles * std::mem::size_of::<BvhTriangle>() as u64;
    const _: () = assert!(3 * std::mem::size_of::<[f32; 3]>() <= std::mem::size_of::<BvhTriangle>());
    if triangle_bytes > range {
        return Err(limit(format!(
            "the scene's {triangles} triangles need {triangle_bytes} bytes of BVH triangles, above the device's maxStorageBufferRange ({range})"
        )));
    }
    let texel_bytes: u64 = scene.textures.iter().map(|t| 4 * t.texels.len() as u64).sum();
    if texel_bytes > range {
        return Err(limit(format!(
            "the scene's {} textures need {texel_bytes} bytes of texels, above the device's maxStorageBufferRange ({range})",
            scene.textures.len()
        )));
    }

    let mut photon_bytes = 0;
    let mut list_bytes = 0;
    if settings.method.splats() {
        let s = &settings.splat;
        let photons = s.paths as u64 * settings.max_bounces.max(1) as u64;
        photon_bytes = photons * std::mem::size_of::<Photon>() as u64;
        let bounds = frame_path_limits(limits, settings.max_bounces);
        if s.paths as u64 > bounds.by_buffer {
            return Err(limit(format!(
                "--paths {} × --max-bounces {}: the photon buffer needs {photon_bytes} bytes, above the device's maxStorageBufferRange ({range})",
                s.paths, settings.max_bounces
            )));
        }
        if s.paths as u64 > bounds.by_workgroups {
            return Err(limit(format!(
                "--paths {} × --max-bounces {}: {photons} photons stored need {} workgroups, above the device's maxComputeWorkGroupCount ({max_groups})",
                s.paths,
                settings.max_bounces,
                groups(photons, 64)
            )));
        }
        // The renderer keeps its own list capacity within the range (max_list_entries); a
        // capacity asked for must fit.
        let entries = match s.list_capacity {
            Some(n) => n,
            None => default_list_capacity(photons.min(u32::MAX as u64) as u32, pixels.min(u32::MAX as u64) as u32)
                .min(max_list_entries(limits)),
        };
        let record_bytes = entries as u64 * std::mem::size_of::<SplatRecord>() as u64;
        if record_bytes > range {
            return Err(limit(format!(
                "--list-capacity {entries}: {record_bytes} bytes, above the device's maxStorageBufferRange ({range})"
            )));
        }
        // The records, the lists' photon indices, and each photon's position for the gather.
        list_bytes = record_bytes + 4 * entries as u64 + photons * std::mem::size_of::<PhotonPosition>() as u64;
    }

    // Everything large at once, with two frames in flight for the per-frame buffers.
    let total = pixels * IMAGE_BYTES_PER_PIXEL
        + 2 * readback
        + photon_bytes * 2
        + list_bytes
        + triangles * SCENE_BYTES_PER_TRIANGLE;
    if limits.device_local_heap > 0 && total > limits.device_local_heap {
        return Err(limit(format!(
            "this render needs about {} of device memory (size {w}x{h}, {} photons' buffers, {} of lists), more than the device's largest heap ({})",
            gib(total),
            gib(photon_bytes * 2),
            gib(list_bytes),
            gib(limits.device_local_heap)
        )));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Method;

    fn limits() -> DeviceLimits {
        DeviceLimits {
            max_image_dimension_2d: 4096,
            max_storage_buffer_range: 1 << 27,
            max_buffer_size: 1 << 30,
            max_compute_work_group_count: [65535; 3],
            max_compute_work_group_invocations: 1024,
            max_compute_shared_memory_size: 32768,
            max_primitive_count: 1,
            device_local_heap: 1 << 32,
            max_per_stage: leakless_device::PerStageLimits {
                storage_buffers: 4,
                storage_images: 4,
                uniform_buffers: 12,
                resources: 128,
            },
            max_push_constants_size: 128,
        }
    }

    fn scene() -> Scene {
        let v = |p: [f32; 3]| leakless_scene::Vertex { position: p, normal: [0.0, 0.0, 1.0], uv: [0.0; 2] };
        let vertices = vec![
            v([0.0; 3]),
            v([1.0, 0.0, 0.0]),
            v([0.0, 1.0, 0.0]),
            v([1.0, 1.0, 0.0]),
            v([1.0, 0.0, 0.0]),
            v([0.0, 1.0, 0.0]),
        ];
        Scene::from_triangles(
            "two",
            vertices,
            vec![0, 0],
            vec![leakless_scene::Material::default_white()],
            vec![],
            None,
        )
    }

    fn error(settings: &RenderSettings, backend: Backend) -> String {
        check(settings, &scene(), backend, &limits()).unwrap_err().to_string()
    }

    #[test]
    fn each_limit_is_named_with_its_value() {
        let ok = RenderSettings { width: 64, height: 48, ..Default::default() };
        assert!(check(&ok, &scene(), Backend::Compute, &limits()).is_ok());
        let big = RenderSettings { width: 5000, ..ok.clone() };
        assert!(error(&big, Backend::Compute).contains("maxImageDimension2D (4096)"));
        // Two triangles, one allowed per BLAS: ray queries refuse, the compute BVH does not.
        assert!(error(&ok, Backend::RayQuery).contains("2 triangles exceed the device's maxPrimitiveCount (1)"));
        let mut many = ok.clone();
        many.splat.paths = 1_000_000; // 8M photons × 64 B > 2^27
        assert!(
            error(&many, Backend::Compute).contains("maxStorageBufferRange (134217728)"),
            "{}",
            error(&many, Backend::Compute)
        );
        // check() holds --paths to max_frame_paths exactly, whichever limit binds: the photon
        // buffer (2^27 B / (8 bounces × 64 B) = 262,144 paths) or the workgroups of the photons
        // stored (65,535 × 64 / 8 = 524,280 paths with a 2 GiB range).
        let cases = [(1u32 << 27, 262_144, "maxStorageBufferRange"), (1 << 31, 524_280, "maxComputeWorkGroupCount")];
        for (range, expected, binds) in cases {
            let device = DeviceLimits { max_storage_buffer_range: range, ..limits() };
            let most = max_frame_paths(&device, ok.max_bounces);
            assert_eq!(most, expected);
            let mut at = ok.clone();
            at.splat.paths = most as u32;
            assert!(check(&at, &scene(), Backend::Compute, &device).is_ok(), "{most} paths");
            at.splat.paths += 1;
            let e = check(&at, &scene(), Backend::Compute, &device).unwrap_err().to_string();
            assert!(e.contains(binds), "{e}");
        }
        many.method = Method::Reference; // no photons: nothing to hold
        assert!(check(&many, &scene(), Backend::Compute, &limits()).is_ok());
        let wide = RenderSettings { width: 2000, height: 2000, ..ok.clone() };
        let mut small_heap = limits();
        small_heap.device_local_heap = 1 << 30;
        let e = check(&wide, &scene(), Backend::Compute, &small_heap).unwrap_err().to_string();
        assert!(e.contains("more than the device's largest heap (1.00 GiB)"), "{e}");
        // One workgroup per 64 view samples: 4096² needs 262,144 along one axis.
        let e = error(&RenderSettings { width: 4096, height: 4096, ..ok.clone() }, Backend::Compute);
        assert!(e.contains("maxComputeWorkGroupCount (65535)"), "{e}");
        let mut lists = ok.clone();
        lists.splat.list_capacity = Some(1 << 25); // 256 MiB of entries
        assert!(error(&lists, Backend::Compute).contains("--list-capacity 33554432"));
        assert_eq!(max_list_entries(&limits()), 1 << 24);
        // The largest per-triangle storage buffer, the BVH's triangles: 2 triangles × 40 B.
        let mut tiny = limits();
        tiny.max_primitive_count = 16;
        tiny.max_storage_buffer_range = 79;
        let e = check(&ok, &scene(), Backend::RayQuery, &tiny).unwrap_err().to_string();
        assert!(e.contains("need 80 bytes of BVH triangles, above the device's maxStorageBufferRange (79)"), "{e}");
        tiny.max_storage_buffer_range = 80;
        assert!(
            check(&RenderSettings { method: Method::Direct, ..ok.clone() }, &scene(), Backend::RayQuery, &tiny).is_ok()
        );
    }
}
