//! Every key of a case file, written once: its table, default (as a user
//! sees it), unit, what is allowed (as text, and where possible as a
//! machine [`Rule`]) and a one-line doc.
//!
//! From this table come the range checks of [`Case::validate`](super::Case::validate)
//! (one generic check per rule, in `validate.rs`), the comments of the
//! template `cyclorub init` prints (`cyclorub-app/src/template/render.rs`) and the key
//! tables of the case-file reference, docs/case-file.md ([`markdown_table`]; a test
//! fails when they differ). serde still owns the shape: unknown keys, types and enum names.

mod tables;

pub use tables::TABLES;

/// Where a value is checked when no rule of the table checks it: by the
/// code that consumes it, which names the key.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Consumer {
    /// The sector model, when it is built (`ModelSpec::build`), or the case
    /// against the built model (`Case::check_model`).
    Model,
    /// The contact law's constructor (`Case::contact_model`, called by `Case::validate`).
    ContactLaw,
    /// The casing (`Case::casing`, called by `Case::validate`): one value, or one per contact dof.
    Casing,
    /// The harmonic balance problem (`ProblemSpec::build`): the memory the
    /// sizes take (`harmonic_balance.time_samples`' own rule,
    /// `N_t ≥ 2 N_h + 1`, is the table's; the problem checks it again for
    /// library callers).
    HarmonicBalance,
}

/// A machine rule on a key's value; a list's entries are checked one by one.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Rule {
    /// One of these names; serde refuses any other while parsing (listed for
    /// the docs, and a test holds the list to serde's).
    OneOf(&'static [&'static str]),
    /// A finite number.
    Finite,
    /// A finite number ≥ 0.
    NonNegative,
    /// A finite number > 0.
    Positive,
    /// An integer at least this.
    AtLeast(i64),
    /// A non-empty list of dofs numbered from 1.
    Dofs,
    /// An integer below the value of the key named.
    Below(&'static str),
    /// An integer below half the value of the key named, for the reason given.
    BelowHalf(&'static str, &'static str),
    /// Integers in `1..=` the value of the key named.
    OneTo(&'static str),
    /// As many values as the value of the key named.
    CountOf(&'static str),
    /// An integer at least twice the value of the key named, plus one
    /// (`N_t ≥ 2 N_h + 1`: the harmonics are sampled without aliasing).
    AboveTwice(&'static str),
    /// Not above the value of the key named.
    AtMost(&'static str),
    /// Not above this number (a tolerance beyond which a "solution" would
    /// not be one).
    NoMoreThan(f64),
    /// Not equal to the value of the key named (when set), for the reason given.
    Differs(&'static str, &'static str),
    /// Checked where the value is consumed.
    CheckedBy(Consumer),
}

/// When a key is used (and checked): always, or with one value of another key.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum When {
    /// Always.
    Always,
    /// When the key named (dotted, e.g. `excitation.kind`) has this value.
    Is(&'static str, &'static str),
    /// Unless the key named has this value.
    IsNot(&'static str, &'static str),
}

/// One key of a table.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Key {
    /// The key, e.g. `gap`.
    pub name: &'static str,
    /// The default as shown to a user: `` `1e-3` ``, `absent: …` (what
    /// applies then) or `required…` (by the kind that uses it).
    pub default: &'static str,
    /// Its unit (empty: none).
    pub unit: &'static str,
    /// What is allowed, as a user reads it (empty: any value of its type).
    pub allowed: &'static str,
    /// The machine rules that check it.
    pub rules: &'static [Rule],
    /// When it is used.
    pub when: When,
    /// What it is, one line.
    pub doc: &'static str,
    /// For a key that may be absent: a value as TOML text, which the
    /// template shows commented out (empty: the template makes one).
    pub example: &'static str,
}

impl Key {
    /// A key used always, with no machine rule (add them with [`Key::rules`]).
    const fn new(
        name: &'static str,
        default: &'static str,
        unit: &'static str,
        allowed: &'static str,
        doc: &'static str,
    ) -> Self {
        Self {
            name,
            default,
            unit,
            allowed,
            rules: &[],
            when: When::Always,
            doc,
            example: "",
        }
    }

    /// The same key checked by `rules`.
    const fn rules(self, rules: &'static [Rule]) -> Self {
        Self { rules, ..self }
    }

    /// The same key, used only `when`.
    const fn when(self, when: When) -> Self {
        Self { when, ..self }
    }

    /// The same key with a TOML example for the template.
    const fn example(self, example: &'static str) -> Self {
        Self { example, ..self }
    }

    /// What it is, with the use it depends on first: `kind = "mixed": …`
    /// (a doc is written lower-case; alone, it starts with a capital).
    pub fn meaning(&self) -> String {
        match self.when {
            When::Is(key, value) => {
                let leaf = key.rsplit('.').next().unwrap_or(key);
                format!("{leaf} = \"{value}\": {}", self.doc)
            }
            _ => {
                let mut doc = self.doc.chars();
                let first = doc.next().map(|c| c.to_uppercase().to_string());
                format!("{}{}", first.unwrap_or_default(), doc.as_str())
            }
        }
    }

    /// The template's comment: the meaning, then unit, what is allowed and
    /// what applies when absent, with `note` after them.
    pub fn comment(&self, note: &str) -> String {
        let absent = (self.default.starts_with("absent") || self.default.starts_with("required"))
            .then(|| self.default.replace('`', ""));
        let details: Vec<&str> = [self.unit, self.allowed, absent.as_deref().unwrap_or("")]
            .into_iter()
            .filter(|d| !d.is_empty())
            .collect();
        if details.is_empty() {
            format!("{}.", self.meaning())
        } else {
            format!("{} ({}{note}).", self.meaning(), details.join("; "))
        }
    }
}

/// One table of a case file and its keys, in the order the template shows them.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Table {
    /// Its dotted name, e.g. `model.damping`.
    pub name: &'static str,
    /// What it is, one line (the template's comment above it).
    pub doc: &'static str,
    /// Its keys.
    pub keys: &'static [Key],
}

impl Table {
    /// The dotted name of one of its keys: `casing.gap`.
    pub fn path(&self, key: &Key) -> String {
        format!("{}.{}", self.name, key.name)
    }
}

/// The reference's table of `table` (docs/case-file.md): key, default,
/// unit, what is allowed, meaning.
pub fn markdown_table(table: &Table) -> String {
    let cell = |text: &str| match text {
        "" => "—".to_string(),
        text => text.replace('|', "\\|"),
    };
    let mut out =
        String::from("| key | default | unit | allowed | meaning |\n|---|---|---|---|---|\n");
    for key in table.keys {
        out.push_str(&format!(
            "| `{}` | {} | {} | {} | {} |\n",
            key.name,
            cell(key.default),
            cell(key.unit),
            cell(key.allowed),
            cell(&key.meaning())
        ));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::case::text::{inline, lookup};
    use crate::case::Case;
    use std::collections::BTreeSet;
    use std::path::Path;

    /// The names serde lists (between backticks) after "expected" when it
    /// refuses `text`.
    fn expected_by_serde(text: &str) -> BTreeSet<String> {
        let message = Case::from_toml(text, Path::new("keys.toml"))
            .unwrap_err()
            .to_string();
        let list = message
            .split("expected")
            .nth(1)
            .unwrap_or_else(|| panic!("{message}"));
        list.split('`')
            .skip(1)
            .step_by(2)
            .map(str::to_string)
            .collect()
    }

    #[test]
    fn the_key_table_holds_every_key_serde_accepts() {
        let mut top: BTreeSet<String> = TABLES
            .iter()
            .map(|t| t.name.split('.').next().unwrap().to_string())
            .collect();
        top.insert("model".into());
        assert_eq!(top, expected_by_serde("zz_not_a_key = 1\n"));
        for table in TABLES {
            let mut keys: BTreeSet<String> =
                table.keys.iter().map(|k| k.name.to_string()).collect();
            // Sub-tables count as keys of their parent.
            for sub in TABLES {
                if let Some(rest) = sub.name.strip_prefix(&format!("{}.", table.name)) {
                    keys.insert(rest.to_string());
                }
            }
            let text = format!("[{}]\nzz_not_a_key = 1\n", table.name);
            assert_eq!(keys, expected_by_serde(&text), "[{}]", table.name);
        }
    }

    /// An enumerated key lists serde's names, and its doc names each.
    #[test]
    fn enumerated_keys_list_every_allowed_name() {
        let mut count = 0;
        for table in TABLES {
            for key in table.keys {
                for rule in key.rules {
                    let Rule::OneOf(names) = rule else { continue };
                    // A list's entries are checked one by one.
                    let value = if key.default.starts_with("`[") {
                        "[\"zz_nothing\"]"
                    } else {
                        "\"zz_nothing\""
                    };
                    let text = format!("[{}]\n{} = {value}\n", table.name, key.name);
                    let listed: BTreeSet<String> = names.iter().map(|n| n.to_string()).collect();
                    assert_eq!(listed, expected_by_serde(&text), "{}", table.path(key));
                    for name in *names {
                        assert!(
                            key.doc.contains(&format!("\"{name}\"")),
                            "{name}: {}",
                            key.doc
                        );
                    }
                    count += 1;
                }
            }
        }
        assert_eq!(count, 11);
    }

    /// The default shown for a key is the default case's value; a key the
    /// default case leaves out says what applies.
    #[test]
    fn the_defaults_shown_are_the_default_case() {
        let root = Case::default().to_value().unwrap();
        for table in TABLES {
            for key in table.keys {
                match lookup(&root, &table.path(key)) {
                    Some(value) => assert_eq!(key.default, format!("`{}`", inline(value))),
                    None => assert!(
                        key.default.starts_with("absent") || key.default.starts_with("required"),
                        "{}: {}",
                        table.path(key),
                        key.default
                    ),
                }
                assert!(
                    !key.doc.ends_with('.'),
                    "{}: one line, no full stop",
                    key.name
                );
            }
        }
    }

    /// The table named by a heading of the reference such as
    /// "## `[casing]`: the gap".
    fn heading_table(line: &str) -> Option<&'static Table> {
        TABLES
            .iter()
            .find(|t| line.starts_with(&format!("## `[{}]`", t.name)))
    }

    /// `reference` with the key tables under its "## `[table]`" headings
    /// rendered from the key table, its prose untouched.
    fn with_key_tables(reference: &str) -> String {
        let lines: Vec<&str> = reference.lines().collect();
        let mut out: Vec<String> = Vec::new();
        let mut table = None;
        let mut i = 0;
        while i < lines.len() {
            let line = lines[i];
            if line.starts_with('#') {
                table = heading_table(line);
            }
            match table {
                Some(t) if line.starts_with('|') => {
                    out.extend(markdown_table(t).lines().map(str::to_string));
                    while i < lines.len() && lines[i].starts_with('|') {
                        i += 1;
                    }
                    table = None;
                    continue;
                }
                _ => out.push(line.to_string()),
            }
            i += 1;
        }
        out.join("\n") + "\n"
    }

    /// The key tables of docs/case-file.md (`## [model]` … `## [mistuning]`)
    /// are rendered from the key table. To rewrite them:
    /// `CYCLORUB_WRITE_KEYS=1 cargo test -p cyclorub --lib reference_key_tables`.
    #[test]
    fn reference_key_tables_are_the_key_table() {
        let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../docs/case-file.md");
        let reference = std::fs::read_to_string(&path).unwrap();
        let expected = with_key_tables(&reference);
        if std::env::var_os("CYCLORUB_WRITE_KEYS").is_some() {
            std::fs::write(&path, &expected).unwrap();
            return;
        }
        for table in TABLES {
            let heading = format!("## `[{}]`", table.name);
            assert!(
                reference.lines().any(|l| l.starts_with(&heading)),
                "docs/case-file.md lacks {heading}"
            );
            let rendered = markdown_table(table);
            assert!(
                expected.contains(&rendered),
                "docs/case-file.md lacks a table under {heading}"
            );
        }
        if expected != reference {
            let old: Vec<&str> = reference.lines().collect();
            let new: Vec<&str> = expected.lines().collect();
            let mut diff = String::new();
            for line in old.iter().filter(|l| !new.contains(l)) {
                diff.push_str(&format!("- {line}\n"));
            }
            for line in new.iter().filter(|l| !old.contains(l)) {
                diff.push_str(&format!("+ {line}\n"));
            }
            panic!(
                "docs/case-file.md's key tables differ from the key table (cyclorub/src/case/keys/tables.rs):\n{diff}\
                 rewrite them with CYCLORUB_WRITE_KEYS=1 cargo test -p cyclorub --lib reference_key_tables"
            );
        }
    }
}
