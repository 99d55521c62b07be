//! Compiles every `.vert` / `.frag` / `.comp` in `shaders-glsl/` to SPIR-V with glslang
//! (`glslangValidator`, Debian's `glslang-tools`: building glslang from source was a third of
//! a clean build's CPU time on two cores),
//! reflects each module and writes `$OUT_DIR/shaders.rs` (included by `crates/renderer/src/shaders.rs`): one
//! `ShaderInfo` static per module plus `ALL`.
//!
//! Reflection: naga gives buffer layouts; a small SPIR-V scan (`crates/renderer/build/spirv_scan.rs`) gives
//! names, sets, bindings and kinds of every module, including those naga cannot parse (ray
//! queries), and must agree with naga on the others. A `:rayquery` variant takes its buffer
//! layouts from its `:compute` twin, by binding name.
//!
//! Includes are expanded here rather than through glslang's include callback: we need the
//! include graph anyway (a module that reaches `trace.glsl` is compiled twice), and emitting
//! `#line <n> <string-index>` around each included file lets us map glslang's
//! `ERROR: <index>:<line>:` messages back to `shaders-glsl/<file>:<line>`.

use std::fmt::Write as _;
use std::path::PathBuf;
use std::{env, fs};

#[path = "build/codegen.rs"]
mod codegen;
#[path = "build/glslang.rs"]
mod glslang;
#[path = "build/includes.rs"]
mod includes;
#[path = "build/reflect.rs"]
mod reflect;
#[path = "build/spirv_scan.rs"]
mod spirv_scan;

use codegen::{emit_static, HEADER};
use glslang::{compile, Compiler};
use includes::expand;
use reflect::{take_twin_layouts, Info};

/// Where the shaders are, from this package's directory (build scripts run there).
const DIR: &str = "../../shaders-glsl";

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
