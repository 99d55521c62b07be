//! Radix sort of (key, value) u32 pairs on the GPU, as passes of the frame's graph
//! (`sort_histogram.comp`, `sort_scan.comp`, `sort_scatter.comp`, `sort_copy.comp`).
//!
//! LSD, stable, 4-bit digits. Each digit pass is three graph passes:
//!
//! 1. **histogram** — workgroup `g` counts the digits of its block of [`BLOCK`] keys and
//!    stores them digit-major (`histograms[d * groups + g]`);
//! 2. **scan** — one workgroup turns those counts into exclusive prefix sums in place: the
//!    first output position of digit `d` of block `g`;
//! 3. **scatter** — workgroup `g` ranks each element among the elements of its digit in the
//!    block (a per-digit workgroup prefix sum in shared memory, then the earlier items of the
//!    same thread; no subgroup operations) and writes it to `offset + rank`. Elements keep
//!    their order within a digit, so the sort is stable.
//!
//! The digit passes ping-pong between the caller's buffers and a scratch pair owned by the
//! sort; an odd number of digit passes ends with a copy pass, so the sorted pairs always end in
//! the caller's buffers.
//!
//! **Keys out of range, and the sentinel.** `key_bits` says how many low bits valid keys use.
//! Every key at or above `2^key_bits` (such as the `0xFFFFFFFF` of an invalid pixel) is ordered
//! as `2^key_bits` itself: after every valid key, and among the other out-of-range keys in
//! input order; the keys themselves are moved unchanged. The passes therefore sort `key_bits +
//! 1` bits (32 at most): for 30-bit Morton codes, 31 bits, the same 8 digit passes as a full
//! 32-bit sort. Sorting only the low 30 bits would instead order the sentinel by its low 30
//! bits, all ones, as a valid key `0x3FFFFFFF`, and a key with higher bits set as its low bits.

use ash::vk;
use bytemuck::{Pod, Zeroable};
use leakless_device::shader::ShaderInfo;
use leakless_device::{gpu_struct, BufferDesc, GpuStruct, MemoryLocation};
use leakless_graph::{shader_bindings, BufferHandle, Graph, PassName};

use crate::error::{RenderError, Result};
use crate::passes::names::group;
use crate::passes::scan;
use crate::pipelines::Threads;
use crate::pipelines::{compute_pass, ComputePass};
use crate::shaders;
use leakless_graph::BindingGroup;

/// Threads per workgroup of every sort shader (`SORT_WORKGROUP_SIZE` in sort.glsl, checked
/// against reflection).
pub const WORKGROUP_SIZE: u32 = 256;
/// Consecutive elements per thread in the histogram and scatter passes (`SORT_ITEMS`; not
/// reflected: a mismatch fails every test of `tests/suite/sort.rs` longer than one block).
/// Measured on lavapipe at 640×480: 4 → ~30 ms, 8 → ~23-36, 16 → ~20, 32 → ~23-27 (noisy).
pub const ITEMS_PER_THREAD: u32 = 16;
/// Elements per workgroup of the histogram and scatter passes.
pub const BLOCK: u32 = WORKGROUP_SIZE * ITEMS_PER_THREAD;
/// Bits per digit: 16 buckets.
pub const DIGIT_BITS: u32 = 4;
pub(crate) const RADIX: u32 = 1 << DIGIT_BITS;
/// Workgroups the histogram and scatter passes may dispatch: Vulkan's guaranteed minimum of
/// `maxComputeWorkGroupCount[0]`, so the bound holds on every device.
pub const MAX_GROUPS: u32 = 65_535;
/// The most elements one sort handles: [`MAX_GROUPS`] blocks of [`BLOCK`] (268,431,360, 32
/// times a 3840×2160 frame); past it the histogram and scatter dispatches would exceed the
/// workgroup count every device allows. The scan, one workgroup of 256 threads, walks the
/// `16 × groups` counts in tiles of 4096 with a running carry, so it has no capacity of its
/// own, only a cost linear in the count: 1,200 counts (1 tile) at 640×480, 32,400 (8 tiles,
/// ~130 counts per thread) at 3840×2160, 1,048,560 (256 tiles, 4096 per thread) at this limit,
/// where it reads 4 MB per digit pass against the 5.4 GB the histogram and scatter passes move
/// (keys read twice, values read, both written).
pub const MAX_LEN: u32 = MAX_GROUPS * BLOCK;
/// Digit passes of a 32-bit sort.
pub const MAX_DIGIT_PASSES: u32 = 32 / DIGIT_BITS;

gpu_struct! {
    /// The `SortParams` push constants of sort.glsl: one digit pass.
    #[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
    pub struct SortParams {
        pub len: u32,
        /// The digit is `(min(key, key_limit) >> shift) & 15`.
        pub shift: u32,
        /// `2^key_bits`, or `u32::MAX` for 32-bit keys.
        pub key_limit: u32,
        /// Workgroups of the histogram and scatter passes: `len.div_ceil(BLOCK)`.
        pub group_count: u32,
    }
}

shader_bindings! {
    pub struct HistogramBindings {
        keys_in: read array(u32::LAYOUT),
        histograms: write array(u32::LAYOUT),
    }
    pub struct HistogramResources;
}

shader_bindings! {
    pub struct ScatterBindings {
        keys_in: read array(u32::LAYOUT),
        values_in: read array(u32::LAYOUT),
        histograms: read array(u32::LAYOUT),
        keys_out: write array(u32::LAYOUT),
        values_out: write array(u32::LAYOUT),
    }
    pub struct ScatterResources;
}

shader_bindings! {
    pub struct CopyBindings {
        keys_in: read array(u32::LAYOUT),
        values_in: read array(u32::LAYOUT),
        keys_out: write array(u32::LAYOUT),
        values_out: write array(u32::LAYOUT),
    }
    pub struct CopyResources;
}

/// Digit passes for keys of `key_bits` valid bits: `key_bits + 1` bits (out-of-range keys
/// sort as `2^key_bits`), at most 32, in 4-bit digits.
pub fn digit_passes(key_bits: u32) -> u32 {
    (key_bits + 1).min(32).div_ceil(DIGIT_BITS)
}

/// Graph passes one [`add`] adds: three per digit pass, plus a copy after an odd
/// number of them. 24 for 30-bit Morton codes and for 32-bit keys.
pub fn graph_passes(key_bits: u32) -> u32 {
    let digits = digit_passes(key_bits);
    3 * digits + digits % 2
}

/// The ordering the sort implements, for CPU references: keys compare as
/// `min(key, 2^key_bits)`.
pub fn sort_key(key: u32, key_bits: u32) -> u32 {
    key.min(key_limit(key_bits))
}

fn key_limit(key_bits: u32) -> u32 {
    if key_bits >= 32 {
        u32::MAX
    } else {
        1 << key_bits
    }
}

/// A pass of the sort (or its scan): one workgroup size, the sort's push constants.
pub(crate) const fn sort_pass<B: BindingGroup>(
    name: PassName,
    shader: &'static ShaderInfo,
) -> ComputePass<B, SortParams> {
    ComputePass::any(name, shader, &[]).workgroup([WORKGROUP_SIZE, 1, 1])
}

compute_pass! {
    pub static SORT_HISTOGRAM in FRAME_PASSES: ComputePass<HistogramBindings, SortParams> =
        sort_pass(PassName::new("sort histogram", group::HIERARCHY), &shaders::SORT_HISTOGRAM_COMP);
    pub static SORT_SCATTER in FRAME_PASSES: ComputePass<ScatterBindings, SortParams> =
        sort_pass(PassName::new("sort scatter", group::HIERARCHY), &shaders::SORT_SCATTER_COMP);
    pub static SORT_COPY in FRAME_PASSES: ComputePass<CopyBindings, SortParams> =
        sort_pass(PassName::new("sort copy", group::HIERARCHY), &shaders::SORT_COPY_COMP);
}

/// Sorts the first `len` (key, value) pairs of `keys` / `values` by key, stably, and leaves
/// them there (elements past `len` are untouched). Keys at or above `2^key_bits` sort last,
/// in input order (see the module documentation); `key_bits = 30` for Morton codes with the
/// `0xFFFFFFFF` sentinel, 32 for arbitrary keys. Adds [`graph_passes`]`(key_bits)` passes
/// named "sort histogram i", "sort scan i", "sort scatter i" (and "sort copy"), and takes
/// its scratch buffers from the graph's pool. On an error the graph may hold some of the
/// passes: drop it.
pub fn add<'r>(
    graph: &mut Graph<'r>,
    len: u32,
    key_bits: u32,
    keys: &mut BufferHandle,
    values: &mut BufferHandle,
) -> Result<()> {
    if len > MAX_LEN {
        return Err(too_long(len));
    }
    if key_bits > 32 {
        return Err(RenderError::Settings(format!("radix sort: key_bits {key_bits} > 32")));
    }
    if len == 0 {
        return Ok(());
    }
    for b in [&*keys, &*values] {
        if b.size() < 4 * len as u64 {
            return Err(RenderError::Settings(format!(
                "radix sort of {len} elements: a buffer holds only {} bytes",
                b.size()
            )));
        }
    }
    let group_count = len.div_ceil(BLOCK);
    let key_limit = key_limit(key_bits);
    let digits = digit_passes(key_bits);
    let mut storage = |name, words: u64| {
        graph.buffer(&BufferDesc {
            name,
            size: 4 * words,
            usage: vk::BufferUsageFlags::STORAGE_BUFFER,
            location: MemoryLocation::GpuOnly,
        })
    };
    let mut histograms = storage("sort histograms", RADIX as u64 * group_count as u64)?;
    let mut scratch_keys = storage("sort scratch keys", len as u64)?;
    let mut scratch_values = storage("sort scratch values", len as u64)?;
    for digit in 0..digits {
        let params = SortParams { len, shift: DIGIT_BITS * digit, key_limit, group_count };
        let ctx = DigitPass { digit, params };
        // Even digit passes read the caller's buffers, odd ones the scratch pair.
        if digit % 2 == 0 {
            ctx.add(graph, (&*keys, &*values), (&mut scratch_keys, &mut scratch_values), &mut histograms)?;
        } else {
            ctx.add(graph, (&scratch_keys, &scratch_values), (&mut *keys, &mut *values), &mut histograms)?;
        }
    }
    if digits % 2 == 1 {
        // The copy reads only `len`.
        let params = SortParams { len, shift: 0, key_limit, group_count };
        let resources =
            CopyResources { keys_in: &scratch_keys, values_in: &scratch_values, keys_out: keys, values_out: values };
        SORT_COPY.add(graph, resources, params, [len, 1, 1]);
    }
    Ok(())
}

/// What the three dispatches of one digit pass share.
struct DigitPass {
    digit: u32,
    params: SortParams,
}

impl DigitPass {
    fn add<'r>(
        &self,
        graph: &mut Graph<'r>,
        (keys_in, values_in): (&BufferHandle, &BufferHandle),
        (keys_out, values_out): (&mut BufferHandle, &mut BufferHandle),
        histograms: &mut BufferHandle,
    ) -> Result<()> {
        let (digit, params) = (self.digit, self.params);
        let threads = [params.group_count * WORKGROUP_SIZE, 1, 1];

        let (label, threads) = ((SORT_HISTOGRAM.name, Some(digit)), Threads::Fixed(threads));
        SORT_HISTOGRAM.add_as(graph, label, HistogramResources { keys_in, histograms }, |_| (), params, threads);

        scan::add(graph, (scan::SCAN.name, Some(digit)), RADIX * params.group_count, histograms)?;

        let resources = ScatterResources { keys_in, values_in, histograms, keys_out, values_out };
        let label = (SORT_SCATTER.name, Some(digit));
        SORT_SCATTER.add_as(graph, label, resources, |_| (), params, threads);
        Ok(())
    }
}

fn too_long(len: u32) -> RenderError {
    RenderError::Settings(format!(
        "radix sort of {len} elements: at most {MAX_LEN} are supported ({MAX_GROUPS} workgroups of {BLOCK}, \
         the workgroup count every Vulkan device allows)"
    ))
}
