//! The reproduction of the paper's academic studies (Sec. 4 and
//! Appendix C): every case file of a folder, with each contact law, solved
//! on the symmetry basis, on the paper's basis and on the full wheel in
//! physical coordinates; the reduced runs checked against the full one
//! ([`exactness`]), their stability checked ([`stability`]: Hill's method
//! per symmetry class on the symmetry basis) and the whole written up as a
//! report ([`report`]).
//!
//! The claim under test is the paper's: the reductions are exact. So
//! nothing here is tuned until it passes: a reduced run that does not
//! reproduce the full one is reported as such, with its figures.

pub mod exactness;
pub mod report;
pub mod stability;

use crate::template::FAN_MODEL_FILES;
use cyclorub::case::{BasisChoice, Case, CaseError, LawKind};
use cyclorub::continuation::{NewtonSettings, Progress, StopReason};
use cyclorub::mesh::{assemble, fan, write_fan, FanGeometry, DEFAULT_REFINE};
use cyclorub::model::ModelKind;
use cyclorub::plot::PlotError;
use cyclorub::results::ResultsError;
use cyclorub::run::{prepare, run_keeping, RunError, RunOptions, RunOutcome, Timings};
use exactness::{Curve, EnergyOutside, PointByPoint};
use serde::Serialize;
use stability::StabilitySummary;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// The cases of the quick reproduction (CI): one traveling, one standing
/// and the mixed case of Sec. 4.3.3, all on N = 24.
pub const QUICK_CASES: &[&str] = &[
    "n24-traveling-h1",
    "n24-standing-h4",
    "n24-mixed-h6-casing-h8",
];

/// Largest relative difference between a reduced run and the full wheel
/// for the reduction to count as exact (the harmonic balance core's).
pub const TOLERANCE: f64 = 1e-8;

/// Largest fraction of the full solution's energy outside a reduced basis
/// for the basis to count as complete.
pub const ENERGY_TOLERANCE: f64 = 1e-10;

/// Largest distance (scaled, see [`exactness::curve_distance`]) between
/// the full branch and a reduced one for the two to count as the same
/// curve: the independent continuations place their points differently,
/// so this judges the path, not round-off.
pub const CURVE_TOLERANCE: f64 = 1e-2;

/// Errors that stop a reproduction before it starts (a run that fails is
/// reported in the report, not here).
#[derive(Debug, thiserror::Error)]
pub enum ReproduceError {
    /// The folder of case files cannot be read or holds none.
    #[error("{folder}: {message}")]
    Folder {
        /// The folder.
        folder: PathBuf,
        /// What is wrong.
        message: String,
    },
    /// A case asked for is not in the folder.
    #[error("--cases: no case named {name:?} in {folder}; the cases there are: {available}")]
    UnknownCase {
        /// The name asked for.
        name: String,
        /// The folder.
        folder: PathBuf,
        /// The names there, comma-separated.
        available: String,
    },
    /// A case file is not valid.
    #[error(transparent)]
    Case(#[from] CaseError),
    /// A case's model or problem cannot be built.
    #[error("case {case}: {message}")]
    Prepare {
        /// The case name.
        case: String,
        /// Why.
        message: String,
    },
    /// Writing the report.
    #[error(transparent)]
    Results(#[from] ResultsError),
    /// Drawing a figure.
    #[error(transparent)]
    Plot(#[from] PlotError),
}

impl ReproduceError {
    /// Whether the error is in what the user gave (the folder, the case
    /// names, the case files), as opposed to a failure while writing the
    /// report or its figures.
    pub fn is_input_error(&self) -> bool {
        !matches!(self, Self::Results(_) | Self::Plot(_))
    }
}

/// What to reproduce.
#[derive(Clone, Debug)]
pub struct ReproduceOptions {
    /// The folder of case files (`examples/`).
    pub folder: PathBuf,
    /// Where the report and every run's results folder go.
    pub output: PathBuf,
    /// Short runs of [`QUICK_CASES`] (see [`quick_case`]).
    pub quick: bool,
    /// Case names (file stems) to run; empty: every case (quick: [`QUICK_CASES`]).
    pub cases: Vec<String>,
    /// Contact laws; empty: both.
    pub laws: Vec<LawKind>,
    /// Check the stability of the symmetry-basis runs (and of the full
    /// wheel's, when its eigenproblem is small: see [`stability`]).
    pub stability: bool,
}

/// What a reproduction reports as it goes.
#[derive(Clone, Copy, Debug)]
pub enum Step<'a> {
    /// A run starts.
    Run {
        /// Case name.
        case: &'a str,
        /// Contact law.
        law: LawKind,
        /// Basis.
        basis: BasisChoice,
    },
    /// A case's finite-element files were missing: the open fan is being
    /// written for it (see [`provide_fan_mesh`]).
    Mesh {
        /// Case name.
        case: &'a str,
        /// The folder written, where the case's model files now point.
        folder: &'a Path,
        /// `cyclorub mesh fan --refine`.
        refine: usize,
    },
    /// A point of the running branch.
    Point(&'a Progress),
    /// The reduced runs are being checked against the full one.
    Checking {
        /// Case name.
        case: &'a str,
        /// Contact law.
        law: LawKind,
    },
}

/// One run of a study.
#[derive(Clone, Debug, Serialize)]
pub struct RunSummary {
    /// `symmetry`, `paper` or `physical`.
    pub basis: String,
    /// Real unknowns solved for.
    pub unknowns: usize,
    /// Real unknowns of the full wheel.
    pub full_unknowns: usize,
    /// Reduction of the unknown count, %.
    pub reduction_percent: f64,
    /// Sectors sampled by the AFT.
    pub sampled_sectors: usize,
    /// Signed nodal diameters per harmonic (cyclic bases).
    pub harmonics: Vec<cyclorub::run::HarmonicRecord>,
    /// Points of the branch (0 when not run).
    pub points: usize,
    /// Newton iterations.
    pub iterations: usize,
    /// Why the branch stopped (absent when not run).
    pub stop: Option<StopReason>,
    /// How the branch was followed from both ends, when the sweep from the
    /// start stopped short.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub sweeps: Option<cyclorub::continuation::Sweeps>,
    /// Wall-clock times (absent when not run).
    pub timings: Option<Timings>,
    /// The run's results folder, relative to the report.
    pub folder: Option<PathBuf>,
    /// Set when this basis is the same as another's and was not run again.
    pub same_as: Option<String>,
    /// Why the run failed, if it did.
    pub error: Option<String>,
    /// The stability of the branch's points (absent when the run failed).
    pub stability: Option<StabilitySummary>,
}

impl RunSummary {
    fn from_outcome(outcome: &RunOutcome, folder: PathBuf, stability: StabilitySummary) -> Self {
        let r = &outcome.record;
        Self {
            basis: r.basis.kind.clone(),
            unknowns: r.basis.unknowns,
            full_unknowns: r.basis.full_unknowns,
            reduction_percent: r.basis.reduction_percent,
            sampled_sectors: r.basis.sampled_sectors,
            harmonics: r.basis.harmonics.clone(),
            points: r.points,
            iterations: r.total_iterations,
            stop: Some(r.stop.clone()),
            sweeps: r.sweeps.clone(),
            timings: Some(r.timings.clone()),
            folder: Some(folder),
            same_as: None,
            error: None,
            stability: Some(stability),
        }
    }

    fn failed(basis: BasisChoice, error: &RunError) -> Self {
        Self {
            basis: basis.name().into(),
            unknowns: 0,
            full_unknowns: 0,
            reduction_percent: 0.0,
            sampled_sectors: 0,
            harmonics: Vec::new(),
            points: 0,
            iterations: 0,
            stop: None,
            sweeps: None,
            timings: None,
            folder: None,
            same_as: None,
            error: Some(error.to_string()),
            stability: None,
        }
    }

    /// Whether the branch reached its end frequency.
    pub fn complete(&self) -> bool {
        matches!(self.stop, Some(StopReason::EndReached))
    }
}

/// A reduced run against the full wheel.
#[derive(Clone, Debug, Serialize)]
pub struct Comparison {
    /// The reduced basis.
    pub basis: String,
    /// Point by point (absent if either run failed).
    pub point_by_point: Option<PointByPoint>,
    /// Curve by curve.
    pub curve_distance: Option<f64>,
    /// The full branch's energy outside this basis (every dof of the
    /// sector), at its resonance and along the branch.
    pub energy_outside: Option<EnergyOutside>,
    /// Full solve time over reduced solve time.
    pub time_ratio: Option<f64>,
}

impl Comparison {
    /// The reduction is exact: every point of the reduced branch is a
    /// solution of the full problem, to [`TOLERANCE`] relative.
    pub fn exact(&self) -> bool {
        self.point_by_point.as_ref().is_some_and(|p| {
            p.points > 0
                && p.not_converged == 0
                && p.largest_unknowns_difference <= TOLERANCE
                && p.largest_displacement_difference <= TOLERANCE
        })
    }

    /// The basis holds the full solution at its resonance, to
    /// [`ENERGY_TOLERANCE`] of its energy.
    pub fn complete(&self) -> bool {
        self.energy_outside
            .as_ref()
            .is_some_and(|e| e.at_resonance <= ENERGY_TOLERANCE)
    }

    /// The independent full branch lies on the reduced one.
    pub fn same_curve(&self) -> bool {
        self.curve_distance.is_some_and(|d| d <= CURVE_TOLERANCE)
    }
}

/// One case with one contact law.
#[derive(Clone, Debug, Serialize)]
pub struct Study {
    /// The case name (file stem).
    pub case: String,
    /// What the case is (the first comment line of its file).
    pub description: String,
    /// Contact law.
    pub law: LawKind,
    /// `N`.
    pub sectors: usize,
    /// `N_h`.
    pub harmonics: usize,
    /// `N_t` used.
    pub time_samples: usize,
    /// `N_t` of the case file.
    pub time_samples_in_file: usize,
    /// Frequency range, Hz.
    pub start_hz: f64,
    /// Frequency range, Hz.
    pub end_hz: f64,
    /// The runs: symmetry, paper, physical.
    pub runs: Vec<RunSummary>,
    /// The reduced runs against the full one.
    pub comparisons: Vec<Comparison>,
    /// Frequency of the full branch's resonance (largest amplitude), Hz.
    pub resonance_hz: Option<f64>,
    /// Figures, relative to the report.
    pub figures: Vec<PathBuf>,
}

impl Study {
    /// Every reduced run is exact (see [`Comparison::exact`]) and no run failed.
    pub fn exact(&self) -> bool {
        !self.comparisons.is_empty()
            && self.comparisons.iter().all(Comparison::exact)
            && self.runs.iter().all(|r| r.error.is_none())
    }

    /// Every reduced basis holds the full solution at its resonance (see
    /// [`Comparison::complete`]).
    pub fn complete(&self) -> bool {
        !self.comparisons.is_empty() && self.comparisons.iter().all(Comparison::complete)
    }
}

/// The whole reproduction.
#[derive(Clone, Debug, Serialize)]
pub struct Report {
    /// `quick` or `full`.
    pub mode: String,
    /// The folder of case files.
    pub folder: PathBuf,
    /// The studies.
    pub studies: Vec<Study>,
    /// Wall time of the whole reproduction, s.
    pub wall_s: f64,
}

impl Report {
    /// Every study is exact.
    pub fn exact(&self) -> bool {
        !self.studies.is_empty() && self.studies.iter().all(Study::exact)
    }

    /// Every study's full solutions lie in the reduced bases at their resonance.
    pub fn complete(&self) -> bool {
        !self.studies.is_empty() && self.studies.iter().all(Study::complete)
    }
}

/// The case files of a folder, by name (file stem), sorted.
pub fn case_files(folder: &Path) -> Result<Vec<(String, PathBuf)>, ReproduceError> {
    let entries = std::fs::read_dir(folder).map_err(|e| ReproduceError::Folder {
        folder: folder.to_path_buf(),
        message: format!("cannot read the folder of case files: {e}"),
    })?;
    let mut files: Vec<(String, PathBuf)> = entries
        .filter_map(Result::ok)
        .map(|e| e.path())
        .filter(|p| p.extension().is_some_and(|e| e == "toml"))
        .filter_map(|p| Some((p.file_stem()?.to_str()?.to_string(), p)))
        .collect();
    files.sort();
    if files.is_empty() {
        return Err(ReproduceError::Folder {
            folder: folder.to_path_buf(),
            message: "no case file (*.toml) there".into(),
        });
    }
    Ok(files)
}

/// The smallest multiple of `sectors` nearest to `time_samples` that is at
/// least `2 N_h + 1`: with it, time-sampling aliases fall on pairs of the
/// same basis and reduced and full agree to round-off (docs/design.md §5).
pub fn multiple_of_sectors(time_samples: usize, sectors: usize, harmonics: usize) -> usize {
    let n = sectors.max(1);
    let nearest = ((time_samples + n / 2) / n).max(1) * n;
    let least = (2 * harmonics + 1).div_ceil(n) * n;
    nearest.max(least)
}

/// The quick version of a case: `N_h = 5`, `N_t` the smallest multiple of
/// `N` of at least `8 (2 N_h + 1)`, the frequency window from 0.99 to
/// 1.03 times the excited resonance `f1` (contact starts inside it for
/// every quick case), at most 150 points, and the smallest step at least
/// 1e-6: a sweep that stalls gives up after a few halvings instead of
/// spending most of the study's time halving down to 1e-7.
///
/// A finite-element case (the open fan) gets `N_h = 2`, the window 0.99855
/// to 1.0005 `f1` and at most 40 points: its full wheel's dense Jacobian
/// is the cost (4752 unknowns with `N_h = 5`: minutes per branch; 1728
/// with `N_h = 2`), and its contact starts at 0.9986 `f1` (coarse mesh,
/// traveling h = 1, gap 0.56 times the linear radial amplitude), after
/// which the branch moves fast in frequency. Measured (release, 2 busy
/// cores): 600 s for `fan16-traveling-h1` with DLFT (full wheel 288 s,
/// the check against it about 300 s), so no fan case is in [`QUICK_CASES`].
pub fn quick_case(case: &mut Case, resonance_hz: f64) {
    let fan = case.model.kind == ModelKind::FiniteElement;
    let harmonics = if fan { 2 } else { 5 };
    case.harmonic_balance.harmonics = harmonics;
    let n = case.model.sectors().max(1);
    case.harmonic_balance.time_samples = (8 * (2 * harmonics + 1)).div_ceil(n) * n;
    let (below, above, points) = if fan {
        (0.99855, 1.0005, 40)
    } else {
        (0.99, 1.03, 150)
    };
    case.continuation.start_hz = Some(below * resonance_hz);
    case.continuation.end_hz = Some(above * resonance_hz);
    case.continuation.max_points = case.continuation.max_points.min(points);
    case.continuation.min_step = case.continuation.min_step.max(1e-6);
}

/// Why the stability of a case with friction is not computed: Hill's
/// method holds friction, but only densely (its velocity terms are outside
/// the targeted solver), and the friction cases are the open fan's.
pub const NO_STABILITY_WITH_FRICTION: &str =
    "friction (contact.friction): Hill's method with friction solves every class densely, \
     minutes a point on the open fan; check chosen points with cyclorub stability RESULTS --point P --largest-eigenproblem 2300";

/// Writes the open fan for a case that needs it. When `case` is a
/// finite-element case whose model files are the open fan's
/// (`sector_mass.mtx`, `sector_stiffness.mtx`, `nodes.csv`,
/// `node_sets.toml`) and one of them is missing from `case_dir`, writes
/// the fan of the case's sector count (`cyclorub mesh fan --refine
/// refine`) into `output/fan<N>-refine<R>` (its files replaced if there)
/// and points the model files there, as absolute paths, as well as any
/// other relative file of the model (so the fan's folder can serve as the
/// case's folder: the reduced models are cached there). Returns that
/// folder; `None` when the files are there or are not the fan's.
pub fn provide_fan_mesh(
    case: &mut Case,
    case_dir: &Path,
    output: &Path,
    refine: usize,
) -> Result<Option<PathBuf>, ReproduceError> {
    let model = &case.model;
    if model.kind != ModelKind::FiniteElement {
        return Ok(None);
    }
    let files = [
        &model.mass_file,
        &model.stiffness_file,
        &model.coordinates_file,
        &model.node_sets_file,
    ];
    let fan_names = files.iter().zip(FAN_MODEL_FILES).all(|(file, (_, name))| {
        file.as_ref()
            .is_some_and(|f| f.file_name().is_some_and(|n| n == name))
    });
    let missing = files
        .iter()
        .any(|file| file.as_ref().is_some_and(|f| !case_dir.join(f).is_file()));
    if !fan_names || !missing {
        return Ok(None);
    }
    let sectors = model.sectors();
    let failed = |message: String| ReproduceError::Prepare {
        case: format!("the open fan of {sectors} sectors"),
        message,
    };
    let folder = output.join(format!("fan{sectors}-refine{refine}"));
    let mesh = fan(sectors, refine, &FanGeometry::default()).map_err(|e| failed(e.to_string()))?;
    let matrices = assemble(&mesh.mesh).map_err(|e| failed(e.to_string()))?;
    write_fan(&mesh, &matrices, &folder, true).map_err(|e| failed(e.to_string()))?;
    let folder = std::fs::canonicalize(&folder).map_err(|source| ResultsError::Io {
        path: folder.clone(),
        source,
    })?;
    let model = &mut case.model;
    for (file, (_, name)) in [
        &mut model.mass_file,
        &mut model.stiffness_file,
        &mut model.coordinates_file,
        &mut model.node_sets_file,
    ]
    .into_iter()
    .zip(FAN_MODEL_FILES)
    {
        *file = Some(folder.join(name));
    }
    // The case is now read from the fan's folder: its other relative
    // files keep pointing where they were.
    if let Some(file) = model.damping.file.as_mut() {
        if file.is_relative() {
            *file = absolute(&case_dir.join(&*file));
        }
    }
    Ok(Some(folder))
}

/// `path` made absolute against the working folder (unchanged if that
/// folder cannot be read).
fn absolute(path: &Path) -> PathBuf {
    std::path::absolute(path).unwrap_or_else(|_| path.to_path_buf())
}

/// The first comment line of a case file, without its `# cyclorub example NAME:` prefix.
fn description(path: &Path) -> String {
    let text = std::fs::read_to_string(path).unwrap_or_default();
    let line = text
        .lines()
        .find_map(|l| l.strip_prefix('#'))
        .unwrap_or("")
        .trim();
    match line.split_once(": ") {
        Some((head, rest)) if head.starts_with("cyclorub example") => rest.to_string(),
        _ => line.to_string(),
    }
}

/// The bases of a study, in order: the two reductions, then the reference.
const BASES: [BasisChoice; 3] = [
    BasisChoice::Symmetry,
    BasisChoice::Paper,
    BasisChoice::Physical,
];

/// Runs the reproduction: every case and law, every basis, the
/// comparisons, the figures, `report.md` and `report.json` in
/// `options.output`. `step` sees the progress.
pub fn reproduce(
    options: &ReproduceOptions,
    mut step: impl FnMut(Step<'_>),
) -> Result<Report, ReproduceError> {
    let clock = Instant::now();
    let files = case_files(&options.folder)?;
    let wanted: Vec<String> = if !options.cases.is_empty() {
        options.cases.clone()
    } else if options.quick {
        QUICK_CASES.iter().map(|s| s.to_string()).collect()
    } else {
        files.iter().map(|(n, _)| n.clone()).collect()
    };
    let mut selected = Vec::new();
    for name in &wanted {
        let Some(file) = files.iter().find(|(n, _)| n == name) else {
            return Err(ReproduceError::UnknownCase {
                name: name.clone(),
                folder: options.folder.clone(),
                available: files
                    .iter()
                    .map(|(n, _)| n.as_str())
                    .collect::<Vec<_>>()
                    .join(", "),
            });
        };
        selected.push(file.clone());
    }
    let laws = if options.laws.is_empty() {
        vec![LawKind::Regularized, LawKind::Dlft]
    } else {
        options.laws.clone()
    };
    // Every case is read and checked before any work.
    let mut cases = Vec::new();
    for (name, path) in &selected {
        let case = Case::from_file_checked(path)?;
        let case_dir = path.parent().unwrap_or(Path::new(".")).to_path_buf();
        cases.push((name.clone(), path.clone(), case, case_dir));
    }
    std::fs::create_dir_all(&options.output).map_err(|source| ResultsError::Io {
        path: options.output.clone(),
        source,
    })?;
    // The open fan's examples ship without their mesh: write it where it
    // is missing (quick: the coarse mesh).
    let refine = if options.quick { 1 } else { DEFAULT_REFINE };
    for (name, _, case, case_dir) in &mut cases {
        if let Some(folder) = provide_fan_mesh(case, case_dir, &options.output, refine)? {
            step(Step::Mesh {
                case: name,
                folder: &folder,
                refine,
            });
            *case_dir = folder;
        }
    }
    let mut studies = Vec::new();
    for (name, path, case, case_dir) in &cases {
        for &law in &laws {
            let study = run_study(options, name, path, case_dir, case, law, &mut step)?;
            studies.push(study);
            // The report so far, so that an interrupted reproduction keeps it.
            let partial = Report {
                mode: mode(options).into(),
                folder: options.folder.clone(),
                studies: studies.clone(),
                wall_s: clock.elapsed().as_secs_f64(),
            };
            report::write(&options.output, &partial)?;
        }
    }
    let report = Report {
        mode: mode(options).into(),
        folder: options.folder.clone(),
        studies,
        wall_s: clock.elapsed().as_secs_f64(),
    };
    report::write(&options.output, &report)?;
    Ok(report)
}

fn mode(options: &ReproduceOptions) -> &'static str {
    if options.quick {
        "quick"
    } else {
        "full"
    }
}

/// One case with one law: the runs, the comparisons, the figures.
/// `path` is the case file, `case_dir` the folder its relative files are
/// read from (the fan's folder when [`provide_fan_mesh`] wrote it).
fn run_study(
    options: &ReproduceOptions,
    name: &str,
    path: &Path,
    case_dir: &Path,
    case: &Case,
    law: LawKind,
    step: &mut impl FnMut(Step<'_>),
) -> Result<Study, ReproduceError> {
    let mut case = case.clone();
    case.contact.law = law;
    let time_samples_in_file = case.harmonic_balance.time_samples;
    // The automatic frequency range, resolved once for every basis.
    let resolved = prepare(&case, case_dir, BasisChoice::Symmetry).map_err(cannot_prepare(name))?;
    // The quick window is set around the excited resonance itself, whatever
    // range the case file gives.
    let f1 =
        cyclorub::run::excited_frequency(&case, &resolved.model).map_err(cannot_prepare(name))?;
    if options.quick {
        quick_case(&mut case, f1);
    } else {
        case.continuation.start_hz = resolved.case.continuation.start_hz;
        case.continuation.end_hz = resolved.case.continuation.end_hz;
        case.harmonic_balance.time_samples = multiple_of_sectors(
            case.harmonic_balance.time_samples,
            case.model.sectors(),
            case.harmonic_balance.harmonics,
        );
    }
    let study_folder = PathBuf::from("runs").join(name).join(law.name());
    let mut runs = Vec::new();
    let mut outcomes: Vec<Option<RunOutcome>> = Vec::new();
    for basis in BASES {
        if basis == BasisChoice::Paper {
            // The paper's basis is often the symmetry basis itself: say so
            // rather than solve the same problem twice.
            let paper = prepare(&case, case_dir, basis).map_err(cannot_prepare(name))?;
            if let Some(symmetry) = runs.first().filter(|r: &&RunSummary| r.error.is_none()) {
                if lists(&paper.basis.harmonics) == lists(&symmetry.harmonics) {
                    let mut same = symmetry.clone();
                    same.basis = basis.name().into();
                    same.same_as = Some(BasisChoice::Symmetry.name().into());
                    runs.push(same);
                    outcomes.push(None);
                    continue;
                }
            }
        }
        step(Step::Run {
            case: name,
            law,
            basis,
        });
        let folder = study_folder.join(basis.name());
        // The symmetry basis's classes together are the full wheel's
        // spectrum; the paper's basis has the same solutions (the report
        // checks it), so it is not checked again; the full wheel is checked
        // without symmetry only when that is cheap.
        let friction = case.contact.friction.is_some_and(|mu| mu > 0.0);
        let (settings, not_asked) = match (options.stability, basis) {
            _ if friction => (None, NO_STABILITY_WITH_FRICTION),
            (false, _) => (None, "not asked (cyclorub reproduce --stability checks it)"),
            (true, BasisChoice::Symmetry) => (Some(stability::symmetry_settings()), ""),
            (true, BasisChoice::Physical) => (Some(stability::full_wheel_settings()), ""),
            (true, _) => (
                None,
                "not asked: the same solutions as the symmetry basis, whose classes give the full wheel's spectrum",
            ),
        };
        let run_options = RunOptions {
            output: options.output.join(&folder),
            basis,
            at_hz: None,
            stability: settings,
            // The reproduction's own folder: a rerun replaces its runs.
            overwrite: true,
            interrupt: Default::default(),
        };
        match run_keeping(&case, case_dir, &run_options, |p| step(Step::Point(p))) {
            Ok(outcome) => {
                let summary = match &settings {
                    Some(s) => StabilitySummary::from_outcome(&outcome, s.tolerance),
                    None if not_asked == NO_STABILITY_WITH_FRICTION => {
                        StabilitySummary::not_computed(not_asked)
                    }
                    None => StabilitySummary::not_asked(not_asked),
                };
                runs.push(RunSummary::from_outcome(&outcome, folder, summary));
                outcomes.push(Some(outcome));
            }
            Err(error) => {
                runs.push(RunSummary::failed(basis, &error));
                outcomes.push(None);
            }
        }
    }
    step(Step::Checking { case: name, law });
    let newton = NewtonSettings {
        tolerance: case.continuation.tolerance,
        max_iterations: case.continuation.max_iterations,
        ..Default::default()
    };
    let observed = case.output.observed_index();
    let mut comparisons = Vec::new();
    let mut resonance_hz = None;
    let (reduced, full) = outcomes.split_at_mut(2);
    if let Some(full) = full[0].as_mut() {
        let energies = exactness::branch_energies(full)?;
        // The resonance among the converged points, as `branch_energies` lists them.
        let resonance = full.data.peak_point().map(|peak| {
            full.data.points[..peak]
                .iter()
                .filter(|p| p.converged)
                .count()
        });
        resonance_hz = full
            .data
            .peak_point()
            .map(|peak| full.data.points[peak].frequency_hz);
        let full_curve: Curve = exactness::curve(full);
        let full_solve = full.record.timings.solve_s;
        for (summary, outcome) in runs.iter().zip(reduced.iter_mut()) {
            let Some(outcome) = outcome else {
                continue;
            };
            let point_by_point =
                exactness::point_by_point(outcome, &mut full.problem, observed, &newton)
                    .map_err(ResultsError::from)?;
            comparisons.push(Comparison {
                basis: summary.basis.clone(),
                point_by_point: Some(point_by_point),
                curve_distance: exactness::curve_distance(&exactness::curve(outcome), &full_curve),
                energy_outside: (!energies.is_empty()).then(|| {
                    exactness::energy_outside(
                        &energies,
                        resonance,
                        &summary.harmonics,
                        ENERGY_TOLERANCE,
                    )
                }),
                time_ratio: (outcome.record.timings.solve_s > 0.0)
                    .then(|| full_solve / outcome.record.timings.solve_s),
            });
        }
    }
    let mut study = Study {
        case: name.to_string(),
        description: description(path),
        law,
        sectors: case.model.sectors(),
        harmonics: case.harmonic_balance.harmonics,
        time_samples: case.harmonic_balance.time_samples,
        time_samples_in_file,
        start_hz: case.continuation.start_hz.unwrap_or(0.0),
        end_hz: case.continuation.end_hz.unwrap_or(0.0),
        runs,
        comparisons,
        resonance_hz,
        figures: Vec::new(),
    };
    study.figures = report::figures(&options.output, &study, &outcomes)?;
    Ok(study)
}

/// The signed diameter lists of a basis record.
fn lists(harmonics: &[cyclorub::run::HarmonicRecord]) -> Vec<&[i64]> {
    harmonics
        .iter()
        .map(|h| h.signed_nodal_diameters.as_slice())
        .collect()
}

/// A case that cannot even be prepared stops the reproduction before it
/// solves anything for that case.
fn cannot_prepare(case: &str) -> impl Fn(RunError) -> ReproduceError + '_ {
    move |error| match error {
        RunError::Case(e) => ReproduceError::Case(e),
        other => ReproduceError::Prepare {
            case: case.to_string(),
            message: other.to_string(),
        },
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::template::{FanExample, FAN_FOLDER};

    /// A fresh folder holding the fan example `name` as `examples/` does,
    /// without its mesh.
    fn fan_example_folder(tag: &str, name: &str) -> (PathBuf, Case) {
        let dir = std::env::temp_dir().join(format!("cyclorub-{tag}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        let example = FanExample::find(name).unwrap();
        std::fs::write(dir.join(format!("{name}.toml")), example.template()).unwrap();
        let case = Case::from_file_checked(&dir.join(format!("{name}.toml"))).unwrap();
        (dir, case)
    }

    /// The reproduction writes the open fan where a fan example's mesh is
    /// missing, points the model there and can build it; with the mesh in
    /// place, or with files that are not the fan's, it leaves the case.
    #[test]
    fn a_missing_fan_mesh_is_written_and_the_case_points_there() {
        let (dir, original) = fan_example_folder("provide-fan", "fan16-partly-standing-h7");
        let output = dir.join("reproduction");
        let mut case = original.clone();
        let folder = provide_fan_mesh(&mut case, &dir, &output, 1)
            .unwrap()
            .expect("the mesh is missing: written");
        assert!(folder.is_absolute() && folder.ends_with("fan16-refine1"));
        for (file, (key, name)) in [
            &case.model.mass_file,
            &case.model.stiffness_file,
            &case.model.coordinates_file,
            &case.model.node_sets_file,
        ]
        .into_iter()
        .zip(FAN_MODEL_FILES)
        {
            let file = file.as_ref().unwrap();
            assert_eq!(file, &folder.join(name), "{key}");
            assert!(file.is_file(), "{key}: {}", file.display());
        }
        // Nothing else of the case changed.
        let mut back = case.clone();
        back.model = original.model.clone();
        assert_eq!(back, original);
        // The coarse fan builds from the case, read from the fan's folder.
        let model = case.model.build(&folder).unwrap();
        assert_eq!(model.sectors(), 16);
        // The mesh where the case expects it: nothing to do.
        let beside = dir.join(FAN_FOLDER);
        std::fs::create_dir_all(&beside).unwrap();
        for (_, name) in FAN_MODEL_FILES {
            std::fs::copy(folder.join(name), beside.join(name)).unwrap();
        }
        let mut present = original.clone();
        assert!(provide_fan_mesh(&mut present, &dir, &output, 1)
            .unwrap()
            .is_none());
        assert_eq!(present, original);
        // Missing files that are not the fan's: left to the run's error.
        let mut other = original.clone();
        other.model.mass_file = Some(PathBuf::from("elsewhere/mass.mtx"));
        let before = other.clone();
        assert!(provide_fan_mesh(&mut other, &dir, &output, 1)
            .unwrap()
            .is_none());
        assert_eq!(other, before);
        let _ = std::fs::remove_dir_all(&dir);
    }

    /// The quick fan: few harmonics, `N_t` a multiple of `N`, a narrow
    /// window around the contact's start and few points.
    #[test]
    fn the_quick_fan_case_is_small() {
        let mut case = FanExample::find("fan16-traveling-h1").unwrap().case();
        quick_case(&mut case, 281.9);
        let hb = &case.harmonic_balance;
        assert_eq!(hb.harmonics, 2);
        assert_eq!(hb.time_samples % 16, 0);
        assert!(hb.time_samples > 2 * hb.harmonics);
        let (start, end) = (
            case.continuation.start_hz.unwrap(),
            case.continuation.end_hz.unwrap(),
        );
        assert!(start < 0.9986 * 281.9 && end > 281.9 && end - start < 0.003 * 281.9);
        assert!(case.continuation.max_points <= 40);
    }

    #[test]
    fn time_samples_become_a_multiple_of_the_sectors() {
        assert_eq!(multiple_of_sectors(10000, 24, 10), 10008);
        assert_eq!(multiple_of_sectors(10000, 45, 10), 9990);
        assert_eq!(multiple_of_sectors(10, 24, 10), 24);
        assert_eq!(multiple_of_sectors(30, 7, 20), 42);
        assert_eq!(multiple_of_sectors(100, 1, 3), 100);
    }
}
