//! Branch switching on a closed-form pitchfork (issue 42): two sectors of
//! one dof, undamped, with a plain penalty contact (R-HBM at γ = 0) and
//! `N_h = 1`, driven in phase (engine order 0). Each sector moves as
//! `x_j(t) = u_j + a_j cos ωt` (the sine coordinates vanish: no damping,
//! a cosine force), and the harmonics of the contact force
//! `κ max(x − g, 0)` of such a motion are known in closed form, so the
//! symmetric branch, its pitchfork and the bifurcated branch are all
//! solved here without the tool's harmonic balance.
//!
//! Sector stiffness `k + 2k_c` and coupling `−k_c` to the next sector: on
//! two sectors the next is also the previous, so the wheel is
//! `[[k + c, −c], [−c, k + c]]` with `c = 2k_c`. The in-phase pattern sees
//! `k` and the class σ = 1 (antiphase) pattern `k + 2c`, at every harmonic.
//! Each sector's balance, `l` the other sector:
//!
//! ```text
//! (k + c) u_j − c u_l + F₀(u_j, a_j) = 0              (harmonic 0)
//! (k + c − mω²) a_j − c a_l + F₁(u_j, a_j) = f        (cos ωt)
//! ```
//!
//! The symmetric branch (`u_1 = u_2`, `a_1 = a_2`) loses its uniqueness
//! where the class-1 block, the 2×2 Jacobian of the antiphase pattern in
//! `(u, a)`, is singular: the pitchfork. Undamped, Hill's markers do not
//! place it (docs/branches.md); the same wheel lightly damped (the sine
//! coordinates then solved too, `(a, b)` rotating the force's first
//! harmonic with the motion's) checks the marker.

use crate::bifurcated::{case, settings};
use crate::common::branches::{crossings, solved, switch_between};
use cyclorub::branches::{switch_at, BranchError};
use cyclorub::forced_response::ForcedResponse;
use cyclorub::hbm::recovery::physical_unknowns;
use cyclorub::stability::{MarkerKind, StabilitySettings};
use std::f64::consts::PI;

const MASS: f64 = 1.0;
/// The in-phase pattern's stiffness `k` (N/m).
const STIFFNESS: f64 = 4e5;
/// The coupling between the two sectors, `c = 2 k_c` (N/m).
const COUPLING: f64 = 2e4;
/// Contact stiffness κ (N/m).
const CONTACT: f64 = 4e5;
const GAP: f64 = 1e-3;
const FORCE: f64 = 400.0;

/// Swept down from 160 Hz (below the contact, one solution) to 120 Hz:
/// the in-phase branch's upper sheet, whose amplitude grows toward the
/// backbone, meets the pitchfork near 122.1 Hz (`|a| = 5.3 g`).
/// `N_t = 100000` and Newton to 1e-12 of the load, so that the tool's
/// points carry the AFT's error alone (see the test).
const TWO_SECTORS: &str = r#"
[model]
kind = "matrices"
sectors = 2
mass = [[1.0]]
stiffness = [[420000.0]]
stiffness_coupling = [[-10000.0]]
[model.damping]
kind = "none"
[excitation]
engine_order = 0
amplitude = 400.0
[casing]
gap = 1e-3
[contact]
stiffness = 4e5
regularization = 0.0
[harmonic_balance]
harmonics = 1
time_samples = 100000
[continuation]
start_hz = 160.0
end_hz = 120.0
tolerance = 1e-12
"#;

/// The mean and first cosine harmonic of `κ max(p + A cos θ, 0)` (`A ≥ 0`,
/// `p = u − g` the mean penetration) and their derivatives in `p` and `A`:
/// `(F₀, F₁, ∂F₀/∂p, ∂F₀/∂A, ∂F₁/∂p, ∂F₁/∂A)`. Contact while
/// `|θ| < θ_c`, `cos θ_c = −p / A`:
/// `F₀ = κ (A sin θ_c + p θ_c) / π`,
/// `F₁ = κ (2 p sin θ_c + A (θ_c + sin θ_c cos θ_c)) / π`.
fn contact_harmonics(p: f64, amplitude: f64) -> [f64; 6] {
    let ratio = if amplitude > 0.0 {
        -p / amplitude
    } else if p > 0.0 {
        -1.0
    } else {
        1.0
    };
    if ratio >= 1.0 {
        return [0.0; 6];
    }
    let theta = ratio.max(-1.0).acos();
    let (sin, cos) = theta.sin_cos();
    let k = CONTACT / PI;
    [
        k * (amplitude * sin + p * theta),
        k * (2.0 * p * sin + amplitude * (theta + sin * cos)),
        k * theta,
        k * sin,
        2.0 * k * sin,
        k * (theta + sin * cos),
    ]
}

/// The harmonics of sector `(u, a)` for either sign of `a`: a negative `a`
/// is `|a|` half a period later, its mean force the same, its first
/// harmonic of opposite sign. `(F₀, F₁, ∂F₀/∂u, ∂F₀/∂a, ∂F₁/∂u, ∂F₁/∂a)`.
fn sector_force(u: f64, a: f64) -> [f64; 6] {
    let s = if a < 0.0 { -1.0 } else { 1.0 };
    let [f0, f1, f0p, f0a, f1p, f1a] = contact_harmonics(u - GAP, a.abs());
    [f0, s * f1, f0p, s * f0a, s * f1p, f1a]
}

/// Both sectors' residuals (harmonic 0, cosine) at `y = [u_1, a_1, u_2,
/// a_2]` and `ω`, and their Jacobian.
fn wheel_residual(y: &[f64; 4], omega: f64) -> ([f64; 4], [[f64; 4]; 4]) {
    let (k, c) = (STIFFNESS, COUPLING);
    let dynamic = k + c - MASS * omega * omega;
    let mut r = [0.0; 4];
    let mut jacobian = [[0.0; 4]; 4];
    for j in 0..2 {
        let l = 1 - j;
        let (u, a) = (y[2 * j], y[2 * j + 1]);
        let [f0, f1, f0u, f0a, f1u, f1a] = sector_force(u, a);
        r[2 * j] = (k + c) * u - c * y[2 * l] + f0;
        r[2 * j + 1] = dynamic * a - c * y[2 * l + 1] + f1 - FORCE;
        jacobian[2 * j][2 * j] = k + c + f0u;
        jacobian[2 * j][2 * j + 1] = f0a;
        jacobian[2 * j][2 * l] = -c;
        jacobian[2 * j + 1][2 * j] = f1u;
        jacobian[2 * j + 1][2 * j + 1] = dynamic + f1a;
        jacobian[2 * j + 1][2 * l + 1] = -c;
    }
    (r, jacobian)
}

/// The wheel's solution at `ω` nearest `start`, by Newton on the closed
/// form to round-off.
fn wheel_solution(start: [f64; 4], omega: f64) -> [f64; 4] {
    let mut y = start;
    for _ in 0..50 {
        let (r, jacobian) = wheel_residual(&y, omega);
        let step = solve(
            jacobian.iter().map(|row| row.to_vec()).collect(),
            r.to_vec(),
        );
        for (y, s) in y.iter_mut().zip(&step) {
            *y -= s;
        }
        // Round-off: a step of 1e-13 of the gap (the amplitudes are
        // 0.5–10 gaps); the residual then at ~1e-13 of the load.
        if step.iter().map(|s| s.abs()).fold(0.0, f64::max) < 1e-13 * GAP {
            let (r, _) = wheel_residual(&y, omega);
            assert!(r.iter().all(|r| r.abs() < 1e-11 * FORCE), "{r:?}");
            return y;
        }
    }
    panic!("no convergence at {} Hz from {start:?}", omega / (2.0 * PI));
}

/// The bifurcated branch's point of antisymmetric amplitude
/// `d = a_1 − a_2` nearest `start` (`[u_1, a_1, u_2, a_2]` and `ω`), by
/// Newton on the closed form in `(u_1, u_2, a_1 + a_2, ω)` to round-off:
/// `d`, not `ω`, parametrizes the branch well at the pitchfork, where it
/// leaves the symmetric one at a right angle to the frequency axis.
fn bifurcated_solution(start: [f64; 4], omega: f64) -> ([f64; 4], f64) {
    let split = start[1] - start[3];
    let (mut y, mut omega) = (start, omega);
    for _ in 0..50 {
        let (r, jacobian) = wheel_residual(&y, omega);
        // Columns: u_1, u_2, s = a_1 + a_2 (a_1 = (s + d)/2, a_2 = (s − d)/2), ω.
        let mut reduced = [[0.0; 4]; 4];
        for (row, out) in reduced.iter_mut().enumerate() {
            out[0] = jacobian[row][0];
            out[1] = jacobian[row][2];
            out[2] = 0.5 * (jacobian[row][1] + jacobian[row][3]);
        }
        reduced[1][3] = -2.0 * MASS * omega * y[1];
        reduced[3][3] = -2.0 * MASS * omega * y[3];
        let step = solve(reduced.iter().map(|row| row.to_vec()).collect(), r.to_vec());
        let sum = y[1] + y[3] - step[2];
        y = [
            y[0] - step[0],
            0.5 * (sum + split),
            y[2] - step[1],
            0.5 * (sum - split),
        ];
        omega -= step[3];
        if step[..3].iter().map(|s| s.abs()).fold(0.0, f64::max) < 1e-13 * GAP
            && step[3].abs() < 1e-14 * omega
        {
            let (r, _) = wheel_residual(&y, omega);
            assert!(r.iter().all(|r| r.abs() < 1e-11 * FORCE), "{r:?}");
            return (y, omega);
        }
    }
    panic!("no convergence from {start:?}, d = {split:e}");
}

/// The root of `f` in `[lo, hi]` (a sign change) by bisection to round-off.
fn bisect(f: impl Fn(f64) -> f64, mut lo: f64, mut hi: f64) -> f64 {
    let below = f(lo) < 0.0;
    assert_ne!(below, f(hi) < 0.0, "no sign change in [{lo}, {hi}]");
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if (f(mid) < 0.0) == below {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    0.5 * (lo + hi)
}

/// The symmetric branch at cosine amplitude `a < 0` (the upper sheet,
/// in antiphase with the force): the mean `u` (harmonic 0, `k u + F₀ = 0`,
/// increasing in `u`) and `ω`; and the class-1 block's determinant there.
fn symmetric_at(a: f64) -> (f64, f64, f64) {
    let u = bisect(|u| STIFFNESS * u + sector_force(u, a)[0], -1.0, 0.0);
    let [_, f1, f0u, f0a, f1u, f1a] = sector_force(u, a);
    // (k − mω²) a + F₁ = f.
    let omega = ((STIFFNESS + (f1 - FORCE) / a) / MASS).sqrt();
    let antiphase = STIFFNESS + 2.0 * COUPLING;
    let determinant = (antiphase + f0u) * (antiphase - MASS * omega * omega + f1a) - f0a * f1u;
    (u, omega, determinant)
}

/// The tool's coordinates of a sector are `[a₀, Re X₁, Im X₁]` for
/// `x = a₀ + 2 Re(X₁ e^{iωt})`: `(u, a, the sine amplitude)`.
fn sector_motion(coordinates: &[f64]) -> (f64, f64, f64) {
    (coordinates[0], 2.0 * coordinates[1], -2.0 * coordinates[2])
}

/// Run, locate and switch on the two-sector wheel, each checked against
/// the closed form. What remains is the AFT's sampling of a force with a
/// kink (the instants of contact fall between samples). Measured at
/// `N_t = 20000` and `100000`: the symmetric branch's amplitudes to 5.9e-9
/// and 2.4e-10 (the force's error, `∝ 1/N_t²`); the located branch point
/// 4.2e-5 and 1.8e-5 Hz below the analytic pitchfork at 122.077354 Hz (the
/// Jacobian samples the contact's on/off indicator: an error `∝ 1/N_t`);
/// the bifurcated branch's points to 8.5e-8 and 2.0e-8 in the sectors'
/// mean and amplitude, 3.1e-9 and 6.5e-10 in frequency (largest at the
/// points nearest the pitchfork, where the branch is steep). 1.1 s in
/// debug.
///
/// A mutation the test catches: an enlarged basis without the pair of
/// class 1 is the symmetric basis; its "bifurcated" points keep `a_1 =
/// a_2`, and the split asserted below (the sectors' amplitudes 3.3 to 1
/// at the last point) fails, as does the basis size.
#[test]
fn the_bifurcated_branch_of_a_two_sector_pitchfork_is_the_closed_forms() {
    let mut solution = solved(&case(TWO_SECTORS));
    let points = solution.branch.points.clone();
    // The symmetric branch is the closed form's.
    for p in &points {
        let x = physical_unknowns(&solution.problem, &p.unknowns);
        assert_eq!(&x[..3], &x[3..], "the sectors move alike");
        let (u, a, sine) = sector_motion(&x[..3]);
        assert!(sine.abs() < 1e-15, "{sine:e}");
        let reference = wheel_solution([u, a, u, a], p.omega);
        assert!(
            (u - reference[0]).abs() < 1e-8 * GAP,
            "{u} vs {reference:?}"
        );
        assert!(
            (a - reference[1]).abs() < 1e-8 * a.abs(),
            "{a} vs {reference:?}"
        );
    }
    // The pitchfork: the class-1 block singular, on the sheet where |a|
    // grows from 4.5 to 6 gaps (5.25 gaps, at 122.077354 Hz).
    let amplitude = bisect(|a| symmetric_at(a).2, -4.5 * GAP, -6.0 * GAP);
    let (_, pitchfork, _) = symmetric_at(amplitude);
    let pitchfork_hz = pitchfork / (2.0 * PI);
    // The enlarged Jacobian's sign change of class 1 between the two
    // points that bracket the pitchfork. Its test function, the block's
    // eigenvalue of least modulus, also changes sign with no zero between,
    // where it passes from one of the block's eigenvalues to another of
    // the other sign: near 143 Hz (the harmonic-0 entry `k + 2c` against
    // the cosine and sine ones `k + 2c − mω²`) and near 120.2 Hz (the
    // cosine entry growing past the pitchfork against the sine one
    // `2c − f/|a|`, which vanishes at `|a| = f/2c`, 119.92 Hz, past the
    // range). `real_crossings` lists those brackets too (its eigenvector
    // turns there from one coordinate to another: alignment 8.5e-2 and
    // 2e-8 between the two points, against 0.27 to 1 at the real crossings
    // of the 8-sector wheel, too close to filter on), and `switch_at`
    // refuses them: located afresh, the least eigenvalue keeps its sign.
    let crossings = crossings(&mut solution, 1, &points);
    assert_eq!(crossings.len(), 3, "{crossings:?}");
    let hz = |i: usize| points[i].omega / (2.0 * PI);
    let i = crossings
        .iter()
        .copied()
        .find(|&i| hz(i).min(hz(i + 1)) <= pitchfork_hz && hz(i).max(hz(i + 1)) >= pitchfork_hz)
        .unwrap_or_else(|| panic!("none around {pitchfork_hz} Hz: {crossings:?}"));
    let max_points = 20;
    let settings = settings(&solution, max_points);
    for &j in crossings.iter().filter(|&&j| j != i) {
        let refused = switch_between(&mut solution, 1, &points, j, &settings);
        assert!(
            matches!(refused, Err(BranchError::NoSignChange { .. })),
            "at {} Hz: {:?}",
            hz(j),
            refused.err()
        );
    }
    let branch = switch_between(&mut solution, 1, &points, i, &settings).unwrap();
    let located_hz = branch.branch_point.omega / (2.0 * PI);
    assert!(
        (located_hz - pitchfork_hz).abs() < 1e-4,
        "located at {located_hz} Hz, the pitchfork at {pitchfork_hz} Hz"
    );
    // Classes 0 and 1 are every class of two sectors: the enlarged basis
    // is the whole wheel's 2 sectors × 3 coordinates, twice the symmetric.
    assert_eq!(solution.problem.layout().unknowns, 3);
    assert_eq!((branch.unknowns, branch.full_unknowns), (6, 6));
    let mut last_split = Vec::new();
    for side in &branch.sides {
        assert_eq!(side.points.len(), max_points, "{:?}", side.stop);
        let mut split: f64 = 0.0;
        for p in &side.points {
            let x = physical_unknowns(&branch.problem, &p.unknowns);
            let (u1, a1, s1) = sector_motion(&x[..3]);
            let (u2, a2, s2) = sector_motion(&x[3..]);
            assert!(s1.abs().max(s2.abs()) < 1e-15, "{s1:e} {s2:e}");
            let (reference, omega) = bifurcated_solution([u1, a1, u2, a2], p.omega);
            let at = format!(
                "{} Hz: {:?} vs {reference:?}",
                p.omega / (2.0 * PI),
                [u1, a1, u2, a2]
            );
            assert!((p.omega - omega).abs() < 2e-9 * omega, "{omega} at {at}");
            for (value, exact) in [u1, u2].iter().zip([reference[0], reference[2]]) {
                assert!((value - exact).abs() < 5e-8 * GAP, "{at}");
            }
            for (value, exact) in [a1, a2].iter().zip([reference[1], reference[3]]) {
                assert!((value - exact).abs() < 5e-8 * exact.abs(), "{at}");
            }
            // The sectors part further at every point.
            assert!((a1 - a2).abs() > split, "{at}");
            split = (a1 - a2).abs();
        }
        last_split.push(side.points.last().map(|p| {
            let x = physical_unknowns(&branch.problem, &p.unknowns);
            (p.omega, 2.0 * x[1], 2.0 * x[4])
        }));
    }
    // The two sides are one branch's two halves: the sectors swapped.
    let (Some((w1, a1, a2)), Some((w2, b1, b2))) = (last_split[0], last_split[1]) else {
        panic!("empty sides");
    };
    assert!((w1 - w2).abs() < 1e-9 * w1);
    assert!((a1 - b2).abs() < 1e-9 * a1.abs() && (a2 - b1).abs() < 1e-9 * a2.abs());
    let ratio = a1.abs().max(a2.abs()) / a1.abs().min(a2.abs());
    assert!(ratio > 3.0, "{ratio}");
}

/// `A x = b` by Gaussian elimination with partial pivoting.
fn solve(mut a: Vec<Vec<f64>>, mut b: Vec<f64>) -> Vec<f64> {
    let n = b.len();
    for col in 0..n {
        let pivot = (col..n)
            .max_by(|&i, &j| a[i][col].abs().total_cmp(&a[j][col].abs()))
            .unwrap();
        a.swap(col, pivot);
        b.swap(col, pivot);
        let pivot_row = a[col].clone();
        for row in col + 1..n {
            let factor = a[row][col] / pivot_row[col];
            for (entry, above) in a[row].iter_mut().zip(&pivot_row).skip(col) {
                *entry -= factor * above;
            }
            b[row] -= factor * b[col];
        }
    }
    let mut x = vec![0.0; n];
    for row in (0..n).rev() {
        let sum: f64 = (row + 1..n).map(|k| a[row][k] * x[k]).sum();
        x[row] = (b[row] - sum) / a[row][row];
    }
    x
}

mod damped;
mod time;
