//! Commented case files: the template that `cyclorub init` prints (the
//! paper's default case, every key with its value and a one-line comment)
//! and the paper's academic studies as ready-made examples (Sec. 4.3 and
//! Appendix C; DESIGN.md §9).
//!
//! The text is rendered from a [`Case`] value, so a template always parses
//! back to the case it was made from: [`default_template`] parses to
//! [`Case::default`], and [`example_template`] to [`Example::case`]. Keys
//! whose value is absent (`None`: an automatic rule or a default computed
//! elsewhere) are shown commented out, with the rule in their comment.

use crate::case::{Case, ExcitationKind, PerContactDof};
use crate::cyclic::fold_nodal_diameter;
use crate::model::{LumpedSector, ModelKind, SpringLink, DEFAULT_SYMMETRY_TOLERANCE};
use serde::Serialize;
use std::num::FpCategory;
use std::path::Path;

/// Mean gap of the paper's academic studies, m (Sec. 4.2).
const PAPER_GAP: f64 = 1e-3;
/// The wall between blade tip and casing in the paper's DLFT-HBM runs (Sec. 4.1), N/m.
const PAPER_WALL_STIFFNESS: f64 = 1e8;

/// Amplitude of the diametral casing of the paper's mixed scenarios, m
/// (`p = 0.05 c`, Appendix C.3).
const PAPER_CASING_AMPLITUDE: f64 = 5e-5;

/// One of the paper's academic studies, ready to run.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Example {
    /// The name given to `cyclorub init --example` (also the file name in
    /// `examples/`, without `.toml`).
    pub name: &'static str,
    /// Where the study is in the paper.
    pub source: &'static str,
    /// Number of sectors `N`.
    pub sectors: usize,
    /// Traveling or standing wave.
    pub excitation: ExcitationKind,
    /// Engine order `h`.
    pub engine_order: usize,
    /// Forcing amplitude `f_ex`, N.
    pub amplitude: f64,
    /// Diametral order `h_c` of the casing (0: circular); its amplitude is
    /// `p = 0.05 c`.
    pub casing_order: usize,
    /// Cap on the points of the branch (`continuation.max_points`; `None`:
    /// the default case's).
    pub max_points: Option<usize>,
    /// Where the values come from, when the paper does not give them all.
    pub note: &'static str,
}

/// The paper's academic studies (DESIGN.md §9), in the paper's order.
pub const EXAMPLES: [Example; 10] = [
    Example {
        name: "n24-traveling-h1",
        source: "Sec. 4.3.1, Fig. 5",
        sectors: 24,
        excitation: ExcitationKind::Traveling,
        engine_order: 1,
        amplitude: 4.0,
        casing_order: 0,
        max_points: None,
        note: "",
    },
    Example {
        name: "n24-traveling-h3",
        source: "Sec. 4.3.1, Fig. 5",
        sectors: 24,
        excitation: ExcitationKind::Traveling,
        engine_order: 3,
        amplitude: 1.75,
        casing_order: 0,
        max_points: None,
        note: "",
    },
    Example {
        name: "n24-standing-h1",
        source: "Sec. 4.3.2, Fig. 8",
        sectors: 24,
        excitation: ExcitationKind::Standing,
        engine_order: 1,
        amplitude: 2.0,
        casing_order: 0,
        max_points: None,
        note: "",
    },
    Example {
        name: "n24-standing-h4",
        source: "Sec. 4.3.2, Fig. 8",
        sectors: 24,
        excitation: ExcitationKind::Standing,
        engine_order: 4,
        amplitude: 1.0,
        casing_order: 0,
        max_points: None,
        note: "",
    },
    Example {
        name: "n24-mixed-h6-casing-h8",
        source: "Sec. 4.3.3, Fig. 11",
        sectors: 24,
        excitation: ExcitationKind::Traveling,
        engine_order: 6,
        amplitude: 3.0,
        casing_order: 8,
        max_points: None,
        note: "The paper gives no forcing amplitude for this case: 3 N is our choice \
               (the same as the reduced-equals-full test of the harmonic balance core).",
    },
    Example {
        name: "n45-traveling-h2",
        source: "Appendix C.1, Fig. 22",
        sectors: 45,
        excitation: ExcitationKind::Traveling,
        engine_order: 2,
        amplitude: 6.0,
        casing_order: 0,
        max_points: None,
        note: "",
    },
    Example {
        name: "n45-traveling-h17",
        source: "Appendix C.1, Fig. 22",
        sectors: 45,
        excitation: ExcitationKind::Traveling,
        engine_order: 17,
        amplitude: 4.0,
        casing_order: 0,
        max_points: None,
        note: "",
    },
    Example {
        name: "n45-standing-h9",
        source: "Appendix C.2, Fig. 23",
        sectors: 45,
        excitation: ExcitationKind::Standing,
        engine_order: 9,
        amplitude: 1.0,
        casing_order: 0,
        max_points: None,
        note: "",
    },
    Example {
        name: "n45-standing-h15",
        source: "Appendix C.2, Fig. 23",
        sectors: 45,
        excitation: ExcitationKind::Standing,
        engine_order: 15,
        amplitude: 1.0,
        casing_order: 0,
        max_points: None,
        note: "",
    },
    Example {
        name: "n45-mixed-h12-casing-h3",
        source: "Appendix C.3, Fig. 25",
        sectors: 45,
        excitation: ExcitationKind::Traveling,
        engine_order: 12,
        amplitude: 2.0,
        casing_order: 3,
        max_points: Some(40_000),
        note: "Its branch snakes through hundreds of folds between 211 and 223 Hz (with R-HBM, \
               longer than 80000 points): up to 40000 points, followed from both ends when needed.",
    },
];

impl Example {
    /// Finds an example by name.
    pub fn find(name: &str) -> Option<&'static Example> {
        EXAMPLES.iter().find(|e| e.name == name)
    }

    /// The names of every example, in order.
    pub fn names() -> Vec<&'static str> {
        EXAMPLES.iter().map(|e| e.name).collect()
    }

    /// One line: sectors, excitation, amplitude and casing.
    pub fn summary(&self) -> String {
        let wave = match self.excitation {
            ExcitationKind::Standing => "standing",
            _ => "traveling",
        };
        let casing = if self.casing_order == 0 {
            "circular casing".to_string()
        } else {
            format!("casing h_c = {}, p = 0.05 c", self.casing_order)
        };
        format!(
            "N = {}, {wave} wave h = {}, f_ex = {} N, {casing} ({})",
            self.sectors, self.engine_order, self.amplitude, self.source
        )
    }

    /// The case: the paper's default case with this study's sectors,
    /// excitation and casing, and results in `results/<name>`.
    pub fn case(&self) -> Case {
        let mut case = Case::default();
        case.model.sectors = self.sectors;
        case.excitation.kind = self.excitation;
        case.excitation.engine_order = self.engine_order;
        case.excitation.amplitude = self.amplitude;
        case.casing.gap = PerContactDof::One(PAPER_GAP);
        case.casing.order = self.casing_order;
        case.casing.amplitude = PerContactDof::One(if self.casing_order == 0 {
            0.0
        } else {
            PAPER_CASING_AMPLITUDE
        });
        case.contact.wall_stiffness = Some(PAPER_WALL_STIFFNESS);
        if let Some(cap) = self.max_points {
            case.continuation.max_points = cap;
        }
        case.output.directory = Path::new("results").join(self.name);
        case
    }

    /// The commented case file of this example.
    pub fn template(&self) -> String {
        let mut header = vec![
            format!("cyclorub example {}: {}.", self.name, self.summary()),
            "Vadcard, Quaegebeur & Thouverez (2024), academic model: ξ = 1e-3, gap 1e-3 m, \
             N_h = 10, N_t = 10000, R-HBM (κ = 1e8 N/m, γ = 2.5 N)."
                .to_string(),
        ];
        if !self.note.is_empty() {
            header.push(self.note.to_string());
        }
        let samples = self.case().harmonic_balance.time_samples;
        if !samples.is_multiple_of(self.sectors) {
            let below = samples / self.sectors * self.sectors;
            header.push(format!(
                "N_t = {samples} (the paper's) is not a multiple of N = {}; a multiple ({below} or \
                 {}) makes reduced and full agree to round-off.",
                self.sectors,
                below + self.sectors
            ));
        }
        header.extend([
            "For DLFT-HBM (wall 1e8 N/m, ε = 1e9 N/m, as in the paper), set \
             contact.law = \"dlft\"."
                .to_string(),
            "Frequency range: the automatic rule (continuation.start_hz and end_hz are absent)."
                .to_string(),
            format!(
                "Run: cyclorub run examples/{}.toml (results in {}).",
                self.name,
                self.case().output.directory.display()
            ),
        ]);
        render(&self.case(), &header)
    }
}

/// The template `cyclorub init` prints: the paper's default case with every
/// key, its value and a one-line comment.
pub fn default_template() -> String {
    let header = [
        "cyclorub case file: the paper's default case (Vadcard, Quaegebeur & Thouverez 2024, \
         Sec. 4):"
            .to_string(),
        "academic model, N = 24, traveling wave h = 1 of 4 N on m1, circular casing with a gap \
         of 1e-3 m,"
            .to_string(),
        "R-HBM (κ = 1e8 N/m, γ = 2.5 N), N_h = 10, N_t = 10000. Start from here: \
         cyclorub init > case.toml"
            .to_string(),
    ];
    render(&Case::default(), &header)
}

/// The commented case file of the example called `name`, if there is one.
pub fn example_template(name: &str) -> Option<String> {
    Example::find(name).map(Example::template)
}

/// Renders any case as a commented case file that parses back to it, with
/// `header` as its first comment lines.
pub fn render(case: &Case, header: &[String]) -> String {
    let mut out = String::new();
    for line in header {
        out.push_str(&format!("# {line}\n"));
    }
    out.push_str(
        "#\n\
         # Every key is shown with its value and a comment: what it is, its unit, what is allowed.\n\
         # A key left out takes the default value of `cyclorub init`. Keys shown commented out\n\
         # (`# key = value`) are absent: the rule in their comment applies. Dofs and sectors are\n\
         # numbered from 1. Natural frequencies: cyclorub modes CASE.toml; basis sizes: cyclorub plan;\n\
         # the forced response: cyclorub run CASE.toml.\n",
    );
    for table in tables(case) {
        out.push('\n');
        out.push_str(&table.render());
    }
    out
}

/// One key of a table.
#[derive(Clone, Debug)]
pub(crate) struct Entry {
    /// The key.
    pub(crate) key: &'static str,
    /// The value as TOML text (may span lines).
    pub(crate) value: String,
    /// What it is, its unit and what is allowed (one line).
    pub(crate) doc: String,
    /// Set (`key = value`), or shown commented out (`# key = value`).
    pub(crate) set: bool,
}

/// One table of the case file.
#[derive(Clone, Debug)]
pub(crate) struct Table {
    /// Its dotted name, e.g. `model.damping`.
    pub(crate) name: &'static str,
    /// What the table is (one line).
    pub(crate) doc: &'static str,
    /// Its keys.
    pub(crate) entries: Vec<Entry>,
}

impl Table {
    fn render(&self) -> String {
        let mut out = format!("# {}\n[{}]\n", self.doc, self.name);
        for entry in &self.entries {
            out.push_str(&format!("# {}\n", entry.doc));
            let line = format!("{} = {}", entry.key, entry.value);
            for part in line.lines() {
                if entry.set {
                    out.push_str(&format!("{part}\n"));
                } else {
                    out.push_str(&format!("# {part}\n"));
                }
            }
        }
        out
    }
}

fn entry(key: &'static str, value: String, doc: impl Into<String>) -> Entry {
    Entry {
        key,
        value,
        doc: doc.into(),
        set: true,
    }
}

/// An optional key: its value when set, else `example` commented out.
fn optional<T>(
    key: &'static str,
    value: &Option<T>,
    example: impl FnOnce() -> String,
    format: impl FnOnce(&T) -> String,
    doc: impl Into<String>,
) -> Entry {
    Entry {
        key,
        set: value.is_some(),
        value: value.as_ref().map_or_else(example, format),
        doc: doc.into(),
    }
}

/// A float as TOML: `0.0`, `4.0`, `1.75`, `1e-3`, `1e8`.
fn float(x: f64) -> String {
    match x.classify() {
        FpCategory::Nan => "nan".into(),
        FpCategory::Infinite if x > 0.0 => "inf".into(),
        FpCategory::Infinite => "-inf".into(),
        FpCategory::Zero => format!("{x:?}"),
        _ if (0.01..1e5).contains(&x.abs()) => format!("{x:?}"),
        _ => format!("{x:e}"),
    }
}

fn floats(values: &[f64]) -> String {
    let items: Vec<String> = values.iter().map(|&v| float(v)).collect();
    format!("[{}]", items.join(", "))
}

fn integers(values: &[usize]) -> String {
    let items: Vec<String> = values.iter().map(usize::to_string).collect();
    format!("[{}]", items.join(", "))
}

fn rows(matrix: &[Vec<f64>]) -> String {
    let mut out = String::from("[\n");
    for row in matrix {
        out.push_str(&format!("    {},\n", floats(row)));
    }
    out.push(']');
    out
}

fn per_contact_dof(value: &PerContactDof) -> String {
    match value {
        PerContactDof::One(v) => float(*v),
        PerContactDof::Each(v) => floats(v),
    }
}

/// A value serialized as TOML text (enum names, strings).
fn toml_value<T: Serialize>(value: &T) -> String {
    toml::Value::try_from(value)
        .map(|v| v.to_string())
        .unwrap_or_else(|_| "\"\"".into())
}

fn path(value: &Path) -> String {
    toml::Value::String(value.display().to_string()).to_string()
}

/// The springs of the paper's academic sector, as a case file writes them.
fn academic_springs() -> String {
    let mut out = String::from("[\n");
    for spring in LumpedSector::academic().springs {
        let (dofs, link) = match spring.link {
            SpringLink::Within(a, b) => (vec![a + 1, b + 1], ""),
            SpringLink::NextSector(a, b) => (vec![a + 1, b + 1], ", link = \"next_sector\""),
            SpringLink::Ground(a) => (vec![a + 1], ", link = \"ground\""),
        };
        out.push_str(&format!(
            "    {{ dofs = {}, stiffness = {}{link} }},\n",
            integers(&dofs),
            float(spring.stiffness)
        ));
    }
    out.push(']');
    out
}

fn springs(list: &[crate::model::SpringSpec]) -> String {
    let mut out = String::from("[\n");
    for spring in list {
        let link = match toml_value(&spring.link).as_str() {
            "\"within\"" => String::new(),
            other => format!(", link = {other}"),
        };
        out.push_str(&format!(
            "    {{ dofs = {}, stiffness = {}{link} }},\n",
            integers(&spring.dofs),
            float(spring.stiffness)
        ));
    }
    out.push(']');
    out
}

/// The automatic frequency range of a case (Hz), when its model builds:
/// 0.95 and 1.10 × the first natural frequency of the excited nodal diameter.
fn automatic_range(case: &Case) -> Option<(f64, f64)> {
    if case.model.kind != ModelKind::Academic {
        return None;
    }
    let model = case.model.build(Path::new(".")).ok()?;
    let order = match case.excitation.kind {
        ExcitationKind::None => case.casing.order,
        _ => case.excitation.engine_order,
    };
    let diameter = fold_nodal_diameter(order as i64, model.sectors()).unsigned_abs() as usize;
    let f = model
        .natural_frequencies()
        .ok()?
        .into_iter()
        .find(|(d, _)| *d == diameter)
        .and_then(|(_, f)| f.first().copied())?;
    Some((0.95 * f, 1.10 * f))
}

/// Rounds a frequency for display (Hz, two decimals).
fn hz(f: f64) -> f64 {
    (f * 100.0).round() / 100.0
}

/// The tables of `case`, every key in order.
pub(crate) fn tables(case: &Case) -> Vec<Table> {
    let m = &case.model;
    let d = &m.damping;
    let e = &case.excitation;
    let c = &case.contact;
    let k = &case.continuation;
    let range = automatic_range(case);
    let here = |i: usize| match range {
        Some(r) => format!(", here {} Hz", hz(if i == 0 { r.0 } else { r.1 })),
        None => String::new(),
    };
    let auto_value =
        |i: usize| float(range.map_or(100.0 * (1.0 + i as f64), |r| hz([r.0, r.1][i])));
    let example_mass = || rows(&[vec![0.2, 0.0], vec![0.0, 0.3]]);
    vec![
        Table {
            name: "model",
            doc: "The sector model (one sector; the wheel is N copies of it).",
            entries: vec![
                entry(
                    "kind",
                    toml_value(&m.kind),
                    "Sector model: \"academic\" (lumped chain: masses, springs), \"matrices\" \
                     (inline matrices) or \"matrix_market\" (files).",
                ),
                entry(
                    "sectors",
                    m.sectors.to_string(),
                    "Number of sectors N (integer ≥ 1).",
                ),
                optional(
                    "symmetry_tolerance",
                    &m.symmetry_tolerance,
                    || float(DEFAULT_SYMMETRY_TOLERANCE),
                    |v| float(*v),
                    format!(
                        "Relative tolerance on the symmetry of the matrices (≥ 0; absent: {}).",
                        float(DEFAULT_SYMMETRY_TOLERANCE)
                    ),
                ),
                optional(
                    "masses",
                    &m.masses,
                    || floats(&LumpedSector::academic().masses),
                    |v| floats(v),
                    "kind = \"academic\": mass of each dof, kg (> 0; absent: the paper's Table 1, \
                     m1..m5).",
                ),
                optional(
                    "springs",
                    &m.springs,
                    academic_springs,
                    |v| springs(v),
                    "kind = \"academic\": springs, N/m (≥ 0); link \"within\" (default), \
                     \"next_sector\" (a in sector j, b in j+1) or \"ground\"; absent: Table 1.",
                ),
                optional(
                    "mass",
                    &m.mass,
                    example_mass,
                    |v| rows(v),
                    "kind = \"matrices\": sector mass matrix, kg (list of rows, symmetric).",
                ),
                optional(
                    "stiffness",
                    &m.stiffness,
                    || rows(&[vec![2e6, -2e6], vec![-2e6, 3.6e6]]),
                    |v| rows(v),
                    "kind = \"matrices\": sector stiffness matrix, N/m (list of rows, symmetric).",
                ),
                optional(
                    "mass_coupling",
                    &m.mass_coupling,
                    || rows(&[vec![0.0, 0.0], vec![0.0, 0.0]]),
                    |v| rows(v),
                    "kind = \"matrices\": mass coupling block to the next sector, kg (rows; \
                     absent: none). Not with left_boundary / right_boundary.",
                ),
                optional(
                    "stiffness_coupling",
                    &m.stiffness_coupling,
                    || rows(&[vec![0.0, 0.0], vec![0.0, -5e5]]),
                    |v| rows(v),
                    "kind = \"matrices\": stiffness coupling block to the next sector, N/m \
                     (rows; absent: none). Not with left_boundary / right_boundary.",
                ),
                optional(
                    "mass_file",
                    &m.mass_file,
                    || path(Path::new("mass.mtx")),
                    |v| path(v),
                    "kind = \"matrix_market\": sector mass matrix, Matrix Market file (relative \
                     to the case file's folder).",
                ),
                optional(
                    "stiffness_file",
                    &m.stiffness_file,
                    || path(Path::new("stiffness.mtx")),
                    |v| path(v),
                    "kind = \"matrix_market\": sector stiffness matrix, Matrix Market file \
                     (relative to the case file's folder).",
                ),
                optional(
                    "left_boundary",
                    &m.left_boundary,
                    || integers(&[1, 2]),
                    |v| integers(v),
                    "kind = \"matrix_market\" (or \"matrices\" without couplings): left cyclic \
                     boundary dofs (1-based).",
                ),
                optional(
                    "right_boundary",
                    &m.right_boundary,
                    || integers(&[7, 8]),
                    |v| integers(v),
                    "Right cyclic boundary dofs (1-based), paired in order with left_boundary \
                     (same count).",
                ),
            ],
        },
        Table {
            name: "model.damping",
            doc: "Damping of the sector model.",
            entries: vec![
                entry(
                    "kind",
                    toml_value(&d.kind),
                    "\"modal\" (ratio, or ratios and others), \"rayleigh\" (alpha, beta), \
                     \"matrix\" (matrix and coupling, or file) or \"none\".",
                ),
                optional(
                    "ratio",
                    &d.ratio,
                    || float(1e-3),
                    |v| float(*v),
                    "modal: damping ratio of every mode (≥ 0; absent, with ratios absent too: \
                     1e-3, the paper's).",
                ),
                optional(
                    "ratios",
                    &d.ratios,
                    || floats(&[1e-3; 5]),
                    |v| floats(v),
                    "modal: ratios by mode index within each nodal diameter's family (≥ 0), \
                     instead of ratio.",
                ),
                optional(
                    "others",
                    &d.others,
                    || float(5e-3),
                    |v| float(*v),
                    "modal, with ratios: ratio of the modes beyond the list (absent: the last of \
                     ratios, if it lists every mode).",
                ),
                optional(
                    "alpha",
                    &d.alpha,
                    || float(0.0),
                    |v| float(*v),
                    "rayleigh: C = alpha M + beta K; mass factor alpha, 1/s (absent: 0).",
                ),
                optional(
                    "beta",
                    &d.beta,
                    || float(1e-6),
                    |v| float(*v),
                    "rayleigh: stiffness factor beta, s (absent: 0).",
                ),
                optional(
                    "matrix",
                    &d.matrix,
                    || rows(&[vec![1.0, 0.0], vec![0.0, 1.0]]),
                    |v| rows(v),
                    "matrix: sector damping matrix, N s/m (rows, laid out like the stiffness).",
                ),
                optional(
                    "coupling",
                    &d.coupling,
                    || rows(&[vec![0.0, 0.0], vec![0.0, 0.0]]),
                    |v| rows(v),
                    "matrix: damping coupling block to the next sector, N s/m (block-circulant \
                     sectors; absent: none).",
                ),
                optional(
                    "file",
                    &d.file,
                    || path(Path::new("damping.mtx")),
                    |v| path(v),
                    "matrix: the damping matrix as a Matrix Market file (relative to the case \
                     file's folder), instead of matrix.",
                ),
            ],
        },
        Table {
            name: "excitation",
            doc: "First-harmonic force on sector dofs (Eq. 48, 75, 86).",
            entries: vec![
                entry(
                    "kind",
                    toml_value(&e.kind),
                    "\"traveling\" (Eq. 48, backward in blade numbering), \"standing\" (Eq. 75), \
                     \"mixed\" (Eq. 86), \"per_sector\" (amplitudes, phases) or \"none\".",
                ),
                entry(
                    "engine_order",
                    e.engine_order.to_string(),
                    "Engine order h (integer, 0 ≤ h < model.sectors).",
                ),
                entry(
                    "amplitude",
                    float(e.amplitude),
                    "Force amplitude f_ex, N (≥ 0).",
                ),
                entry(
                    "dofs",
                    integers(&e.dofs),
                    "Sector dofs (1-based, at least one) where the force acts; 1 is the blade \
                     tip m1 of the academic model.",
                ),
                entry(
                    "backward_weight",
                    float(e.backward_weight),
                    "kind = \"mixed\": weight of the backward wave (Eq. 86: 0.9).",
                ),
                entry(
                    "forward_weight",
                    float(e.forward_weight),
                    "kind = \"mixed\": weight of the forward wave (Eq. 86: 0.1).",
                ),
                entry(
                    "amplitudes",
                    floats(&e.amplitudes),
                    "kind = \"per_sector\": amplitude factor of each sector, multiplies amplitude \
                     (one per sector).",
                ),
                entry(
                    "phases",
                    floats(&e.phases),
                    "kind = \"per_sector\": phase of each sector, rad (one per sector).",
                ),
                entry(
                    "static_force",
                    float(e.static_force),
                    "Static force (harmonic 0) on the same dofs of every sector, N (finite; 0: no \
                     preload).",
                ),
            ],
        },
        Table {
            name: "casing",
            doc:
                "The gap seen by each contact dof, Eq. (74): g0(t) = c + p cos(h_c (Ωt − 2πj/N)), \
                  rotating with Ω = ω.",
            entries: vec![
                entry(
                    "gap",
                    per_contact_dof(&case.casing.gap),
                    "Mean gap c between blade tip and casing, m (≥ 0): one value, or a list with \
                     one per contact dof.",
                ),
                entry(
                    "order",
                    case.casing.order.to_string(),
                    "Diametral order h_c of the casing shape (integer ≥ 0; 0: circular).",
                ),
                entry(
                    "amplitude",
                    per_contact_dof(&case.casing.amplitude),
                    "Amplitude p of the diametral shape, m (≥ 0): one value, or one per contact \
                     dof (the paper: 0.05 c).",
                ),
            ],
        },
        Table {
            name: "contact",
            doc: "Contact dofs and contact law.",
            entries: vec![
                entry(
                    "law",
                    toml_value(&c.law),
                    "\"regularized\" (R-HBM, Eq. 70: stiffness, regularization) or \"dlft\" \
                     (DLFT-HBM: epsilon, wall_stiffness).",
                ),
                entry(
                    "dofs",
                    integers(&c.dofs),
                    "Contact dofs of a sector (1-based, at least one); positive displacement is \
                     toward the casing.",
                ),
                entry(
                    "stiffness",
                    float(c.stiffness),
                    "regularized: contact stiffness κ, N/m (> 0).",
                ),
                entry(
                    "regularization",
                    float(c.regularization),
                    "regularized: regularization γ, N (≥ 0; 0: the plain penalty law).",
                ),
                entry(
                    "epsilon",
                    float(c.epsilon),
                    "dlft: Lagrangian weight ε, N/m (> 0).",
                ),
                optional(
                    "wall_stiffness",
                    &c.wall_stiffness,
                    || float(1e8),
                    |v| float(*v),
                    "dlft: stiffness of the wall between tip and casing, N/m (> 0; absent: a rigid casing; the paper's academic runs: 1e8).",
                ),
            ],
        },
        Table {
            name: "harmonic_balance",
            doc: "Harmonic balance discretization.",
            entries: vec![
                entry(
                    "harmonics",
                    case.harmonic_balance.harmonics.to_string(),
                    "Number of harmonics N_h (integer ≥ 1).",
                ),
                entry(
                    "time_samples",
                    case.harmonic_balance.time_samples.to_string(),
                    "Time samples per period N_t (integer ≥ 2 N_h + 1); a multiple of N makes \
                     reduced and full agree to round-off.",
                ),
            ],
        },
        Table {
            name: "continuation",
            doc: "Pseudo-arc-length continuation in frequency; steps are scaled (one gap of \
                  displacement and the whole range each count 1).",
            entries: vec![
                optional(
                    "start_hz",
                    &k.start_hz,
                    || auto_value(0),
                    |v| float(*v),
                    format!(
                        "Start frequency, Hz (> 0; absent: 0.95 × the first natural frequency of \
                         the excited nodal diameter{}).",
                        here(0)
                    ),
                ),
                optional(
                    "end_hz",
                    &k.end_hz,
                    || auto_value(1),
                    |v| float(*v),
                    format!(
                        "End frequency, Hz (> 0, ≠ start_hz; below it to sweep down; absent: \
                         1.10 × that frequency{}).",
                        here(1)
                    ),
                ),
                entry(
                    "initial_step",
                    float(k.initial_step),
                    "First step, scaled arc length (> 0).",
                ),
                entry(
                    "min_step",
                    float(k.min_step),
                    "Smallest step (> 0, ≤ max_step); the run stops when it would go below.",
                ),
                entry("max_step", float(k.max_step), "Largest step (> 0)."),
                entry(
                    "tolerance",
                    float(k.tolerance),
                    "Newton tolerance on ‖R‖ / f_ex (> 0).",
                ),
                entry(
                    "max_iterations",
                    k.max_iterations.to_string(),
                    "Newton iterations per step (integer ≥ 1).",
                ),
                entry(
                    "max_points",
                    k.max_points.to_string(),
                    "Cap on the number of points, both sweeps together (integer ≥ 1); the run stops there.",
                ),
            ],
        },
        Table {
            name: "basis",
            doc: "Which unknowns are solved for (`cyclorub plan` shows their sizes).",
            entries: vec![entry(
                "kind",
                toml_value(&case.basis.kind),
                "\"symmetry\" (the smallest exact basis), \"paper\" (the paper's choice), \
                 \"nodal_diameter\", \"full\" (every pair) or \"physical\" (full wheel).",
            )],
        },
        Table {
            name: "output",
            doc: "Result files: branch.csv, observed_harmonics.csv, run.json.",
            entries: vec![
                entry(
                    "directory",
                    path(&case.output.directory),
                    "Results folder, relative to the working directory (`cyclorub run --output` \
                     overrides it).",
                ),
                entry(
                    "observed_dof",
                    case.output.observed_dof.to_string(),
                    "Dof (1-based) whose amplitude branch.csv reports.",
                ),
                entry(
                    "sectors",
                    integers(&case.output.sectors),
                    "Sectors (1-based, 1..=N) reported in branch.csv; [] for all.",
                ),
            ],
        },
    ]
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::case::CaseError;
    use std::collections::BTreeSet;
    use std::path::PathBuf;

    fn parse(text: &str) -> Result<Case, CaseError> {
        Case::from_toml(text, Path::new("template.toml"))
    }

    #[test]
    fn the_default_template_parses_to_the_default_case() {
        let text = default_template();
        let case = parse(&text).unwrap_or_else(|e| panic!("{e}\n{text}"));
        assert_eq!(case, Case::default());
        case.validate().unwrap();
    }

    #[test]
    fn every_example_parses_to_its_case_and_validates() {
        for example in &EXAMPLES {
            let text = example.template();
            let case = parse(&text).unwrap_or_else(|e| panic!("{}: {e}", example.name));
            assert_eq!(case, example.case(), "{}", example.name);
            case.validate()
                .unwrap_or_else(|e| panic!("{}: {e}", example.name));
            case.model
                .build(Path::new("."))
                .unwrap_or_else(|e| panic!("{}: {e}", example.name));
            assert_eq!(example_template(example.name), Some(text));
        }
        assert_eq!(example_template("no-such-case"), None);
    }

    #[test]
    fn examples_have_the_papers_parameters() {
        let names = Example::names();
        assert_eq!(names.len(), 10);
        assert_eq!(names.iter().collect::<BTreeSet<_>>().len(), 10);
        for example in &EXAMPLES {
            let case = example.case();
            assert_eq!(case.harmonic_balance.harmonics, 10);
            assert_eq!(case.harmonic_balance.time_samples, 10000);
            let mut contact = Case::default().contact;
            contact.wall_stiffness = Some(1e8);
            assert_eq!(case.contact, contact);
            assert_eq!(case.continuation.start_hz, None);
            let p = match &case.casing.amplitude {
                PerContactDof::One(p) => *p,
                PerContactDof::Each(_) => panic!("one value"),
            };
            if example.casing_order > 0 {
                assert!((p - 0.05 * PAPER_GAP).abs() < 1e-18);
            } else {
                assert_eq!(p.classify(), FpCategory::Zero);
            }
        }
        let h17 = Example::find("n45-traveling-h17").unwrap();
        assert_eq!((h17.sectors, h17.engine_order), (45, 17));
        assert!((h17.amplitude - 4.0).abs() < 1e-15);
    }

    /// Any case, with every optional key set, renders and parses back.
    #[test]
    fn a_case_with_every_optional_key_round_trips() {
        let mut case = Case::default();
        case.model.kind = ModelKind::Matrices;
        case.model.symmetry_tolerance = Some(1e-6);
        case.model.mass = Some(vec![vec![1.0, 0.0], vec![0.0, 2.0]]);
        case.model.stiffness = Some(vec![vec![3e6, -1e6], vec![-1e6, 2.5e6]]);
        case.model.left_boundary = Some(vec![1]);
        case.model.right_boundary = Some(vec![2]);
        case.model.mass_file = Some(PathBuf::from("dir/m \"x\".mtx"));
        case.model.damping.ratios = Some(vec![1e-3, 2e-3]);
        case.model.damping.others = Some(0.01);
        case.excitation.kind = ExcitationKind::PerSector;
        case.excitation.amplitudes = vec![1.0; 24];
        case.excitation.phases = vec![0.123_456_789; 24];
        case.excitation.static_force = -12.5;
        case.casing.gap = PerContactDof::Each(vec![1e-3, 2.5e-4]);
        case.contact.dofs = vec![1, 2];
        case.contact.law = crate::case::LawKind::Dlft;
        case.contact.wall_stiffness = Some(5e7);
        case.continuation.start_hz = Some(150.0);
        case.continuation.end_hz = Some(120.5);
        case.output.sectors = vec![1, 4];
        let text = render(&case, &["a test".to_string()]);
        assert_eq!(parse(&text).unwrap_or_else(|e| panic!("{e}\n{text}")), case);
    }

    /// The keys serde accepts in the table at `prefix` (empty: the top
    /// level), read from its message for an unknown key.
    fn accepted_keys(prefix: &str) -> BTreeSet<String> {
        let text = if prefix.is_empty() {
            "zz_not_a_key = 1\n".to_string()
        } else {
            format!("[{prefix}]\nzz_not_a_key = 1\n")
        };
        let message = parse(&text).unwrap_err().to_string();
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
    fn the_template_shows_every_key_of_every_table() {
        let tables = tables(&Case::default());
        let mut names: BTreeSet<String> = tables
            .iter()
            .map(|t| t.name.split('.').next().unwrap().to_string())
            .collect();
        names.insert("model".into());
        assert_eq!(names, accepted_keys(""));
        for table in &tables {
            let mut shown: BTreeSet<String> =
                table.entries.iter().map(|e| e.key.to_string()).collect();
            // Sub-tables count as keys of their parent.
            for sub in &tables {
                if let Some(rest) = sub.name.strip_prefix(&format!("{}.", table.name)) {
                    shown.insert(rest.to_string());
                }
            }
            assert_eq!(shown, accepted_keys(table.name), "[{}]", table.name);
        }
    }

    /// Every key shown commented out parses once uncommented.
    #[test]
    fn every_commented_out_key_parses_once_uncommented() {
        let mut count = 0;
        for table in tables(&Case::default()) {
            for entry in table.entries.iter().filter(|e| !e.set) {
                let text = format!("[{}]\n{} = {}\n", table.name, entry.key, entry.value);
                parse(&text).unwrap_or_else(|e| panic!("{e}\n{text}"));
                count += 1;
            }
        }
        assert!(count >= 15, "{count}");
    }

    /// The enumerated keys name every allowed value in their comment.
    #[test]
    fn enumerated_keys_name_every_allowed_value() {
        let tables = tables(&Case::default());
        for (table, key) in [
            ("model", "kind"),
            ("model.damping", "kind"),
            ("excitation", "kind"),
            ("contact", "law"),
            ("basis", "kind"),
        ] {
            let message = parse(&format!("[{table}]\n{key} = \"zz_nothing\"\n"))
                .unwrap_err()
                .to_string();
            let doc = &tables
                .iter()
                .find(|t| t.name == table)
                .and_then(|t| t.entries.iter().find(|e| e.key == key))
                .unwrap()
                .doc;
            let list = message.split("expected").nth(1).unwrap();
            for variant in list.split('`').skip(1).step_by(2) {
                assert!(
                    doc.contains(&format!("\"{variant}\"")),
                    "{table}.{key}: {variant} missing from {doc:?}"
                );
            }
        }
    }

    /// The springs and masses shown commented out are the defaults: set
    /// them and the model is the same.
    #[test]
    fn the_commented_academic_model_is_the_default_one() {
        let tables = tables(&Case::default());
        let model = tables.iter().find(|t| t.name == "model").unwrap();
        let mut text = String::from("[model]\n");
        for entry in &model.entries {
            if ["masses", "springs", "symmetry_tolerance"].contains(&entry.key) {
                text.push_str(&format!("{} = {}\n", entry.key, entry.value));
            }
        }
        let case = parse(&text).unwrap();
        assert!(case.model.springs.is_some());
        let explicit = case.model.build(Path::new(".")).unwrap();
        let default = Case::default().model.build(Path::new(".")).unwrap();
        assert_eq!(
            explicit.natural_frequencies().unwrap(),
            default.natural_frequencies().unwrap()
        );
    }

    /// The inline-matrix model shown commented out builds.
    #[test]
    fn the_commented_matrices_model_builds() {
        let tables = tables(&Case::default());
        let model = tables.iter().find(|t| t.name == "model").unwrap();
        let mut text = String::from("[model]\nkind = \"matrices\"\n");
        for entry in &model.entries {
            if ["mass", "stiffness", "mass_coupling", "stiffness_coupling"].contains(&entry.key) {
                text.push_str(&format!("{} = {}\n", entry.key, entry.value));
            }
        }
        let case = parse(&text).unwrap();
        case.model.build(Path::new(".")).unwrap();
    }

    /// The frequencies shown for the automatic range are the run's.
    #[test]
    fn the_automatic_range_shown_is_the_runs() {
        for case in [Case::default(), EXAMPLES[9].case()] {
            let (start, end) = automatic_range(&case).unwrap();
            let prepared = crate::run::prepare(&case, Path::new("."), case.basis.kind).unwrap();
            let k = prepared.case.continuation;
            assert!((k.start_hz.unwrap() - start).abs() < 1e-9 * start);
            assert!((k.end_hz.unwrap() - end).abs() < 1e-9 * end);
        }
        let text = default_template();
        assert!(text.contains("# start_hz = 121.31\n"), "{text}");
        assert!(text.contains(", here 121.31 Hz)"), "{text}");
    }

    #[test]
    fn floats_are_short_and_exact() {
        for (x, s) in [
            (0.0, "0.0"),
            (4.0, "4.0"),
            (1.75, "1.75"),
            (0.05, "0.05"),
            (1e-3, "1e-3"),
            (5e-5, "5e-5"),
            (1e8, "1e8"),
            (2.5, "2.5"),
            (-12.5, "-12.5"),
            (10000.0, "10000.0"),
        ] {
            assert_eq!(float(x), s);
        }
    }
}
