//! Include expansion for crates/renderer/build.rs: `#include "x.glsl"` inlined with `#line` markers, so that
//! glslang's `<string>:<line>` errors map back to the file and line they came from, and the
//! include graph tells which modules trace.

use std::collections::HashSet;
use std::fmt::Write as _;
use std::fs;
use std::path::Path;

use crate::DIR;

/// A module's source after include expansion: `files[i]` is the file of `#line` string `i`.
#[derive(Default)]
pub(crate) struct Expanded {
    pub(crate) text: String,
    pub(crate) files: Vec<String>,
    pub(crate) stack: Vec<String>,
    pub(crate) once: HashSet<String>,
}

/// Expands `#include "x.glsl"` (relative to shaders-glsl/, nested, `#pragma once` honoured,
/// `#ifndef` guards left to the preprocessor) and inserts `#define <define> 1` after `#version`.
/// Includes are expanded regardless of surrounding `#if`s, so a conditionally included file
/// must still exist.
pub(crate) fn expand(file: &str, defines: &[&str]) -> Result<Expanded, String> {
    let mut out = Expanded::default();
    out.include(file, defines)?;
    Ok(out)
}

impl Expanded {
    pub(crate) fn include(&mut self, file: &str, defines: &[&str]) -> Result<(), String> {
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
