//! One contact law trait for R-HBM and DLFT-HBM: what a law reads at a
//! point, formed by the residual and by the recovery of results, and the
//! derivative along the load scale that starts a branch.

use cyclorub::case::{BasisChoice, Case};
use cyclorub::continuation::{Evaluation, Problem};
use cyclorub::hbm::{HarmonicBalance, LoadHomotopy};
use cyclorub::run::prepare;
use std::f64::consts::PI;
use std::path::Path;

const STANDING: &str =
    "[model]\nsectors = 6\n[excitation]\nkind = \"standing\"\nengine_order = 1\n\
                        [casing]\norder = 2\namplitude = 5e-5\n\
                        [harmonic_balance]\nharmonics = 3\ntime_samples = 60\n";

fn problems(law: &str) -> Vec<(BasisChoice, HarmonicBalance)> {
    let text = match law {
        "dlft" => format!("{STANDING}[contact]\nlaw = \"dlft\"\nwall_stiffness = 1e8\n"),
        "dlft-rigid" => format!("{STANDING}[contact]\nlaw = \"dlft\"\n"),
        _ => STANDING.to_string(),
    };
    let case = Case::from_toml(&text, Path::new("t.toml")).expect("case");
    [
        BasisChoice::Symmetry,
        BasisChoice::Full,
        BasisChoice::Physical,
    ]
    .into_iter()
    .map(|basis| {
        let prepared = prepare(&case, Path::new("."), basis).expect("prepare");
        (basis, prepared.problem)
    })
    .collect()
}

/// A point in contact: the linear response at 210 Hz, scaled up.
fn point(problem: &mut HarmonicBalance) -> (Vec<f64>, f64) {
    let omega = 2.0 * PI * 210.0;
    let x = problem.linear_solution(omega).expect("linear");
    (x.iter().map(|v| 30.0 * v).collect(), omega * 1.01)
}

#[test]
fn the_recovery_reads_what_the_residual_reads() {
    // `law_variable` forms Z x − F block by block at any frequency (for
    // recovery in parallel); the residual forms it from the dense Z of its
    // current frequency. They agree to round-off on every basis, with and
    // without a wall, and for a law of the penetration it is x itself.
    for law in ["regularized", "dlft", "dlft-rigid"] {
        for (basis, mut problem) in problems(law) {
            let (x, omega) = point(&mut problem);
            let v = problem.law_variable(&x, omega).expect("variable");
            if law == "regularized" {
                assert_eq!(v, x);
                continue;
            }
            // The dense route: v = ε x − (Z x − F) with Z at omega.
            let samples = problem.contact_samples(&x, omega).expect("samples");
            let linear = problem.linear();
            let epsilon = problem.law().input().penetration;
            let dense: Vec<f64> = (0..x.len())
                .map(|r| {
                    let zx: f64 = (0..x.len()).map(|c| linear.dynamic[(r, c)] * x[c]).sum();
                    epsilon * x[r] - (zx - linear.load[r])
                })
                .collect();
            let scale = dense.iter().fold(0.0_f64, |m, d| m.max(d.abs()));
            let worst = v
                .iter()
                .zip(&dense)
                .fold(0.0_f64, |m, (a, b)| m.max((a - b).abs()));
            assert!(
                worst <= 1e-11 * scale,
                "{law} {basis:?}: {worst:e} of {scale:e}"
            );
            assert!(samples.multiplier.is_some(), "DLFT tells its multiplier");
        }
    }
}

#[test]
fn the_load_scale_derivative_matches_central_differences() {
    for law in ["regularized", "dlft"] {
        for (basis, mut problem) in problems(law) {
            let (x, omega) = point(&mut problem);
            let mut homotopy = LoadHomotopy::new(&mut problem, omega);
            let s = 0.7;
            let mut at = Evaluation::default();
            homotopy.evaluate(&x, s, true, &mut at).expect("evaluate");
            // The piece of that evaluation is told, as the frequency's
            // problem tells it (DLFT only: R-HBM's law is smooth).
            let told = homotopy.piece_of_last_evaluation();
            assert_eq!(told.is_some(), law == "dlft", "{law} {basis:?}");
            if law == "dlft" {
                assert_eq!(told, homotopy.piece(&x, s).expect("piece"), "{basis:?}");
            }
            // The residual is affine in s (piecewise for DLFT): a longer
            // step keeps round-off of the large contact forces small.
            let h = 1e-3;
            let (mut plus, mut minus) = (Evaluation::default(), Evaluation::default());
            homotopy
                .evaluate(&x, s + h, false, &mut plus)
                .expect("plus");
            homotopy
                .evaluate(&x, s - h, false, &mut minus)
                .expect("minus");
            let scale = at
                .derivative_omega
                .iter()
                .fold(0.0_f64, |m, d| m.max(d.abs()));
            assert!(scale > 0.0);
            let size = at.residual.iter().fold(0.0_f64, |m, r| m.max(r.abs()));
            let round_off = 1e3 * f64::EPSILON * size / h;
            for (i, d) in at.derivative_omega.iter().enumerate() {
                let fd = (plus.residual[i] - minus.residual[i]) / (2.0 * h);
                assert!(
                    (fd - d).abs() <= 1e-9 * scale + round_off,
                    "{law} {basis:?} row {i}: {d:e} against {fd:e}"
                );
            }
            // At s = 1 the homotopy is the problem itself.
            let mut full = Evaluation::default();
            homotopy.evaluate(&x, 1.0, false, &mut full).expect("s = 1");
            let mut direct = Evaluation::default();
            problem
                .evaluate(&x, omega, false, &mut direct)
                .expect("direct");
            assert_eq!(full.residual, direct.residual, "{law} {basis:?}");
        }
    }
}
