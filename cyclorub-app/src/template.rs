//! Commented case files: the template that `cyclorub init` prints (the
//! paper's default case, every key with its value and a one-line comment),
//! the paper's academic studies as ready-made examples (Sec. 4.3 and
//! Appendix C; docs/design.md §9) and its Sec. 5 studies on the open fan of
//! `cyclorub mesh fan` ([`FAN_EXAMPLES`]).
//!
//! The text is rendered from a [`Case`] value, so a template always parses
//! back to the case it was made from: [`default_template`] parses to
//! [`Case::default`], and [`example_template`] to [`Example::case`]. Keys
//! whose value is absent (`None`: an automatic rule or a default computed
//! elsewhere) are shown commented out, with the rule in their comment.

use cyclorub::case::keys::{Key, Table, TABLES};
use cyclorub::case::text::{block, float, lookup, parse_value};
use cyclorub::case::{Case, CaseError, ExcitationKind, PerContactDof};
use cyclorub::forced_response::excited_frequency;
use cyclorub::model::{LumpedSector, ModelKind, SpringLink, DEFAULT_SYMMETRY_TOLERANCE};
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

/// The paper's academic studies (docs/design.md §9), in the paper's order.
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

/// Sectors of the open fan of the paper's Sec. 5 studies
/// (`cyclorub mesh fan`'s default).
pub const FAN_SECTORS: usize = 16;

/// The folder of the open fan's mesh, next to the fan examples' case
/// files (written by `cyclorub mesh fan --output examples/fan16`, not
/// committed: the default mesh is tens of MB).
pub const FAN_FOLDER: &str = "fan16";

/// The files of a fan folder that a fan case reads, by their `[model]` key.
pub const FAN_MODEL_FILES: [(&str, &str); 4] = [
    ("mass_file", "sector_mass.mtx"),
    ("stiffness_file", "sector_stiffness.mtx"),
    ("coordinates_file", "nodes.csv"),
    ("node_sets_file", "node_sets.toml"),
];

/// The paper's mean gap of the fan studies, m (Sec. 5.2), kept by the
/// traveling studies.
const PAPER_FAN_GAP: f64 = 4e-4;

/// Largest radial amplitude of the contact nodes in the traveling h = 1
/// study without contact (linear response at the ND1 resonance, 2 N,
/// default mesh, measured: the leading-edge node), m.
const TRAVELING_H1_LINEAR_RADIAL: f64 = 7.11e-4;

/// The open fan's case as `cyclorub mesh fan` writes it (`fan16.toml`,
/// the paper's Sec. 5 settings) with the model files in [`FAN_FOLDER`]:
/// Craig–Bampton per nodal diameter, radial 3D contact with sliding
/// friction μ = 0.15 (DLFT, ε = 1e7), Ω = 1151.9 rad/s, N_h = 10,
/// N_t = 2000 (125 × 16), the secant predictor with steps up to 0.2
/// (traveling h = 4: 416 points, each within 2.5e-5 of the curve of 4398
/// points the tangent predictor gave). Its dofs count the reduced model's:
/// x, y, z of the 9 contact nodes (radial, circumferential, axial there:
/// 1–27), of the excitation node (28–30), of the observation node (31–33).
const FAN_CASE: &str = r#"
[model]
kind = "finite_element"
sectors = 16
mass_file = "fan16/sector_mass.mtx"
stiffness_file = "fan16/sector_stiffness.mtx"
coordinates_file = "fan16/nodes.csv"
dofs_per_node = 3
axis = "z"
boundary_frame = "cartesian"
node_sets_file = "fan16/node_sets.toml"
contact_frame = "cylindrical"

[model.reduction]
internal_modes = 20

[model.damping]
kind = "modal"
ratios = [1e-3, 1e-3, 1e-3, 1e-3, 1e-3]
others = 5e-3

[excitation]
kind = "traveling"
engine_order = 1
amplitude = 2.0
dofs = [29]

[casing]
gap = 4e-4
order = 0
amplitude = 0.0

[contact]
law = "dlft"
epsilon = 1e7
dofs = [1, 4, 7, 10, 13, 16, 19, 22, 25]
friction = 0.15
circumferential_dofs = [2, 5, 8, 11, 14, 17, 20, 23, 26]
axial_dofs = [3, 6, 9, 12, 15, 18, 21, 24, 27]

[rotation]
speed = 1151.9

[preload]
centrifugal = true

[stability]
enabled = false

[harmonic_balance]
harmonics = 10
time_samples = 2000

[continuation]
max_step = 0.2
dlft_predictor = "secant"

[output]
observed_dof = 32
"#;

/// One of the paper's Sec. 5 studies on the open fan (`cyclorub mesh
/// fan`), ready to run once the mesh is written.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FanExample {
    /// The name given to `cyclorub init --example` (also the file name in
    /// `examples/`, without `.toml`).
    pub name: &'static str,
    /// Where the study is in the paper.
    pub source: &'static str,
    /// Traveling, or partly standing (`Mixed`, Eq. 86: backward 0.9,
    /// forward 0.1).
    pub excitation: ExcitationKind,
    /// Engine order `h`.
    pub engine_order: usize,
    /// Forcing amplitude `f_ex`, N.
    pub amplitude: f64,
    /// Largest radial amplitude of the contact nodes without contact
    /// (linear response at the resonance, default mesh, measured), m.
    pub linear_radial_amplitude: f64,
    /// Mean gap `c`, m: the paper's 4e-4 m where the linear amplitude
    /// exceeds it by the traveling h = 1 study's ratio, else the gap with
    /// that same ratio (see [`FanExample::gap_note`]).
    pub gap: f64,
}

/// The paper's Sec. 5 studies on the open fan, in the paper's order.
pub const FAN_EXAMPLES: [FanExample; 4] = [
    FanExample {
        name: "fan16-traveling-h1",
        source: "Sec. 5, traveling waves",
        excitation: ExcitationKind::Traveling,
        engine_order: 1,
        amplitude: 2.0,
        linear_radial_amplitude: 7.11e-4,
        gap: PAPER_FAN_GAP,
    },
    FanExample {
        name: "fan16-traveling-h4",
        source: "Sec. 5, traveling waves",
        excitation: ExcitationKind::Traveling,
        engine_order: 4,
        amplitude: 2.0,
        linear_radial_amplitude: 7.12e-4,
        gap: PAPER_FAN_GAP,
    },
    FanExample {
        name: "fan16-partly-standing-h4",
        source: "Sec. 5, partly standing waves, Eq. 86",
        excitation: ExcitationKind::Mixed,
        engine_order: 4,
        amplitude: 1.0,
        linear_radial_amplitude: 3.55e-4,
        gap: 2e-4,
    },
    FanExample {
        name: "fan16-partly-standing-h7",
        source: "Sec. 5, partly standing waves, Eq. 86",
        excitation: ExcitationKind::Mixed,
        engine_order: 7,
        amplitude: 0.3,
        linear_radial_amplitude: 4.52e-5,
        gap: 2.5e-5,
    },
];

impl FanExample {
    /// Finds a fan example by name.
    pub fn find(name: &str) -> Option<&'static FanExample> {
        FAN_EXAMPLES.iter().find(|e| e.name == name)
    }

    /// One line: the fan, excitation, amplitude and gap.
    pub fn summary(&self) -> String {
        let wave = match self.excitation {
            ExcitationKind::Mixed => "partly standing wave (0.9 backward, 0.1 forward)",
            _ => "traveling wave",
        };
        format!(
            "open fan N = {FAN_SECTORS}, {wave} h = {}, f_ex = {} N, friction 0.15, gap {} m ({})",
            self.engine_order,
            self.amplitude,
            float(self.gap),
            self.source
        )
    }

    /// The case: the open fan's case (`fan16.toml` of `cyclorub mesh fan`,
    /// model files in [`FAN_FOLDER`]) with this study's excitation, the gap
    /// [`FanExample::gap`] and results in `results/<name>`.
    pub fn case(&self) -> Case {
        let mut case = Case::from_toml(FAN_CASE, Path::new("fan16.toml"))
            .expect("the fan's case text is a valid case file");
        case.excitation.kind = self.excitation;
        case.excitation.engine_order = self.engine_order;
        case.excitation.amplitude = self.amplitude;
        case.excitation.backward_weight = 0.9;
        case.excitation.forward_weight = 0.1;
        case.casing.gap = PerContactDof::One(self.gap);
        case.output.directory = Path::new("results").join(self.name);
        case
    }

    /// Why the gap is what it is, for the header: the open fan's tips do
    /// not move as the ECL5's, so the paper's gap is kept only where the
    /// load moves them past it as far as in the traveling h = 1 study.
    pub fn gap_note(&self) -> String {
        let ratio = TRAVELING_H1_LINEAR_RADIAL / PAPER_FAN_GAP;
        let reason = format!(
            "without contact (linear response at the resonance, default mesh) this load moves \
             the contact nodes radially by {} m at most (the leading-edge node)",
            float(self.linear_radial_amplitude)
        );
        if (self.gap - PAPER_FAN_GAP).abs() <= 1e-15 {
            format!(
                "Gap {} m, the paper's: {reason}, {ratio:.2} times the gap.",
                float(self.gap)
            )
        } else {
            format!(
                "Gap {} m, not the paper's {} m: on our open fan {reason}, so {} m would be \
                 reached barely or never; this gap keeps the traveling h = 1 study's ratio of \
                 {ratio:.2} between that amplitude and the gap.",
                float(self.gap),
                float(PAPER_FAN_GAP),
                float(PAPER_FAN_GAP)
            )
        }
    }

    /// The commented case file of this example.
    pub fn template(&self) -> String {
        let case = self.case();
        let header = vec![
            format!("cyclorub example {}: {}.", self.name, self.summary()),
            format!(
                "Vadcard, Quaegebeur & Thouverez (2024), Sec. 5, on our open fan (cyclorub mesh \
                 fan): Craig–Bampton per nodal diameter (20 internal modes), DLFT-HBM \
                 (ε = 1e7), friction μ = 0.15 at the 9 tip nodes (radial normal), \
                 Ω = 1151.9 rad/s, N_h = 10, N_t = 2000 (125 × {FAN_SECTORS})."
            ),
            format!(
                "The mesh is not committed (the default mesh is tens of MB): write it first, \
                 next to this file, with: cyclorub mesh fan --output examples/{FAN_FOLDER}"
            ),
            self.gap_note(),
            "The stability check is off: with friction Hill's method solves every class densely \
             (2226 unknowns each here), minutes a point; check chosen points with cyclorub \
             stability RESULTS --point P --largest-eigenproblem 2300."
                .to_string(),
            "Frequency range: the automatic rule (continuation.start_hz and end_hz are absent)."
                .to_string(),
            format!(
                "Run: cyclorub run examples/{}.toml (results in {}); the full wheel: add \
                 --basis physical.",
                self.name,
                case.output.directory.display()
            ),
        ];
        render(&case, &header).expect("a fan example holds only UTF-8 file names")
    }
}

/// The names of every example, academic then fan, in order.
pub fn example_names() -> Vec<&'static str> {
    EXAMPLES
        .iter()
        .map(|e| e.name)
        .chain(FAN_EXAMPLES.iter().map(|e| e.name))
        .collect()
}

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
        render(&self.case(), &header).expect("an example holds only UTF-8 file names")
    }
}

/// The examples, academic then fan, one per line: name, then
/// [`Example::summary`] or [`FanExample::summary`] (what `cyclorub init
/// --list` prints).
pub fn listing() -> String {
    let width = example_names().iter().map(|n| n.len()).max().unwrap_or(0);
    let academic = EXAMPLES.iter().map(|e| (e.name, e.summary()));
    let fans = FAN_EXAMPLES.iter().map(|e| (e.name, e.summary()));
    academic
        .chain(fans)
        .map(|(name, summary)| format!("{name:width$}  {summary}\n"))
        .collect()
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
    render(&Case::default(), &header).expect("the default case holds only UTF-8 file names")
}

/// The commented case file of the example called `name`, if there is one.
pub fn example_template(name: &str) -> Option<String> {
    Example::find(name)
        .map(Example::template)
        .or_else(|| FanExample::find(name).map(FanExample::template))
}

/// Renders any case as a commented case file that parses back to it, with
/// `header` as its first comment lines: every key of the key table
/// ([`TABLES`]) in order, its comment made from the table, its value from
/// `case` (or, when absent, an example commented out). Fails only for a
/// case that TOML cannot hold (a file name that is not UTF-8).
pub fn render(case: &Case, header: &[String]) -> Result<String, CaseError> {
    let root = case.to_value()?;
    let range = automatic_range(case);
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
    for table in TABLES {
        out.push_str(&format!("\n# {}\n[{}]\n", table.doc, table.name));
        for key in table.keys {
            let path = table.path(key);
            let note = match (path.as_str(), range) {
                ("continuation.start_hz", Some((start, _))) => format!(", here {} Hz", hz(start)),
                ("continuation.end_hz", Some((_, end))) => format!(", here {} Hz", hz(end)),
                _ => String::new(),
            };
            out.push_str(&format!("# {}\n", key.comment(&note)));
            let (prefix, value) = match lookup(&root, &path) {
                Some(value) => ("", block(value)),
                None => ("# ", example(table, key, range)),
            };
            for line in format!("{} = {value}", key.name).lines() {
                out.push_str(&format!("{prefix}{line}\n"));
            }
        }
    }
    Ok(out)
}

/// The value shown commented out for a key absent from a case: the key
/// table's example, or one made here from the defaults it stands for.
fn example(table: &Table, key: &Key, range: Option<(f64, f64)>) -> String {
    let auto = |i: usize| float(range.map_or(100.0 * (1.0 + i as f64), |r| hz([r.0, r.1][i])));
    match table.path(key).as_str() {
        "model.symmetry_tolerance" => float(DEFAULT_SYMMETRY_TOLERANCE),
        "model.masses" => floats(&LumpedSector::academic().masses),
        "model.springs" => academic_springs(),
        "continuation.start_hz" => auto(0),
        "continuation.end_hz" => auto(1),
        _ => parse_value(key.example).map_or_else(|| key.example.to_string(), |v| block(&v)),
    }
}

fn floats(values: &[f64]) -> String {
    let items: Vec<String> = values.iter().map(|&v| float(v)).collect();
    format!("[{}]", items.join(", "))
}

/// The springs of the paper's academic sector, as a case file writes them.
fn academic_springs() -> String {
    let mut out = String::from("[\n");
    for spring in LumpedSector::academic().springs {
        let (dofs, link) = match spring.link {
            SpringLink::Within(a, b) => (format!("[{}, {}]", a + 1, b + 1), ""),
            SpringLink::NextSector(a, b) => (
                format!("[{}, {}]", a + 1, b + 1),
                ", link = \"next_sector\"",
            ),
            SpringLink::Ground(a) => (format!("[{}]", a + 1), ", link = \"ground\""),
        };
        out.push_str(&format!(
            "    {{ dofs = {dofs}, stiffness = {}{link} }},\n",
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
    let f = excited_frequency(case, &model).ok()?;
    Some((0.95 * f, 1.10 * f))
}

/// Rounds a frequency for display (Hz, two decimals).
fn hz(f: f64) -> f64 {
    (f * 100.0).round() / 100.0
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::collections::BTreeSet;
    use std::num::FpCategory;
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

    #[test]
    fn every_fan_example_parses_to_its_case_and_validates() {
        for example in &FAN_EXAMPLES {
            let text = example.template();
            let case = parse(&text).unwrap_or_else(|e| panic!("{}: {e}", example.name));
            assert_eq!(case, example.case(), "{}", example.name);
            case.validate()
                .unwrap_or_else(|e| panic!("{}: {e}", example.name));
            assert_eq!(example_template(example.name), Some(text.clone()));
            assert!(
                text.contains("cyclorub mesh fan --output examples/fan16"),
                "{}",
                example.name
            );
            assert!(text.contains(&example.gap_note()), "{}", example.name);
        }
        assert_eq!(example_names().len(), EXAMPLES.len() + FAN_EXAMPLES.len());
    }

    /// The fan examples are the case that `cyclorub mesh fan` writes, with
    /// only their own excitation, gap, results folder and the model files
    /// in `fan16/`.
    #[test]
    fn the_fan_examples_are_the_mesh_commands_case() {
        let dir =
            std::env::temp_dir().join(format!("cyclorub-fan-template-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        let fan =
            cyclorub::mesh::fan(FAN_SECTORS, 1, &cyclorub::mesh::FanGeometry::default()).unwrap();
        let matrices = cyclorub::mesh::assemble(&fan.mesh).unwrap();
        cyclorub::mesh::write_fan(&fan, &matrices, &dir, false).unwrap();
        let written = Case::from_file_checked(&dir.join("fan16.toml")).unwrap();
        let _ = std::fs::remove_dir_all(&dir);
        for example in &FAN_EXAMPLES {
            let mut expected = written.clone();
            let m = &mut expected.model;
            for file in [
                &mut m.mass_file,
                &mut m.stiffness_file,
                &mut m.coordinates_file,
                &mut m.node_sets_file,
            ] {
                *file = file.as_ref().map(|f| Path::new(FAN_FOLDER).join(f));
            }
            let e = &mut expected.excitation;
            e.kind = example.excitation;
            e.engine_order = example.engine_order;
            e.amplitude = example.amplitude;
            expected.casing.gap = PerContactDof::One(example.gap);
            expected.output.directory = Path::new("results").join(example.name);
            assert_eq!(example.case(), expected, "{}", example.name);
        }
        // The paper's Sec. 5 settings.
        let h7 = FanExample::find("fan16-partly-standing-h7").unwrap().case();
        assert_eq!(h7.excitation.kind, ExcitationKind::Mixed);
        assert!((h7.excitation.backward_weight - 0.9).abs() < 1e-15);
        assert!((h7.excitation.forward_weight - 0.1).abs() < 1e-15);
        assert!(h7
            .contact
            .friction
            .is_some_and(|mu| (mu - 0.15).abs() < 1e-15));
        assert_eq!(h7.contact.law, cyclorub::case::LawKind::Dlft);
        assert_eq!(h7.harmonic_balance.time_samples % FAN_SECTORS, 0);
        for (key, file) in FAN_MODEL_FILES {
            let text = h7.to_value().unwrap();
            let value = lookup(&text, &format!("model.{key}")).unwrap();
            assert_eq!(
                value.as_str(),
                Some(format!("{FAN_FOLDER}/{file}").as_str())
            );
        }
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
        case.model.springs = Some(vec![cyclorub::model::SpringSpec {
            dofs: vec![1, 2],
            stiffness: 2e6,
            link: cyclorub::model::SpringLinkSpec::NextSector,
        }]);
        case.model.damping.ratios = Some(vec![1e-3, 2e-3]);
        case.model.damping.others = Some(0.01);
        case.excitation.kind = ExcitationKind::PerSector;
        case.excitation.amplitudes = vec![1.0; 24];
        case.excitation.phases = vec![0.123_456_789; 24];
        case.excitation.static_force = -12.5;
        case.casing.gap = PerContactDof::Each(vec![1e-3, 2.5e-4]);
        case.contact.dofs = vec![1, 2];
        case.contact.law = cyclorub::case::LawKind::Dlft;
        case.contact.wall_stiffness = Some(5e7);
        case.continuation.start_hz = Some(150.0);
        case.continuation.end_hz = Some(120.5);
        case.output.sectors = vec![1, 4];
        let text = render(&case, &["a test".to_string()]).unwrap();
        assert_eq!(parse(&text).unwrap_or_else(|e| panic!("{e}\n{text}")), case);
    }

    /// Every key shown commented out parses once uncommented, and every
    /// key's comment is the key table's.
    #[test]
    fn every_commented_out_key_parses_once_uncommented() {
        let text = default_template();
        let root = Case::default().to_value().unwrap();
        let range = automatic_range(&Case::default());
        let mut count = 0;
        for table in TABLES {
            for key in table.keys {
                assert!(
                    text.contains(&format!("# {}", key.meaning())),
                    "{}",
                    key.name
                );
                if lookup(&root, &table.path(key)).is_some() {
                    continue;
                }
                let value = example(table, key, range);
                let uncommented = format!("[{}]\n{} = {value}\n", table.name, key.name);
                parse(&uncommented).unwrap_or_else(|e| panic!("{e}\n{uncommented}"));
                count += 1;
            }
        }
        assert!(count >= 15, "{count}");
    }

    /// Sets the examples of `keys` in a `[model]` table of `kind`.
    fn model_with_examples(kind: &str, keys: &[&str]) -> Case {
        let table = TABLES.iter().find(|t| t.name == "model").unwrap();
        let mut text = format!("[model]\nkind = \"{kind}\"\n");
        for key in table.keys.iter().filter(|k| keys.contains(&k.name)) {
            text.push_str(&format!("{} = {}\n", key.name, example(table, key, None)));
        }
        parse(&text).unwrap()
    }

    /// The springs and masses shown commented out are the defaults: set
    /// them and the model is the same.
    #[test]
    fn the_commented_academic_model_is_the_default_one() {
        let case = model_with_examples("academic", &["masses", "springs", "symmetry_tolerance"]);
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
        let keys = ["mass", "stiffness", "mass_coupling", "stiffness_coupling"];
        let case = model_with_examples("matrices", &keys);
        case.model.build(Path::new(".")).unwrap();
    }

    /// The frequencies shown for the automatic range are the run's.
    #[test]
    fn the_automatic_range_shown_is_the_runs() {
        for case in [Case::default(), EXAMPLES[9].case()] {
            let (start, end) = automatic_range(&case).unwrap();
            let prepared = cyclorub::run::prepare(&case, Path::new("."), case.basis.kind).unwrap();
            let k = prepared.case.continuation;
            assert!((k.start_hz.unwrap() - start).abs() < 1e-9 * start);
            assert!((k.end_hz.unwrap() - end).abs() < 1e-9 * end);
        }
        let text = default_template();
        assert!(text.contains("# start_hz = 121.31\n"), "{text}");
        assert!(text.contains(", here 121.31 Hz)"), "{text}");
    }
}
