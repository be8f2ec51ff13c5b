//! Every key of a case file, written once: its table, default (as a user
//! sees it), unit, what is allowed (as text, and where possible as a
//! machine [`Rule`]) and a one-line doc.
//!
//! From this table come the range checks of [`Case::validate`](super::Case::validate)
//! (one generic check per rule, in `validate.rs`), the comments of the
//! template `cyclorub init` prints (`cyclorub-app/src/template.rs`) and the key tables of
//! README's "Case file" section ([`markdown_table`]; a test fails when they
//! differ). serde still owns the shape: unknown keys, types and enum names.

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
    /// The harmonic balance problem (`ProblemSpec::build`): `N_t ≥ 2 N_h + 1`.
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
    /// Not above the value of the key named.
    AtMost(&'static str),
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

    const fn rules(self, rules: &'static [Rule]) -> Self {
        Self { rules, ..self }
    }

    const fn when(self, when: When) -> Self {
        Self { when, ..self }
    }

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

use Consumer::{ContactLaw, HarmonicBalance, Model};
use Rule::{
    AtLeast, AtMost, Below, BelowHalf, CheckedBy, CountOf, Differs, Dofs, Finite, NonNegative,
    OneOf, OneTo, Positive,
};

const ACADEMIC: When = When::Is("model.kind", "academic");
const MATRICES: When = When::Is("model.kind", "matrices");
const MATRIX_MARKET: When = When::Is("model.kind", "matrix_market");
const MODAL: When = When::Is("model.damping.kind", "modal");
const RAYLEIGH: When = When::Is("model.damping.kind", "rayleigh");
const MATRIX: When = When::Is("model.damping.kind", "matrix");
const EXCITED: When = When::IsNot("excitation.kind", "none");
const REGULARIZED: When = When::Is("contact.law", "regularized");
const DLFT: When = When::Is("contact.law", "dlft");
const BY_MODEL: &[Rule] = &[CheckedBy(Model)];
const BY_LAW: &[Rule] = &[CheckedBy(ContactLaw)];

/// Every table of a case file, in the order of the file.
#[rustfmt::skip]
pub const TABLES: &[Table] = &[
    Table {
        name: "model",
        doc: "The sector model (one sector; the wheel is N copies of it).",
        keys: &[
            Key::new("kind", "`\"academic\"`", "", "",
                "Sector model: \"academic\" (lumped chain: masses, springs), \"matrices\" (inline \
                 matrices) or \"matrix_market\" (Matrix Market files)")
                .rules(&[OneOf(&["academic", "matrices", "matrix_market"])]),
            Key::new("sectors", "`24`", "", "integer ≥ 1", "Number of sectors N")
                .rules(&[AtLeast(1)]),
            Key::new("symmetry_tolerance", "absent: `1e-8`", "", "≥ 0",
                "Relative tolerance on the symmetry of the matrices")
                .rules(BY_MODEL),
            Key::new("masses", "absent: the paper's Table 1", "kg", "> 0", "mass of each dof")
                .rules(BY_MODEL).when(ACADEMIC),
            Key::new("springs", "absent: the paper's Table 1", "N/m", "stiffness ≥ 0",
                "springs { dofs = [a, b], stiffness = k, link = \"within\" | \"next_sector\" \
                 (a in sector j, b in j+1) | \"ground\" (dofs = [a]) }")
                .rules(BY_MODEL).when(ACADEMIC),
            Key::new("mass", "required", "kg", "list of rows, symmetric", "sector mass matrix")
                .rules(BY_MODEL).when(MATRICES).example("[[0.2, 0.0], [0.0, 0.3]]"),
            Key::new("stiffness", "required", "N/m", "list of rows, symmetric",
                "sector stiffness matrix")
                .rules(BY_MODEL).when(MATRICES).example("[[2e6, -2e6], [-2e6, 3.6e6]]"),
            Key::new("mass_coupling", "absent: none", "kg",
                "rows; not with left_boundary / right_boundary",
                "mass coupling block to the next sector")
                .rules(BY_MODEL).when(MATRICES).example("[[0.0, 0.0], [0.0, 0.0]]"),
            Key::new("stiffness_coupling", "absent: none", "N/m",
                "rows; not with left_boundary / right_boundary",
                "stiffness coupling block to the next sector")
                .rules(BY_MODEL).when(MATRICES).example("[[0.0, 0.0], [0.0, -5e5]]"),
            Key::new("mass_file", "required", "", "",
                "sector mass matrix, a Matrix Market file relative to the case file's folder")
                .rules(BY_MODEL).when(MATRIX_MARKET).example("\"mass.mtx\""),
            Key::new("stiffness_file", "required", "", "",
                "sector stiffness matrix, a Matrix Market file relative to the case file's folder")
                .rules(BY_MODEL).when(MATRIX_MARKET).example("\"stiffness.mtx\""),
            Key::new("left_boundary", "absent: none", "", "1-based",
                "Left cyclic boundary dofs of a finite-element sector: kind = \"matrix_market\", \
                 or \"matrices\" without couplings")
                .rules(BY_MODEL).example("[1, 2]"),
            Key::new("right_boundary", "absent: none", "", "1-based, as many as left_boundary",
                "Right cyclic boundary dofs, paired in order with left_boundary")
                .rules(BY_MODEL).example("[7, 8]"),
        ],
    },
    Table {
        name: "model.damping",
        doc: "Damping of the sector model.",
        keys: &[
            Key::new("kind", "`\"modal\"`", "", "",
                "\"modal\" (ratio, or ratios and others), \"rayleigh\" (alpha, beta), \"matrix\" \
                 (matrix and coupling, or file) or \"none\"")
                .rules(&[OneOf(&["none", "modal", "rayleigh", "matrix"])]),
            Key::new("ratio", "absent: `1e-3`, the paper's", "", "≥ 0",
                "damping ratio of every mode")
                .rules(BY_MODEL).when(MODAL).example("1e-3"),
            Key::new("ratios", "absent: ratio applies", "", "≥ 0",
                "ratios by mode index within each nodal diameter's family, instead of ratio")
                .rules(BY_MODEL).when(MODAL).example("[1e-3, 1e-3, 1e-3, 1e-3, 1e-3]"),
            Key::new("others", "absent: the last of ratios, if it lists every mode", "", "≥ 0",
                "with ratios: ratio of the modes beyond the list")
                .rules(BY_MODEL).when(MODAL).example("5e-3"),
            Key::new("alpha", "absent: `0`", "1/s", "≥ 0", "mass factor of C = alpha M + beta K")
                .rules(BY_MODEL).when(RAYLEIGH).example("0.0"),
            Key::new("beta", "absent: `0`", "s", "≥ 0", "stiffness factor of C = alpha M + beta K")
                .rules(BY_MODEL).when(RAYLEIGH).example("1e-6"),
            Key::new("matrix", "required, or file", "N s/m", "list of rows, symmetric",
                "sector damping matrix, laid out like the stiffness")
                .rules(BY_MODEL).when(MATRIX).example("[[1.0, 0.0], [0.0, 1.0]]"),
            Key::new("coupling", "absent: none", "N s/m", "rows",
                "damping coupling block to the next sector, for block-circulant sectors")
                .rules(BY_MODEL).when(MATRIX).example("[[0.0, 0.0], [0.0, 0.0]]"),
            Key::new("file", "absent: matrix applies", "", "",
                "the damping matrix as a Matrix Market file relative to the case file's folder, \
                 instead of matrix")
                .rules(BY_MODEL).when(MATRIX).example("\"damping.mtx\""),
        ],
    },
    Table {
        name: "excitation",
        doc: "First-harmonic force on sector dofs (Eq. 48, 75, 86).",
        keys: &[
            Key::new("kind", "`\"traveling\"`", "", "",
                "\"traveling\" (Eq. 48, backward in blade numbering), \"standing\" (Eq. 75), \
                 \"mixed\" (Eq. 86), \"per_sector\" (amplitudes, phases) or \"none\"")
                .rules(&[OneOf(&["traveling", "standing", "mixed", "per_sector", "none"])]),
            Key::new("engine_order", "`1`", "", "integer, 0 ≤ h < model.sectors", "Engine order h")
                .rules(&[Below("model.sectors")]).when(EXCITED),
            Key::new("amplitude", "`4.0`", "N", "≥ 0", "Force amplitude f_ex")
                .rules(&[NonNegative]).when(EXCITED),
            Key::new("dofs", "`[1]`", "", "1-based, at least one",
                "Sector dofs where the force acts; 1 is the blade tip m1 of the academic model")
                .rules(&[Dofs]).when(EXCITED),
            Key::new("backward_weight", "`0.9`", "", "", "weight of the backward wave (Eq. 86: 0.9)")
                .when(When::Is("excitation.kind", "mixed")),
            Key::new("forward_weight", "`0.1`", "", "", "weight of the forward wave (Eq. 86: 0.1)")
                .when(When::Is("excitation.kind", "mixed")),
            Key::new("amplitudes", "`[]`", "", "one per sector",
                "amplitude factor of each sector, multiplies amplitude")
                .rules(&[CountOf("model.sectors")]).when(When::Is("excitation.kind", "per_sector")),
            Key::new("phases", "`[]`", "rad", "one per sector", "phase of each sector")
                .rules(&[CountOf("model.sectors")]).when(When::Is("excitation.kind", "per_sector")),
            Key::new("static_force", "`0.0`", "N", "finite",
                "Static force (harmonic 0) on the same dofs of every sector; 0: no preload")
                .rules(&[Finite]),
        ],
    },
    Table {
        name: "casing",
        doc: "The gap seen by each contact dof, Eq. (74): g0(t) = c + p cos(h_c (Ωt − 2πj/N)), \
              rotating with Ω = ω.",
        keys: &[
            Key::new("gap", "`1e-3`", "m", "≥ 0; one value, or one per contact dof",
                "Mean gap c between blade tip and casing")
                .rules(&[NonNegative, CheckedBy(Consumer::Casing)]),
            Key::new("order", "`0`", "", "integer < harmonic_balance.time_samples / 2",
                "Diametral order h_c of the casing shape; 0: circular")
                .rules(&[BelowHalf(
                    "harmonic_balance.time_samples",
                    "so that its gap is sampled without aliasing",
                )]),
            Key::new("amplitude", "`0.0`", "m", "≥ 0; one value, or one per contact dof",
                "Amplitude p of the diametral shape; the paper: 0.05 c")
                .rules(&[NonNegative, CheckedBy(Consumer::Casing)]),
        ],
    },
    Table {
        name: "contact",
        doc: "Contact dofs and contact law.",
        keys: &[
            Key::new("law", "`\"regularized\"`", "", "",
                "\"regularized\" (R-HBM, Eq. 70: stiffness, regularization) or \"dlft\" \
                 (DLFT-HBM: epsilon, wall_stiffness)")
                .rules(&[OneOf(&["regularized", "dlft"])]),
            Key::new("dofs", "`[1]`", "", "1-based, at least one",
                "Contact dofs of a sector; positive displacement is toward the casing")
                .rules(&[Dofs]),
            Key::new("stiffness", "`1e8`", "N/m", "> 0", "contact stiffness κ")
                .rules(BY_LAW).when(REGULARIZED),
            Key::new("regularization", "`2.5`", "N", "≥ 0", "regularization γ; 0: the plain penalty law")
                .rules(BY_LAW).when(REGULARIZED),
            Key::new("epsilon", "`1e9`", "N/m", "> 0", "Lagrangian weight ε")
                .rules(BY_LAW).when(DLFT),
            Key::new("wall_stiffness", "absent: a rigid casing", "N/m", "> 0",
                "stiffness of the wall between tip and casing; the paper's academic runs: 1e8")
                .rules(BY_LAW).when(DLFT).example("1e8"),
        ],
    },
    Table {
        name: "harmonic_balance",
        doc: "Harmonic balance discretization.",
        keys: &[
            Key::new("harmonics", "`10`", "", "integer ≥ 1", "Number of harmonics N_h")
                .rules(&[AtLeast(1)]),
            Key::new("time_samples", "`10000`", "", "integer ≥ 2 N_h + 1",
                "Time samples per period N_t; a multiple of N makes reduced and full agree to \
                 round-off")
                .rules(&[CheckedBy(HarmonicBalance)]),
        ],
    },
    Table {
        name: "continuation",
        doc: "Pseudo-arc-length continuation in frequency; steps are scaled (one gap of \
              displacement and the whole range each count 1).",
        keys: &[
            Key::new("start_hz", "absent: `0.95 f₁`", "Hz", "> 0",
                "Start frequency; f₁ is the first natural frequency of the excited nodal diameter")
                .rules(&[Positive]),
            Key::new("end_hz", "absent: `1.10 f₁`", "Hz", "> 0, ≠ start_hz",
                "End frequency; below the start to sweep down")
                .rules(&[Positive, Differs("continuation.start_hz", "the frequency range is empty")]),
            Key::new("initial_step", "`0.01`", "", "> 0", "First step, scaled arc length")
                .rules(&[Positive]),
            Key::new("min_step", "`1e-7`", "", "> 0, ≤ max_step",
                "Smallest step; the run stops when it would go below")
                .rules(&[Positive, AtMost("continuation.max_step")]),
            Key::new("max_step", "`0.1`", "", "> 0", "Largest step").rules(&[Positive]),
            Key::new("tolerance", "`1e-8`", "", "> 0", "Newton tolerance on ‖R‖ / f_ex")
                .rules(&[Positive]),
            Key::new("max_iterations", "`15`", "", "integer ≥ 1", "Newton iterations per step")
                .rules(&[AtLeast(1)]),
            Key::new("max_points", "`5000`", "", "integer ≥ 1",
                "Cap on the number of points, both sweeps together; the run stops there")
                .rules(&[AtLeast(1)]),
        ],
    },
    Table {
        name: "basis",
        doc: "Which unknowns are solved for (`cyclorub plan` shows their sizes).",
        keys: &[Key::new("kind", "`\"symmetry\"`", "", "",
            "\"symmetry\" (the smallest exact basis), \"paper\" (the paper's choice), \
             \"nodal_diameter\", \"full\" (every pair) or \"physical\" (the full wheel, the \
             reference); `cyclorub run --basis` overrides it")
            .rules(&[OneOf(&["symmetry", "paper", "nodal_diameter", "full", "physical"])])],
    },
    Table {
        name: "output",
        doc: "Result files: branch.csv, observed_harmonics.csv, run.json, results.h5.",
        keys: &[
            Key::new("directory", "`\"results\"`", "", "",
                "Results folder, relative to the working directory; `cyclorub run --output` \
                 overrides it"),
            Key::new("observed_dof", "`1`", "", "1..=the dofs of a sector",
                "Dof whose amplitude branch.csv reports")
                .rules(BY_MODEL),
            Key::new("sectors", "`[]`", "", "1..=model.sectors; [] for all",
                "Sectors reported in branch.csv")
                .rules(&[OneTo("model.sectors")]),
        ],
    },
];

/// README's table of `table`: key, default, unit, what is allowed, meaning.
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
                    let text = format!("[{}]\n{} = \"zz_nothing\"\n", table.name, key.name);
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
        assert_eq!(count, 5);
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

    /// The table named by a README heading such as "### `[casing]`: the gap".
    fn heading_table(line: &str) -> Option<&'static Table> {
        TABLES
            .iter()
            .find(|t| line.starts_with(&format!("### `[{}]`", t.name)))
    }

    /// `readme` with the key tables under its "### `[table]`" headings
    /// rendered from the key table, its prose untouched.
    fn with_key_tables(readme: &str) -> String {
        let lines: Vec<&str> = readme.lines().collect();
        let mut out: Vec<String> = Vec::new();
        let mut table = None;
        let mut i = 0;
        while i < lines.len() {
            let line = lines[i];
            if line.starts_with("### ") || line.starts_with("## ") {
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

    /// README's key tables (`### [model]` … `### [output]`) are rendered
    /// from the key table. To rewrite them:
    /// `CYCLORUB_WRITE_README=1 cargo test -p cyclorub --lib readme_key_tables`.
    #[test]
    fn readme_key_tables_are_the_key_table() {
        let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../README.md");
        let readme = std::fs::read_to_string(&path).unwrap();
        let expected = with_key_tables(&readme);
        if std::env::var_os("CYCLORUB_WRITE_README").is_some() {
            std::fs::write(&path, &expected).unwrap();
            return;
        }
        for table in TABLES {
            let heading = format!("### `[{}]`", table.name);
            assert!(
                readme.lines().any(|l| l.starts_with(&heading)),
                "README lacks {heading}"
            );
            let rendered = markdown_table(table);
            assert!(
                expected.contains(&rendered),
                "README lacks a table under {heading}"
            );
        }
        if expected != readme {
            let old: Vec<&str> = readme.lines().collect();
            let new: Vec<&str> = expected.lines().collect();
            let mut diff = String::new();
            for line in old.iter().filter(|l| !new.contains(l)) {
                diff.push_str(&format!("- {line}\n"));
            }
            for line in new.iter().filter(|l| !old.contains(l)) {
                diff.push_str(&format!("+ {line}\n"));
            }
            panic!(
                "README's key tables differ from the key table (cyclorub/src/case/keys.rs):\n{diff}\
                 rewrite them with CYCLORUB_WRITE_README=1 cargo test -p cyclorub --lib readme_key_tables"
            );
        }
    }
}
