//! The continuation driver, iterated by hand, on closed-form scalar
//! branches: it gives the points `continue_branch` gives, records the folds,
//! branch points and kinks of a branch where they are, and tells its
//! observers of every point in order, of every event and of the end.

use crate::common;

use common::scalar_branch::{
    s_curve, s_curve_root as root, settings, zigzag, zigzag_frequency, zigzag_piece, Faulty,
    ScalarBranch, ZIGZAG_BACKWARD as BACKWARD,
};
use cyclorub::continuation::{
    continue_branch, continue_from_both_ends, ArcLengthSettings, AtFrequencies, Bordered, BothEnds,
    Branch, Continuation, DenseLu, Event, EventKind, Interrupt, LinearSolver, NewtonSettings,
    Observer, Point, PolicyKind, ProgressFn, Settings, Solution, State, Step, StepSettings,
    StopReason,
};
use std::cell::Cell;
use std::f64::consts::PI;
use std::rc::Rc;

/// `x² − λ² = ε` (`λ = ω − 2`); with `ε < 0`, the sheets `λ = ±√(x² − ε)`
/// fold at `x = 0`.
fn hyperbola(gap: f64) -> impl Fn(f64, f64) -> (f64, f64, f64) {
    move |x: f64, omega: f64| {
        let lambda = omega - 2.0;
        (x * x - lambda * lambda - gap, 2.0 * x, -2.0 * lambda)
    }
}

fn hz(omega: f64) -> f64 {
    omega / (2.0 * PI)
}

fn assert_same_points(a: &[Point], b: &[Point], case: &str) {
    assert_eq!(a.len(), b.len(), "{case}");
    for (p, q) in a.iter().zip(b) {
        assert_eq!(p.omega.to_bits(), q.omega.to_bits(), "{case}");
        assert_eq!(p.unknowns, q.unknowns, "{case}");
        assert_eq!(p.iterations, q.iterations, "{case}");
    }
}

/// A named branch: how to make its residual, its start `x` and settings.
type Case = (&'static str, fn() -> ScalarBranch, f64, ArcLengthSettings);

/// The three kinds of residual, with their start and settings.
fn cases() -> Vec<Case> {
    let zigzag_settings = ArcLengthSettings {
        max_step: 0.03,
        ..settings(zigzag_frequency(-0.5), zigzag_frequency(1.2))
    };
    vec![
        (
            "smooth",
            || ScalarBranch::smooth(s_curve),
            root(-1.0),
            settings(1.0, 3.0),
        ),
        (
            "piecewise",
            || ScalarBranch::piecewise(zigzag, zigzag_piece),
            -0.5,
            zigzag_settings,
        ),
        (
            "nonsmooth",
            || ScalarBranch::new(zigzag),
            -0.5,
            zigzag_settings,
        ),
    ]
}

#[test]
fn the_driver_stepped_by_hand_gives_the_points_of_continue_branch() {
    let kinds = [
        PolicyKind::Smooth,
        PolicyKind::Piecewise,
        PolicyKind::Nonsmooth,
    ];
    for ((case, problem, start, arc_length), kind) in cases().into_iter().zip(kinds) {
        let whole = continue_branch(&mut problem(), vec![start], &arc_length, |_, _| {});
        let mut stepped = problem();
        let mut driver =
            Continuation::new(&mut stepped, vec![start], arc_length.into()).expect("valid");
        assert_eq!(driver.policy(), None);
        let mut points = Vec::new();
        let stop = loop {
            match driver.step() {
                Step::Point(point) => points.push(point.clone()),
                Step::Stopped(stop) => break stop.clone(),
            }
        };
        assert_eq!(driver.policy(), Some(kind), "{case}");
        // Stopped for good.
        assert!(matches!(driver.step(), Step::Stopped(_)));
        assert_same_points(&points, &whole.points, case);
        assert_eq!(stop, whole.stop, "{case}");
        let branch = driver.finish();
        assert_same_points(&branch.points, &whole.points, case);
        assert_eq!(branch.total_iterations, whole.total_iterations, "{case}");
        assert_eq!(branch.events, whole.events, "{case}");
        // As an iterator.
        let mut again = problem();
        let driver = Continuation::new(&mut again, vec![start], arc_length.into()).expect("valid");
        let collected: Vec<Point> = driver.collect();
        assert_same_points(&collected, &whole.points, case);
    }
}

fn folds(branch: &Branch) -> Vec<&Event> {
    branch
        .events
        .iter()
        .filter(|e| e.kind == EventKind::Fold)
        .collect()
}

#[test]
fn folds_are_recorded_where_the_branch_turns() {
    // The S curve turns at x = ∓1/√6, λ = ±1/(3√6).
    let branch = continue_branch(
        &mut ScalarBranch::smooth(s_curve),
        vec![root(-1.0)],
        &settings(1.0, 3.0),
        |_, _| {},
    );
    let tip = 1.0 / (3.0 * 6f64.sqrt());
    let expected = [2.0 + tip, 2.0 - tip];
    let found = folds(&branch);
    assert_eq!(found.len(), 2, "{:?}", branch.events);
    for (event, omega) in found.iter().zip(expected) {
        assert!(
            (event.frequency_hz - hz(omega)).abs() < 1e-6 * hz(omega),
            "fold at {} Hz, expected {} Hz",
            event.frequency_hz,
            hz(omega)
        );
        // Between the two points it comes before and after.
        let (before, after) = (&branch.points[event.index - 1], &branch.points[event.index]);
        assert!(before.unknowns[0] < after.unknowns[0]);
    }
    // The hyperbola's left sheet λ = −√(x² + 0.01) turns at λ = −0.1, and
    // the circle at ω = 3; both then go back past their start.
    for (problem, start, arc_length, omega) in [
        (
            ScalarBranch::smooth(hyperbola(-0.01)),
            0.99_f64.sqrt(),
            settings(1.0, 3.0),
            1.9,
        ),
        (
            ScalarBranch::new(|x, omega| {
                let lambda = omega - 2.0;
                (x * x + lambda * lambda - 1.0, 2.0 * x, 2.0 * lambda)
            }),
            0.75_f64.sqrt(),
            ArcLengthSettings {
                min_step: 1e-9,
                ..settings(1.5, 10.0)
            },
            3.0,
        ),
    ] {
        let mut problem = problem;
        let branch = continue_branch(&mut problem, vec![start], &arc_length, |_, _| {});
        assert!(matches!(branch.stop, StopReason::LeftRange { .. }));
        let found = folds(&branch);
        assert_eq!(found.len(), 1, "{:?}", branch.events);
        // A tighter fold (radius 0.1), met with longer steps: to 1e-5.
        let error = (found[0].frequency_hz - hz(omega)).abs() / hz(omega);
        assert!(error < 1e-5, "fold at {} Hz", found[0].frequency_hz);
    }
    // The stop is the last event, after the last point.
    let last = branch.events.last().expect("events");
    assert_eq!(last.kind, EventKind::Stop(StopReason::EndReached));
    assert_eq!(last.index, branch.points.len());
}

#[test]
fn a_branch_point_crossed_is_recorded_between_the_points_around_it() {
    // On x = −λ from λ = −1: it crosses x = λ at λ = 0 (ω = 2).
    let arc_length = ArcLengthSettings {
        max_step: 0.2,
        newton: cyclorub::continuation::NewtonSettings {
            tolerance: 1e-13,
            max_iterations: 20,
            ..Default::default()
        },
        ..settings(1.0, 3.0)
    };
    let branch = continue_branch(
        &mut ScalarBranch::smooth(hyperbola(0.0)),
        vec![1.0],
        &arc_length,
        |_, _| {},
    );
    assert_eq!(branch.stop, StopReason::EndReached);
    let crossings: Vec<&Event> = branch
        .events
        .iter()
        .filter(|e| e.kind == EventKind::BranchPoint)
        .collect();
    assert_eq!(crossings.len(), 1, "{:?}", branch.events);
    let index = crossings[0].index;
    assert!(branch.points[index - 1].omega <= 2.0 && branch.points[index].omega >= 2.0);
    assert!(folds(&branch).is_empty());
}

#[test]
fn kinks_turned_are_recorded_at_the_kinks() {
    let (_, problem, start, arc_length) = cases().remove(1);
    let branch = continue_branch(&mut problem(), vec![start], &arc_length, |_, _| {});
    assert_eq!(branch.stop, StopReason::EndReached);
    let corners: Vec<f64> = BACKWARD
        .iter()
        .flat_map(|&(start, length)| [start, start + length])
        .map(|x| hz(zigzag_frequency(x)))
        .collect();
    let kinks: Vec<&Event> = branch
        .events
        .iter()
        .filter(|e| e.kind == EventKind::Kink)
        .collect();
    assert!(!kinks.is_empty(), "{:?}", branch.events);
    for kink in kinks {
        assert!(
            corners.iter().any(|c| (kink.frequency_hz - c).abs() < 1e-6),
            "a kink at {} Hz, corners at {corners:?}",
            kink.frequency_hz
        );
    }
    // The wide backward interval is followed: the branch turns back at its
    // two corners (nonsmooth folds).
    let found = folds(&branch);
    assert!(found.len() >= 2, "{:?}", branch.events);
    for fold in &found[..2] {
        assert!(corners.iter().any(|c| (fold.frequency_hz - c).abs() < 1e-3));
    }
}

/// Everything an observer is told, in order.
#[derive(Default)]
struct Record {
    points: Vec<(usize, f64, bool, bool)>,
    events: Vec<Event>,
    sweep_back: Option<usize>,
    finished: Option<Branch>,
}

impl Observer for &mut Record {
    fn point(&mut self, index: usize, point: &Point, state: &State<'_>) {
        let with_jacobian = state.evaluation.is_some_and(|e| e.residual.len() == 1);
        self.points
            .push((index, point.omega, state.sweep_back, with_jacobian));
    }
    fn event(&mut self, event: &Event) {
        self.events.push(event.clone());
    }
    fn sweep_back(&mut self, first: &Branch) {
        self.sweep_back = Some(first.points.len());
    }
    fn finished(&mut self, branch: &Branch) {
        self.finished = Some(branch.clone());
    }
}

#[test]
fn an_observer_sees_every_point_in_order_every_event_and_the_end() {
    for (case, problem, start, arc_length) in cases() {
        let mut record = Record::default();
        let mut problem = problem();
        let branch = Continuation::new(&mut problem, vec![start], arc_length.into())
            .expect("valid")
            .with_observer(&mut record)
            .finish();
        let seen: Vec<(usize, f64)> = record.points.iter().map(|p| (p.0, p.1)).collect();
        let expected: Vec<(usize, f64)> = branch
            .points
            .iter()
            .enumerate()
            .map(|(i, p)| (i, p.omega))
            .collect();
        assert_eq!(seen, expected, "{case}");
        assert!(record.points.iter().all(|p| !p.2 && p.3), "{case}");
        assert_eq!(record.events, branch.events, "{case}");
        assert!(matches!(
            record.events.last().map(|e| &e.kind),
            Some(EventKind::Stop(_))
        ));
        let finished = record.finished.expect("told");
        assert_same_points(&finished.points, &branch.points, case);
        assert_eq!(record.sweep_back, None);
    }
}

#[test]
fn an_observer_of_both_ends_sees_both_sweeps_and_the_joined_branch() {
    // Evaluations fail in a band of the middle sheet until the sweep back
    // starts (at the end frequency, 3).
    let stalled = || {
        let active = Rc::new(Cell::new(true));
        let problem = Faulty {
            curve: ScalarBranch::smooth(s_curve),
            band: (0.1, 0.2),
            active: active.clone(),
        };
        let lift = ProgressFn(move |point: &Point, _: &_| {
            if point.omega == 3.0 {
                active.set(false);
            }
        });
        (problem, lift)
    };
    let mut record = Record::default();
    let (mut problem, lift) = stalled();
    let guesses = (vec![root(-1.0)], vec![root(1.0)]);
    let branch = BothEnds::new(
        &mut problem,
        guesses.0.clone(),
        guesses.1.clone(),
        settings(1.0, 3.0).into(),
    )
    .expect("valid")
    .with_observer(lift)
    .with_observer(&mut record)
    .finish();
    let sweeps = branch.sweeps.clone().expect("both ends");
    assert!(matches!(sweeps.from_end, StopReason::MetOtherSweep { .. }));
    // The points seen: the first sweep, then the sweep back, numbered on.
    let first = sweeps.from_start_points;
    assert_eq!(record.sweep_back, Some(first));
    let indices: Vec<usize> = record.points.iter().map(|p| p.0).collect();
    assert_eq!(
        indices,
        (0..first + sweeps.from_end_points).collect::<Vec<_>>()
    );
    assert!(record.points.iter().all(|p| p.2 == (p.0 >= first)));
    // The branch: the first sweep up to the meeting, the sweep back reversed.
    let mut expected: Vec<f64> = record.points[..sweeps.from_start_kept]
        .iter()
        .map(|p| p.1)
        .collect();
    expected.extend(record.points[first..].iter().rev().map(|p| p.1));
    let omegas: Vec<f64> = branch.points.iter().map(|p| p.omega).collect();
    assert_eq!(omegas, expected);
    assert_same_points(
        &record.finished.expect("told").points,
        &branch.points,
        "both ends",
    );
    // The two folds, one seen by each sweep, are where they were: in the
    // branch's order, the first sweep's before the sweep back's.
    let tip = 1.0 / (3.0 * 6f64.sqrt());
    let found = folds(&branch);
    assert_eq!(found.len(), 2, "{:?}", branch.events);
    for (fold, omega) in found.iter().zip([2.0 + tip, 2.0 - tip]) {
        assert!((fold.frequency_hz - hz(omega)).abs() < 1e-6 * hz(omega));
        let (before, after) = (&branch.points[fold.index - 1], &branch.points[fold.index]);
        assert!(before.unknowns[0] < after.unknowns[0]);
    }
    // The same branch as the closure entry point's.
    let (mut again, lift) = stalled();
    let ProgressFn(lift) = lift;
    let whole = continue_from_both_ends(
        &mut again,
        guesses.0,
        guesses.1,
        &settings(1.0, 3.0),
        |point, progress| lift(point, progress),
    );
    assert_same_points(&whole.points, &branch.points, "both ends");
    assert_eq!(whole.events, branch.events);
}

/// Raises `interrupt` when the observer is told of point `at`.
fn raise_at(at: usize, interrupt: Interrupt) -> impl Observer {
    struct Raise(usize, Interrupt, usize);
    impl Observer for Raise {
        fn point(&mut self, _: usize, _: &Point, _: &State<'_>) {
            self.2 += 1;
            if self.2 == self.0 + 1 {
                self.1.raise();
            }
        }
    }
    Raise(at, interrupt, 0)
}

#[test]
fn an_interrupt_stops_each_driver_after_the_point_it_came_during() {
    let stop_at = |branch: &Branch, count: usize| {
        assert_eq!(branch.points.len(), count);
        let last = branch.points.last().map(|p| hz(p.omega));
        assert_eq!(branch.stop, StopReason::Interrupted { frequency_hz: last });
        assert!(matches!(
            branch.events.last().map(|e| &e.kind),
            Some(EventKind::Stop(StopReason::Interrupted { .. }))
        ));
    };
    for (case, problem, start, arc_length) in cases() {
        let whole = continue_branch(&mut problem(), vec![start], &arc_length, |_, _| {});
        assert!(whole.points.len() > 6, "{case}");
        let interrupt = Interrupt::new();
        let mut problem = problem();
        let branch = Continuation::new(&mut problem, vec![start], arc_length.into())
            .expect("valid")
            .with_observer(raise_at(4, interrupt.clone()))
            .with_interrupt(interrupt)
            .finish();
        stop_at(&branch, 5);
        assert_same_points(&branch.points, &whole.points[..5], case);
    }
    // Raised before the first point: nothing is solved.
    let interrupt = Interrupt::new();
    interrupt.raise();
    let mut problem = ScalarBranch::smooth(s_curve);
    let branch = Continuation::new(&mut problem, vec![root(-1.0)], settings(1.0, 3.0).into())
        .expect("valid")
        .with_interrupt(interrupt.clone())
        .finish();
    stop_at(&branch, 0);
    // Both ends: an interrupt on the first sweep starts no sweep back.
    let mut problem = ScalarBranch::smooth(s_curve);
    let fresh = Interrupt::new();
    let branch = BothEnds::new(
        &mut problem,
        vec![root(-1.0)],
        vec![root(1.0)],
        settings(1.0, 3.0).into(),
    )
    .expect("valid")
    .with_observer(raise_at(2, fresh.clone()))
    .with_interrupt(fresh)
    .finish();
    stop_at(&branch, 3);
    assert!(branch.sweeps.is_none());
    // Fixed frequencies.
    let mut problem = ScalarBranch::smooth(s_curve);
    let omegas = [1.0, 1.2, 1.4, 1.6];
    let fresh = Interrupt::new();
    let branch = AtFrequencies::new(
        &mut problem,
        vec![root(-1.0)],
        &omegas,
        NewtonSettings::default().into(),
    )
    .expect("valid")
    .with_observer(raise_at(1, fresh.clone()))
    .with_interrupt(fresh)
    .finish();
    stop_at(&branch, 2);
}

#[test]
fn a_step_setting_changes_the_branch_and_a_bad_one_is_refused() {
    let arc_length = settings(1.0, 3.0);
    let follow = |settings: Settings| {
        Continuation::new(
            &mut ScalarBranch::smooth(s_curve),
            vec![root(-1.0)],
            settings,
        )
        .expect("valid")
        .finish()
    };
    let default = follow(arc_length.into());
    // Never growing the step from 0.01: more points to the end.
    let slow = follow(Settings {
        step: StepSettings {
            growth: 1.0,
            ..Default::default()
        },
        ..arc_length.into()
    });
    assert_eq!(slow.stop, StopReason::EndReached);
    assert!(slow.points.len() > default.points.len());
    let bad = Settings {
        step: StepSettings {
            shrink: 1.0,
            ..Default::default()
        },
        ..arc_length.into()
    };
    let mut problem = ScalarBranch::smooth(s_curve);
    let refused = Continuation::new(&mut problem, vec![0.0], bad);
    let error = refused.err().expect("a shrink of 1 never shrinks");
    assert!(error.to_string().contains("step.shrink"), "{error}");
    // A guess of the wrong length: the entry point says so in its stop.
    let branch = continue_branch(
        &mut ScalarBranch::smooth(s_curve),
        vec![0.0, 1.0],
        &arc_length,
        |_, _| {},
    );
    assert!(branch.points.is_empty());
    assert!(
        matches!(&branch.stop, StopReason::EvaluationError { message, .. } if message.contains("2 unknowns")),
        "{:?}",
        branch.stop
    );
}

/// Dense LU, counting its solves.
struct Counting(usize);

impl LinearSolver for &mut Counting {
    fn solve(&mut self, system: &Bordered<'_>, rhs: &[f64]) -> Solution {
        self.0 += 1;
        DenseLu::default().solve(system, rhs)
    }
}

#[test]
fn another_linear_solver_is_plugged_in() {
    let arc_length = settings(1.0, 3.0);
    let mut counting = Counting(0);
    let branch = Continuation::new(
        &mut ScalarBranch::smooth(s_curve),
        vec![root(-1.0)],
        arc_length.into(),
    )
    .expect("valid")
    .with_linear_solver(&mut counting)
    .finish();
    let whole = continue_branch(
        &mut ScalarBranch::smooth(s_curve),
        vec![root(-1.0)],
        &arc_length,
        |_, _| {},
    );
    assert_same_points(&branch.points, &whole.points, "counted");
    // A tangent per point at least, and the corrector's steps.
    assert!(counting.0 >= branch.points.len(), "{}", counting.0);
}

/// The root of `x³ − x/2 = λ` Newton reaches from `x0`.
fn root_from(lambda: f64, x0: f64) -> f64 {
    let mut x = x0;
    for _ in 0..100 {
        x -= (x * x * x - 0.5 * x - lambda) / (3.0 * x * x - 0.5);
    }
    x
}

/// Fixed frequencies across a fold: the S curve's lower sheet ends at
/// ω = 2 + 1/(3√6) ≈ 2.136. Without a bridge the frequencies just past it
/// fail (Newton is drawn to the fold); with one, the branch is followed in arc
/// length through the fold and back, and every frequency converges, those
/// past the fold on the upper sheet (to 1e-9 of the closed form).
#[test]
fn fixed_frequencies_pass_a_fold_along_the_branch() {
    let omegas: Vec<f64> = (0..=20).map(|i| 1.0 + 0.1 * i as f64).collect();
    let fold = 2.0 + 1.0 / (3.0 * 6f64.sqrt());
    let newton = settings(1.0, 3.0).newton;
    let natural = AtFrequencies::new(
        &mut ScalarBranch::smooth(s_curve),
        vec![root(-1.0)],
        &omegas,
        newton.into(),
    )
    .expect("valid")
    .finish();
    let past: Vec<&Point> = natural.points.iter().filter(|p| p.omega > fold).collect();
    // Stuck at the fold (x ≈ −0.408) until the residual's local minimum
    // there is far enough above 0 for Newton to escape (2.4 here).
    assert!(past.len() > 2 && !past[0].converged && !past[1].converged);
    assert!((past[0].unknowns[0] + 1.0 / 6f64.sqrt()).abs() < 1e-2);
    let bridged = bridged_sweep(
        &mut ScalarBranch::smooth(s_curve),
        root(-1.0),
        &omegas,
        newton,
    );
    assert_eq!(bridged.stop, StopReason::AllFrequenciesDone);
    assert_eq!(bridged.points.len(), omegas.len());
    for (point, &omega) in bridged.points.iter().zip(&omegas) {
        assert!(point.converged, "{omega}");
        assert_eq!(point.omega.to_bits(), omega.to_bits());
        let lambda = omega - 2.0;
        let expected = if omega < fold {
            root_from(lambda, -1.0)
        } else {
            root_from(lambda, 1.0)
        };
        assert!(
            (point.unknowns[0] - expected).abs() < 1e-9,
            "ω = {omega}: {} against {expected}",
            point.unknowns[0]
        );
    }
}

/// Fixed frequencies from `start` with `newton`, bridged with the test
/// settings' steps where Newton fails.
fn bridged_sweep(
    problem: &mut ScalarBranch,
    start: f64,
    omegas: &[f64],
    newton: NewtonSettings,
) -> Branch {
    AtFrequencies::new(
        problem,
        vec![start],
        omegas,
        cyclorub::continuation::AtFrequenciesSettings {
            bridge: Some(settings(0.0, 0.0)),
            ..newton.into()
        },
    )
    .expect("valid")
    .finish()
}

/// A bridge's own points are solved to a looser tolerance than the run's
/// (a hundred times, at most 1e-6); the frequency it reaches is then solved
/// to the run's. Across the S curve's fold, at several tolerances, every
/// frequency (those reached by the bridge included) is at the run's: left
/// at the bridge's, some are above it.
#[test]
fn a_bridged_frequency_is_solved_to_the_runs_tolerance() {
    let omegas: Vec<f64> = (0..=20).map(|i| 1.0 + 0.1 * i as f64).collect();
    for tolerance in [1e-7, 1e-8, 1e-9, 1e-10, 1e-11] {
        let newton = NewtonSettings {
            tolerance,
            ..settings(1.0, 3.0).newton
        };
        let bridged = AtFrequencies::new(
            &mut ScalarBranch::smooth(s_curve),
            vec![root(-1.0)],
            &omegas,
            cyclorub::continuation::AtFrequenciesSettings {
                bridge: Some(ArcLengthSettings {
                    newton,
                    ..settings(0.0, 0.0)
                }),
                ..newton.into()
            },
        )
        .expect("valid")
        .finish();
        assert_eq!(bridged.stop, StopReason::AllFrequenciesDone);
        for (point, &omega) in bridged.points.iter().zip(&omegas) {
            assert!(point.converged, "{omega}");
            assert!(
                point.residual_norm <= tolerance,
                "ω = {omega}: residual {:e} above the run's {tolerance:e}",
                point.residual_norm
            );
        }
    }
}

/// Fixed frequencies on a branch the tangent predicts exactly (`x = 2ω`):
/// each frequency costs one evaluation, Newton's check of the predicted
/// point (the tangent is taken from the evaluation Newton left at the
/// last point, not from evaluating it again: 10 evaluations, not 19).
#[test]
fn fixed_frequencies_evaluate_each_point_once_where_the_tangent_is_exact() {
    let count = Rc::new(Cell::new(0_usize));
    let counter = count.clone();
    let mut line = ScalarBranch::smooth(move |x, omega| {
        counter.set(counter.get() + 1);
        (x - 2.0 * omega, 1.0, -2.0)
    });
    let omegas: Vec<f64> = (0..10).map(|i| 1.0 + 0.5 * i as f64).collect();
    let branch = AtFrequencies::new(
        &mut line,
        vec![2.0],
        &omegas,
        settings(1.0, 6.0).newton.into(),
    )
    .expect("valid")
    .finish();
    assert_eq!(branch.points.len(), omegas.len());
    for (point, omega) in branch.points.iter().zip(&omegas) {
        assert!(point.converged && point.iterations == 0, "{omega}");
        assert_eq!(point.unknowns[0], 2.0 * omega);
    }
    assert_eq!(count.get(), omegas.len());
}

/// Two sheets with a gap between (`λ = ω − 2`): `x² = −λ − 1/2` (for
/// `λ ≤ −1/2`, folding back at its edge) and `(x − 10)² = λ − 1/2` (for
/// `λ ≥ 1/2`), the zeros of the product of their residuals.
fn two_sheets(x: f64, omega: f64) -> (f64, f64, f64) {
    let lambda = omega - 2.0;
    let a = x * x + lambda + 0.5;
    let b = (x - 10.0) * (x - 10.0) - lambda + 0.5;
    (a * b, 2.0 * x * b + 2.0 * (x - 10.0) * a, b - a)
}

/// Fixed frequencies across the gap of [`two_sheets`]: the branch through
/// the first sheet's fold never comes back, so the bridge fails (once: the
/// frequencies after it do not follow the same branch again); the
/// frequencies in the gap fail, as they must, and those past it are solved
/// from the problem's fresh guess (`x = 9.7`), on the second sheet, to 1e-9
/// of the closed form (`x = 10 ± √(λ − 1/2)`). Without a fresh guess the first of them fails.
#[test]
fn fixed_frequencies_past_a_sheet_that_does_not_come_back_start_again() {
    let omegas: Vec<f64> = (0..=19).map(|i| 1.05 + 0.1 * i as f64).collect();
    // Newton held to 8 iterations: from the last point of the first sheet
    // it cannot walk to the second (it can from a guess near it).
    let newton = NewtonSettings {
        max_iterations: 8,
        ..settings(1.0, 3.0).newton
    };
    let settings = cyclorub::continuation::AtFrequenciesSettings {
        bridge: Some(settings(0.0, 0.0)),
        ..newton.into()
    };
    let start = vec![0.45f64.sqrt()];
    let run = |problem: &mut ScalarBranch| {
        AtFrequencies::new(problem, start.clone(), &omegas, settings)
            .expect("valid")
            .finish()
    };
    let restarted = run(&mut ScalarBranch::smooth(two_sheets).with_fresh_guess(9.7));
    let without = run(&mut ScalarBranch::smooth(two_sheets));
    for (point, &omega) in restarted.points.iter().zip(&omegas) {
        let lambda: f64 = omega - 2.0;
        if lambda.abs() < 0.5 {
            assert!(!point.converged, "ω = {omega}: no solution");
            continue;
        }
        assert!(point.converged, "ω = {omega}");
        // The second sheet's either root.
        let (found, expected) = if lambda < 0.0 {
            (point.unknowns[0], (-lambda - 0.5).sqrt())
        } else {
            ((point.unknowns[0] - 10.0).abs(), (lambda - 0.5).sqrt())
        };
        assert!(
            (found - expected).abs() < 1e-9,
            "ω = {omega}: {} against {expected}",
            point.unknowns[0]
        );
    }
    let first_past = omegas.iter().position(|&w| w - 2.0 > 0.5).unwrap();
    assert!(!without.points[first_past].converged);
}

/// A closed sheet, the ellipse `((ω − 2)/0.3)² + x² = 1` (folds at 1.7 and
/// 2.3), and a second sheet `(x − 10)² = ω − 2.5` beyond it: the zeros of
/// the product of their residuals.
fn loop_and_sheet(x: f64, omega: f64) -> (f64, f64, f64) {
    let u = (omega - 2.0) / 0.3;
    let e = u * u + x * x - 1.0;
    let s = (x - 10.0) * (x - 10.0) - (omega - 2.5);
    (
        e * s,
        2.0 * x * s + 2.0 * (x - 10.0) * e,
        2.0 * u / 0.3 * s - e,
    )
}

/// Fixed frequencies up the lower half of [`loop_and_sheet`]'s ellipse:
/// past its fold at 2.3 the branch goes round the ellipse and back along
/// the frequencies already solved. The bridge stops where it comes back
/// onto them, at the first (79 evaluations on the lower half in all;
/// without the stop 243: the bridge ran the lower half again up to its own
/// start, where its step underflowed); the frequencies before the second
/// sheet fail, those on it are solved from the fresh guess, to 1e-9 of the
/// closed form.
#[test]
fn a_bridge_round_a_loop_stops_where_it_comes_back_onto_the_sweep() {
    let count = Rc::new(Cell::new(0_usize));
    let counter = count.clone();
    let mut problem = ScalarBranch::smooth(move |x, omega| {
        // On the lower half, away from the folds: the sweep's own points,
        // and a bridge that runs along them again.
        if x < -0.2 && omega < 2.2 {
            counter.set(counter.get() + 1);
        }
        loop_and_sheet(x, omega)
    })
    .with_fresh_guess(9.7);
    // Up the ellipse to its fold (2.3, where either is right), one
    // frequency between the sheets, then the second sheet (the range wide
    // enough for a bridge to go round the ellipse).
    let omegas: Vec<f64> = (0..=11)
        .map(|i| 1.75 + 0.05 * i as f64)
        .chain(std::iter::once(2.4))
        .chain((0..=12).map(|i| 2.6 + 0.2 * i as f64))
        .collect();
    let newton = NewtonSettings {
        max_iterations: 8,
        ..settings(1.0, 3.0).newton
    };
    let start = -(1.0 - (0.25f64 / 0.3).powi(2)).sqrt();
    let run = bridged_sweep(&mut problem, start, &omegas, newton);
    for (point, &omega) in run.points.iter().zip(&omegas) {
        if omega < 2.29 {
            let u: f64 = (omega - 2.0) / 0.3;
            assert!(point.converged, "ω = {omega}");
            assert!(
                (point.unknowns[0] + (1.0 - u * u).sqrt()).abs() < 1e-9,
                "ω = {omega}: {} off the ellipse's lower half",
                point.unknowns[0]
            );
        } else if omega > 2.31 && omega < 2.49 {
            assert!(!point.converged, "ω = {omega}: no solution");
        } else if omega > 2.51 {
            assert!(point.converged, "ω = {omega}");
            let found: f64 = (point.unknowns[0] - 10.0).abs();
            assert!((found - (omega - 2.5).sqrt()).abs() < 1e-9, "ω = {omega}");
        }
    }
    assert!(
        count.get() < 120,
        "{} evaluations on the lower half: the bridge ran along the sweep again",
        count.get()
    );
}
