//! A marker's kind read where it is located (docs/design.md §10,
//! "Located"): a slowly modulated complex pair is a Neimark–Sacker crossing
//! however it was located, and a basis that holds every nodal diameter (the
//! full basis) tells no fold from a branch point by its one class; where
//! the exponents jump at a change of contact, the marker says so.

use crate::stability::solve;
use cyclorub::case::BasisChoice;
use cyclorub::continuation::EventKind;
use cyclorub::forced_response::{Solution, BRACKET_FRACTION, REAL_AT_LOCATION};
use cyclorub::stability::{BranchStability, MarkerKind, StabilitySettings};

/// Six sectors, traveling wave h = 2 at 4 N, `N_h = 3`: its class-1
/// crossings near 212.8 Hz are complex pairs of small imaginary part
/// (about 8.5 rad/s) whose followed exponents jump, located by the count.
const SIX_SECTORS: &str = "[model]\nsectors = 6\n[excitation]\nengine_order = 2\namplitude = 4.0\n\
                           [harmonic_balance]\nharmonics = 3\ntime_samples = 60\n\
                           [continuation]\nmax_points = 300\n";

/// The branch's stability with its markers where interpolation placed them.
fn interpolated(solution: &Solution) -> BranchStability {
    solution
        .stability_check(&StabilitySettings::default())
        .unwrap()
        .branch(&solution.branch.points)
        .unwrap()
}

fn located(solution: &Solution) -> BranchStability {
    let mut stability = interpolated(solution);
    solution
        .locate_markers(&StabilitySettings::default(), &mut stability)
        .unwrap();
    stability
}

fn is_real(kind: MarkerKind) -> bool {
    matches!(
        kind,
        MarkerKind::Fold | MarkerKind::BranchPoint | MarkerKind::RealCrossing
    )
}

#[test]
fn a_slow_complex_crossing_located_by_the_count_is_not_a_branch_point() {
    let solution = solve(SIX_SECTORS, BasisChoice::Symmetry);
    let stability = located(&solution);
    let mut complex_by_count = 0;
    for m in &stability.markers {
        let Some(location) = m.located else { continue };
        eprintln!(
            "{:?} class {:?} at {:.6} Hz, angle {:.3e}, by count {}",
            m.kind, m.nodal_diameter, m.frequency_hz, location.angle, location.by_count
        );
        // A real crossing's multiplier angle is at round-off of the
        // location; a pair keeping a finite one is complex.
        if is_real(m.kind) {
            assert!(location.angle.abs() < REAL_AT_LOCATION, "{m:?}");
        } else if m.kind == MarkerKind::NeimarkSacker {
            assert!(location.angle.abs() >= REAL_AT_LOCATION, "{m:?}");
        }
        if location.by_count && location.angle.abs() >= REAL_AT_LOCATION {
            complex_by_count += 1;
        }
    }
    // A smooth law (the regularized one) has no jump.
    assert!(stability.markers.iter().all(|m| m.kind != MarkerKind::Jump));
    // The case has them (three measured, angles 0.024 to 0.040 rad, once
    // labelled branch points from Hill's interpolated side).
    assert!(complex_by_count >= 1, "{complex_by_count}");
}

#[test]
fn on_the_full_basis_a_real_crossing_is_of_no_class() {
    // The symmetry basis calls its class-3 crossings branch points; on the
    // full basis they fall in its one class with the folds: real
    // crossings, no nodal diameter (as on the physical full wheel).
    let symmetric = located(&solve(SIX_SECTORS, BasisChoice::Symmetry));
    assert!(symmetric
        .markers
        .iter()
        .any(|m| m.kind == MarkerKind::BranchPoint && m.nodal_diameter == Some(3)));
    let full = located(&solve(SIX_SECTORS, BasisChoice::Full));
    let real: Vec<_> = full.markers.iter().filter(|m| is_real(m.kind)).collect();
    assert!(!real.is_empty());
    for m in real {
        assert_eq!(m.kind, MarkerKind::RealCrossing, "{m:?}");
        assert_eq!(m.nodal_diameter, None, "{m:?}");
    }
}

/// Six sectors, traveling wave h = 1, DLFT: a branch of nonsmooth folds
/// (the continuation turns at changes of contact, its points placed on
/// them), where the class-0 exponents jump across 0.
const SIX_SECTORS_DLFT: &str =
    "[model]\nsectors = 6\n[excitation]\nengine_order = 1\namplitude = 4.0\n\
                                [contact]\nlaw = \"dlft\"\n\
                                [harmonic_balance]\nharmonics = 5\ntime_samples = 200\n\
                                [continuation]\nmax_points = 400\n";

#[test]
fn a_jump_at_a_change_of_contact_is_a_change_of_the_class_count_at_one_point() {
    let solution = solve(SIX_SECTORS_DLFT, BasisChoice::Symmetry);
    let stability = located(&solution);
    let check = solution
        .stability_check(&StabilitySettings::default())
        .unwrap();
    let points = &solution.branch.points;
    let jumps: Vec<_> = stability
        .markers
        .iter()
        .filter(|m| m.kind == MarkerKind::Jump)
        .collect();
    // Measured: 15 of the 84 events.
    assert!(jumps.len() >= 5, "{} jumps", jumps.len());
    for m in jumps {
        let location = m.located.expect("a jump is found by locating");
        let class = m.nodal_diameter.unwrap();
        // Closed to the chord's resolution, beside one of its points.
        assert!(location.bracket_fraction <= BRACKET_FRACTION, "{m:?}");
        assert!(m.fraction.min(1.0 - m.fraction) < 1e-5, "{m:?}");
        // Not a crossing through 0: across that bracket the exponent on
        // its growing side is already clearly growing (above 1e-4 ω, a
        // hundred times the markers' band).
        assert!(m.exponent.re > 1e-4 * points[m.index].omega, "{m:?}");
        // A real change of stability, not two exponents paired by the
        // tracking: where the class's stability changes, it grows a
        // different number of exponents (faster than 1e-6 ω) at the two
        // points, solved again here (a further exponent of an unstable
        // class may be followed by others crossing within the step).
        if !m.class_changes {
            continue;
        }
        let growing = |i: usize| {
            let p = &points[i];
            check
                .class_exponents(&p.unknowns, p.omega, class)
                .unwrap()
                .iter()
                .filter(|e| e.re > 1e-6 * p.omega)
                .count()
        };
        assert_ne!(growing(m.index), growing(m.index + 1), "{m:?}");
    }
    // The smooth crossings keep their kinds, located through 0.
    for m in &stability.markers {
        if let (Some(location), false) = (m.located, m.kind == MarkerKind::Jump) {
            if !location.by_count {
                assert!(m.exponent.re.abs() < 1e-3 * points[m.index].omega, "{m:?}");
            }
        }
    }
}

/// Six sectors, standing wave h = 1, DLFT: a trial point of its fold at
/// 208.89 Hz (class 0) is out of Newton's reach from the chord; walked to
/// from the bracket's nearer end it is solved, and every event that
/// changes its class's stability is located (before the walk that one was
/// left where interpolation placed it).
#[test]
fn every_change_of_a_class_stability_on_a_standing_dlft_branch_is_located() {
    let case = SIX_SECTORS_DLFT.replace("[excitation]\n", "[excitation]\nkind = \"standing\"\n");
    let stability = located(&solve(&case, BasisChoice::Symmetry));
    let changes: Vec<_> = stability
        .markers
        .iter()
        .filter(|m| m.class_changes)
        .collect();
    // Measured: 71 markers, 34 of them changes of a class's stability.
    assert!(changes.len() > 25, "{}", changes.len());
    for m in changes {
        assert!(m.located.is_some(), "{m:?}");
    }
}

/// The default case's folds (class 0): at the plateau's end (129.99 Hz)
/// the branch bends so sharply between its two points, seen in a metric
/// that weighs the chord's unknowns and frequency alike, that Newton from
/// the chord's point 2 % from a point does not converge there (the marker
/// was left where interpolation placed it, 0.3 mHz off); on planes square
/// to the chord in the continuation's metric each fold is located, at the
/// turn of the branch's frequency.
#[test]
fn the_default_branchs_folds_are_located_at_the_turns_of_its_frequency() {
    let solution = solve("", BasisChoice::Symmetry);
    let mut stability = interpolated(&solution);
    stability
        .markers
        .retain(|m| m.kind == MarkerKind::Fold && m.nodal_diameter == Some(0));
    // Measured: 129.99 and 127.92 Hz.
    assert_eq!(stability.markers.len(), 2, "{:?}", stability.markers);
    solution
        .locate_markers(&StabilitySettings::default(), &mut stability)
        .unwrap();
    let points = &solution.branch.points;
    // The arc travelled in the unknowns: monotone through a fold, where
    // the frequency is not.
    let mut arc = vec![0.0];
    for pair in points.windows(2) {
        let step: f64 = pair[1]
            .unknowns
            .iter()
            .zip(&pair[0].unknowns)
            .map(|(a, b)| (a - b) * (a - b))
            .sum();
        arc.push(arc[arc.len() - 1] + step.sqrt());
    }
    assert_eq!(stability.markers.len(), 2, "{:?}", stability.markers);
    for m in &stability.markers {
        assert!(m.located.is_some(), "{m:?}");
        assert_eq!(m.kind, MarkerKind::Fold, "{m:?}");
        // The turn: the vertex of the parabola through the frequencies of
        // the three points about the extreme one, against the arc.
        let (i, j) = (m.index, m.index + 1);
        let turning = (points[i].omega - points[i - 1].omega).signum();
        let middle = if (points[j].omega - points[i].omega) * turning > 0.0 {
            j
        } else {
            i
        };
        let (s, w): (Vec<f64>, Vec<f64>) = (middle - 1..=middle + 1)
            .map(|k| (arc[k], points[k].omega))
            .unzip();
        let first = |a: usize, b: usize| (w[b] - w[a]) / (s[b] - s[a]);
        let curvature = (first(1, 2) - first(0, 1)) / (s[2] - s[0]);
        let vertex_arc = 0.5 * (s[0] + s[1]) - first(0, 1) / (2.0 * curvature);
        let vertex = w[0]
            + first(0, 1) * (vertex_arc - s[0])
            + curvature * (vertex_arc - s[0]) * (vertex_arc - s[1]);
        let vertex_hz = vertex / (2.0 * std::f64::consts::PI);
        assert!(
            (m.frequency_hz - vertex_hz).abs() < 1e-4,
            "{m:?}: the turn at {vertex_hz} Hz"
        );
    }
}

/// A real crossing of class 0 is a fold where the branch turns in
/// frequency, and a branch point (two branches of one symmetry crossing)
/// where it goes on through: Hill's markers say what the continuation's
/// own events say, fold for fold and branch point for branch point.
#[test]
fn a_class_zero_crossing_is_a_fold_at_a_turn_and_a_branch_point_elsewhere() {
    // Six sectors, standing wave h = 1, R-HBM: its class-0 exponents cross
    // 0 at turns of the branch in frequency and, many times, where it goes
    // on through (the continuation's orientation changes there: another
    // branch of the same symmetry crosses it).
    let case = SIX_SECTORS_DLFT
        .replace("[excitation]\n", "[excitation]\nkind = \"standing\"\n")
        .replace("[contact]\nlaw = \"dlft\"\n", "");
    let solution = solve(&case, BasisChoice::Symmetry);
    let stability = located(&solution);
    let points = &solution.branch.points;
    // The continuation's events lie between points `index − 1` and `index`.
    let event_near = |index: usize| {
        solution
            .branch
            .events
            .iter()
            .filter(|e| e.index == index + 1 || e.index == index)
            .map(|e| e.kind.clone())
            .collect::<Vec<_>>()
    };
    let class_zero: Vec<_> = stability
        .markers
        .iter()
        .filter(|m| is_real(m.kind) && m.nodal_diameter == Some(0))
        .collect();
    let branch_points = class_zero
        .iter()
        .filter(|m| m.kind == MarkerKind::BranchPoint)
        .count();
    // Measured: 31 crossings, 21 of them branch points.
    assert!(
        branch_points >= 10,
        "{branch_points} of {}",
        class_zero.len()
    );
    assert!(class_zero.len() > branch_points);
    for m in class_zero {
        // Its step goes the other way from one of its neighbours (none of
        // these markers is at an end of the branch).
        let step = |i: usize| points[i + 1].omega - points[i].omega;
        let here = step(m.index);
        let turns = step(m.index - 1) * here < 0.0 || here * step(m.index + 1) < 0.0;
        assert_eq!(m.kind == MarkerKind::Fold, turns, "{m:?}");
        let expected = if turns {
            EventKind::Fold
        } else {
            EventKind::BranchPoint
        };
        assert!(event_near(m.index).contains(&expected), "{m:?}");
    }
}
