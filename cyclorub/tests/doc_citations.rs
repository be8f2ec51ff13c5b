//! Every document the code, the tests and the README cite exists, and
//! every section of docs/design.md they cite is one of its headings (issue
//! 41: a newcomer who clones the repository can read the map the code
//! points at).

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
