//! The docs stay true to the tree: every relative link in the README and `docs/` resolves (to a
//! heading too, where it names one), and
//! the README's layout table names every top-level source path there is and only passes that
//! exist, so a moved file fails here until the table says so (a new pass collects itself and
//! needs no line). No device needed.

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

/// The targets of the document's links and images, as CommonMark reads them: relative ones
/// only, as (path, anchor); a link within the document has an empty path.
fn relative_links(text: &str) -> Vec<(String, Option<String>)> {
    use pulldown_cmark::{Event, Parser, Tag};
    Parser::new(text)
        .filter_map(|event| match event {
            Event::Start(Tag::Link { dest_url, .. } | Tag::Image { dest_url, .. }) => Some(dest_url.to_string()),
            _ => None,
        })
        .filter(|target| !target.contains("://") && !target.starts_with("mailto:"))
        .map(|target| match target.split_once('#') {
            Some((path, anchor)) => (path.to_string(), Some(anchor.to_string())),
            None => (target, None),
        })
        .collect()
}

/// The anchors of a document's headings, as GitHub makes them: lower case, spaces to hyphens,
/// other punctuation dropped, a repeated heading numbered (`-1`, `-2`, …).
fn heading_anchors(text: &str) -> Vec<String> {
    use pulldown_cmark::{Event, Parser, Tag, TagEnd};
    let (mut anchors, mut heading): (Vec<String>, Option<String>) = (Vec::new(), None);
    for event in Parser::new(text) {
        match event {
            Event::Start(Tag::Heading { .. }) => heading = Some(String::new()),
            Event::Text(t) | Event::Code(t) => {
                if let Some(h) = heading.as_mut() {
                    h.push_str(&t);
                }
            }
            Event::End(TagEnd::Heading(_)) => {
                let text = heading.take().unwrap_or_default().to_lowercase();
                let slug: String = text
                    .chars()
                    .filter(|c| c.is_alphanumeric() || *c == ' ' || *c == '-' || *c == '_')
                    .map(|c| if c == ' ' { '-' } else { c })
                    .collect();
                let repeats = anchors.iter().filter(|a| **a == slug).count();
                anchors.push(slug.clone());
                if repeats > 0 {
                    anchors.push(format!("{slug}-{repeats}"));
                }
            }
            _ => {}
        }
    }
    anchors
}

#[test]
fn every_relative_link_resolves() {
    let root = common::root();
    let (mut broken, mut checked) = (Vec::new(), 0);
    for doc in documents() {
        let base = Path::new(&doc).parent().unwrap_or(Path::new(""));
        for (path, anchor) in relative_links(&read(&doc)) {
            checked += 1;
            let target = if path.is_empty() { Path::new(&doc).to_path_buf() } else { base.join(&path) };
            if !root.join(&target).exists() {
                broken.push(format!("{doc}: {path}"));
                continue;
            }
            let is_markdown = target.extension().is_some_and(|e| e == "md");
            if let Some(anchor) = anchor.filter(|_| is_markdown) {
                if !heading_anchors(&read(&target.to_string_lossy())).contains(&anchor) {
                    broken.push(format!("{doc}: {path}#{anchor} (no such heading)"));
                }
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
    // The passes collect themselves (passes::FRAME_PASSES): a new one needs no line here. What
    // the row names must exist.
    let passes = rows
        .iter()
        .find(|(p, _)| p == "`crates/renderer/src/passes/`")
        .map(|(_, w)| w.clone())
        .expect("a crates/renderer/src/passes row");
    let mut stale = Vec::new();
    for name in passes.split('`').skip(1).step_by(2).filter(|n| !n.contains(' ') && !n.contains("::")) {
        let name = name.trim_end_matches('/').trim_end_matches(".rs");
        let exists = ["crates/renderer/src/passes", "crates/renderer/src/passes/hierarchy"].iter().any(|dir| {
            let base = root.join(dir).join(name);
            base.with_extension("rs").exists() || base.is_dir()
        });
        if !exists {
            stale.push(name.to_string());
        }
    }
    assert!(stale.is_empty(), "README's crates/renderer/src/passes row names passes that do not exist: {stale:?}");
    assert!(missing.is_empty(), "README's layout table does not mention:\n{}", missing.join("\n"));
}

/// The figures the README states (ratios and percentages: `1.44–1.71×`, `17%`), each end of a
/// range on its own; sizes (`640×480`) are not figures.
fn stated_figures(text: &str) -> Vec<String> {
    let chars: Vec<char> = text.chars().collect();
    let mut figures = Vec::new();
    let mut i = 0;
    while i < chars.len() {
        let starts = chars[i].is_ascii_digit() && (i == 0 || !(chars[i - 1].is_alphanumeric() || chars[i - 1] == '.'));
        if !starts {
            i += 1;
            continue;
        }
        let mut j = i;
        while j < chars.len() && (chars[j].is_ascii_digit() || chars[j] == '.' || chars[j] == '–') {
            j += 1;
        }
        let unit = chars.get(j).copied().filter(|c| *c == '×' || *c == '%');
        let size = chars.get(j + 1).is_some_and(|c| c.is_ascii_digit());
        if let (Some(unit), false) = (unit, size) {
            let number: String = chars[i..j].iter().collect();
            figures.extend(number.split('–').filter(|n| !n.is_empty()).map(|n| format!("{n}{unit}")));
        }
        i = j.max(i + 1);
    }
    figures
}

/// Every figure the README states is one that docs/ measures (docs/results.md and the pages
/// beside it, which give the command that makes it): the README does not carry figures of its
/// own that could drift from what was measured.
#[test]
fn the_readmes_figures_are_measured_in_docs() {
    let docs: String = documents().iter().filter(|d| d.starts_with("docs/")).map(|d| read(d)).collect();
    let figures = stated_figures(&read("README.md"));
    assert!(!figures.is_empty(), "no figure found in the README: is the scanner broken?");
    let unmeasured: Vec<&String> = figures.iter().filter(|f| !docs.contains(f.as_str())).collect();
    assert!(unmeasured.is_empty(), "README figures that no page of docs/ states: {unmeasured:?}");
}

#[test]
fn figures_are_ratios_and_percentages_not_sizes() {
    let found = stated_figures("costs 1.44–1.71× at 640×480; 17% of them, v1.5× no, (2×)");
    assert_eq!(found, ["1.44×", "1.71×", "17%", "2×"]);
}
