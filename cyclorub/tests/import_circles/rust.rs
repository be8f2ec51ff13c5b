//! The arrows between the files of one crate, read from their source text:
//! comments and literals dropped, `use` trees, `mod` items, item
//! definitions and the paths written in code (`crate::`, `super::`,
//! `self::`, a child module's or an imported module's name).

use super::graph::Graph;
use std::collections::{BTreeMap, BTreeSet};
use std::path::Path;

/// One `use` leaf: its path as written and the name it binds (`None` for
/// a glob).
struct Use {
    scope: Vec<String>,
    path: Vec<String>,
    alias: Option<String>,
    public: bool,
}

/// One source file of a crate.
pub struct File {
    rel: String,
    /// Its module path from the crate root (`lib.rs`: empty).
    pub module: Vec<String>,
    inline: Vec<Vec<String>>,
    defs: Vec<(Vec<String>, String)>,
    uses: Vec<Use>,
    paths: Vec<(Vec<String>, Vec<String>)>,
    words: BTreeSet<String>,
    /// Modules declared `#[cfg(test)] mod name;` here.
    tests: Vec<Vec<String>>,
}

impl File {
    /// The file's path under `src/`.
    pub fn label(&self) -> String {
        self.rel.clone()
    }
}

/// Every `.rs` file under `src`, read and parsed.
pub fn crate_files(src: &Path) -> Vec<File> {
    let mut found = Vec::new();
    walk(src, src, &mut found);
    found.sort();
    // `#[path = "x.rs"] mod name;`: x.rs is module `name` of its file.
    let mut moved: BTreeMap<String, (String, String)> = BTreeMap::new();
    for (rel, text) in &found {
        let dir = rel.rsplit_once('/').map_or("", |(d, _)| d);
        let mut rest = text.as_str();
        while let Some(at) = rest.find("#[path = \"") {
            rest = &rest[at + 10..];
            let Some(end) = rest.find('"') else { break };
            let target = if dir.is_empty() {
                rest[..end].to_string()
            } else {
                format!("{dir}/{}", &rest[..end])
            };
            let after = rest[end..].split("mod ").nth(1).unwrap_or("");
            let name: String = after
                .chars()
                .take_while(|c| c.is_alphanumeric() || *c == '_')
                .collect();
            moved.insert(target, (rel.clone(), name));
        }
    }
    let module_of = |rel: &str| -> Vec<String> {
        let stem = rel.trim_end_matches(".rs");
        let mut parts: Vec<String> = stem.split('/').map(str::to_string).collect();
        if matches!(
            parts.last().map(String::as_str),
            Some("mod" | "lib" | "main")
        ) {
            parts.pop();
        }
        parts
    };
    found
        .iter()
        .map(|(rel, text)| {
            let module = match moved.get(rel) {
                Some((owner, name)) => {
                    let mut m = module_of(owner);
                    m.push(name.clone());
                    m
                }
                None => module_of(rel),
            };
            parse(rel, module, text)
        })
        .collect()
}

fn walk(src: &Path, dir: &Path, out: &mut Vec<(String, String)>) {
    for entry in std::fs::read_dir(dir).expect("a source folder").flatten() {
        let path = entry.path();
        if path.is_dir() {
            walk(src, &path, out);
        } else if path.extension().is_some_and(|e| e == "rs") {
            let rel = path.strip_prefix(src).unwrap().to_string_lossy();
            let text = std::fs::read_to_string(&path).unwrap();
            out.push((rel.replace('\\', "/"), text));
        }
    }
}

/// Parses files given as (path under `src/`, module path, text).
pub fn parse_files(files: Vec<(&str, Vec<&str>, &str)>) -> Vec<File> {
    files
        .into_iter()
        .map(|(rel, module, text)| {
            let module = module.into_iter().map(str::to_string).collect();
            parse(rel, module, text)
        })
        .collect()
}

/// Source text without comments, strings and character literals, as
/// identifiers and punctuation (`::` is one token).
fn tokens(text: &str) -> Vec<String> {
    let c: Vec<char> = text.chars().collect();
    let ident = |ch: char| ch.is_alphanumeric() || ch == '_';
    let mut out = Vec::new();
    let mut i = 0;
    while i < c.len() {
        let ch = c[i];
        let next = c.get(i + 1).copied().unwrap_or(' ');
        if ch == '/' && next == '/' {
            while i < c.len() && c[i] != '\n' {
                i += 1;
            }
        } else if ch == '/' && next == '*' {
            let mut depth = 0;
            while i < c.len() {
                if c[i] == '/' && c.get(i + 1) == Some(&'*') {
                    depth += 1;
                    i += 2;
                } else if c[i] == '*' && c.get(i + 1) == Some(&'/') {
                    depth -= 1;
                    i += 2;
                    if depth == 0 {
                        break;
                    }
                } else {
                    i += 1;
                }
            }
        } else if ch == '"' {
            i += 1;
            while i < c.len() && c[i] != '"' {
                i += if c[i] == '\\' { 2 } else { 1 };
            }
            i += 1;
        } else if ch == '\'' {
            if next == '\\' {
                i += 3;
                while i < c.len() && c[i] != '\'' {
                    i += 1;
                }
                i += 1;
            } else if c.get(i + 2) == Some(&'\'') {
                i += 3;
            } else {
                i += 1;
            }
        } else if ch.is_ascii_digit() {
            while i < c.len()
                && (ident(c[i]) || (c[i] == '.' && c.get(i + 1).is_some_and(char::is_ascii_digit)))
            {
                i += 1;
            }
        } else if ident(ch) {
            let start = i;
            while i < c.len() && ident(c[i]) {
                i += 1;
            }
            let word: String = c[start..i].iter().collect();
            let raw = (word == "r" || word == "br") && matches!(c.get(i), Some('"' | '#'));
            if raw {
                let mut hashes = 0;
                while c.get(i) == Some(&'#') {
                    hashes += 1;
                    i += 1;
                }
                if c.get(i) == Some(&'"') {
                    i += 1;
                    loop {
                        if i >= c.len() {
                            break;
                        }
                        if c[i] == '"' && (1..=hashes).all(|k| c.get(i + k) == Some(&'#')) {
                            i += 1 + hashes;
                            break;
                        }
                        i += 1;
                    }
                }
                // Otherwise a raw identifier `r#name`: its name follows.
            } else {
                out.push(word);
            }
        } else if ch == ':' && next == ':' {
            out.push("::".to_string());
            i += 2;
        } else {
            if !ch.is_whitespace() {
                out.push(ch.to_string());
            }
            i += 1;
        }
    }
    out
}

const ITEM_KEYWORDS: &[&str] = &[
    "struct", "enum", "fn", "trait", "type", "const", "static", "union",
];

fn parse(rel: &str, module: Vec<String>, text: &str) -> File {
    let t = tokens(text);
    let mut file = File {
        rel: rel.to_string(),
        module: module.clone(),
        inline: Vec::new(),
        defs: Vec::new(),
        uses: Vec::new(),
        paths: Vec::new(),
        words: BTreeSet::new(),
        tests: Vec::new(),
    };
    // The inline modules open around the cursor: (path, depth of their body).
    let mut scopes: Vec<(Vec<String>, usize)> = vec![(module, 0)];
    let mut depth = 0;
    let mut i = 0;
    while i < t.len() {
        let scope = scopes.last().expect("the file's scope").clone();
        let tok = t[i].as_str();
        let after_colons = i > 0 && t[i - 1] == "::";
        if is_cfg_test(&t, i) {
            // Test code is not part of the build: its item is left out (a
            // test module's file is marked, its arrows dropped).
            i = skip_item(&t, i + 7, &scope.0, &mut file.tests);
            continue;
        }
        match tok {
            "{" => depth += 1,
            "}" => {
                depth -= 1;
                if scopes.len() > 1 && scopes.last().is_some_and(|s| s.1 > depth) {
                    scopes.pop();
                }
            }
            "mod" if t.get(i + 2).is_some_and(|s| s == "{") => {
                let mut path = scope.0.clone();
                path.push(t[i + 1].clone());
                file.inline.push(path.clone());
                scopes.push((path, depth + 1));
                depth += 1;
                i += 3;
                continue;
            }
            "use" if !after_colons => {
                let public = is_public(&t, i);
                i += 1;
                let mut leaves = Vec::new();
                use_tree(&t, &mut i, Vec::new(), &mut leaves);
                while i < t.len() && t[i] != ";" {
                    i += 1;
                }
                for (path, alias) in leaves {
                    file.uses.push(Use {
                        scope: scope.0.clone(),
                        path,
                        alias,
                        public,
                    });
                }
                continue;
            }
            _ => {}
        }
        if ITEM_KEYWORDS.contains(&tok) && depth == scope.1 {
            if let Some(name) = t.get(i + 1) {
                file.defs.push((scope.0.clone(), name.clone()));
            }
        }
        let is_word = tok
            .chars()
            .next()
            .is_some_and(|c| c.is_alphanumeric() || c == '_');
        if is_word {
            file.words.insert(tok.to_string());
            if !after_colons && t.get(i + 1).is_some_and(|s| s == "::") {
                let mut path = vec![tok.to_string()];
                let mut j = i + 1;
                while t.get(j).is_some_and(|s| s == "::")
                    && t.get(j + 1)
                        .is_some_and(|s| s.chars().all(|c| c.is_alphanumeric() || c == '_'))
                {
                    path.push(t[j + 1].clone());
                    j += 2;
                }
                if path.len() > 1 {
                    file.paths.push((scope.0.clone(), path));
                }
            }
        }
        i += 1;
    }
    file
}

/// Whether `#[cfg(test)]` starts at `i`.
fn is_cfg_test(t: &[String], i: usize) -> bool {
    let want = ["#", "[", "cfg", "(", "test", ")", "]"];
    t.len() >= i + want.len() && want.iter().zip(&t[i..]).all(|(a, b)| a == b)
}

/// The index after the item starting at `i` (past its other attributes);
/// `mod name;` is recorded in `tests`.
fn skip_item(t: &[String], mut i: usize, scope: &[String], tests: &mut Vec<Vec<String>>) -> usize {
    while t.get(i).is_some_and(|s| s == "#") {
        let mut depth = 0;
        while i < t.len() {
            match t[i].as_str() {
                "[" => depth += 1,
                "]" => {
                    depth -= 1;
                    if depth == 0 {
                        i += 1;
                        break;
                    }
                }
                _ => {}
            }
            i += 1;
        }
    }
    let start = i;
    let mut depth = 0;
    while i < t.len() {
        match t[i].as_str() {
            "{" => depth += 1,
            "}" => {
                depth -= 1;
                if depth == 0 {
                    return i + 1;
                }
            }
            ";" if depth == 0 => {
                if t[start..i].ends_with(&["mod".to_string(), t[i - 1].clone()]) {
                    let mut path = scope.to_vec();
                    path.push(t[i - 1].clone());
                    tests.push(path);
                }
                return i + 1;
            }
            _ => {}
        }
        i += 1;
    }
    i
}

/// Whether the `use` at `i` is `pub` or `pub(…)`.
fn is_public(t: &[String], i: usize) -> bool {
    if i == 0 {
        return false;
    }
    if t[i - 1] == "pub" {
        return true;
    }
    if t[i - 1] == ")" {
        let mut j = i - 1;
        while j > 0 && t[j] != "(" {
            j -= 1;
        }
        return j > 0 && t[j - 1] == "pub";
    }
    false
}

/// The leaves of the `use` tree at `i`, under `prefix`.
fn use_tree(
    t: &[String],
    i: &mut usize,
    mut prefix: Vec<String>,
    out: &mut Vec<(Vec<String>, Option<String>)>,
) {
    while *i < t.len() {
        let tok = t[*i].as_str();
        match tok {
            "::" => *i += 1,
            "*" => {
                out.push((prefix, None));
                *i += 1;
                return;
            }
            "{" => {
                *i += 1;
                while *i < t.len() && t[*i] != "}" {
                    use_tree(t, i, prefix.clone(), out);
                    if t.get(*i).is_some_and(|s| s == ",") {
                        *i += 1;
                    }
                }
                *i += 1;
                return;
            }
            _ if tok.chars().all(|c| c.is_alphanumeric() || c == '_') => {
                if t.get(*i + 1).is_some_and(|s| s == "::") {
                    prefix.push(tok.to_string());
                    *i += 2;
                    continue;
                }
                let (path, mut alias) = if tok == "self" {
                    (prefix.clone(), prefix.last().cloned().unwrap_or_default())
                } else {
                    let mut p = prefix.clone();
                    p.push(tok.to_string());
                    (p, tok.to_string())
                };
                *i += 1;
                if t.get(*i).is_some_and(|s| s == "as") {
                    alias = t.get(*i + 1).cloned().unwrap_or_default();
                    *i += 2;
                }
                out.push((path, Some(alias)));
                return;
            }
            _ => {
                *i += 1;
                return;
            }
        }
    }
}

/// A name a `use` item binds (`None`: a glob) and its absolute path
/// (`None`: outside the crate).
type Import = (Option<String>, Option<Vec<String>>);

/// The crate's modules and names, to resolve paths to files.
struct Crate {
    module_file: BTreeMap<Vec<String>, usize>,
    defs: BTreeMap<Vec<String>, BTreeSet<String>>,
    /// Per module: the names its `use` items bind (`None`: a glob) and
    /// their absolute paths (`None`: outside the crate).
    imports: BTreeMap<Vec<String>, Vec<Import>>,
}

impl Crate {
    fn new(files: &[File]) -> Self {
        let mut module_file = BTreeMap::new();
        let mut defs: BTreeMap<Vec<String>, BTreeSet<String>> = BTreeMap::new();
        for (k, f) in files.iter().enumerate() {
            module_file.insert(f.module.clone(), k);
            for m in &f.inline {
                module_file.insert(m.clone(), k);
            }
            for (m, name) in &f.defs {
                defs.entry(m.clone()).or_default().insert(name.clone());
            }
        }
        let mut krate = Crate {
            module_file,
            defs,
            imports: BTreeMap::new(),
        };
        let mut imports: BTreeMap<_, Vec<_>> = BTreeMap::new();
        for f in files {
            for u in &f.uses {
                let abs = krate.absolute(f, &u.scope, &u.path);
                imports
                    .entry(u.scope.clone())
                    .or_default()
                    .push((u.alias.clone(), abs));
            }
        }
        krate.imports = imports;
        krate
    }

    fn is_module(&self, path: &[String]) -> bool {
        self.module_file.contains_key(path)
    }

    /// `path` as written in `scope` of `file`, from the crate root; `None`
    /// for a path outside the crate.
    fn absolute(&self, file: &File, scope: &[String], path: &[String]) -> Option<Vec<String>> {
        let first = path.first()?.as_str();
        let mut base: Vec<String> = scope.to_vec();
        let mut rest = path;
        match first {
            "crate" => {
                base.clear();
                rest = &path[1..];
            }
            "self" => rest = &path[1..],
            "super" => {
                while rest.first().is_some_and(|s| s == "super") {
                    base.pop();
                    rest = &rest[1..];
                }
            }
            _ => {
                let mut child = scope.to_vec();
                child.push(first.to_string());
                if !self.is_module(&child) {
                    // An imported name of this file (`use super::b;` then
                    // `b::Other`); the imports map is not built yet while
                    // `use` items themselves are read, so read the file.
                    let target = file
                        .uses
                        .iter()
                        .find(|u| u.alias.as_deref() == Some(first) && u.path != path);
                    let target = target?;
                    let mut abs = self.absolute(file, &target.scope, &target.path)?;
                    abs.extend(path[1..].iter().cloned());
                    return Some(abs);
                }
            }
        }
        base.extend(rest.iter().cloned());
        Some(base)
    }

    /// The file that defines what `path` names. `strict`: `None` unless
    /// the name is found (for globs); otherwise the innermost module.
    fn resolve(&self, path: &[String], strict: bool, depth: usize) -> Option<usize> {
        if depth > 24 {
            return None;
        }
        let k = (0..=path.len())
            .rev()
            .find(|&k| self.is_module(&path[..k]))?;
        let (module, rest) = path.split_at(k);
        let file = self.module_file[module];
        let Some(name) = rest.first() else {
            return Some(file);
        };
        if self.defs.get(module).is_some_and(|d| d.contains(name)) {
            return Some(file);
        }
        let imports = self.imports.get(module).map(Vec::as_slice).unwrap_or(&[]);
        for (alias, target) in imports {
            if alias.as_ref() == Some(name) {
                let mut target = target.clone()?;
                target.extend(rest[1..].iter().cloned());
                return self.resolve(&target, strict, depth + 1);
            }
        }
        for (alias, target) in imports {
            if let (None, Some(target)) = (alias, target) {
                let mut target = target.clone();
                target.extend(rest.iter().cloned());
                if let Some(found) = self.resolve(&target, true, depth + 1) {
                    return Some(found);
                }
            }
        }
        (!strict).then_some(file)
    }
}

/// The arrows `(from, to)` between the files (indices into `files`).
pub fn file_edges(files: &[File]) -> BTreeSet<(usize, usize)> {
    let krate = Crate::new(files);
    let tests: Vec<&Vec<String>> = files.iter().flat_map(|f| &f.tests).collect();
    let mut edges = BTreeSet::new();
    for (k, f) in files.iter().enumerate() {
        if tests.iter().any(|m| f.module.starts_with(m)) {
            continue;
        }
        let mut add = |to: Option<usize>| {
            if let Some(to) = to {
                if to != k {
                    edges.insert((k, to));
                }
            }
        };
        for u in &f.uses {
            let Some(abs) = krate.absolute(f, &u.scope, &u.path) else {
                continue;
            };
            match &u.alias {
                Some(alias) => {
                    if !u.public || f.words.contains(alias) {
                        add(krate.resolve(&abs, false, 0));
                    }
                }
                None if krate.is_module(&abs) => {
                    for word in &f.words {
                        let mut item = abs.clone();
                        item.push(word.clone());
                        add(krate.resolve(&item, true, 0));
                    }
                }
                None => add(krate.resolve(&abs, false, 0)),
            }
        }
        for (scope, path) in &f.paths {
            let first = path[0].as_str();
            let mut child = scope.clone();
            child.push(first.to_string());
            let local = matches!(first, "crate" | "self" | "super")
                || krate.is_module(&child)
                || f.uses.iter().any(|u| {
                    u.alias.as_deref() == Some(first)
                        && krate
                            .absolute(f, &u.scope, &u.path)
                            .is_some_and(|abs| krate.is_module(&abs))
                });
            if local {
                if let Some(abs) = krate.absolute(f, scope, path) {
                    add(krate.resolve(&abs, false, 0));
                }
            }
        }
    }
    edges
}

/// The file arrows lifted to modules: an arrow between files in two
/// sibling modules (or sibling files) is an arrow between those, in the
/// graph of their parent module (the crate root: the empty path).
pub fn module_graphs(
    files: &[File],
    edges: &BTreeSet<(usize, usize)>,
) -> BTreeMap<Vec<String>, Graph> {
    let mut out: BTreeMap<Vec<String>, Graph> = BTreeMap::new();
    for (from, to) in edges {
        let (a, b) = (&files[*from].module, &files[*to].module);
        let p = a.iter().zip(b).take_while(|(x, y)| x == y).count();
        if p < a.len() && p < b.len() {
            out.entry(a[..p].to_vec()).or_default().edge(&a[p], &b[p]);
        }
    }
    out.entry(Vec::new()).or_default();
    out
}

/// The crate's top-level modules.
pub fn top_modules(files: &[File]) -> BTreeSet<String> {
    files
        .iter()
        .filter_map(|f| f.module.first().cloned())
        .collect()
}

/// Whether one file's module holds the other's (a `mod.rs` and its
/// children: one unit, whose children may use their parent's items).
pub fn nested(a: &File, b: &File) -> bool {
    a.module.starts_with(&b.module) || b.module.starts_with(&a.module)
}
