//! No import circle in the workspace and no arrow back up (issue 41 item
//! 2, docs/design.md §1): the `use`, `mod`, `crate::`, `super::` and
//! `self::` paths of every Rust source file under each crate's `src/`,
//! and the `from . import` / `from ._x import` lines of the Python
//! package, give a dependency graph between files; a circle (files that
//! import each other, directly or around a loop) fails the test with the
//! loop named. The same graph lifted to modules (an arrow between two
//! files is an arrow between the sibling modules that hold them) must be
//! free of circles too, and the library's top-level modules must follow
//! the flow order of [`LIBRARY_ORDER`].
//!
//! A path is resolved to the file that defines the item it names: through
//! `use` re-exports and globs, so that a `mod.rs` which only re-exports a
//! child's items is not an arrow of its own. A `pub use` counts as an
//! arrow of its file only when the file also uses the name.

mod graph;
mod rust;

use graph::{circles, Graph};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// The library's top-level modules, lowest first: a module may use the
/// modules of the lines before its own, never one of its own line or
/// after it (an arrow back up). The flow of docs/design.md §1 (case file →
/// model → basis → harmonic balance → continuation → stability → results)
/// is the flow of data; the uses go the other way round where a later
/// stage is a generic tool: `continuation` knows nothing of harmonic
/// balance (`hbm` implements its `Problem`), `cyclic` and `memory` are
/// vocabulary and estimates that every stage may use. `case` reads every
/// table of a case file, so it sits above what those tables configure;
/// `forced_response` (the front door) and `simulate` (time integration)
/// use them all; `run` writes a results folder of a forced response and
/// `branches` switches from its branch to the bifurcated ones.
/// `mesh` only writes model files (its tests read them back with `model`).
const LIBRARY_ORDER: &[&[&str]] = &[
    &["memory", "cyclic", "continuation"],
    &["contact", "model", "mesh"],
    &["basis"],
    &["hbm"],
    &["stability"],
    &["case"],
    &["results"],
    &["plot"],
    &["forced_response", "simulate"],
    &["branches", "run"],
];

/// The circles left, each as the test names it: the mistuning of issue 44
/// (`model/mistuning.rs` builds on the academic chain and on
/// `SectorModel`, which holds the mistuning and adds it to the full
/// wheel's stiffness) is being changed by other work at the time of this
/// check; its circle is to be broken there (the deviations as a value the
/// sector holds, their application beside them). A circle fixed fails the
/// test until it leaves this list, so the list only shrinks.
const KNOWN_CIRCLES: &[&str] = &[
    "cyclorub files: model/academic.rs -> model/sector/mod.rs -> model/mistuning.rs -> model/academic.rs",
    "cyclorub modules in model: academic -> sector -> mistuning -> academic",
];

/// The workspace's root (this crate's parent).
fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .expect("the crate lies in the workspace")
        .to_path_buf()
}

/// The workspace's crates with a Rust `src/`.
const CRATES: &[&str] = &["cyclorub", "cyclorub-cli", "cyclorub-app", "cyclorub-py"];

/// The Python package's directory.
const PYTHON_PACKAGE: &str = "cyclorub-py/python/cyclorub";

/// The `from .x import …` / `from . import x` arrows of a Python package
/// (its `.py` files; the `.pyi` stubs are the same modules' types).
fn python_graph(dir: &Path) -> Graph {
    let mut graph = Graph::default();
    let mut entries: Vec<PathBuf> = std::fs::read_dir(dir)
        .expect("the Python package is in the tree")
        .flatten()
        .map(|e| e.path())
        .filter(|p| p.extension().is_some_and(|e| e == "py"))
        .collect();
    entries.sort();
    for path in entries {
        let name = path.file_stem().unwrap().to_string_lossy().to_string();
        graph.node(&name);
        let text = std::fs::read_to_string(&path).unwrap();
        for line in text.lines() {
            let line = line.trim_start();
            let Some(rest) = line.strip_prefix("from .") else {
                continue;
            };
            let Some((module, names)) = rest.split_once(" import ") else {
                continue;
            };
            let module = module.trim();
            if module.is_empty() {
                // `from . import x, y`: the sibling modules x and y.
                for target in names.split(',') {
                    let target = target.split(" as ").next().unwrap_or("").trim();
                    let target = target.trim_matches(|c| c == '(' || c == ')');
                    if !target.is_empty() {
                        graph.edge(&name, target);
                    }
                }
            } else {
                graph.edge(&name, module.split('.').next().unwrap_or(module));
            }
        }
    }
    graph
}

/// Every circle of `graph`, one line each, for a failure message.
fn describe(what: &str, graph: &Graph) -> Vec<String> {
    circles(graph)
        .into_iter()
        .map(|c| format!("{what}: {}", c.join(" -> ")))
        .collect()
}

#[test]
fn no_import_circle_between_files_or_modules() {
    let root = root();
    let mut problems = Vec::new();
    for krate in CRATES {
        let files = rust::crate_files(&root.join(krate).join("src"));
        let edges = rust::file_edges(&files);
        let mut file_graph = Graph::default();
        for (from, to) in &edges {
            if !rust::nested(&files[*from], &files[*to]) {
                file_graph.edge(&files[*from].label(), &files[*to].label());
            }
        }
        problems.extend(describe(&format!("{krate} files"), &file_graph));
        for (parent, graph) in rust::module_graphs(&files, &edges) {
            let at = if parent.is_empty() {
                "crate".to_string()
            } else {
                parent.join("::")
            };
            problems.extend(describe(&format!("{krate} modules in {at}"), &graph));
        }
    }
    problems.extend(describe(
        "Python package",
        &python_graph(&root.join(PYTHON_PACKAGE)),
    ));
    let fixed: Vec<&str> = KNOWN_CIRCLES
        .iter()
        .copied()
        .filter(|known| !problems.iter().any(|p| p == known))
        .collect();
    problems.retain(|p| !KNOWN_CIRCLES.contains(&p.as_str()));
    assert!(
        problems.is_empty(),
        "import circles (docs/design.md §1):\n{}",
        problems.join("\n")
    );
    assert!(
        fixed.is_empty(),
        "circles gone: remove them from KNOWN_CIRCLES:\n{}",
        fixed.join("\n")
    );
}

#[test]
fn the_library_flows_one_way() {
    let src = root().join("cyclorub").join("src");
    let files = rust::crate_files(&src);
    let edges = rust::file_edges(&files);
    let mut rank = BTreeMap::new();
    for (level, names) in LIBRARY_ORDER.iter().enumerate() {
        for name in *names {
            rank.insert(name.to_string(), level);
        }
    }
    let mut problems = Vec::new();
    for module in rust::top_modules(&files) {
        if !rank.contains_key(&module) {
            problems.push(format!("{module} is not in LIBRARY_ORDER"));
        }
    }
    let mut seen = std::collections::BTreeSet::new();
    for (from, to) in &edges {
        let (Some(a), Some(b)) = (files[*from].module.first(), files[*to].module.first()) else {
            continue;
        };
        if a == b {
            continue;
        }
        let (Some(ra), Some(rb)) = (rank.get(a), rank.get(b)) else {
            continue;
        };
        if ra <= rb && seen.insert((files[*from].label(), files[*to].label())) {
            problems.push(format!(
                "{a} uses {b} ({} -> {})",
                files[*from].label(),
                files[*to].label()
            ));
        }
    }
    assert!(
        problems.is_empty(),
        "arrows back up in the library (the order is LIBRARY_ORDER, docs/design.md §1):\n{}",
        problems.join("\n")
    );
}

/// The checks can fail: a made-up graph with a loop gives that loop, one
/// without gives none.
#[test]
fn a_made_up_loop_is_found() {
    let mut graph = Graph::default();
    graph.edge("case", "model");
    graph.edge("model", "basis");
    graph.edge("basis", "hbm");
    graph.edge("hbm", "model");
    graph.edge("hbm", "results");
    assert_eq!(
        circles(&graph),
        vec![vec![
            "basis".to_string(),
            "hbm".to_string(),
            "model".to_string(),
            "basis".to_string()
        ]]
    );
    graph = Graph::default();
    graph.edge("a", "b");
    graph.edge("b", "c");
    graph.edge("a", "c");
    assert!(circles(&graph).is_empty());
    // Two files that import each other.
    graph.edge("c", "a");
    assert_eq!(circles(&graph).len(), 1);
}

/// The Rust reader finds a circle written in source text, and resolves a
/// re-export to the file that defines the item.
#[test]
fn a_made_up_crate_with_a_loop_is_found() {
    let files = rust::parse_files(vec![
        ("lib.rs", vec![], "pub mod a; pub mod b; mod c;"),
        ("a/mod.rs", vec!["a"], "mod inner; pub use inner::Thing;"),
        ("a/inner.rs", vec!["a", "inner"], "pub struct Thing;"),
        (
            "b.rs",
            vec!["b"],
            "// use crate::c::Nothing;\npub struct Other; fn f() -> crate::a::Thing { crate::a::Thing }",
        ),
        ("c.rs", vec!["c"], "use super::b; fn g() { b::Other; }"),
    ]);
    let edges = rust::file_edges(&files);
    let mut graph = Graph::default();
    for (from, to) in &edges {
        graph.edge(&files[*from].label(), &files[*to].label());
    }
    // a/mod.rs re-exports Thing without using it: b reaches a/inner.rs.
    assert!(circles(&graph).is_empty(), "{:?}", circles(&graph));
    assert!(graph.has_edge("b.rs", "a/inner.rs"));
    assert!(graph.has_edge("c.rs", "b.rs"));
    let modules = rust::module_graphs(&files, &edges);
    assert!(describe("m", &modules[&Vec::<String>::new()]).is_empty());
    // b uses a and a uses b: a circle of modules (not of files).
    let files = rust::parse_files(vec![
        ("lib.rs", vec![], "pub mod a; pub mod b;"),
        ("a/mod.rs", vec!["a"], "mod x; mod y;"),
        (
            "a/x.rs",
            vec!["a", "x"],
            "use crate::b::Other; pub struct X;",
        ),
        ("a/y.rs", vec!["a", "y"], "pub struct Y;"),
        ("b.rs", vec!["b"], "use crate::a::y::Y; pub struct Other;"),
    ]);
    let edges = rust::file_edges(&files);
    let modules = rust::module_graphs(&files, &edges);
    assert_eq!(
        circles(&modules[&Vec::<String>::new()]),
        vec![vec!["a".to_string(), "b".to_string(), "a".to_string()]]
    );
}
