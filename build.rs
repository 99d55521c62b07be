//! Compiles every `.vert` / `.frag` / `.comp` in `shaders-glsl/` to SPIR-V with glslang
//! (`glslangValidator`, Debian's `glslang-tools`: building glslang from source was a third of
//! a clean build's CPU time on two cores),
//! reflects each module and writes `$OUT_DIR/shaders.rs` (included by `src/shaders.rs`): one
//! `ShaderInfo` static per module plus `ALL`.
//!
//! Reflection: naga gives buffer layouts; a small SPIR-V scan (`build/spirv_scan.rs`) gives
//! names, sets, bindings and kinds of every module, including those naga cannot parse (ray
//! queries), and must agree with naga on the others. A `:rayquery` variant takes its buffer
//! layouts from its `:compute` twin, by binding name.
//!
//! Includes are expanded here rather than through glslang's include callback: we need the
//! include graph anyway (a module that reaches `trace.glsl` is compiled twice), and emitting
//! `#line <n> <string-index>` around each included file lets us map glslang's
//! `ERROR: <index>:<line>:` messages back to `shaders-glsl/<file>:<line>`.

use std::collections::HashSet;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::{env, fs};

use naga::{AddressSpace, ArraySize, Handle, ImageClass, Module, Type, TypeInner};

#[path = "build/spirv_scan.rs"]
mod spirv_scan;

const DIR: &str = "shaders-glsl";

/// The compiler: `glslangValidator` on the PATH, or the one `LEAKLESS_GLSLANG` names.
const GLSLANG: &str = "glslangValidator";

/// SPIR-V 1.3 for everything naga must reflect: from 1.4 on glslang copies structs between
/// layouts with `OpCopyLogical` and (1.6) turns `discard` into `OpTerminateInvocation`, and
/// naga's SPIR-V front end parses neither. Ray queries need >= 1.4 and naga rejects those
/// modules anyway, so the `:rayquery` variants get 1.6. Vulkan 1.3 accepts both.
const SPIRV: SpirvVersion = "spirv1.3";
const RAY_QUERY_SPIRV: SpirvVersion = "spirv1.6";

/// A `--target-env` value of glslangValidator.
type SpirvVersion = &'static str;

#[derive(Clone, Copy, Debug)]
enum Stage {
    Vertex,
    Fragment,
    Compute,
}

impl Stage {
    /// glslangValidator's `-S` name.
    fn glslang(self) -> &'static str {
        match self {
            Stage::Vertex => "vert",
            Stage::Fragment => "frag",
            Stage::Compute => "comp",
        }
    }
}

/// A module that includes `trace.glsl` is compiled once per trace backend:
/// (name suffix, define, SPIR-V version). The ray-query variant comes first, the compute one
/// (the one naga reflects) last.
const TRACE_VARIANTS: [(&str, &str, SpirvVersion); 2] =
    [("rayquery", "TRACE_RAYQUERY", RAY_QUERY_SPIRV), ("compute", "TRACE_COMPUTE", SPIRV)];

fn main() {
    println!("cargo:rerun-if-changed=build.rs");
    println!("cargo:rerun-if-changed={DIR}");
    let out_dir = PathBuf::from(env::var_os("OUT_DIR").unwrap());
    let mut files: Vec<PathBuf> = fs::read_dir(DIR)
        .unwrap_or_else(|e| panic!("cannot read {DIR}/: {e}"))
        .map(|entry| entry.unwrap().path())
        .collect();
    files.sort();

    println!("cargo:rerun-if-env-changed=LEAKLESS_GLSLANG");
    let compiler = Compiler::find();
    let (mut code, mut all, mut errors) = (String::from(HEADER), Vec::new(), Vec::new());
    for path in &files {
        println!("cargo:rerun-if-changed={}", path.display());
        let file = path.file_name().unwrap().to_string_lossy().into_owned();
        let stage = match path.extension().and_then(|e| e.to_str()) {
            Some("vert") => Stage::Vertex,
            Some("frag") => Stage::Fragment,
            Some("comp") => Stage::Compute,
            _ => continue, // `.glsl` files are include-only
        };
        // Expanded once without defines only to learn whether the module traces.
        let Ok(src) = expand(&file, &[]).map_err(|e| errors.push(e)) else {
            continue;
        };
        let variants = if src.files.iter().any(|f| f == "trace.glsl") {
            let variant = |(suffix, def, v)| (format!("{file}:{suffix}"), Some(def), v);
            TRACE_VARIANTS.map(variant).to_vec()
        } else {
            vec![(file.clone(), None, SPIRV)]
        };
        let mut built = Vec::new();
        for (name, define, version) in variants {
            match build_module(&compiler, stage, &file, &name, define, version) {
                Ok((spirv, info)) => built.push((name, spirv, info)),
                Err(e) => errors.push(e),
            }
        }
        if let [(rq_name, _, rq), (twin_name, _, twin)] = &mut built[..] {
            if let Err(e) = take_twin_layouts(&file, (rq_name, rq), (twin_name, twin)) {
                errors.push(e);
            }
        }
        for (name, spirv, info) in &built {
            let ident = name.to_uppercase().replace(['.', ':', '-'], "_");
            let bytes: Vec<u8> = spirv.iter().flat_map(|w| w.to_ne_bytes()).collect();
            fs::write(out_dir.join(format!("{ident}.spv")), &bytes).unwrap();
            emit_static(&mut code, &ident, name, stage, bytes.len(), info);
            all.push(format!("&{ident}"));
        }
    }
    if !errors.is_empty() {
        panic!("shader build failed:\n{}", errors.join("\n"));
    }
    let all = all.join(", ");
    writeln!(code, "\n/// Every module above.\npub static ALL: &[&ShaderInfo] = &[{all}];").unwrap();
    fs::write(out_dir.join("shaders.rs"), code).unwrap();
}

/// A module's source after include expansion: `files[i]` is the file of `#line` string `i`.
#[derive(Default)]
struct Expanded {
    text: String,
    files: Vec<String>,
    stack: Vec<String>,
    once: HashSet<String>,
}

/// Expands `#include "x.glsl"` (relative to shaders-glsl/, nested, `#pragma once` honoured,
/// `#ifndef` guards left to the preprocessor) and inserts `#define <define> 1` after `#version`.
/// Includes are expanded regardless of surrounding `#if`s, so a conditionally included file
/// must still exist.
fn expand(file: &str, defines: &[&str]) -> Result<Expanded, String> {
    let mut out = Expanded::default();
    out.include(file, defines)?;
    Ok(out)
}

impl Expanded {
    fn include(&mut self, file: &str, defines: &[&str]) -> Result<(), String> {
        let src =
            fs::read_to_string(Path::new(DIR).join(file)).map_err(|e| format!("{DIR}/{file}: cannot read: {e}"))?;
        if src.lines().any(|l| l.trim() == "#pragma once") && !self.once.insert(file.into()) {
            return Ok(()); // already included in this module
        }
        if self.stack.iter().any(|f| f == file) {
            let chain = self.stack.join(" -> ");
            return Err(format!("{DIR}/{file}: include cycle {chain} -> {file}; use #pragma once"));
        }
        self.stack.push(file.into());
        let (index, top) = (self.files.len(), self.stack.len() == 1);
        self.files.push(file.into());
        if !top {
            // `#line` may not precede `#version`, so the top-level file relies on the default
            // (string 0, line 1) until its `#version` line.
            writeln!(self.text, "#line 1 {index}").unwrap();
        }
        let mut saw_version = false;
        for (lineno, line) in (1..).zip(src.lines()) {
            let t = line.trim();
            if let Some(rest) = t.strip_prefix("#include") {
                let name = rest.trim().trim_matches('"'); // `#include "x.glsl"`
                self.include(name, &[]).map_err(|e| format!("{e}\n  included from {DIR}/{file}:{lineno}"))?;
                writeln!(self.text, "#line {} {index}", lineno + 1).unwrap();
            } else if t == "#pragma once" {
                self.text.push('\n'); // keeps line numbers; glslang would warn about the pragma
            } else {
                writeln!(self.text, "{line}").unwrap();
                if top && !saw_version && t.starts_with("#version") {
                    saw_version = true;
                    for d in defines {
                        writeln!(self.text, "#define {d} 1").unwrap();
                    }
                    writeln!(self.text, "#line {} 0", lineno + 1).unwrap();
                }
            }
        }
        if top && !saw_version {
            return Err(format!("{DIR}/{file}:1: must start with #version 460"));
        }
        self.stack.pop();
        Ok(())
    }
}

fn build_module(
    compiler: &Compiler,
    stage: Stage,
    file: &str,
    name: &str,
    define: Option<&str>,
    spirv_version: SpirvVersion,
) -> Result<(Vec<u32>, Info), String> {
    let (spirv, mut info) = compile(compiler, stage, file, name, define.as_slice(), spirv_version)?;
    // A ray-query variant takes its layouts from its compute twin (`take_twin_layouts`).
    if info.naga_error.is_none() || define == Some("TRACE_RAYQUERY") {
        return Ok((spirv, info));
    }
    // naga parses neither subgroup operations nor arrays sized by specialization constants:
    // such a module's layouts come from a twin compiled with LEAKLESS_REFLECTION, under which
    // counters.glsl and the queues use plain equivalents with the same bindings.
    let twin_name = format!("{name}:reflection");
    let defines: Vec<&str> = define.into_iter().chain(["LEAKLESS_REFLECTION"]).collect();
    let (_, twin) = compile(compiler, stage, file, &twin_name, &defines, spirv_version)?;
    match &twin.naga_error {
        None => take_twin_layouts(file, (name, &mut info), (&twin_name, &twin))?,
        Some(e) => println!("cargo:warning={name}: buffer layouts not reflected, so not checked: {e}"),
    }
    Ok((spirv, info))
}

/// Compiles one variant of `file` with `defines` and reflects it.
fn compile(
    compiler: &Compiler,
    stage: Stage,
    file: &str,
    name: &str,
    defines: &[&str],
    spirv_version: SpirvVersion,
) -> Result<(Vec<u32>, Info), String> {
    let src = expand(file, defines)?;
    let (spirv, log) = compiler.run(stage, spirv_version, &src.text, name)?;
    let spirv = spirv.ok_or_else(|| match map_log(&log, &src.files, name) {
        mapped if mapped.is_empty() => format!("{DIR}/{file}: {} (compiling {name})", log.trim()),
        mapped => mapped,
    })?;
    for warning in map_log(&log, &src.files, name).lines() {
        println!("cargo:warning={warning}");
    }
    let info = reflect(&spirv, stage, file)?;
    Ok((spirv, info))
}

/// glslangValidator, run once per module variant.
struct Compiler {
    program: std::ffi::OsString,
    scratch: PathBuf,
}

impl Compiler {
    fn find() -> Compiler {
        let program = env::var_os("LEAKLESS_GLSLANG").unwrap_or_else(|| GLSLANG.into());
        let found = std::process::Command::new(&program).arg("--version").output();
        if !found.is_ok_and(|o| o.status.success()) {
            panic!(
                "cannot run {}: the shaders are compiled with glslang's glslangValidator \
                 (Debian/Ubuntu package glslang-tools; tools/install-deps installs it)",
                program.to_string_lossy()
            );
        }
        let scratch = PathBuf::from(env::var_os("OUT_DIR").unwrap()).join("glslang");
        fs::create_dir_all(&scratch).unwrap();
        Compiler { program, scratch }
    }

    /// Compiles expanded GLSL from standard input (so that glslang numbers its `#line` strings
    /// instead of naming them after a file): the SPIR-V if it compiled, and glslang's log.
    /// glslang's default SPIR-V options keep OpName / OpMemberName, which reflection needs.
    fn run(
        &self,
        stage: Stage,
        spirv: SpirvVersion,
        text: &str,
        name: &str,
    ) -> Result<(Option<Vec<u32>>, String), String> {
        use std::io::Write as _;
        let out = self.scratch.join(format!("{}.spv", name.replace(':', "_")));
        let _ = fs::remove_file(&out);
        let mut child = std::process::Command::new(&self.program)
            .args(["-V", "--target-env", "vulkan1.3", "--target-env", spirv, "--stdin", "-S", stage.glslang(), "-o"])
            .arg(&out)
            .stdin(std::process::Stdio::piped())
            .stdout(std::process::Stdio::piped())
            .stderr(std::process::Stdio::piped())
            .spawn()
            .map_err(|e| format!("{name}: cannot run glslang: {e}"))?;
        child.stdin.take().unwrap().write_all(text.as_bytes()).map_err(|e| format!("{name}: glslang's input: {e}"))?;
        let output = child.wait_with_output().map_err(|e| format!("{name}: glslang: {e}"))?;
        let log = String::from_utf8_lossy(&output.stdout).into_owned() + &String::from_utf8_lossy(&output.stderr);
        if !output.status.success() {
            return Ok((None, log));
        }
        let bytes = fs::read(&out).map_err(|e| format!("{name}: glslang wrote no SPIR-V: {e}"))?;
        let words = bytes.chunks_exact(4).map(|w| u32::from_le_bytes(w.try_into().unwrap())).collect();
        Ok((Some(words), log))
    }
}

/// Rewrites glslang's `ERROR: <string>:<line>: msg` lines to `shaders-glsl/<file>:<line>: msg`
/// and drops the rest of its log (summaries, the empty debug log).
fn map_log(log: &str, files: &[String], name: &str) -> String {
    let mut out = Vec::new();
    for line in log.lines().map(str::trim) {
        let Some((severity @ ("ERROR" | "WARNING"), rest)) = line.split_once(": ") else {
            continue;
        };
        if rest.ends_with("No code generated.") || rest.ends_with("compilation terminated") {
            continue;
        }
        let locate = || {
            let (string, rest) = rest.split_once(':')?;
            let (lineno, msg) = rest.split_once(':')?;
            let file = files.get(string.parse::<usize>().ok()?)?;
            let line: u32 = lineno.parse().ok()?;
            Some(format!("{DIR}/{file}:{line}:{msg}"))
        };
        let severity = severity.to_lowercase();
        out.push(match locate() {
            Some(at) => format!("{at} ({severity} compiling {name})"),
            None => format!("{name}: {severity}: {rest}"),
        });
    }
    out.join("\n")
}

/// What reflection found for one module.
struct Info {
    workgroup_size: [u32; 3],
    /// `SpecConstant { .. }` literals, by id.
    spec_constants: Vec<String>,
    /// Ordered by (set, binding).
    bindings: Vec<Binding>,
    /// Why naga could not parse the module: its bindings come from the SPIR-V scan alone,
    /// without buffer layouts.
    naga_error: Option<String>,
    /// Whether the module declares a push-constant block (from the scan).
    has_push_constants: bool,
    /// `Some(BlockLayout { .. })` literal of that block, once reflected (naga, or the twin).
    push_constants: Option<String>,
}

/// One resource binding, to become a `ReflectedBinding` literal.
struct Binding {
    name: String,
    set: u32,
    binding: u32,
    /// `BindingKind` variant.
    kind: &'static str,
    /// `Some(BlockLayout { .. })` literal: buffers naga reflected.
    layout: Option<String>,
    /// `BindingAccess` variant, from the scan's `readonly` / `writeonly` decorations.
    access: &'static str,
}

impl Binding {
    fn id(&self) -> (&str, u32, u32, &str) {
        (&self.name, self.set, self.binding, self.kind)
    }
}

fn reflect(spirv: &[u32], stage: Stage, file: &str) -> Result<Info, String> {
    let scan = spirv_scan::scan(spirv).map_err(|e| format!("{DIR}/{file}: {e}"))?;
    let spec_constants = scan
        .spec_constants
        .iter()
        .map(|c| format!("SpecConstant {{ name: {:?}, id: {}, default: {} }}", c.name, c.id, c.default))
        .collect();
    // The scan's size: naga's ignores a `local_size_x_id` composite's defaults.
    let workgroup_size = match stage {
        Stage::Compute => scan.local_size,
        _ => [1, 1, 1],
    };
    let scanned: Vec<Binding> = scan
        .resources
        .into_iter()
        .map(|r| Binding { name: r.name, set: r.set, binding: r.binding, kind: r.kind, layout: None, access: r.access })
        .collect();
    let options = naga::front::spv::Options {
        adjust_coordinate_space: false,
        strict_capabilities: false,
        block_ctx_dump_prefix: None,
    };
    let module = match naga::front::spv::Frontend::new(spirv.iter().copied(), &options).parse() {
        Ok(module) => module,
        Err(e) => {
            // Expected for ray-query modules; their TRACE_COMPUTE twin lends them its layouts.
            let mut msg = format!("naga: {}", e.to_string().lines().next().unwrap_or_default());
            if scanned.iter().any(|b| b.kind == "CombinedImageSampler") {
                msg += " (naga cannot parse sampling through a combined image sampler; \
                        use a texture and a sampler)";
            }
            let naga_error = Some(msg);
            let has_push_constants = scan.push_constants;
            return Ok(Info {
                workgroup_size,
                spec_constants,
                bindings: scanned,
                naga_error,
                has_push_constants,
                push_constants: None,
            });
        }
    };
    let mut bindings = Vec::new();
    let mut push_constants = None;
    for (_, var) in module.global_variables.iter() {
        // naga calls push constants "immediates".
        if var.space == AddressSpace::Immediate {
            push_constants = Some(block_layout(&module, var.ty));
            continue;
        }
        let Some(rb) = &var.binding else { continue };
        let (set, binding) = (rb.group, rb.binding);
        let (kind, layout) = match var.space {
            AddressSpace::Uniform => ("UniformBuffer", Some(block_layout(&module, var.ty))),
            AddressSpace::Storage { .. } => ("StorageBuffer", Some(block_layout(&module, var.ty))),
            AddressSpace::Handle => {
                // naga folds a combined image sampler into its image type.
                let combined =
                    scanned.iter().any(|b| (b.set, b.binding, b.kind) == (set, binding, "CombinedImageSampler"));
                (handle_kind(&module, var.ty, combined), None)
            }
            _ => continue,
        };
        // glslang names the variable of `buffer Photons { .. } photons;` "photons" (the scan
        // has already rejected blocks without an instance name).
        let name = var.name.clone().unwrap_or_default();
        let access = scanned.iter().find(|b| (b.set, b.binding) == (set, binding)).map_or("ReadWrite", |b| b.access);
        bindings.push(Binding { name, set, binding, kind, layout, access });
    }
    bindings.sort_by(|a, b| (a.set, a.binding, &a.name).cmp(&(b.set, b.binding, &b.name)));
    // The scan stands in for naga where naga cannot parse, so it must agree where it can.
    let ids = |bs: &[Binding]| bs.iter().map(|b| format!("{:?}", b.id())).collect::<Vec<_>>().join(", ");
    if ids(&bindings) != ids(&scanned) {
        return Err(format!(
            "{DIR}/{file}: build.rs bug: the SPIR-V scan (build/spirv_scan.rs) disagrees with naga:\n  \
             scan: {}\n  naga: {}",
            ids(&scanned),
            ids(&bindings)
        ));
    }
    if push_constants.is_some() != scan.push_constants {
        return Err(format!("{DIR}/{file}: build.rs bug: the SPIR-V scan and naga disagree on push constants"));
    }
    let has_push_constants = scan.push_constants;
    Ok(Info { workgroup_size, spec_constants, bindings, naga_error: None, has_push_constants, push_constants })
}

/// Gives a `:rayquery` module naga could not parse the buffer layouts of its `:compute` twin,
/// matched by binding name, after checking that every binding the two variants share has the
/// same set, number and kind. Bindings of the ray-query variant alone (`tlas`) keep `None`.
fn take_twin_layouts(file: &str, rq: (&str, &mut Info), twin: (&str, &Info)) -> Result<(), String> {
    let ((rq_name, rq), (twin_name, twin)) = (rq, twin);
    let mut mismatches = Vec::new();
    for b in &mut rq.bindings {
        let Some(t) = twin.bindings.iter().find(|t| t.name == b.name) else {
            if b.layout.is_none() && b.kind.ends_with("Buffer") {
                println!("cargo:warning={rq_name}: `{}` is not in {twin_name}, so its layout is not checked", b.name);
            }
            continue;
        };
        if (t.set, t.binding, t.kind, t.access) != (b.set, b.binding, b.kind, b.access) {
            mismatches.push(format!(
                "{DIR}/{file}: binding `{}` is set {}, binding {}, {} {} in {rq_name} but set {}, binding {}, {} {} \
                 in {twin_name}; trace variants must agree on every binding they share",
                b.name, b.set, b.binding, b.access, b.kind, t.set, t.binding, t.access, t.kind
            ));
        } else if rq.naga_error.is_some() {
            b.layout.clone_from(&t.layout);
        }
    }
    if rq.has_push_constants != twin.has_push_constants {
        mismatches.push(format!(
            "{DIR}/{file}: {rq_name} and {twin_name} disagree on whether there is a push_constant block"
        ));
    } else if rq.naga_error.is_some() {
        rq.push_constants.clone_from(&twin.push_constants);
    }
    if mismatches.is_empty() {
        Ok(())
    } else {
        Err(mismatches.join("\n"))
    }
}

fn handle_kind(module: &Module, ty: Handle<Type>, combined: bool) -> &'static str {
    match &module.types[ty].inner {
        TypeInner::BindingArray { base, .. } => handle_kind(module, *base, combined),
        TypeInner::Image { class, .. } => match class {
            ImageClass::Storage { .. } => "StorageImage",
            _ if combined => "CombinedImageSampler",
            _ => "SampledImage",
        },
        TypeInner::Sampler { .. } => "Sampler",
        TypeInner::AccelerationStructure { .. } => "AccelerationStructure",
        other => panic!("unexpected resource type {other:?}"),
    }
}

/// `Some(BlockLayout { .. })` literal for a uniform or storage block.
fn block_layout(module: &Module, ty: Handle<Type>) -> String {
    let members_of = |ty: Handle<Type>| match &module.types[ty].inner {
        TypeInner::Struct { members, .. } => {
            let members = members.iter().map(|m| {
                let name = m.name.as_deref().unwrap_or_default();
                format!("Member {{ name: {name:?}, offset: {} }}", m.offset)
            });
            format!("&[{}]", members.collect::<Vec<_>>().join(", "))
        }
        _ => "&[]".to_string(),
    };
    let TypeInner::Struct { members, span } = &module.types[ty].inner else {
        panic!("buffer block is not a struct: {:?}", module.types[ty]);
    };
    let last = members.last().map(|m| (m.offset, &module.types[m.ty].inner));
    let (size, stride, element) = match last {
        // A trailing runtime array: the fixed part ends where the array starts.
        Some((offset, TypeInner::Array { base, size, stride })) if *size == ArraySize::Dynamic => {
            (offset, Some(stride), members_of(*base))
        }
        // naga's span: the last member's end rounded up to the block's alignment, as the
        // size of a `#[repr(C)]` mirror of it.
        _ => (*span, None, "&[]".into()),
    };
    format!(
        "Some(BlockLayout {{ size: {size}, members: {}, array_stride: {stride:?}, \
         element_members: {element} }})",
        members_of(ty)
    )
}

const HEADER: &str = "// Generated by build.rs from shaders-glsl/. Do not edit.
#[allow(unused_imports)]
use leakless_device::shader::{
    BindingAccess, BindingKind, BlockLayout, Member, ReflectedBinding, ShaderInfo, ShaderStage, SpecConstant,
};

/// Gives `include_bytes!` data the alignment of `u32` so it can be viewed as SPIR-V words.
#[repr(C, align(4))]
#[allow(dead_code)]
struct Aligned<T: ?Sized>(T);
";

fn emit_static(code: &mut String, ident: &str, name: &str, stage: Stage, len: usize, info: &Info) {
    let literal = |b: &Binding| {
        let (name, set, binding, kind) = b.id();
        let layout = b.layout.as_deref().unwrap_or("None");
        format!(
            "ReflectedBinding {{ name: {name:?}, set: {set}, binding: {binding}, \
             kind: BindingKind::{kind}, access: BindingAccess::{access}, layout: {layout} }}",
            access = b.access
        )
    };
    let bindings: Vec<String> = info.bindings.iter().map(literal).collect();
    let reflection = if bindings.is_empty() {
        "Ok(&[])".to_string()
    } else {
        format!("Ok(&[\n        {},\n    ])", bindings.join(",\n        "))
    };
    let workgroup_size = info.workgroup_size;
    let push_constants = info.push_constants.as_deref().unwrap_or("None");
    let spec_constants = info.spec_constants.join(", ");
    writeln!(
        code,
        r#"
static {ident}_SPV: Aligned<[u8; {len}]> =
    Aligned(*include_bytes!(concat!(env!("OUT_DIR"), "/{ident}.spv")));
/// `shaders-glsl/{name}`
pub static {ident}: ShaderInfo = ShaderInfo {{
    name: {name:?},
    stage: ShaderStage::{stage:?},
    // SAFETY: 4-byte aligned, {len} bytes of native-endian words.
    spirv: unsafe {{ core::slice::from_raw_parts({ident}_SPV.0.as_ptr().cast::<u32>(), {len} / 4) }},
    workgroup_size: {workgroup_size:?},
    spec_constants: &[{spec_constants}],
    reflection: {reflection},
    push_constants: {push_constants},
}};"#
    )
    .unwrap();
}
