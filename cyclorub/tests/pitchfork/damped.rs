//! The same two-sector pitchfork lightly damped (see the parent module):
//! Hill's branch-point marker of class 1 and the bifurcated branch against
//! the closed form with the sine coordinates.

use super::*;

/// Light damping `C = α M` (`ζ ≈ 1e-3` at 100 Hz): the stable side's
/// exponents leave the imaginary axis, and Hill's branch-point marker can
/// be checked against the pitchfork. The sine coordinates no longer
/// vanish: the closed form reads `x = u + a cos ωt + b sin ωt`.
const DAMPING: f64 = 1.26;

/// Both sectors' residuals (harmonic 0, cosine, sine) at `y = [u_1, a_1,
/// b_1, u_2, a_2, b_2]` and `ω` with damping `α M`: the contact's first
/// harmonic lies along the motion's, `F₁ (a, b) / R`, `R = |(a, b)|`.
fn damped_residual(y: &[f64], omega: f64) -> Vec<f64> {
    let (k, c) = (STIFFNESS, COUPLING);
    let dynamic = k + c - MASS * omega * omega;
    let damping = DAMPING * MASS * omega;
    let mut r = vec![0.0; 6];
    for j in 0..2 {
        let l = 1 - j;
        let (u, a, b) = (y[3 * j], y[3 * j + 1], y[3 * j + 2]);
        let amplitude = a.hypot(b);
        let [f0, f1, ..] = contact_harmonics(u - GAP, amplitude);
        let along = if amplitude > 0.0 { f1 / amplitude } else { 0.0 };
        r[3 * j] = (k + c) * u - c * y[3 * l] + f0;
        r[3 * j + 1] = dynamic * a - c * y[3 * l + 1] + damping * b + along * a - FORCE;
        r[3 * j + 2] = dynamic * b - c * y[3 * l + 2] - damping * a + along * b;
    }
    r
}

/// The Jacobian of `f` at `z` by central differences of steps `h`.
fn differences(f: &impl Fn(&[f64]) -> Vec<f64>, z: &[f64], h: &[f64]) -> Vec<Vec<f64>> {
    let n = f(z).len();
    let mut jacobian = vec![vec![0.0; z.len()]; n];
    for (i, h) in h.iter().enumerate() {
        let (mut plus, mut minus) = (z.to_vec(), z.to_vec());
        plus[i] += h;
        minus[i] -= h;
        let (fp, fm) = (f(&plus), f(&minus));
        for (row, (p, m)) in jacobian.iter_mut().zip(fp.iter().zip(&fm)) {
            row[i] = (p - m) / (2.0 * h);
        }
    }
    jacobian
}

/// The root of `f` nearest `z` by Newton (the Jacobian by differences of
/// steps `h`; the residual is exact, so the root is the closed form's to
/// round-off): to 1e-12 of the load, then two more steps.
fn newton(f: impl Fn(&[f64]) -> Vec<f64>, mut z: Vec<f64>, h: &[f64]) -> Vec<f64> {
    let mut polish = 0;
    for _ in 0..60 {
        let r = f(&z);
        if r.iter().all(|r| r.abs() < 1e-12 * FORCE) {
            polish += 1;
            if polish > 2 {
                return z;
            }
        }
        let step = solve(differences(&f, &z, h), r);
        for (z, s) in z.iter_mut().zip(step) {
            *z -= s;
        }
    }
    panic!("no convergence from {z:?}: {:?}", f(&z));
}

/// The damped symmetric solution `(u, a, b)` at `ω` nearest `start`, and
/// the determinant of its class-1 (antiphase) block.
fn damped_symmetric(start: &[f64], omega: f64) -> (Vec<f64>, f64) {
    let h = [1e-9, 1e-9, 1e-9];
    let both = |y: &[f64]| [y, y].concat();
    let y = newton(
        |y| damped_residual(&both(y), omega)[..3].to_vec(),
        start.to_vec(),
        &h,
    );
    // The antiphase perturbation (v, −v): the block in sector 1's rows.
    let antiphase = |v: &[f64]| {
        let z: Vec<f64> = (0..3)
            .map(|i| y[i] + v[i])
            .chain((0..3).map(|i| y[i] - v[i]))
            .collect();
        damped_residual(&z, omega)[..3].to_vec()
    };
    let block = differences(&antiphase, &[0.0; 3], &h);
    let determinant = block[0][0] * (block[1][1] * block[2][2] - block[1][2] * block[2][1])
        - block[0][1] * (block[1][0] * block[2][2] - block[1][2] * block[2][0])
        + block[0][2] * (block[1][0] * block[2][1] - block[1][1] * block[2][0]);
    (y, determinant)
}

/// Both sectors' `[u, a, b]` at the tool's point `p` of `problem`.
fn motion(problem: &cyclorub::hbm::HarmonicBalance, p: &cyclorub::continuation::Point) -> Vec<f64> {
    let x = physical_unknowns(problem, &p.unknowns);
    let (u1, a1, b1) = sector_motion(&x[..3]);
    let (u2, a2, b2) = sector_motion(&x[3..]);
    vec![u1, a1, b1, u2, a2, b2]
}

/// The same wheel lightly damped: Hill's branch-point marker of class 1
/// where the closed form's antiphase block is singular, and the branch
/// switched from it. Measured: the pitchfork at 122.074717 Hz, the marker
/// located 6.7e-7 Hz from it (a real multiplier: angle 9e-15 rad), the
/// switch's own location 6.5e-7 Hz; the symmetric branch to 9.2e-9 of the
/// gap, the bifurcated branch to 4.8e-8 of the gap and 3.4e-10 in
/// frequency. 1.4 s in debug.
#[test]
fn with_damping_hills_marker_and_the_bifurcated_branch_are_the_closed_forms() {
    let text = TWO_SECTORS.replace(
        "kind = \"none\"",
        &format!("kind = \"rayleigh\"\nalpha = {DAMPING}"),
    );
    let mut solution = ForcedResponse::from_case(&case(&text))
        .unwrap()
        .stability(Some(StabilitySettings::default()))
        .build()
        .unwrap()
        .run(&mut [])
        .unwrap();
    let points = solution.branch.points.clone();
    // The symmetric branch is the closed form's; the sign of its class-1
    // block's determinant at each point.
    let mut determinants = Vec::new();
    for p in &points {
        let y = motion(&solution.problem, p);
        assert_eq!(&y[..3], &y[3..], "the sectors move alike");
        let (reference, determinant) = damped_symmetric(&y[..3], p.omega);
        for (value, exact) in y.iter().zip(&reference) {
            assert!((value - exact).abs() < 3e-8 * GAP, "{y:?} vs {reference:?}");
        }
        determinants.push(determinant);
    }
    // The pitchfork, between the two points where the sign changes, by
    // bisection along their chord (the symmetric closed form re-solved).
    let i = determinants
        .windows(2)
        .position(|w| w[0].signum() != w[1].signum())
        .expect("a pitchfork");
    assert_eq!(
        determinants
            .windows(2)
            .filter(|w| w[0].signum() != w[1].signum())
            .count(),
        1
    );
    let (a, b) = (&points[i], &points[i + 1]);
    let (ya, yb) = (motion(&solution.problem, a), motion(&solution.problem, b));
    let t = bisect(
        |t| {
            let start: Vec<f64> = (0..3).map(|k| ya[k] + t * (yb[k] - ya[k])).collect();
            damped_symmetric(&start, a.omega + t * (b.omega - a.omega)).1
        },
        0.0,
        1.0,
    );
    let pitchfork_hz = (a.omega + t * (b.omega - a.omega)) / (2.0 * PI);
    // Hill's marker: a branch point of class 1 there, a real crossing.
    let stability = solution.stability.computed().expect("stability");
    let marker = stability
        .markers
        .iter()
        .find(|m| m.kind == MarkerKind::BranchPoint && m.nodal_diameter == Some(1))
        .unwrap_or_else(|| panic!("{:?}", stability.markers));
    assert_eq!(marker.index, i);
    let located = marker.located.expect("located");
    assert!(located.angle.abs() < 1e-9, "{located:?}");
    assert!(
        (marker.frequency_hz - pitchfork_hz).abs() < 1e-5,
        "the marker at {} Hz, the pitchfork at {pitchfork_hz} Hz",
        marker.frequency_hz
    );
    // The switch at the marker.
    let max_points = 20;
    let settings = settings(&solution, max_points);
    let branch = switch_at(
        &solution.case,
        &solution.model,
        &mut solution.problem,
        1,
        (&a.unknowns, a.omega),
        (&b.unknowns, b.omega),
        &settings,
    )
    .unwrap();
    let located_hz = branch.branch_point.omega / (2.0 * PI);
    assert!((located_hz - pitchfork_hz).abs() < 1e-5, "{located_hz}");
    let mut ends = Vec::new();
    for side in &branch.sides {
        assert_eq!(side.points.len(), max_points, "{:?}", side.stop);
        let mut last_split: f64 = 0.0;
        for p in &side.points {
            let y = motion(&branch.problem, p);
            let split = y[1] - y[4];
            // Unknowns (u_1, b_1, u_2, b_2, a_1 + a_2, ω), the split fixed.
            let unpack = |z: &[f64]| {
                let y = vec![
                    z[0],
                    0.5 * (z[4] + split),
                    z[1],
                    z[2],
                    0.5 * (z[4] - split),
                    z[3],
                ];
                (y, z[5])
            };
            let z = newton(
                |z| {
                    let (y, omega) = unpack(z);
                    damped_residual(&y, omega)
                },
                vec![y[0], y[2], y[3], y[5], y[1] + y[4], p.omega],
                &[1e-9, 1e-9, 1e-9, 1e-9, 1e-9, 1e-6],
            );
            let (reference, omega) = unpack(&z);
            let at = format!("{} Hz: {y:?} vs {reference:?}", p.omega / (2.0 * PI));
            assert!((p.omega - omega).abs() < 1e-9 * omega, "{omega} at {at}");
            for (value, exact) in y.iter().zip(&reference) {
                assert!((value - exact).abs() < 1e-7 * GAP, "{at}");
            }
            // The sectors part further at every point.
            assert!(split.abs() > last_split, "{at}");
            last_split = split.abs();
        }
        ends.push(
            side.points
                .last()
                .map(|p| (p.omega, motion(&branch.problem, p))),
        );
    }
    // The two sides: the sectors swapped.
    let (Some((w1, y1)), Some((w2, y2))) = (&ends[0], &ends[1]) else {
        panic!("empty sides");
    };
    assert!((w1 - w2).abs() < 1e-9 * w1);
    for k in 0..3 {
        assert!((y1[k] - y2[k + 3]).abs() < 1e-9 * GAP, "{y1:?} vs {y2:?}");
    }
    let ratio = y1[1].abs().max(y1[4].abs()) / y1[1].abs().min(y1[4].abs());
    assert!(ratio > 3.0, "{ratio}");
}
