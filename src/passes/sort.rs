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
use leakless_device::{
    rust_layout, BindingDecl, Bound, Buffer, BufferDesc, ComputePipeline, Gpu, MemoryLocation, RustLayout,
};
use leakless_graph::{Access, BufferHandle, Graph};

use crate::error::{RenderError, Result};
use crate::gpu_types::U32_LAYOUT;
use crate::passes::uniform::Uniform;
use crate::shaders;

/// Threads per workgroup of every sort shader (`SORT_WORKGROUP_SIZE` in sort.glsl, checked
/// against reflection).
pub const WORKGROUP_SIZE: u32 = 256;
/// Consecutive elements per thread in the histogram and scatter passes (`SORT_ITEMS`; not
/// reflected: a mismatch fails every test of `tests/sort.rs` longer than one block).
/// Measured on lavapipe at 640×480: 4 → ~30 ms, 8 → ~23-36, 16 → ~20, 32 → ~23-27 (noisy).
pub const ITEMS_PER_THREAD: u32 = 16;
/// Elements per workgroup of the histogram and scatter passes.
pub const BLOCK: u32 = WORKGROUP_SIZE * ITEMS_PER_THREAD;
/// Bits per digit: 16 buckets.
pub const DIGIT_BITS: u32 = 4;
const RADIX: u32 = 1 << DIGIT_BITS;
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

/// The `SortParams` block of sort.glsl: one digit pass.
#[repr(C)]
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

pub const SORT_PARAMS_LAYOUT: RustLayout = rust_layout!(SortParams { len, shift, key_limit, group_count });

pub const HISTOGRAM_BINDINGS: &[BindingDecl] = &[
    BindingDecl::uniform("params", SORT_PARAMS_LAYOUT),
    BindingDecl::storage_array("keys_in", U32_LAYOUT),
    BindingDecl::storage_array("histograms", U32_LAYOUT),
];

pub const SCAN_BINDINGS: &[BindingDecl] =
    &[BindingDecl::uniform("params", SORT_PARAMS_LAYOUT), BindingDecl::storage_array("histograms", U32_LAYOUT)];

pub const SCATTER_BINDINGS: &[BindingDecl] = &[
    BindingDecl::uniform("params", SORT_PARAMS_LAYOUT),
    BindingDecl::storage_array("keys_in", U32_LAYOUT),
    BindingDecl::storage_array("values_in", U32_LAYOUT),
    BindingDecl::storage_array("histograms", U32_LAYOUT),
    BindingDecl::storage_array("keys_out", U32_LAYOUT),
    BindingDecl::storage_array("values_out", U32_LAYOUT),
];

pub const COPY_BINDINGS: &[BindingDecl] = &[
    BindingDecl::uniform("params", SORT_PARAMS_LAYOUT),
    BindingDecl::storage_array("keys_in", U32_LAYOUT),
    BindingDecl::storage_array("values_in", U32_LAYOUT),
    BindingDecl::storage_array("keys_out", U32_LAYOUT),
    BindingDecl::storage_array("values_out", U32_LAYOUT),
];

/// Digit passes for keys of `key_bits` valid bits: `key_bits + 1` bits (out-of-range keys
/// sort as `2^key_bits`), at most 32, in 4-bit digits.
pub fn digit_passes(key_bits: u32) -> u32 {
    (key_bits + 1).min(32).div_ceil(DIGIT_BITS)
}

/// Graph passes one [`SortPass::add`] adds: three per digit pass, plus a copy after an odd
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

pub struct SortPass {
    histogram: ComputePipeline,
    scan: ComputePipeline,
    scatter: ComputePipeline,
    copy: ComputePipeline,
    /// One per digit pass: a host-written uniform holds one value per graph run. The copy
    /// pass reads only `len`, which every one of them holds.
    params: Vec<Uniform<SortParams>>,
    scratch_keys: Buffer,
    scratch_values: Buffer,
    histograms: Buffer,
    max_len: u32,
}

impl SortPass {
    /// Pipelines, and scratch keys/values and histograms for sorts of up to `max_len` pairs
    /// (at most [`MAX_LEN`]).
    pub fn new(gpu: &Gpu, max_len: u32) -> Result<Self> {
        if max_len > MAX_LEN {
            return Err(too_long(max_len));
        }
        let histogram = ComputePipeline::new(gpu, "sort histogram", &shaders::SORT_HISTOGRAM_COMP, HISTOGRAM_BINDINGS)?;
        let scan = ComputePipeline::new(gpu, "sort scan", &shaders::SORT_SCAN_COMP, SCAN_BINDINGS)?;
        let scatter = ComputePipeline::new(gpu, "sort scatter", &shaders::SORT_SCATTER_COMP, SCATTER_BINDINGS)?;
        let copy = ComputePipeline::new(gpu, "sort copy", &shaders::SORT_COPY_COMP, COPY_BINDINGS)?;
        for p in [&histogram, &scan, &scatter, &copy] {
            if p.workgroup_size() != [WORKGROUP_SIZE, 1, 1] {
                return Err(RenderError::Settings(format!(
                    "sort shaders have workgroup size {:?}; sort.rs expects [{WORKGROUP_SIZE}, 1, 1]",
                    p.workgroup_size()
                )));
            }
        }
        let params = (0..MAX_DIGIT_PASSES)
            .map(|i| Uniform::new(gpu, &format!("sort params {i}")))
            .collect::<Result<Vec<_>>>()?;
        let storage = |name: &str, words: u64| {
            Buffer::new(
                gpu,
                &BufferDesc {
                    name,
                    size: 4 * words,
                    usage: vk::BufferUsageFlags::STORAGE_BUFFER,
                    location: MemoryLocation::GpuOnly,
                },
            )
        };
        let groups = max_len.div_ceil(BLOCK) as u64;
        Ok(SortPass {
            histogram,
            scan,
            scatter,
            copy,
            params,
            scratch_keys: storage("sort scratch keys", max_len as u64)?,
            scratch_values: storage("sort scratch values", max_len as u64)?,
            histograms: storage("sort histograms", RADIX as u64 * groups)?,
            max_len,
        })
    }

    pub fn max_len(&self) -> u32 {
        self.max_len
    }

    /// Sorts the first `len` (key, value) pairs of `keys` / `values` by key, stably, and leaves
    /// them there (elements past `len` are untouched). Keys at or above `2^key_bits` sort last,
    /// in input order (see the module documentation); `key_bits = 30` for Morton codes with the
    /// `0xFFFFFFFF` sentinel, 32 for arbitrary keys. Adds [`graph_passes`]`(key_bits)` passes
    /// named "sort histogram i", "sort scan i", "sort scatter i" (and "sort copy").
    ///
    /// The parameters are written now, into buffers that hold one value per graph run: call
    /// `add` at most once per graph. On an error the graph may hold some of the passes: drop it.
    pub fn add<'r>(
        &'r self,
        graph: &mut Graph<'r>,
        len: u32,
        key_bits: u32,
        keys: &mut BufferHandle,
        values: &mut BufferHandle,
    ) -> Result<()> {
        if len > self.max_len {
            return Err(if len > MAX_LEN {
                too_long(len)
            } else {
                RenderError::Settings(format!(
                    "radix sort of {len} elements: this SortPass was made for at most {}",
                    self.max_len
                ))
            });
        }
        if key_bits > 32 {
            return Err(RenderError::Settings(format!("radix sort: key_bits {key_bits} > 32")));
        }
        if len == 0 {
            return Ok(());
        }
        let group_count = len.div_ceil(BLOCK);
        let key_limit = key_limit(key_bits);
        let digits = digit_passes(key_bits);
        let mut histograms = graph.import_buffer(&self.histograms);
        let mut scratch_keys = graph.import_buffer(&self.scratch_keys);
        let mut scratch_values = graph.import_buffer(&self.scratch_values);
        let mut params = None;
        for digit in 0..digits {
            let uniform = &self.params[digit as usize];
            uniform.set(&SortParams { len, shift: DIGIT_BITS * digit, key_limit, group_count })?;
            let params = &*params.insert(graph.import_buffer(&uniform.buffer));
            let ctx = DigitPass { sort: self, digit, len, group_count, params };
            // Even digit passes read the caller's buffers, odd ones the scratch pair.
            if digit % 2 == 0 {
                ctx.add(graph, (&*keys, &*values), (&mut scratch_keys, &mut scratch_values), &mut histograms)?;
            } else {
                ctx.add(graph, (&scratch_keys, &scratch_values), (&mut *keys, &mut *values), &mut histograms)?;
            }
        }
        if let (1, Some(params)) = (digits % 2, &params) {
            // The last digit pass's parameters: the copy reads only `len`.
            let mut pass = graph.pass("sort copy");
            let bound = vec![
                ("params", Bound::Buffer(pass.read(params, Access::ComputeRead))),
                ("keys_in", Bound::Buffer(pass.read(&scratch_keys, Access::ComputeRead))),
                ("values_in", Bound::Buffer(pass.read(&scratch_values, Access::ComputeRead))),
                ("keys_out", Bound::Buffer(checked(pass.write(keys, Access::ComputeWrite), len)?)),
                ("values_out", Bound::Buffer(checked(pass.write(values, Access::ComputeWrite), len)?)),
            ];
            pass.record(move |cmd| cmd.dispatch(&self.copy, &bound, [len, 1, 1]));
        }
        Ok(())
    }
}

/// What the three dispatches of one digit pass share.
struct DigitPass<'a, 'r> {
    sort: &'r SortPass,
    digit: u32,
    len: u32,
    group_count: u32,
    params: &'a BufferHandle,
}

impl<'r> DigitPass<'_, 'r> {
    fn add(
        &self,
        graph: &mut Graph<'r>,
        (keys_in, values_in): (&BufferHandle, &BufferHandle),
        (keys_out, values_out): (&mut BufferHandle, &mut BufferHandle),
        histograms: &mut BufferHandle,
    ) -> Result<()> {
        let (sort, digit, len) = (self.sort, self.digit, self.len);
        let threads = [self.group_count * WORKGROUP_SIZE, 1, 1];

        let mut pass = graph.pass(&format!("sort histogram {digit}"));
        let bound = vec![
            ("params", Bound::Buffer(pass.read(self.params, Access::ComputeRead))),
            ("keys_in", Bound::Buffer(checked(pass.read(keys_in, Access::ComputeRead), len)?)),
            ("histograms", Bound::Buffer(pass.write(histograms, Access::ComputeWrite))),
        ];
        pass.record(move |cmd| cmd.dispatch(&sort.histogram, &bound, threads));

        let mut pass = graph.pass(&format!("sort scan {digit}"));
        let bound = vec![
            ("params", Bound::Buffer(pass.read(self.params, Access::ComputeRead))),
            ("histograms", Bound::Buffer(pass.write(histograms, Access::ComputeReadWrite))),
        ];
        pass.record(move |cmd| cmd.dispatch(&sort.scan, &bound, [WORKGROUP_SIZE, 1, 1]));

        let mut pass = graph.pass(&format!("sort scatter {digit}"));
        let bound = vec![
            ("params", Bound::Buffer(pass.read(self.params, Access::ComputeRead))),
            ("keys_in", Bound::Buffer(pass.read(keys_in, Access::ComputeRead))),
            ("values_in", Bound::Buffer(checked(pass.read(values_in, Access::ComputeRead), len)?)),
            ("histograms", Bound::Buffer(pass.read(histograms, Access::ComputeRead))),
            ("keys_out", Bound::Buffer(checked(pass.write(keys_out, Access::ComputeWrite), len)?)),
            ("values_out", Bound::Buffer(checked(pass.write(values_out, Access::ComputeWrite), len)?)),
        ];
        pass.record(move |cmd| cmd.dispatch(&sort.scatter, &bound, threads));
        Ok(())
    }
}

/// `buffer`, if it holds `len` words.
fn checked(buffer: &Buffer, len: u32) -> Result<&Buffer> {
    if buffer.size() < 4 * len as u64 {
        return Err(RenderError::Settings(format!(
            "radix sort of {len} elements: buffer {} holds only {} bytes",
            buffer.name(),
            buffer.size()
        )));
    }
    Ok(buffer)
}

fn too_long(len: u32) -> RenderError {
    RenderError::Settings(format!(
        "radix sort of {len} elements: at most {MAX_LEN} are supported ({MAX_GROUPS} workgroups of {BLOCK}, \
         the workgroup count every Vulkan device allows)"
    ))
}
