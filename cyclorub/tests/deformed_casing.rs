//! The paper's N = 24 deformed-casing case (traveling wave h = 6, casing
//! h_c = 8, Sec. 4.3.3, Fig. 11) with R-HBM at its settings (N_h = 10,
//! N_t = 10008): the branch folds twenty times between 211 and 220 Hz, two
//! of the folds nearly coincide near 218.6 Hz (sheets 1e-5 gaps apart), and
//! the continuation must reach the end of the range. A jump onto another
//! sheet shows as different turning points for a different largest step,
//! so the same branch is followed with two and compared fold by fold.

use cyclorub::case::{BasisChoice, Case};
use cyclorub::continuation::{continue_branch, ArcLengthSettings, NewtonSettings, StopReason};
use cyclorub::forced_response::length_scale;
use cyclorub::run::prepare;
use std::f64::consts::PI;
use std::path::Path;

/// Turning points (frequency, Hz) of the branch followed with `max_step`.
fn turning_points(max_step: f64) -> Vec<f64> {
    let path =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../examples/n24-mixed-h6-casing-h8.toml");
    let mut case = Case::from_file(&path).expect("the example case reads");
    case.harmonic_balance.time_samples = 10_008;
    let prepared = prepare(&case, path.parent().unwrap(), BasisChoice::Symmetry).unwrap();
    let mut problem = prepared.problem;
    let k = &prepared.case.continuation;
    let start = 2.0 * PI * k.start_hz.unwrap();
    let guess = problem.linear_solution(start).unwrap();
    let settings = ArcLengthSettings {
        start,
        end: 2.0 * PI * k.end_hz.unwrap(),
        initial_step: k.initial_step,
        min_step: k.min_step,
        max_step,
        length_scale: length_scale(problem.casing(), &guess).unwrap(),
        newton: NewtonSettings {
            tolerance: k.tolerance,
            max_iterations: k.max_iterations,
            ..Default::default()
        },
        max_points: k.max_points,
    };
    let branch = continue_branch(&mut problem, guess, &settings, |_, _| {});
    assert_eq!(
        branch.stop,
        StopReason::EndReached,
        "largest step {max_step}"
    );
    assert!(branch
        .points
        .iter()
        .all(|p| p.converged && p.residual_norm <= k.tolerance));
    branch
        .points
        .windows(3)
        .filter(|w| (w[1].omega - w[0].omega) * (w[2].omega - w[1].omega) < 0.0)
        .map(|w| w[1].omega / (2.0 * PI))
        .collect()
}

#[test]
fn the_regularized_branch_runs_through_its_folds_to_the_end_whatever_the_step() {
    let coarse = turning_points(0.1);
    let fine = turning_points(0.03);
    eprintln!("turning points (Hz): {coarse:.3?}");
    assert!(coarse.len() >= 10, "{coarse:?}");
    assert_eq!(coarse.len(), fine.len(), "{coarse:?}\n{fine:?}");
    for (a, b) in coarse.iter().zip(&fine) {
        // Points sample a fold to within the local step: 0.01 Hz of 30.
        assert!((a - b).abs() < 1e-2, "{coarse:?}\n{fine:?}");
    }
}
