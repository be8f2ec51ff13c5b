//! The study runner of the reproduction: the case files of a folder, each
//! solved with each contact law on every basis ([`reproduce`]), the quick
//! mode's short cases and the open fan's mesh written where a case needs
//! it. What the runs give is gathered in the parent's records and written
//! up by [`report`](super::report).

use super::exactness::{self, Curve};
use super::stability::{self, StabilitySummary};
use super::{
    report, Comparison, Report, ReproduceError, ReproduceMode, ReproduceOptions, RunSummary, Step,
    Study, ENERGY_TOLERANCE, QUICK_CASES,
};
use crate::template::FAN_MODEL_FILES;
use cyclorub::case::{BasisChoice, Case, LawKind};
use cyclorub::continuation::NewtonSettings;
use cyclorub::mesh::{assemble, fan, write_fan, FanGeometry, DEFAULT_REFINE};
use cyclorub::model::ModelKind;
use cyclorub::results::ResultsError;
use cyclorub::run::{prepare, run_keeping, RunError, RunOptions, RunOutcome};
use std::path::{Path, PathBuf};
use std::time::Instant;

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
                mode: ReproduceMode::of(options),
                folder: options.folder.clone(),
                studies: studies.clone(),
                wall_s: clock.elapsed().as_secs_f64(),
            };
            report::write(&options.output, &partial)?;
        }
    }
    let report = Report {
        mode: ReproduceMode::of(options),
        folder: options.folder.clone(),
        studies,
        wall_s: clock.elapsed().as_secs_f64(),
    };
    report::write(&options.output, &report)?;
    Ok(report)
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
                    same.basis = basis;
                    same.same_as = Some(BasisChoice::Symmetry);
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
        // With friction too: the condensed solver holds its velocity
        // terms (docs/stability.md).
        let (settings, not_asked) = match (options.stability, basis) {
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
                    Some(s) => StabilitySummary::from_outcome(&outcome, basis, s.tolerance),
                    None => StabilitySummary::not_asked(not_asked),
                };
                runs.push(RunSummary::from_outcome(&outcome, basis, folder, summary));
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
                basis: summary.basis,
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
