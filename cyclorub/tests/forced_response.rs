//! The library's front door: a case in, a branch in memory out.

use cyclorub::case::{BasisChoice, Case};
use cyclorub::continuation::{
    Branch, Evaluation, Event, EventKind, Observer, Point, Problem, State, StopReason,
};
use cyclorub::forced_response::{ForcedResponse, StartRecord};
use std::path::Path;

fn case(text: &str) -> Case {
    Case::from_toml(text, Path::new("test.toml")).expect("case")
}

const SMALL: &str = "[model]\nsectors = 6\n[harmonic_balance]\nharmonics = 3\ntime_samples = 60\n\
                     [continuation]\nmax_points = 400\n";

#[test]
fn the_branch_in_memory_is_the_branch_the_run_writes() {
    let small = case(SMALL);
    let solution = ForcedResponse::from_case(&small)
        .unwrap()
        .basis(BasisChoice::Symmetry)
        .build()
        .unwrap()
        .run(&mut [])
        .unwrap();
    assert!(
        solution.branch.points.len() > 10,
        "{:?}",
        solution.branch.stop
    );
    assert_eq!(solution.start, StartRecord::LinearGuess);
    let folder = std::env::temp_dir().join(format!("cyclorub-api-{}", std::process::id()));
    let (record, data) = cyclorub::run::write(&solution, &folder).unwrap();
    assert_eq!(record.points, solution.branch.points.len());
    assert_eq!(data.points.len(), solution.branch.points.len());
    for (written, point) in data.points.iter().zip(&solution.branch.points) {
        assert_eq!(written.unknowns, point.unknowns);
    }
    // Exactly the files the features allow: results.h5 with `hdf5`, plots/
    // with `plot`, branch.csv and run.json always, observed_harmonics.csv
    // only when the case asks (`[output] harmonics_csv`, off here).
    let mut files: Vec<String> = std::fs::read_dir(&folder)
        .unwrap()
        .map(|entry| {
            let entry = entry.unwrap();
            let name = entry.file_name().to_string_lossy().into_owned();
            if entry.path().is_dir() {
                name + "/"
            } else {
                name
            }
        })
        .collect();
    files.sort();
    let mut expected: Vec<&str> = cyclorub::run::OUTPUT_FILES
        .iter()
        .copied()
        .filter(|f| *f != "observed_harmonics.csv")
        .collect();
    expected.sort();
    assert_eq!(files, expected);
    assert_eq!(expected.contains(&"results.h5"), cfg!(feature = "hdf5"));
    assert_eq!(expected.contains(&"plots/"), cfg!(feature = "plot"));
    let _ = std::fs::remove_dir_all(&folder);
}

#[test]
fn a_bad_case_is_refused_before_any_work_with_its_key() {
    let mut bad = case(SMALL);
    bad.contact.stiffness = -1.0;
    let message = ForcedResponse::from_case(&bad).unwrap_err().to_string();
    assert!(message.contains("contact.stiffness = -1"), "{message}");
    // N_t < 2 N_h + 1 is refused with the case's keys, before any solve.
    let mut bad = case(SMALL);
    bad.harmonic_balance.time_samples = 5;
    let error = ForcedResponse::from_case(&bad)
        .and_then(|request| request.build())
        .err()
        .expect("too few time samples");
    assert!(error.is_input_error(), "{error}");
    assert!(
        error.to_string().contains("harmonic_balance.time_samples"),
        "{error}"
    );
    let e = ForcedResponse::from_case(&case(SMALL))
        .unwrap()
        .at_frequencies_hz(vec![f64::NAN])
        .build()
        .err()
        .expect("a NaN frequency is refused");
    assert!(e.is_input_error(), "{e}");
    let e = ForcedResponse::from_case(&case(SMALL))
        .unwrap()
        .at_frequencies_hz(Vec::new())
        .build()
        .err()
        .expect("an empty list is refused");
    assert!(e.to_string().contains("at least one frequency"), "{e}");
}

#[test]
fn a_blade_touching_its_casing_at_rest_starts_by_continuation_in_the_load() {
    // casing.gap = 0 with R-HBM: the law's force γ at zero penetration
    // pushes every blade off the casing, and Newton from the linear
    // response fails at the start frequency.
    let touching = case(&format!("{SMALL}[casing]\ngap = 0.0\n"));
    let mut solution = ForcedResponse::from_case(&touching)
        .unwrap()
        .build()
        .unwrap()
        .run(&mut [])
        .unwrap();
    assert!(
        matches!(solution.start, StartRecord::LoadContinuation { points, .. } if points > 1),
        "{:?}",
        solution.start
    );
    assert!(
        solution.branch.points.len() > 10,
        "{:?}",
        solution.branch.stop
    );
    // The first point solves the full load at the start frequency.
    let first = solution.branch.points[0].clone();
    let start_hz = solution.case.continuation.start_hz.expect("resolved");
    let first_hz = first.omega / (2.0 * std::f64::consts::PI);
    assert!(
        (first_hz - start_hz).abs() < 1e-9 * start_hz,
        "{first_hz} Hz"
    );
    let mut evaluation = Evaluation::default();
    solution
        .problem
        .evaluate(&first.unknowns, first.omega, false, &mut evaluation)
        .unwrap();
    let norm = evaluation
        .residual
        .iter()
        .map(|r| r * r)
        .sum::<f64>()
        .sqrt()
        / solution.problem.force_scale();
    assert!(norm <= solution.case.continuation.tolerance, "{norm:e}");
}

#[test]
fn a_dlft_blade_touching_its_casing_at_rest_starts_by_continuation_in_the_gap() {
    // casing.gap = 0 with DLFT: Newton from the linear response fails, and
    // so does the load continuation (at a tiny load every instant of the
    // period switches at once); the gap is brought down from a casing the
    // linear response does not touch.
    use cyclorub::results::recovery::dof_peaks;
    let touching = case(&format!(
        "{SMALL}[casing]\ngap = 0.0\n[contact]\nlaw = \"dlft\"\n"
    ));
    let mut solution = ForcedResponse::from_case(&touching)
        .unwrap()
        .build()
        .unwrap()
        .run(&mut [])
        .unwrap();
    assert!(
        matches!(solution.start, StartRecord::GapContinuation { points, .. } if points > 1),
        "{:?}",
        solution.start
    );
    assert!(
        matches!(solution.branch.stop, StopReason::EndReached),
        "{:?}",
        solution.branch.stop
    );
    let first = solution.branch.points[0].clone();
    let start_hz = solution.case.continuation.start_hz.expect("resolved");
    assert!((first.omega / (2.0 * std::f64::consts::PI) - start_hz).abs() < 1e-9 * start_hz);
    // The first point solves the case's own problem (gap 0)…
    let mut evaluation = Evaluation::default();
    solution
        .problem
        .evaluate(&first.unknowns, first.omega, false, &mut evaluation)
        .unwrap();
    let norm = evaluation
        .residual
        .iter()
        .map(|r| r * r)
        .sum::<f64>()
        .sqrt()
        / solution.problem.force_scale();
    assert!(norm <= solution.case.continuation.tolerance, "{norm:e}");
    // …in which the casing stops the blade: its tip stays at the casing
    // (a rigid casing, up to the truncation of the harmonics) where the
    // linear response goes through it.
    let nt = solution.case.harmonic_balance.time_samples;
    let sectors: Vec<usize> = (0..6).collect();
    let linear = solution.problem.linear_solution(first.omega).unwrap();
    let free = dof_peaks(&solution.problem, &linear, first.omega, 0, &sectors, nt).unwrap();
    let held = dof_peaks(
        &solution.problem,
        &first.unknowns,
        first.omega,
        0,
        &sectors,
        nt,
    )
    .unwrap();
    for (free, held) in free.iter().zip(&held) {
        assert!(*free > 1e-5, "the linear response touches: {free:e} m");
        assert!(
            held.abs() < 1e-3 * free,
            "held at the casing: {held:e} m of {free:e} m"
        );
    }
}

/// Counts what it is shown.
#[derive(Default)]
struct Watcher {
    points: Vec<(usize, f64)>,
    stops: usize,
    finished: Option<usize>,
}

impl Observer for Watcher {
    fn point(&mut self, index: usize, point: &Point, _state: &State<'_>) {
        self.points.push((index, point.omega));
    }
    fn event(&mut self, event: &Event) {
        if matches!(event.kind, EventKind::Stop(_)) {
            self.stops += 1;
        }
    }
    fn finished(&mut self, branch: &Branch) {
        self.finished = Some(branch.points.len());
    }
}

#[test]
fn observers_see_every_point_as_it_is_accepted() {
    let mut watcher = Watcher::default();
    let mut also = Watcher::default();
    let solution = ForcedResponse::from_case(&case(SMALL))
        .unwrap()
        .build()
        .unwrap()
        .run(&mut [&mut watcher, &mut also])
        .unwrap();
    let branch = &solution.branch;
    assert!(branch.sweeps.is_none(), "one sweep: {:?}", branch.stop);
    assert_eq!(watcher.points.len(), branch.points.len());
    for (i, ((index, omega), point)) in watcher.points.iter().zip(&branch.points).enumerate() {
        assert_eq!(*index, i);
        assert_eq!(omega.to_bits(), point.omega.to_bits());
    }
    assert_eq!(watcher.stops, 1);
    assert_eq!(watcher.finished, Some(branch.points.len()));
    assert_eq!(also.points, watcher.points, "every observer is told");
}

#[test]
fn a_frequency_listed_twice_is_solved_again_with_its_residual() {
    // `--at-hz 205,205,206`: the second 205 Hz has no step to take; its
    // point keeps the residual measured there (it once read `inf`,
    // marked converged).
    let solution = ForcedResponse::from_case(&case(SMALL))
        .unwrap()
        .stability(None)
        .at_frequencies_hz(vec![205.0, 205.0, 206.0])
        .build()
        .unwrap()
        .run(&mut [])
        .unwrap();
    let points = &solution.branch.points;
    assert_eq!(points.len(), 3);
    for p in points {
        assert!(p.converged, "{p:?}");
        assert!(
            p.residual_norm.is_finite() && p.residual_norm <= 1e-8,
            "{}",
            p.residual_norm
        );
    }
    let (first, second) = (&points[0], &points[1]);
    assert_eq!(first.omega, second.omega);
    let distance = first
        .unknowns
        .iter()
        .zip(&second.unknowns)
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max);
    let size = first.unknowns.iter().map(|a| a.abs()).fold(0.0, f64::max);
    assert!(distance <= 1e-10 * size, "{distance} of {size}");
}

/// Fixed frequencies past the end of the default case's contact plateau
/// (a fold at 129.99 Hz): each used to fail (Newton drawn to the fold);
/// now the branch is followed through the fold and back, and the last
/// frequency's point is the arc-length branch's own there (its end, on the
/// lower sheet after the back-turn), to 1e-9 of the amplitude.
#[test]
fn fixed_frequencies_past_the_plateaus_end_are_the_branchs_lower_sheet() {
    let mut case = Case::default();
    // From below the plateau, where the response has one sheet.
    case.continuation.start_hz = Some(127.0);
    case.continuation.end_hz = Some(130.6);
    let at = ForcedResponse::from_case(&case)
        .unwrap()
        .stability(None)
        .at_frequencies_hz(vec![127.0, 127.6, 128.2, 128.8, 129.4, 129.8, 130.2, 130.6])
        .build()
        .unwrap()
        .run(&mut [])
        .unwrap();
    assert!(at.branch.points.iter().all(|p| p.converged));
    // On the plateau at 129.8 Hz (above the 1 mm gap), off it at 130.2.
    let tip = |p: &cyclorub::continuation::Point| {
        cyclorub::results::recovery::dof_peaks(&at.problem, &p.unknowns, p.omega, 0, &[0], 10_000)
            .unwrap()[0]
    };
    assert!(tip(&at.branch.points[5]) > 1e-3 && tip(&at.branch.points[6]) < 1e-3);
    let along = ForcedResponse::from_case(&case)
        .unwrap()
        .stability(None)
        .build()
        .unwrap()
        .run(&mut [])
        .unwrap();
    assert_eq!(along.branch.stop, StopReason::EndReached);
    // The arc-length branch turned back at the fold: it went down in
    // frequency before reaching its end.
    assert!(along
        .branch
        .points
        .windows(2)
        .any(|w| w[1].omega < w[0].omega));
    let (a, b) = (
        at.branch.points.last().unwrap(),
        along.branch.points.last().unwrap(),
    );
    assert_eq!(a.omega.to_bits(), b.omega.to_bits());
    let size = b.unknowns.iter().map(|v| v.abs()).fold(0.0, f64::max);
    let distance = a
        .unknowns
        .iter()
        .zip(&b.unknowns)
        .map(|(p, q)| (p - q).abs())
        .fold(0.0, f64::max);
    assert!(distance <= 1e-9 * size, "{distance} of {size}");
}

/// A fresh start on the contact plateau of the default case mistuned at 1 %
/// (seed 15, the pattern a 100-pattern study left unconverged there):
/// Newton from the linear response (an amplitude many gaps wide) does not
/// converge at 127.5 Hz, so the fresh guess is the continuation in the
/// load's point (with the run's steps), a solution to the tolerance; and
/// that continuation stops when the run is interrupted.
#[test]
fn a_fresh_start_on_the_plateau_is_reached_by_the_load() {
    use cyclorub::continuation::{correct, NewtonSettings, Problem};
    let case = Case::from_toml(
        "[mistuning]\nstandard_deviation = 0.01\nseed = 15\n[basis]\nkind = \"physical\"\n",
        Path::new("mistuned.toml"),
    )
    .unwrap();
    let built = ForcedResponse::from_case(&case)
        .unwrap()
        .stability(None)
        .build()
        .unwrap();
    let mut problem = built.problem().clone();
    let omega = 2.0 * std::f64::consts::PI * 127.5;
    let newton = NewtonSettings::default();
    let mut from_linear = problem.linear_solution(omega).unwrap();
    let (converged, ..) = correct(&mut problem, &mut from_linear, omega, &newton).unwrap();
    assert!(!converged, "Newton from the linear response converged");
    // The run's steps, as `--at-hz` passes them.
    let k = &case.continuation;
    let steps = cyclorub::continuation::ArcLengthSettings {
        start: omega,
        end: omega,
        initial_step: k.initial_step,
        min_step: k.min_step,
        max_step: k.max_step,
        length_scale: cyclorub::forced_response::length_scale(
            &case.casing().unwrap(),
            &from_linear,
        )
        .unwrap(),
        newton: NewtonSettings {
            tolerance: k.tolerance,
            max_iterations: k.max_iterations,
            ..Default::default()
        },
        max_points: k.max_points,
    };
    let mut fresh = problem
        .fresh_guess(omega, &steps)
        .unwrap()
        .expect("a guess");
    let (converged, iterations, residual) =
        correct(&mut problem, &mut fresh, omega, &newton).unwrap();
    assert!(
        converged && iterations <= 1,
        "{iterations} iterations, {residual:e}"
    );
    // A run interrupted meanwhile: the continuation in the load stops at
    // once, and there is no guess (Newton from the linear response, which
    // failed above, is not tried again; the run then stops too).
    let interrupt = cyclorub::continuation::Interrupt::new();
    interrupt.raise();
    problem.watch_interrupt(&interrupt);
    assert!(problem.fresh_guess(omega, &steps).unwrap().is_none());
}
