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
//! This module holds the templates' text (the examples and their headers);
//! [`render`] makes a case file of any case from the key table.

mod render;
#[cfg(test)]
mod tests;

pub use render::render;

use cyclorub::case::text::float;
use cyclorub::case::{Case, ExcitationKind, PerContactDof};
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

    /// Why the example's stability check is off, and how to run it.
    fn stability_note(&self) -> String {
        match self.excitation {
            ExcitationKind::Mixed => "The stability check is off: a partly standing case \
                samples two sectors, so a class has 1134 contact positions (an eigenproblem of \
                2268 unknowns), above the run's limit of 2000; check chosen points with \
                cyclorub stability RESULTS --point P --largest-eigenproblem 2300 \
                (docs/stability.md)."
                .to_string(),
            _ => "The stability check is off: about 1-1.5 s a point in contact along the \
                branch, up to 8 s from fresh contours (567 contact positions a class, \
                docs/stability.md), 8.9 min for the traveling h = 4 run against 10 s for its \
                solve; turn it on \
                with [stability] enabled = true, or check chosen points with cyclorub \
                stability RESULTS --point P."
                .to_string(),
        }
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
            self.stability_note(),
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
