//! Every document the code, the tests and the README cite exists, and
//! every section of docs/design.md they cite is one of its headings (issue
//! 41: a newcomer who clones the repository can read the map the code
//! points at). A cited `README.md#…` or `docs/….md#…`, and every
//! relative link of the Markdown pages (README.md, docs/), must land on a
//! file and on one of its headings.

use std::path::{Path, PathBuf};

/// The workspace's root (this crate's parent).
fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .expect("the crate lies in the workspace")
        .to_path_buf()
}

/// Every source and text file of the workspace, outside build output.
fn files(dir: &Path, out: &mut Vec<PathBuf>) {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return;
    };
    for entry in entries.flatten() {
        let path = entry.path();
        let name = entry.file_name().to_string_lossy().to_string();
        if path.is_dir() {
            if !(name == "target" || name.starts_with('.') || name == "node_modules") {
                files(&path, out);
            }
        } else if ["rs", "md", "py", "pyi", "toml"]
            .iter()
            .any(|ext| name.ends_with(&format!(".{ext}")))
        {
            out.push(path);
        }
    }
}

/// The citations of a document under `docs/` (with ` §N` when given) in
/// `text`.
fn citations(text: &str) -> Vec<(String, Option<u32>)> {
    let mut out = Vec::new();
    let mut rest = text;
    while let Some(at) = rest.find("docs/") {
        let tail = &rest[at..];
        let end = tail
            .find(|c: char| !(c.is_ascii_alphanumeric() || "/_.-".contains(c)))
            .unwrap_or(tail.len());
        let path = tail[..end].trim_end_matches('.');
        if path.ends_with(".md") {
            let after = &tail[end..];
            let section = after.strip_prefix(" §").and_then(|s| {
                let digits: String = s.chars().take_while(char::is_ascii_digit).collect();
                digits.parse().ok()
            });
            out.push((path.to_string(), section));
        }
        rest = &tail[end.max(5)..];
    }
    out
}

#[test]
fn every_cited_document_and_design_section_exists() {
    let root = root();
    let design = std::fs::read_to_string(root.join("docs/design.md")).expect("docs/design.md");
    let sections: Vec<u32> = design
        .lines()
        .filter_map(|l| l.strip_prefix("## "))
        .filter_map(|l| l.split('.').next()?.trim().parse().ok())
        .collect();
    let mut all = Vec::new();
    files(&root, &mut all);
    let mut cited = 0;
    let mut missing = Vec::new();
    for file in &all {
        let Ok(text) = std::fs::read_to_string(file) else {
            continue;
        };
        for (path, section) in citations(&text) {
            cited += 1;
            if !root.join(&path).is_file() {
                missing.push(format!("{}: {path} does not exist", file.display()));
            } else if path == "docs/design.md" {
                if let Some(s) = section.filter(|s| !sections.contains(s)) {
                    missing.push(format!("{}: {path} §{s} is no section", file.display()));
                }
            }
        }
    }
    assert!(
        cited > 20,
        "only {cited} citations found: is the walk right?"
    );
    assert!(missing.is_empty(), "{}", missing.join("\n"));
}

/// GitHub's anchor of a heading: lower case, letters, digits, `-` and `_`
/// kept, spaces made `-`, everything else dropped.
fn slug(heading: &str) -> String {
    heading
        .trim()
        .to_lowercase()
        .chars()
        .filter_map(|c| match c {
            ' ' => Some('-'),
            c if c.is_alphanumeric() || c == '-' || c == '_' => Some(c),
            _ => None,
        })
        .collect()
}

/// The anchors of a Markdown page's headings (outside code blocks), a
/// repeated one numbered as GitHub does (`-1`, `-2`…).
fn anchors(markdown: &str) -> Vec<String> {
    let mut out: Vec<String> = Vec::new();
    let mut fenced = false;
    for line in markdown.lines() {
        if line.starts_with("```") {
            fenced = !fenced;
            continue;
        }
        let Some(text) = line.strip_prefix('#') else {
            continue;
        };
        if fenced {
            continue;
        }
        let base = slug(text.trim_start_matches('#'));
        let repeats = out
            .iter()
            .filter(|a| {
                *a == &base
                    || a.strip_prefix(&format!("{base}-"))
                        .is_some_and(|n| n.parse::<u32>().is_ok())
            })
            .count();
        out.push(match repeats {
            0 => base,
            n => format!("{base}-{n}"),
        });
    }
    out
}

/// The citations with an anchor in `text`: `README.md#…` and
/// `docs/….md#…`, as (path from the root, anchor).
fn anchored_citations(text: &str) -> Vec<(String, String)> {
    let word = |c: char| c.is_ascii_alphanumeric() || "/_.-".contains(c);
    let anchor = |c: char| c.is_alphanumeric() || "-_".contains(c);
    let mut out = Vec::new();
    let mut rest = text;
    while let Some(at) = rest.find(".md#") {
        let before = &rest[..at];
        let start = before
            .char_indices()
            .rev()
            .find(|&(_, c)| !word(c))
            .map_or(0, |(i, c)| i + c.len_utf8());
        let path = format!("{}.md", &before[start..]);
        let tail = &rest[at + 4..];
        let end = tail.find(|c: char| !anchor(c)).unwrap_or(tail.len());
        // `README.md#…` in prose names the form, not an anchor.
        if end > 0 && (path == "README.md" || path.starts_with("docs/")) {
            out.push((path, tail[..end].to_string()));
        }
        rest = &tail[end..];
    }
    out
}

/// The relative links of a Markdown page (`[text](target)`, not a URL),
/// as (file relative to the page's folder, or empty for the page itself;
/// anchor, if any).
fn markdown_links(markdown: &str) -> Vec<(String, Option<String>)> {
    let mut out = Vec::new();
    let mut fenced = false;
    for line in markdown.lines() {
        if line.starts_with("```") {
            fenced = !fenced;
        }
        if fenced {
            continue;
        }
        let mut rest = line;
        while let Some(at) = rest.find("](") {
            let tail = &rest[at + 2..];
            let Some(end) = tail.find(')') else {
                break;
            };
            let target = &tail[..end];
            rest = &tail[end..];
            if target.contains("://") || target.starts_with("mailto:") || target.contains(' ') {
                continue;
            }
            let (file, anchor) = match target.split_once('#') {
                Some((file, anchor)) => (file, Some(anchor.to_string())),
                None => (target, None),
            };
            out.push((file.to_string(), anchor));
        }
    }
    out
}

#[test]
fn every_cited_anchor_and_relative_link_lands_on_a_heading() {
    let root = root();
    let mut all = Vec::new();
    files(&root, &mut all);
    let heading_anchors = |path: &Path| std::fs::read_to_string(path).ok().map(|t| anchors(&t));
    let mut checked = 0;
    let mut missing = Vec::new();
    for file in &all {
        let Ok(text) = std::fs::read_to_string(file) else {
            continue;
        };
        let mut targets: Vec<(PathBuf, Option<String>)> = anchored_citations(&text)
            .into_iter()
            .map(|(path, anchor)| (root.join(path), Some(anchor)))
            .collect();
        let page = file.strip_prefix(&root).unwrap_or(file);
        let is_page = page.extension().is_some_and(|e| e == "md")
            && (page == Path::new("README.md") || page.starts_with("docs"));
        if is_page {
            let folder = file.parent().unwrap_or(&root);
            for (target, anchor) in markdown_links(&text) {
                let path = if target.is_empty() {
                    file.clone()
                } else {
                    folder.join(&target)
                };
                targets.push((path, anchor));
            }
        }
        for (path, anchor) in targets {
            checked += 1;
            let shown = path
                .strip_prefix(&root)
                .unwrap_or(&path)
                .display()
                .to_string();
            if !path.exists() {
                missing.push(format!("{}: {shown} does not exist", page.display()));
                continue;
            }
            let Some(anchor) = anchor else {
                continue;
            };
            if !heading_anchors(&path).is_some_and(|a| a.contains(&anchor)) {
                missing.push(format!(
                    "{}: {shown}#{anchor} is no heading of {shown}",
                    page.display()
                ));
            }
        }
    }
    assert!(
        checked > 20,
        "only {checked} links found: is the walk right?"
    );
    assert!(missing.is_empty(), "{}", missing.join("\n"));
}

#[test]
fn anchors_and_links_are_read_as_github_makes_them() {
    let page = "# The case file\n## `[preload]`: centrifugal and static preload (Sec. 5.2)\n\
                ```sh\n# not a heading\n```\n## Run time\n## Run time\n";
    assert_eq!(
        anchors(page),
        [
            "the-case-file",
            "preload-centrifugal-and-static-preload-sec-52",
            "run-time",
            "run-time-1"
        ]
    );
    assert_eq!(
        markdown_links("see [a](fan.md#run-time), [b](https://x.org/a.md) and [c](#top)"),
        [
            ("fan.md".to_string(), Some("run-time".to_string())),
            (String::new(), Some("top".to_string()))
        ]
    );
    assert_eq!(
        // Spelled in two halves so that this example is no citation.
        anchored_citations(&format!("(see {DOCS}fan.md#run-time, README.md#install)")),
        [
            (format!("{DOCS}fan.md"), "run-time".to_string()),
            ("README.md".to_string(), "install".to_string())
        ]
    );
    assert!(anchored_citations("the form README.md#…").is_empty());
}

/// The documents' folder, for examples that must not read as citations.
const DOCS: &str = concat!("do", "cs/");

#[test]
fn a_citation_is_read_with_its_section() {
    assert_eq!(
        // Spelled in two halves so that this example is no citation.
        citations(&format!(
            "see {DOCS}design.md §10, and {DOCS}other-notes.md."
        )),
        vec![
            (format!("{DOCS}design.md"), Some(10)),
            (format!("{DOCS}other-notes.md"), None)
        ]
    );
}
