//! Continuation gives bit for bit the branches it gave before its driver
//! was split into parts (issue 16): on each closed-form branch of the other
//! `continuation_*` tests, and on a few more that reach the policies for
//! nonsmooth residuals, the number of points, the iterations spent
//! (failed attempts included, so the same steps were tried), the stop and
//! a hash of the bits of every point are those recorded on `main` before.
//!
//! Run with `CYCLORUB_RECORD=1` to print the fingerprints instead of
//! checking them (after a deliberate change of behaviour).

use crate::common;

use common::scalar_branch::{
    s_curve, s_curve_root as root, settings, zigzag, zigzag_frequency, zigzag_piece, Faulty,
    ScalarBranch,
};
use cyclorub::continuation::{continue_branch, continue_from_both_ends, ArcLengthSettings, Branch};
use std::cell::Cell;
use std::f64::consts::PI;
use std::rc::Rc;

/// What must not change: points, iterations, stop, and the FNV-1a hash of
/// the bits of every frequency, unknown and iteration count.
fn fingerprint(branch: &Branch) -> String {
    let mut hash = 0xcbf2_9ce4_8422_2325_u64;
    let mut add = |bits: u64| {
        for byte in bits.to_le_bytes() {
            hash = (hash ^ u64::from(byte)).wrapping_mul(0x0100_0000_01b3);
        }
    };
    for p in &branch.points {
        add(p.omega.to_bits());
        p.unknowns.iter().for_each(|v| add(v.to_bits()));
        add(p.iterations as u64);
        add(p.residual_norm.to_bits());
    }
    format!(
        "{} points, {} iterations, last ω {:?}, stop {:?}, sweeps {:?}, hash {hash:016x}",
        branch.points.len(),
        branch.total_iterations,
        branch.points.last().map(|p| p.omega),
        branch.stop,
        branch.sweeps,
    )
}

fn check(cases: Vec<(String, Branch)>, expected: &[&str]) {
    let record = std::env::var_os("CYCLORUB_RECORD").is_some();
    let got: Vec<String> = cases
        .iter()
        .map(|(name, branch)| format!("{name}: {}", fingerprint(branch)))
        .collect();
    if record {
        for line in &got {
            println!("        {line:?},");
        }
        return;
    }
    assert_eq!(got.len(), expected.len());
    for (got, expected) in got.iter().zip(expected) {
        assert_eq!(got, expected);
    }
}

fn run(mut problem: ScalarBranch, start_x: f64, settings: &ArcLengthSettings) -> Branch {
    continue_branch(&mut problem, vec![start_x], settings, |_, _| {})
}

fn hyperbola(gap: f64) -> impl Fn(f64, f64) -> (f64, f64, f64) {
    move |x: f64, omega: f64| {
        let lambda = omega - 2.0;
        (x * x - lambda * lambda - gap, 2.0 * x, -2.0 * lambda)
    }
}

fn hairpin(width: f64) -> impl Fn(f64, f64) -> (f64, f64, f64) {
    move |x: f64, omega: f64| {
        let u = x / width;
        let slope = 1.0 - 2.0 * u / width / (1.0 + u * u).powi(2);
        (omega - (2.0 + x + 1.0 / (1.0 + u * u)), -slope, 1.0)
    }
}

fn circle(x: f64, omega: f64) -> (f64, f64, f64) {
    (
        x * x + (omega - 2.0).powi(2) - 1.0,
        2.0 * x,
        2.0 * (omega - 2.0),
    )
}

const SNAKE_PERIOD: f64 = 0.02;

fn snake_frequency(x: f64) -> f64 {
    0.15 * (2.0 * PI * x / SNAKE_PERIOD).sin() - 4.0 * x
}

fn snake(x: f64, omega: f64) -> (f64, f64, f64) {
    let slope = 0.15 * 2.0 * PI / SNAKE_PERIOD * (2.0 * PI * x / SNAKE_PERIOD).cos() - 4.0;
    (omega - snake_frequency(x), -slope, 1.0)
}

/// A nonsmooth fold told by no pieces: `ω = 2 + x` for `x < 0`, then
/// `ω = 2 − x/2`: the branch turns back at the corner.
fn vee(x: f64, omega: f64) -> (f64, f64, f64) {
    if x < 0.0 {
        (omega - 2.0 - x, -1.0, 1.0)
    } else {
        (omega - 2.0 + 0.5 * x, 0.5, 1.0)
    }
}

#[test]
fn scalar_branches_are_unchanged() {
    let mut cases = Vec::new();
    for gap in [1e-4, 1e-8, 0.0] {
        for max_step in [0.05, 0.2] {
            let settings = ArcLengthSettings {
                max_step,
                ..settings(1.0, 3.0)
            };
            let branch = run(
                ScalarBranch::smooth(hyperbola(gap)),
                (1.0 + gap).sqrt(),
                &settings,
            );
            cases.push((format!("hyperbola {gap} {max_step}"), branch));
        }
    }
    for width in [1e-2, 1e-4] {
        let start = -1.0;
        let settings = ArcLengthSettings {
            min_step: 1e-9,
            max_step: 10.0 * width,
            ..settings(2.0 + start + 1.0 / (1.0 + (start / width).powi(2)), 3.5)
        };
        cases.push((
            format!("hairpin {width}"),
            run(ScalarBranch::smooth(hairpin(width)), start, &settings),
        ));
    }
    let circle_settings = ArcLengthSettings {
        min_step: 1e-9,
        ..settings(1.5, 10.0)
    };
    cases.push((
        "circle nonsmooth".into(),
        run(ScalarBranch::new(circle), 0.75_f64.sqrt(), &circle_settings),
    ));
    cases.push((
        "circle smooth".into(),
        run(
            ScalarBranch::smooth(circle),
            0.75_f64.sqrt(),
            &circle_settings,
        ),
    ));
    let s_settings = settings(1.0, 3.0);
    let x = root(-1.0);
    cases.push((
        "s-curve smooth".into(),
        run(ScalarBranch::smooth(s_curve), x, &s_settings),
    ));
    cases.push((
        "s-curve nonsmooth".into(),
        run(ScalarBranch::new(s_curve), x, &s_settings),
    ));
    let start_x = 0.3 * SNAKE_PERIOD;
    let end_x = start_x + 20.0 * SNAKE_PERIOD;
    let snake_settings = |max_step| ArcLengthSettings {
        max_step,
        ..settings(snake_frequency(start_x), snake_frequency(end_x))
    };
    cases.push((
        "snake smooth".into(),
        run(ScalarBranch::smooth(snake), start_x, &snake_settings(0.05)),
    ));
    cases.push((
        "snake piecewise".into(),
        run(
            ScalarBranch::piecewise(snake, |x| (x / 1e-3).floor() as i64 as u64),
            start_x,
            &snake_settings(0.03),
        ),
    ));
    cases.push((
        "snake nonsmooth".into(),
        run(ScalarBranch::new(snake), start_x, &snake_settings(0.05)),
    ));
    let zigzag_settings = ArcLengthSettings {
        max_step: 0.03,
        ..settings(zigzag_frequency(-0.5), zigzag_frequency(3.0))
    };
    cases.push((
        "zigzag piecewise".into(),
        run(
            ScalarBranch::piecewise(zigzag, zigzag_piece),
            -0.5,
            &zigzag_settings,
        ),
    ));
    cases.push((
        "zigzag nonsmooth".into(),
        run(ScalarBranch::new(zigzag), -0.5, &zigzag_settings),
    ));
    cases.push((
        "vee nonsmooth".into(),
        run(ScalarBranch::new(vee), -1.0, &settings(1.0, 3.0)),
    ));
    cases.push((
        "vee piecewise".into(),
        run(
            ScalarBranch::piecewise(vee, |x| u64::from(x >= 0.0)),
            -1.0,
            &settings(1.0, 3.0),
        ),
    ));
    check(cases, EXPECTED_SCALAR);
}

#[test]
fn both_ends_branches_are_unchanged() {
    let mut cases = Vec::new();
    for (band, transient) in [
        ((0.1, 0.2), true),
        ((0.1, 0.2), false),
        ((-2.0, -1.0), true),
        ((-2.0, -1.0), false),
    ] {
        let active = Rc::new(Cell::new(true));
        let mut problem = Faulty {
            curve: ScalarBranch::smooth(s_curve),
            band,
            active: active.clone(),
        };
        let mut seen = 0;
        let branch = continue_from_both_ends(
            &mut problem,
            vec![root(-1.0)],
            vec![root(1.0)],
            &settings(1.0, 3.0),
            |point, progress| {
                seen += 1;
                assert_eq!(progress.points, seen);
                if transient && point.omega == 3.0 {
                    active.set(false);
                }
            },
        );
        cases.push((format!("both ends {band:?} {transient}"), branch));
    }
    check(cases, EXPECTED_BOTH_ENDS);
}

const EXPECTED_SCALAR: &[&str] = &[
        "hyperbola 0.0001 0.05: 71 points, 150 iterations, last ω Some(3.0), stop EndReached, sweeps None, hash bb89535c8991d3a4",
        "hyperbola 0.0001 0.2: 41 points, 132 iterations, last ω Some(3.0), stop EndReached, sweeps None, hash 086e78bd28bf7b48",
        "hyperbola 0.00000001 0.05: 87 points, 171 iterations, last ω Some(3.0), stop EndReached, sweeps None, hash 52fe78cb356d5cf1",
        "hyperbola 0.00000001 0.2: 57 points, 198 iterations, last ω Some(3.0), stop EndReached, sweeps None, hash f15f07fd1f20fb55",
        "hyperbola 0 0.05: 49 points, 0 iterations, last ω Some(3.0), stop EndReached, sweeps None, hash 413c5657e47e7492",
        "hyperbola 0 0.2: 18 points, 0 iterations, last ω Some(3.0), stop EndReached, sweeps None, hash 85385db4221ec29b",
        "hairpin 0.01: 97 points, 308 iterations, last ω Some(3.5), stop EndReached, sweeps None, hash 7472b1d9ba11834f",
        "hairpin 0.0001: 3546 points, 2863 iterations, last ω Some(3.5), stop EndReached, sweeps None, hash e63484f084e858d8",
        "circle nonsmooth: 58 points, 178 iterations, last ω Some(1.4922255176129482), stop LeftRange { frequency_hz: 0.23749506733596285 }, sweeps None, hash 550fc5e1c05dbbaa",
        "circle smooth: 86 points, 276 iterations, last ω Some(1.4710684984089901), stop LeftRange { frequency_hz: 0.23412782314856276 }, sweeps None, hash 87bc1b36fb1d65fa",
        "s-curve smooth: 60 points, 120 iterations, last ω Some(3.0), stop EndReached, sweeps None, hash cb564ffd746f383a",
        "s-curve nonsmooth: 60 points, 120 iterations, last ω Some(3.0), stop EndReached, sweeps None, hash 1f4704b4b17eb3b5",
        "snake smooth: 1193 points, 4652 iterations, last ω Some(-1.4813415225557274), stop EndReached, sweeps None, hash 9da27d0e7aaa7739",
        "snake piecewise: 1225 points, 4939 iterations, last ω Some(-1.4813415225557274), stop EndReached, sweeps None, hash edb6c0b6498c8382",
        "snake nonsmooth: 35 points, 814 iterations, last ω Some(-0.29051550842027524), stop StepUnderflow { frequency_hz: -0.04623697920994195, step: 7.275957614183426e-13 }, sweeps None, hash 5f10d073ba9a4025",
        "zigzag piecewise: 129 points, 17 iterations, last ω Some(4.9234835), stop EndReached, sweeps None, hash 4b27c07e39a49124",
        "zigzag nonsmooth: 124 points, 5 iterations, last ω Some(4.9234835), stop EndReached, sweeps None, hash 9ea64b861fa61b7f",
        "vee nonsmooth: 67 points, 1 iterations, last ω Some(0.9971605374805668), stop LeftRange { frequency_hz: 0.1587030285962034 }, sweeps None, hash d80beee79ebe85d7",
        "vee piecewise: 112 points, 7 iterations, last ω Some(0.9954477579340653), stop LeftRange { frequency_hz: 0.15843043126495096 }, sweeps None, hash bdefa722cffb77eb",
];

const EXPECTED_BOTH_ENDS: &[&str] = &[
        "both ends (0.1, 0.2) true: 63 points, 133 iterations, last ω Some(3.0), stop EndReached, sweeps Some(Sweeps { from_start: StepUnderflow { frequency_hz: 0.31051129397221067, step: 7.275957614183426e-13 }, from_start_points: 56, from_start_kept: 31, from_end: MetOtherSweep { frequency_hz: 0.31980149799762747, point: 30 }, from_end_points: 32 }), hash 2614027ac311a377",
        "both ends (0.1, 0.2) false: 96 points, 128 iterations, last ω Some(3.0), stop StepUnderflow { frequency_hz: 0.31051129397221067, step: 7.275957614183426e-13 }, sweeps Some(Sweeps { from_start: StepUnderflow { frequency_hz: 0.31051129397221067, step: 7.275957614183426e-13 }, from_start_points: 56, from_start_kept: 56, from_end: StepUnderflow { frequency_hz: 0.30366763141926556, step: 7.275957614183426e-13 }, from_end_points: 40 }), hash a9e7afb4ccd40189",
        "both ends (-2.0, -1.0) true: 60 points, 120 iterations, last ω Some(3.0), stop EndReached, sweeps Some(Sweeps { from_start: EvaluationError { frequency_hz: 0.15915494309189535, message: \"fault at x = -1.1653730430624147\" }, from_start_points: 0, from_start_kept: 0, from_end: EndReached, from_end_points: 60 }), hash d8d74112a6429f06",
        "both ends (-2.0, -1.0) false: 68 points, 117 iterations, last ω Some(3.0), stop EvaluationError { frequency_hz: 0.15915494309189535, message: \"fault at x = -1.1653730430624147\" }, sweeps Some(Sweeps { from_start: EvaluationError { frequency_hz: 0.15915494309189535, message: \"fault at x = -1.1653730430624147\" }, from_start_points: 0, from_start_kept: 0, from_end: StepUnderflow { frequency_hz: 0.23873241463818273, step: 7.275957614183426e-13 }, from_end_points: 68 }), hash 6c5dc02fdf79ae34",
];
