//! Bifurcated branches (docs/design.md §11) against independent references.

use crate::common::branches::{crossings, solved};
use cyclorub::branches::{follow_from, sector_amplitudes, switch_at, BranchPoint};
use cyclorub::case::Case;
use cyclorub::continuation::{
    correct, ArcLengthSettings, Evaluation, NewtonSettings, Problem, Settings,
};
use cyclorub::forced_response::{problem_on_basis, ForcedResponse, Solution};
use cyclorub::hbm::recovery::physical_unknowns;
use std::f64::consts::PI;
use std::path::Path;

pub(crate) fn case(text: &str) -> Case {
    Case::from_toml(text, Path::new("test.toml")).expect("case")
}

/// Eight sectors, traveling excitation h = 4 (a standing pattern (−1)^j
/// that travels): its symmetric branch loses stability to class 1 through
/// real multipliers (Hill's markers at 212.70 and 220.26 Hz).
const EIGHT_SECTORS: &str = "[model]\nsectors = 8\n[excitation]\nengine_order = 4\n";

fn symmetric_branch() -> Solution {
    solved(&case(EIGHT_SECTORS))
}

pub(crate) fn settings(solution: &Solution, max_points: usize) -> Settings {
    let k = &solution.case.continuation;
    let hz = |f: Option<f64>| 2.0 * PI * f.unwrap();
    Settings::from(ArcLengthSettings {
        start: hz(k.start_hz),
        end: hz(k.end_hz),
        initial_step: k.initial_step,
        min_step: k.min_step,
        max_step: k.max_step,
        length_scale: 1e-3,
        newton: NewtonSettings {
            tolerance: k.tolerance,
            max_iterations: k.max_iterations,
            ..Default::default()
        },
        max_points,
    })
}

/// The relative residual of the physical full wheel at `x` (physical
/// unknowns).
fn full_residual(full: &mut cyclorub::hbm::HarmonicBalance, x: &[f64], omega: f64) -> f64 {
    let mut evaluation = Evaluation::default();
    full.evaluate(x, omega, false, &mut evaluation).unwrap();
    evaluation
        .residual
        .iter()
        .map(|r| r * r)
        .sum::<f64>()
        .sqrt()
        / full.force_scale()
}

#[test]
fn a_bifurcated_branch_solves_the_full_wheel_and_the_full_wheel_follows_it_from_the_same_point() {
    // The enlarged Jacobian finds the real crossings Hill's markers place
    // near 212.70 and 220.26 Hz; the branch from the second.
    let solution = symmetric_branch();
    switch_and_compare(solution, 1, &[212.702], 220.256);
}

/// The N = 6 chain, traveling h = 2 (the pattern (−1)^j of three diameters
/// traveling): class 3 doubles the pairs (42 of the full wheel's 126
/// unknowns); Hill's branch-point markers at 211.247 and 212.354 Hz.
/// `N_t = 9996`, a multiple of N: with the default 10000 the full wheel's
/// sectors are sampled at instants the reduced problem's one sector does
/// not hold (its time shifts of T/6 fall off the grid), and the two
/// residuals differ by their aliasing, 2.1e-10 of the load here.
#[test]
fn on_the_six_sector_chain_the_bifurcated_branch_is_the_full_wheels() {
    let solution = solved(&case(
        "[model]\nsectors = 6\n[excitation]\nengine_order = 2\n[harmonic_balance]\ntime_samples = 9996\n[stability]\nenabled = false\n",
    ));
    switch_and_compare(solution, 3, &[212.354], 211.247);
}

/// Finds the real crossings of `class` along `solution`'s branch (one near
/// each of `also`, and one near `at` Hz), switches at the one near `at`,
/// and checks the side against the physical full wheel: each point
/// polished on the enlarged basis solves it to 1e-10 of the load, and the
/// full wheel's own continuation from the same point and direction gives
/// the same frequencies and sector amplitudes to 1e-8.
fn switch_and_compare(mut solution: Solution, class: i64, also: &[f64], at: f64) {
    let points = solution.branch.points.clone();
    let crossings = crossings(&mut solution, class, &points);
    let hz = |i: usize| points[i].omega / (2.0 * PI);
    let around =
        |i: usize, f: f64| hz(i).min(hz(i + 1)) - 0.01 <= f && hz(i).max(hz(i + 1)) + 0.01 >= f;
    let frequencies: Vec<f64> = crossings.iter().map(|&i| hz(i)).collect();
    for &f in also {
        assert!(crossings.iter().any(|&i| around(i, f)), "{frequencies:?}");
    }
    let i = crossings
        .iter()
        .copied()
        .find(|&i| around(i, at))
        .unwrap_or_else(|| panic!("none near {at} Hz: {frequencies:?}"));
    let (a, b) = (&points[i], &points[i + 1]);
    let max_points = 12;
    let settings = settings(&solution, max_points);
    let branch = switch_at(
        &solution.case,
        &solution.model,
        &mut solution.problem,
        class,
        (&a.unknowns, a.omega),
        (&b.unknowns, b.omega),
        &settings,
    )
    .unwrap();
    let point = &branch.branch_point;
    assert!(point.omega >= a.omega.min(b.omega) && point.omega <= a.omega.max(b.omega));
    assert!(point.relative_eigenvalue.abs() < 1e-10);
    let side = &branch.sides[0];
    assert_eq!(side.points.len(), max_points, "{:?}", side.stop);
    // Every point of the bifurcated branch, polished on the enlarged basis
    // to round-off, solves the full wheel, and its sectors do not move
    // alike (it is not the symmetric branch).
    let mut full = problem_on_basis(&solution.case, &solution.model, None).unwrap();
    let mut enlarged =
        problem_on_basis(&solution.case, &solution.model, Some(branch.basis.clone())).unwrap();
    let polish = NewtonSettings {
        tolerance: 1e-14,
        max_iterations: 8,
        ..Default::default()
    };
    for p in &side.points {
        let mut y = p.unknowns.clone();
        let (_, _, reduced) = correct(&mut enlarged, &mut y, p.omega, &polish).unwrap();
        assert!(reduced < 1e-11, "{reduced:e}");
        let x = physical_unknowns(&branch.problem, &y);
        let r = full_residual(&mut full, &x, p.omega);
        assert!(r < 1e-10, "{r:e} at {} Hz", p.omega / (2.0 * PI));
    }
    // Its pairs outside the symmetric basis carry a share of the response
    // that grows away from the branch point: it is not the symmetric branch.
    let share = |x: &[f64]| {
        let along: f64 = x
            .iter()
            .zip(&point.null_vector)
            .map(|(x, v)| x * v)
            .sum::<f64>()
            .abs();
        along / x.iter().map(|x| x * x).sum::<f64>().sqrt()
    };
    let shares: Vec<f64> = side.points.iter().map(|p| share(&p.unknowns)).collect();
    assert!(
        shares.windows(2).all(|w| w[1] > w[0]) && shares[0] > 1e-3,
        "{shares:?}"
    );
    // The full wheel's continuation from the same branch point along the
    // same direction: the same points.
    let on_full = BranchPoint {
        unknowns: physical_unknowns(&branch.problem, &point.unknowns),
        null_vector: {
            let v = physical_unknowns(&branch.problem, &point.null_vector);
            let w = full.norm_weights();
            let n = v.iter().zip(&w).map(|(v, w)| w * v * v).sum::<f64>().sqrt();
            v.iter().map(|v| v / n).collect()
        },
        ..point.clone()
    };
    let full_side = follow_from(&mut full, &on_full, 1.0, &settings).unwrap();
    assert_eq!(full_side.points.len(), side.points.len());
    for (p, q) in side.points.iter().zip(&full_side.points) {
        assert!(
            (p.omega - q.omega).abs() < 1e-8 * p.omega,
            "{} vs {}",
            p.omega,
            q.omega
        );
        let reduced = sector_amplitudes(&branch.problem, p, 0, 1024).unwrap();
        let physical = sector_amplitudes(&full, q, 0, 1024).unwrap();
        for (x, y) in reduced.iter().zip(&physical) {
            assert!((x - y).abs() < 1e-8 * x.abs().max(1e-6), "{x} vs {y}");
        }
    }
}

#[test]
fn a_crossing_of_sigma_and_minus_sigma_together_is_found_in_the_class_block() {
    // Hill's marker of class 3 near 211.5969 Hz: class 3 is not its own
    // conjugate, and its real crossing is σ and −σ crossing together (the
    // real block of the pairs of the cosets (±3, 0) + P has a double real
    // eigenvalue there). Measured (the blocks' eigenvalues, relative to
    // their largest entry, at the branch's points 211.596864 and
    // 211.597112 Hz): the class block's least goes from −1.75e-4 to
    // +4.95e-4, twice each; the whole new block of class 3's enlarged basis
    // (here the full wheel: classes 1 to 7) keeps +7.7e-5 at both, class
    // 1's eigenvalue, which hid the crossing from the test function when
    // it looked at every new pair (it listed no crossing there; this test
    // expected that). The class-2 crossing 1 mHz below (211.595880 to
    // 211.596154 Hz: its block's least from +3.6e-6 to −9.8e-5) is the
    // other class's and is not listed for class 3.
    let mut solution = symmetric_branch();
    let points = solution.branch.points.clone();
    let hz = |i: usize| points[i].omega / (2.0 * PI);
    let brackets = |at: f64| {
        (0..points.len() - 1)
            .filter(|&i| hz(i).min(hz(i + 1)) <= at && hz(i).max(hz(i + 1)) >= at)
            .collect::<Vec<_>>()
    };
    let three = crossings(&mut solution, 3, &points);
    let around = brackets(211.5969);
    assert!(three.iter().any(|i| around.contains(i)), "{three:?}");
    let two = brackets(211.596);
    assert!(
        !three.iter().any(|i| two.contains(i) && !around.contains(i)),
        "{three:?}"
    );
    let i = *three.iter().find(|i| around.contains(i)).unwrap();
    let (a, b) = (&points[i], &points[i + 1]);
    let settings = settings(&solution, 10);
    // The class block is singular there: located at 211.5969345 Hz (its
    // least eigenvalue 8e-14 of its largest entry; Hill's marker 211.5969
    // Hz). Its kernel is two-dimensional (σ and −σ): one vector of it is
    // followed, and the enlarged basis is the whole wheel here, so the
    // points found are the full wheel's solutions by construction.
    let branch = switch_at(
        &solution.case,
        &solution.model,
        &mut solution.problem,
        3,
        (&a.unknowns, a.omega),
        (&b.unknowns, b.omega),
        &settings,
    )
    .unwrap();
    let located = branch.branch_point.omega / (2.0 * PI);
    assert!((located - 211.5969).abs() < 1e-4, "{located}");
    assert!(branch.branch_point.relative_eigenvalue.abs() < 1e-12);
    assert_eq!(branch.unknowns, branch.full_unknowns);
    for side in &branch.sides {
        assert_eq!(side.points.len(), 10, "{}", side.stop);
        let last = side.points.last().unwrap();
        let peaks = sector_amplitudes(&branch.problem, last, 0, 64).unwrap();
        let (low, high) = peaks
            .iter()
            .fold((f64::INFINITY, 0.0_f64), |(l, h), p| (l.min(*p), h.max(*p)));
        eprintln!("side {}: sectors {low:.4e} to {high:.4e} m", side.direction);
        assert!(high > low * (1.0 + 1e-6), "{peaks:?}");
    }
}

/// The open fan (coarse mesh, Craig–Bampton per nodal diameter, 16 sectors,
/// 27 contact dofs a sector with friction, centrifugal preload) under
/// engine order 4 with the regularized law, a 20 µm gap and a short
/// balance (`N_h = 3`, `N_t = 64`): its symmetric branch (on 189 of the
/// full wheel's 3024 unknowns) meets a real crossing of class 8 near
/// 302.47 Hz, whose branch lives on 378 unknowns. Measured: located at
/// 302.472071 Hz; six points a side, the largest full-wheel residual
/// 8.9e-11 of the load; the sectors 2.118e-4 to 2.229e-4 m at 302.354 Hz.
mod fan {
    use super::*;
    use cyclorub::case::{LawKind, PerContactDof};
    use cyclorub::mesh::{assemble, fan, write_fan, FanGeometry};

    #[test]
    fn a_bifurcated_branch_of_the_fan_solves_its_full_wheel() {
        let dir = std::env::temp_dir().join(format!("cyclorub-fan-branch-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        let mesh = fan(16, 1, &FanGeometry::default()).unwrap();
        let matrices = assemble(&mesh.mesh).unwrap();
        write_fan(&mesh, &matrices, &dir, false).unwrap();
        let mut case = Case::from_file_checked(&dir.join("fan16.toml")).unwrap();
        case.excitation.engine_order = 4;
        case.contact.law = LawKind::Regularized;
        case.casing.gap = PerContactDof::One(2e-5);
        case.harmonic_balance.harmonics = 3;
        case.harmonic_balance.time_samples = 64;
        case.stability.enabled = false;
        let mut solution = ForcedResponse::from_case(&case)
            .unwrap()
            .case_dir(&dir)
            .build()
            .unwrap()
            .run(&mut [])
            .unwrap();
        let _ = std::fs::remove_dir_all(&dir);
        let points = solution.branch.points.clone();
        let crossings = crossings(&mut solution, 8, &points);
        let hz = |i: usize| points[i].omega / (2.0 * PI);
        let i = crossings
            .iter()
            .copied()
            .find(|&i| (hz(i) - 302.47).abs() < 0.1)
            .unwrap_or_else(|| {
                panic!(
                    "no crossing near 302.47 Hz: {:?}",
                    crossings.iter().map(|&i| hz(i)).collect::<Vec<_>>()
                )
            });
        let (a, b) = (&points[i], &points[i + 1]);
        let max_points = 6;
        let settings = settings(&solution, max_points);
        let branch = switch_at(
            &solution.case,
            &solution.model,
            &mut solution.problem,
            8,
            (&a.unknowns, a.omega),
            (&b.unknowns, b.omega),
            &settings,
        )
        .unwrap();
        assert_eq!((branch.unknowns, branch.full_unknowns), (378, 3024));
        let mut full = problem_on_basis(&solution.case, &solution.model, None).unwrap();
        let mut enlarged =
            problem_on_basis(&solution.case, &solution.model, Some(branch.basis.clone())).unwrap();
        let polish = NewtonSettings {
            tolerance: 1e-14,
            max_iterations: 8,
            ..Default::default()
        };
        let observed = solution.case.output.observed_index();
        let mut worst = 0.0_f64;
        for side in &branch.sides {
            assert_eq!(side.points.len(), max_points, "{:?}", side.stop);
            for p in &side.points {
                let mut y = p.unknowns.clone();
                let (_, _, reduced) = correct(&mut enlarged, &mut y, p.omega, &polish).unwrap();
                assert!(reduced < 1e-10, "{reduced:e}");
                let x = physical_unknowns(&branch.problem, &y);
                let r = full_residual(&mut full, &x, p.omega);
                assert!(r < 1e-10, "{r:e} at {} Hz", p.omega / (2.0 * PI));
                worst = worst.max(r);
            }
            // The sectors no longer move alike at the side's last point.
            let last = side.points.last().unwrap();
            let amplitudes = sector_amplitudes(&branch.problem, last, observed, 256).unwrap();
            let (low, high) = amplitudes
                .iter()
                .fold((f64::MAX, 0.0_f64), |(l, h), &a| (l.min(a), h.max(a)));
            assert!(high - low > 1e-6 * high, "{amplitudes:?}");
            println!(
                "side {}: to {:.4} Hz, sectors {low:.6e} to {high:.6e} m",
                side.direction,
                last.omega / (2.0 * PI)
            );
        }
        println!(
            "branch point {:.6} Hz; largest full-wheel residual {worst:.2e} of the load",
            branch.branch_point.omega / (2.0 * PI)
        );
    }
}

#[test]
fn the_markers_located_on_the_branch_are_where_the_enlarged_jacobian_is_singular() {
    // Hill's markers of the 8-sector branch, located on the branch by the
    // tracked exponent (forced_response::locate_markers), checked against
    // the enlarged Jacobian, which uses no exponent:
    // - class 1 (220.252 Hz): the enlarged Jacobian's regula falsi
    //   (branches::locate_branch_point) from the symmetric solutions
    //   2e-6 Hz either side of the marker finds a sign change and its zero
    //   within 1e-4 Hz, and the located real part is below the growth
    //   tolerance;
    // - classes 2 and 3 (211.596–212.703 Hz), which Hill labels branch
    //   points from |Im λ|·T < 0.05 and which the test function's inverse
    //   iteration misses (its least eigenvalue is not real at one end, or
    //   keeps its sign: σ and −σ cross together): once located, the
    //   multiplier is real (angle at round-off) and the new block is
    //   singular there (least singular value, relative, 2e-12 to 3e-8
    //   against 8e-5 to 1e-4 at the marker's points): real crossings,
    //   labelled branch points.
    use cyclorub::branches::locate_branch_point;
    use cyclorub::stability::{MarkerKind, StabilitySettings};
    let mut solution = symmetric_branch();
    let settings = StabilitySettings::default();
    let mut stability = solution
        .stability_check(&settings)
        .unwrap()
        .branch(&solution.branch.points)
        .unwrap();
    let interpolated = stability.markers.clone();
    let report = solution.locate_markers(&settings, &mut stability).unwrap();
    eprintln!("{report:?}");
    // The markers are paired with their interpolated places below: none
    // removed as not a crossing here.
    assert!(report.unmatched.is_empty(), "{report:?}");
    let points = solution.branch.points.clone();
    let (mut real, mut other) = (0, 0);
    for (m, before) in stability.markers.iter().zip(&interpolated) {
        eprintln!(
            "class {:?} {:?} → {:?}: {:.6} → {:.6} Hz, {:?}",
            m.nodal_diameter, before.kind, m.kind, before.frequency_hz, m.frequency_hz, m.located
        );
        let class = m.nodal_diameter.unwrap();
        if before.kind != MarkerKind::BranchPoint {
            continue;
        }
        let Some(location) = m.located else {
            eprintln!("not located");
            continue;
        };
        let (a, b) = (&points[m.index], &points[m.index + 1]);
        if class == 1 {
            assert_eq!(m.kind, MarkerKind::BranchPoint, "{m:?}");
            assert!(location.angle.abs() < 1e-6, "{m:?}");
            // The enlarged Jacobian's regula falsi from the symmetric
            // solutions 2e-6 Hz either side of the located marker (the fold
            // at 212.702174 Hz is 9e-6 Hz from one): its test function
            // changes sign there, its zero within 1e-4 Hz of the marker.
            let side = |f: f64, solution: &mut Solution| {
                let omega = 2.0 * PI * f;
                let t = (omega - a.omega) / (b.omega - a.omega);
                let mut x: Vec<f64> = a
                    .unknowns
                    .iter()
                    .zip(&b.unknowns)
                    .map(|(p, q)| p + t * (q - p))
                    .collect();
                let newton = NewtonSettings {
                    tolerance: 1e-12,
                    ..Default::default()
                };
                let (converged, ..) =
                    correct(&mut solution.problem, &mut x, omega, &newton).unwrap();
                assert!(converged);
                (x, omega)
            };
            let below = side(m.frequency_hz - 2e-6, &mut solution);
            let above = side(m.frequency_hz + 2e-6, &mut solution);
            let located = locate_branch_point(
                &solution.case,
                &solution.model,
                &mut solution.problem,
                1,
                (&below.0, below.1),
                (&above.0, above.1),
            )
            .unwrap();
            let hz = located.omega / (2.0 * PI);
            eprintln!(
                "class 1: marker {:.7} Hz ({} solves), enlarged Jacobian {hz:.7} Hz (|μ| {:.1e})",
                m.frequency_hz, location.solves, located.relative_eigenvalue
            );
            assert!((m.frequency_hz - hz).abs() < 1e-4, "{m:?} against {hz}");
            assert!(
                m.exponent.re.abs() <= 1e-8 * 2.0 * PI * m.frequency_hz,
                "{m:?}"
            );
            real += 1;
        } else if class == 2 || class == 3 {
            // The new block's least singular value (relative) at both ends
            // and at the located point (the branch re-solved there).
            let mut x = a.unknowns.clone();
            let omega = 2.0 * PI * m.frequency_hz;
            let t = (omega - a.omega) / (b.omega - a.omega);
            for (xi, bi) in x.iter_mut().zip(&b.unknowns) {
                *xi += t * (bi - *xi);
            }
            correct(
                &mut solution.problem,
                &mut x,
                omega,
                &NewtonSettings {
                    tolerance: 1e-12,
                    ..Default::default()
                },
            )
            .unwrap();
            let least = |x: &[f64], w: f64| least_singular_value(&solution, class, x, w);
            let ends = least(&a.unknowns, a.omega).min(least(&b.unknowns, b.omega));
            let at = least(&x, omega);
            eprintln!("  least singular value {at:.3e} at the marker, {ends:.3e} at its points");
            assert_eq!(m.kind, MarkerKind::BranchPoint, "{m:?}");
            assert!(location.angle.abs() < 1e-6, "{m:?}");
            // Located by the class's count (its followed exponent jumps),
            // the bracket is 1e-4 Hz wide but up to 1e-2 of the chord long
            // at a fold, and the point re-solved at its frequency is that
            // far from the crossing: measured 1.8e-2 of the ends' value.
            let drop = if location.by_count { 5e-2 } else { 1e-3 };
            assert!(at < drop * ends, "{at:e} against {ends:e}");
            other += 1;
        }
    }
    assert!(
        real >= 1 && other >= 2,
        "{real} of class 1, {other} of classes 2 and 3"
    );
}

/// The least singular value, relative to the largest, of the enlarged
/// Jacobian's block on the new unknowns of class `class` at the symmetric
/// point `(x, omega)`.
fn least_singular_value(solution: &Solution, class: i64, x: &[f64], omega: f64) -> f64 {
    use cyclorub::branches::EnlargedBasis;
    let enlarged = EnlargedBasis::new(solution.problem.layout(), class).unwrap();
    let mut problem = problem_on_basis(
        &solution.case,
        &solution.model,
        Some(enlarged.basis.clone()),
    )
    .unwrap();
    let new = enlarged.new_unknowns(problem.layout());
    let y = solution
        .problem
        .layout()
        .embed(x, problem.layout())
        .unwrap();
    let mut evaluation = Evaluation::default();
    problem.evaluate(&y, omega, true, &mut evaluation).unwrap();
    let m = new.len();
    let block = faer::Mat::from_fn(m, m, |r, c| evaluation.jacobian[(new[r], new[c])]);
    let values = block.singular_values().unwrap();
    let largest = values.iter().copied().fold(0.0, f64::max);
    let least = values.iter().copied().fold(f64::INFINITY, f64::min);
    least / largest
}
