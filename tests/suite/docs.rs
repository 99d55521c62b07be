//! The docs stay true to the tree: every relative link in the README and `docs/` resolves, and
//! the README's layout table names every path it lists and every pass file there is, so a new
//! pass or a moved file fails here until the table says so. No device needed.

use std::path::Path;

use crate::common;

fn read(path: &str) -> String {
    std::fs::read_to_string(common::root().join(path)).unwrap_or_else(|e| panic!("{path}: {e}"))
}

/// The markdown files whose links are checked.
fn documents() -> Vec<String> {
    let mut docs = vec!["README.md".to_string()];
    for entry in std::fs::read_dir(common::root().join("docs")).expect("docs/") {
        let path = entry.unwrap().path();
        if path.extension().is_some_and(|e| e == "md") {
            docs.push(format!("docs/{}", path.file_name().unwrap().to_string_lossy()));
        }
    }
    docs
}

/// The targets of `[text](target)` links: relative ones only, without their `#anchor`.
fn relative_links(text: &str) -> Vec<String> {
    let mut links = Vec::new();
    let mut rest = text;
    while let Some(at) = rest.find("](") {
        rest = &rest[at + 2..];
        let Some(end) = rest.find(')') else { break };
        let target = rest[..end].split('#').next().unwrap_or_default().trim();
        if !target.is_empty() && !target.contains("://") && !target.starts_with("mailto:") {
            links.push(target.to_string());
        }
    }
    links
}

#[test]
fn every_relative_link_resolves() {
    let root = common::root();
    let (mut broken, mut checked) = (Vec::new(), 0);
    for doc in documents() {
        let base = Path::new(&doc).parent().unwrap_or(Path::new(""));
        for link in relative_links(&read(&doc)) {
            checked += 1;
            if !root.join(base).join(&link).exists() {
                broken.push(format!("{doc}: {link}"));
            }
        }
    }
    assert!(checked > 30, "only {checked} relative links found: is the parser broken?");
    assert!(broken.is_empty(), "links to nothing:\n{}", broken.join("\n"));
}

/// The README's "Layout" table: (path, what) per row.
fn layout_rows() -> Vec<(String, String)> {
    let readme = read("README.md");
    let table = readme.split("\n## Layout\n").nth(1).expect("README has a Layout section");
    table
        .lines()
        .filter(|l| l.starts_with("| `"))
        .map(|l| {
            let cells: Vec<&str> = l.trim_matches('|').split('|').map(str::trim).collect();
            (cells[0].to_string(), cells.get(1).copied().unwrap_or_default().to_string())
        })
        .collect()
}

#[test]
fn the_layout_table_names_what_exists() {
    let root = common::root();
    let rows = layout_rows();
    assert!(rows.len() >= 10, "the layout table has {} rows", rows.len());
    // Every path a row names exists.
    for (paths, _) in &rows {
        for path in paths.split('`').skip(1).step_by(2) {
            assert!(root.join(path).exists(), "README's layout table names {path}, which does not exist");
        }
    }
    // Every crate, every source directory and every pass file has its row or its mention: a
    // backticked name in the table, or the end of a backticked path.
    let tokens: Vec<String> = rows
        .iter()
        .flat_map(|(p, w)| format!("{p} {w}").split('`').skip(1).step_by(2).map(str::to_string).collect::<Vec<_>>())
        .collect();
    let mentions = |name: &str| {
        let stem = name.trim_end_matches(".rs");
        tokens.iter().any(|t| {
            let t = t.trim_end_matches('/');
            t == name || t == stem || t.ends_with(&format!("/{name}")) || t.contains(&format!("/{name}/"))
        })
    };
    let mut missing = Vec::new();
    for dir in ["crates", "src", "tools"] {
        for entry in std::fs::read_dir(root.join(dir)).unwrap() {
            let path = entry.unwrap().path();
            let name = path.file_name().unwrap().to_string_lossy().to_string();
            let is_source = path.is_dir() || name.ends_with(".rs") || dir == "tools";
            let small = ["lib.rs", "error.rs", "shaders.rs", "__pycache__"].contains(&name.as_str());
            if is_source && !small && !mentions(&name) {
                missing.push(format!("{dir}/{name}"));
            }
        }
    }
    let passes = rows.iter().find(|(p, _)| p == "`src/passes/`").map(|(_, w)| w.clone()).expect("a src/passes row");
    for dir in ["src/passes", "src/passes/hierarchy"] {
        for entry in std::fs::read_dir(root.join(dir)).unwrap() {
            let name = entry.unwrap().file_name().to_string_lossy().to_string();
            let stem = name.trim_end_matches(".rs");
            let named = [format!("`{stem}`"), format!("`{name}`"), format!("`{name}/`")];
            if name != "mod.rs" && !named.iter().any(|n| passes.contains(n.as_str())) {
                missing.push(format!("{dir}/{name}"));
            }
        }
    }
    assert!(missing.is_empty(), "README's layout table does not mention:\n{}", missing.join("\n"));
}
