//! Compiling one module variant with glslangValidator (expanded source on standard input),
//! its log mapped back to `shaders-glsl/<file>:<line>`, then reflected.

use std::path::PathBuf;
use std::{env, fs};

use crate::includes::expand;
use crate::reflect::{reflect, Info};
use crate::{SpirvVersion, Stage, DIR, GLSLANG};

/// Compiles one variant of `file` with `defines` and reflects it.
pub(crate) fn compile(
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
pub(crate) struct Compiler {
    pub(crate) program: std::ffi::OsString,
    pub(crate) scratch: PathBuf,
}

impl Compiler {
    pub(crate) fn find() -> Compiler {
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
    pub(crate) fn run(
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
pub(crate) fn map_log(log: &str, files: &[String], name: &str) -> String {
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
