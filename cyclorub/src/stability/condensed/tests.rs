//! The condensed solver against the dense eigenproblem of the same block,
//! and its structured evaluations against the matrices.

use super::contour::{drawn, poles_inside};
use super::*;
use crate::stability::hill::LocalDynamics;
use faer::Mat;
use std::sync::Arc;

/// A 3-dof chain with a damper, harmonics −H..H, contact on dof 2 with a
/// periodic stiffness of mean `mean` (and, with `friction`, velocity terms
/// on dof 1).
fn block(harmonics: i64, mean: f64, friction: bool) -> BlockParts {
    // The Fourier coefficients of d(t) = mean (1 + cos t + 0.4 sin 2t).
    let coefficient = |m: i64| match m {
        0 => c64::new(mean, 0.0),
        1 | -1 => c64::new(0.5 * mean, 0.0),
        2 => c64::new(0.0, -0.2 * mean),
        -2 => c64::new(0.0, 0.2 * mean),
        _ => c64::new(0.0, 0.0),
    };
    block_with(harmonics, friction, coefficient)
}

/// The block of [`block`] touched by two impacts a period, at `t = 0.4`
/// and `t = 2.1` (stiffness impulses of 300 and 120 N/m·rad): a contact
/// of rank 2 in Hill's harmonics, what a tip hitting the casing during a
/// few time samples gives.
fn pulsed_block(harmonics: i64, friction: bool) -> BlockParts {
    let coefficient = |m: i64| {
        let m = m as f64;
        (c64::cis(-0.4 * m) * 300.0 + c64::cis(-2.1 * m) * 120.0) / (2.0 * std::f64::consts::PI)
    };
    block_with(harmonics, friction, coefficient)
}

/// The 3-dof chain's groups with the contact of Fourier coefficients
/// `coefficient(m)` on dof 2 (and, with `friction`, scaled copies on
/// dof 1's stiffness from dof 2 and its velocity).
fn block_with(harmonics: i64, friction: bool, coefficient: impl Fn(i64) -> c64) -> BlockParts {
    let real = |rows: [[f64; 3]; 3]| Mat::from_fn(3, 3, |r, c| c64::new(rows[r][c], 0.0));
    let mass = real([[2.0, 0.1, 0.0], [0.1, 1.0, 0.0], [0.0, 0.0, 0.5]]);
    let stiffness = real([
        [300.0, -100.0, 0.0],
        [-100.0, 200.0, -100.0],
        [0.0, -100.0, 100.0],
    ]);
    let damping = real([[0.3, 0.0, 0.0], [0.0, 0.2, -0.1], [0.0, -0.1, 0.1]]);
    let dynamics = Arc::new(LocalDynamics::new(&mass, &stiffness, &damping, "test").unwrap());
    let groups: Vec<Group> = (-harmonics..=harmonics)
        .map(|k| Group {
            harmonic: k,
            dynamics: Arc::clone(&dynamics),
        })
        .collect();
    let size = groups.len();
    let (mut coupling, mut velocity) = (Vec::new(), Vec::new());
    for row in 0..size {
        for col in 0..size {
            let m = groups[row].harmonic - groups[col].harmonic;
            coupling.push((3 * row + 2, 3 * col + 2, coefficient(m)));
            if friction {
                velocity.push((3 * row + 1, 3 * col + 1, coefficient(m) * 2e-3));
                coupling.push((3 * row + 1, 3 * col + 2, coefficient(m) * 0.3));
            }
        }
    }
    (groups, coupling, velocity)
}

type BlockParts = (
    Vec<Group>,
    Vec<(usize, usize, c64)>,
    Vec<(usize, usize, c64)>,
);

/// Each exponent of `a` has one in `b` within `tolerance`, and the counts
/// agree.
fn same(a: &[Picked], b: &[Picked], tolerance: f64) {
    assert_eq!(
        a.len(),
        b.len(),
        "counts differ: {:?} vs {:?}",
        a.iter().map(|p| p.exponent).collect::<Vec<_>>(),
        b.iter().map(|p| p.exponent).collect::<Vec<_>>()
    );
    for p in a {
        let nearest = b
            .iter()
            .map(|q| (q.exponent - p.exponent).norm())
            .fold(f64::INFINITY, f64::min);
        assert!(nearest < tolerance, "{:?}: nearest {nearest:e}", p.exponent);
    }
}

fn compare(harmonics: i64, mean: f64, friction: bool, omega: f64) -> usize {
    compare_block(block(harmonics, mean, friction), omega)
}

/// The condensed method's exponents of `parts` in the default region
/// against the dense eigenproblem's (1e-8 ω); their count.
fn compare_block(parts: BlockParts, omega: f64) -> usize {
    let (groups, coupling, damping) = parts;
    let region = Region::default();
    // The condensed method itself, not its dense fallback.
    let operator = ClassOperator::new(&groups, &coupling, &damping, omega).unwrap();
    let found = condensed(&operator, omega, 1.0, &region)
        .unwrap()
        .expect("the contour's estimates confirmed");
    let inside = found
        .found
        .into_iter()
        .filter(|(mu, _)| region.holds(*mu, 1.0))
        .collect();
    let condensed = picked(&operator, inside, omega, 1.0);
    let mut dense = dense_in_region(&groups, &coupling, &damping, omega, 1.0, &region).unwrap();
    // Beyond the growth the contour is drawn for, the condensed method
    // does not look (a known limit, see `Region::upper`).
    dense.retain(|p| p.exponent.re <= region.upper * omega);
    same(&condensed, &dense, 1e-8 * omega);
    condensed.len()
}

#[test]
fn an_exponent_beyond_the_contours_growth_is_not_seen() {
    // The known limit, kept in sight: a contact of mean 1e5 N/m on the
    // 3-dof block at ω = 4 rad/s gives a real exponent near 38 ω, which
    // the dense eigenproblem finds and the contour (drawn up to 0.5 ω)
    // does not.
    let (groups, coupling, damping) = block(4, 1e5, false);
    let region = Region::default();
    let dense = dense_in_region(&groups, &coupling, &damping, 4.0, 1.0, &region).unwrap();
    assert!(dense[0].exponent.re > 30.0 * 4.0, "{:?}", dense[0].exponent);
    let operator = ClassOperator::new(&groups, &coupling, &damping, 4.0).unwrap();
    let found = condensed(&operator, 4.0, 1.0, &region).unwrap().unwrap();
    assert!(found.found.iter().all(|(mu, _)| mu.re < region.upper));
}

#[test]
fn the_condensed_exponents_are_the_dense_ones_in_the_region() {
    let mut found = 0;
    for (mean, omega) in [(1.0, 7.0), (80.0, 7.0), (2000.0, 9.5), (1e5, 4.0)] {
        found += compare(4, mean, false, omega);
    }
    assert!(found > 8, "the region holds exponents: {found}");
}

#[test]
fn a_wide_contact_with_fewer_nodes_gives_the_dense_exponents() {
    // 129 harmonics of the 3-dof block: 129 contact positions, a contact of
    // full rank (not compressed), so the contour takes [`FEW_NODES`]; its
    // exponents are still the dense eigenproblem's (1e-8 ω).
    let (groups, coupling, damping) = block(64, 2000.0, false);
    let operator = ClassOperator::new(&groups, &coupling, &damping, 9.5).unwrap();
    let width = operator.contact_rank().unwrap_or(operator.positions());
    assert!(width >= MANY_POSITIONS, "{width} wide: the 32-node path");
    let found = compare(64, 2000.0, false, 9.5);
    assert!(found > 2, "the region holds exponents: {found}");
}

#[test]
fn the_condensed_exponents_with_friction_are_the_dense_ones() {
    for (mean, omega) in [(50.0, 7.0), (3000.0, 9.5)] {
        compare(5, mean, true, omega);
    }
}

#[test]
fn the_structured_solve_inverts_q() {
    let (groups, coupling, damping) = block(3, 500.0, true);
    let operator = ClassOperator::new(&groups, &coupling, &damping, 7.0).unwrap();
    let mu = c64::new(0.03, 0.31);
    let factored = operator.factor(mu).unwrap();
    let b: Vec<c64> = (0..operator.dofs())
        .map(|i| c64::new((i as f64).sin(), (2.0 * i as f64).cos()))
        .collect();
    let x = operator.solve(&factored, &b);
    let (back, _) = operator.times(mu, &x);
    let error = norm(&back.iter().zip(&b).map(|(p, q)| p - q).collect::<Vec<_>>());
    assert!(error < 1e-11 * norm(&b), "{error:e}");
}

#[test]
fn a_contact_whose_entries_are_all_zero_adds_nothing() {
    // Friction's velocity terms and the stiffness present but zero (the
    // contact opens for the whole period): Q(μ) q is the wheel's alone,
    // as without the contact terms at all.
    let (groups, coupling, damping) = block(2, 0.0, true);
    let operator = ClassOperator::new(&groups, &coupling, &damping, 7.0).unwrap();
    let (bare_groups, bare_coupling, _) = block(2, 0.0, false);
    let bare = ClassOperator::new(&bare_groups, &bare_coupling, &[], 7.0).unwrap();
    let q: Vec<c64> = (0..operator.dofs())
        .map(|i| c64::new((0.9 * i as f64).sin(), (0.4 * i as f64).cos()))
        .collect();
    let mu = c64::new(-0.01, 0.2);
    let ((value, slope), (expected, expected_slope)) = (operator.times(mu, &q), bare.times(mu, &q));
    assert_eq!(value, expected);
    assert_eq!(slope, expected_slope);
    assert_eq!(operator.residual(mu, &q).0, bare.residual(mu, &q).0);
}

#[test]
fn the_slope_of_q_is_its_derivative() {
    let (groups, coupling, damping) = block(2, 500.0, true);
    let operator = ClassOperator::new(&groups, &coupling, &damping, 7.0).unwrap();
    let q: Vec<c64> = (0..operator.dofs())
        .map(|i| c64::new((0.7 * i as f64).cos(), (1.3 * i as f64).sin()))
        .collect();
    let mu = c64::new(-0.02, 0.4);
    let h = 1e-6;
    let (_, slope) = operator.times(mu, &q);
    let (up, _) = operator.times(mu + c64::new(h, 0.0), &q);
    let (down, _) = operator.times(mu - c64::new(h, 0.0), &q);
    let difference: Vec<c64> = up
        .iter()
        .zip(&down)
        .map(|(a, b)| (a - b) / (2.0 * h))
        .collect();
    let error = norm(
        &difference
            .iter()
            .zip(&slope)
            .map(|(a, b)| a - b)
            .collect::<Vec<_>>(),
    );
    assert!(error < 1e-6 * norm(&slope), "{error:e}");
}

#[test]
fn exponents_followed_from_a_nearby_contact_are_the_contours() {
    // The 3-dof block at mean contact 100 N/m, then 1 % stiffer: each
    // exponent followed from the first point equals the contour's at the
    // second (the same count, each within 1e-9 ω), with friction too.
    for friction in [false, true] {
        let omega = 4.0;
        let region = Region::default();
        let (groups, coupling, damping) = block(4, 100.0, friction);
        let first = followed_exponents(&groups, &coupling, &damping, omega, 1, &region, None)
            .unwrap()
            .1
            .expect("found by the contour");
        let (groups, coupling, damping) = block(4, 101.0, friction);
        let (followed, track) = followed_exponents(
            &groups,
            &coupling,
            &damping,
            omega,
            1,
            &region,
            Some(&first),
        )
        .unwrap();
        let track = track.expect("a track");
        assert_eq!(track.age(), 1, "followed, not found by the contour");
        let afresh = region_exponents(&groups, &coupling, &damping, omega, 1, &region).unwrap();
        assert_eq!(followed.len(), afresh.len());
        same(&followed, &afresh, 1e-9 * omega);
    }
}

#[test]
fn a_cluster_followed_as_one_block_lands_on_the_dense_exponents() {
    // The 3-dof block at ω = 6.27 rad/s, where the first mode's exponent
    // and the second's copy one harmonic over nearly meet (their
    // frequencies differ by about ω): at mean contact 100 N/m, then 3 %
    // stiffer, the two nearest exponents of the first point, started
    // from mixtures of their vectors (the block needs their span, not
    // their order), land on two distinct exponents of the dense
    // eigenproblem at the second point, each within 1e-9, and on the same
    // two from either mixing.
    let omega = 6.27;
    let region = Region::default();
    let (groups, coupling, damping) = block(4, 100.0, true);
    let first = followed_exponents(&groups, &coupling, &damping, omega, 1, &region, None)
        .unwrap()
        .1
        .expect("found by the contour");
    let found: Vec<(c64, Vec<c64>)> = first
        .exponents()
        .filter(|(mu, _)| mu.im.abs() < 0.45)
        .map(|(mu, q)| (mu, q.to_vec()))
        .collect();
    let mut closest = (0, 0, f64::INFINITY);
    for i in 0..found.len() {
        for j in 0..i {
            let d = (found[i].0 - found[j].0).norm();
            if d < closest.2 {
                closest = (i, j, d);
            }
        }
    }
    let pair = [&found[closest.0], &found[closest.1]];
    assert!(closest.2 < 0.1, "a close pair: {:e} apart", closest.2);
    let (groups, coupling, damping) = block(4, 103.0, true);
    let operator = ClassOperator::new(&groups, &coupling, &damping, omega).unwrap();
    let dense = dense_in_region(&groups, &coupling, &damping, omega, 1.0, &near(&region)).unwrap();
    let mut landed: Vec<Vec<c64>> = Vec::new();
    for (a, b) in [(1.0, 0.0), (0.6, 0.8)] {
        let mixed: [Vec<c64>; 2] = [
            pair[0]
                .1
                .iter()
                .zip(&pair[1].1)
                .map(|(x, y)| x * a + y * b)
                .collect(),
            pair[0]
                .1
                .iter()
                .zip(&pair[1].1)
                .map(|(x, y)| x * -b + y * a)
                .collect(),
        ];
        let starts = [
            (pair[0].0, mixed[0].as_slice()),
            (pair[1].0, mixed[1].as_slice()),
        ];
        let together = cluster::followed_together(&operator, &starts).expect("followed");
        let mut values: Vec<c64> = together.iter().map(|(mu, _)| *mu).collect();
        for (i, mu) in values.iter().enumerate() {
            let off = dense
                .iter()
                .map(|p| (p.exponent / omega - mu).norm())
                .fold(f64::INFINITY, f64::min);
            assert!(off < 1e-9, "{mu}: {off:e} from the dense exponents");
            for other in &values[..i] {
                assert!((other - mu).norm() > 1e-6, "{mu} found twice");
            }
        }
        values.sort_by(|a, b| a.re.total_cmp(&b.re));
        landed.push(values);
    }
    let apart = landed[0]
        .iter()
        .zip(&landed[1])
        .map(|(x, y)| (x - y).norm())
        .fold(0.0, f64::max);
    assert!(apart < 1e-9, "the mixings land apart: {apart:e}");
}

#[test]
fn fewer_probes_than_contact_positions_find_the_same_poles() {
    // 25 harmonics with friction: 50 contact positions, a few poles
    // inside; the contour probed by 12 vectors against all 50.
    let omega = 9.5;
    let (groups, coupling, damping) = block(12, 3000.0, true);
    let region = Region::default();
    let operator = ClassOperator::new(&groups, &coupling, &damping, omega).unwrap();
    let r = operator.positions();
    assert_eq!(r, 50);
    let poles = linear_poles(&operator, omega).unwrap();
    let ellipse = contour_for(&poles, 1.0, &region);
    let inside = |c: &contour::Contour| -> Vec<c64> {
        c.estimates
            .iter()
            .map(|(mu, _)| *mu)
            .filter(|mu| ellipse.level(*mu) < 1.0)
            .collect()
    };
    let full = poles_inside(&operator, &ellipse, NODES, MOMENTS, r).unwrap();
    let probed = poles_inside(&operator, &ellipse, NODES, MOMENTS, 12).unwrap();
    let (full_poles, probed_poles) = (inside(&full), inside(&probed));
    assert!(full_poles.len() >= 4, "{full_poles:?}");
    assert_eq!(full_poles.len(), probed_poles.len());
    for mu in &full_poles {
        let nearest = probed_poles
            .iter()
            .map(|p| (p - mu).norm())
            .fold(f64::INFINITY, f64::min);
        assert!(nearest < 1e-8, "{mu}: nearest {nearest:e}");
    }
    assert_eq!(full.winding, probed.winding);
    // And the whole method, which probes this block by fewer vectors,
    // against the dense eigenproblem.
    compare(12, 3000.0, true, omega);
}

#[test]
fn a_contact_of_low_rank_is_compressed_and_gives_the_same_operator() {
    // 25 harmonics with friction: 50 contact positions, D and E of rank 2
    // each; the compressed Schur complement against the dense one.
    let omega = 9.5;
    let (groups, coupling, damping) = pulsed_block(12, true);
    let compressed = ClassOperator::new(&groups, &coupling, &damping, omega).unwrap();
    let dense = ClassOperator::built(&groups, &coupling, &damping, omega, false).unwrap();
    assert_eq!(compressed.positions(), 50);
    let rank = compressed.contact_rank().expect("compressed");
    assert_eq!(rank, 4, "D and E of rank 2 each");
    assert_eq!(dense.contact_rank(), None);
    let r = compressed.positions();
    let probing = Mat::from_fn(r, 7, |i, j| low_rank::unit_phase((i * 7 + j) as u64));
    for mu in [
        c64::new(0.01, 0.3),
        c64::new(-0.04, -0.45),
        c64::new(0.2, 0.05),
    ] {
        let (a, arg_a) = compressed.probed_resolvent(mu, &probing).unwrap();
        let (b, arg_b) = dense.probed_resolvent(mu, &probing).unwrap();
        let scale = b.iter().map(|z| z.norm()).fold(0.0, f64::max);
        let off = a
            .iter()
            .zip(&b)
            .map(|(x, y)| (x - y).norm())
            .fold(0.0, f64::max);
        assert!(off < 1e-11 * scale, "μ = {mu}: {off:e} of {scale:e}");
        let turn = 2.0 * std::f64::consts::PI;
        let d = arg_a - arg_b;
        assert!(
            (d - turn * (d / turn).round()).abs() < 1e-9,
            "det S's argument: {d}"
        );
        // The structured solve inverts Q through the compression too.
        let f = compressed.factor(mu).unwrap();
        let x: Vec<c64> = (0..compressed.dofs())
            .map(|i| c64::new((i % 5) as f64 - 2.0, 0.3 * (i % 3) as f64))
            .collect();
        let solved = compressed.solve(&f, &x);
        let (back, _) = compressed.times(mu, &solved);
        let error = back
            .iter()
            .zip(&x)
            .map(|(p, q)| (p - q).norm())
            .fold(0.0, f64::max);
        assert!(error < 1e-10, "μ = {mu}: Q Q⁻¹ x − x = {error:e}");
    }
}

#[test]
fn the_exponents_with_a_compressed_contact_are_the_dense_ones() {
    for (omega, friction) in [(7.0, false), (9.5, true)] {
        let parts = pulsed_block(if friction { 12 } else { 24 }, friction);
        let operator = ClassOperator::new(&parts.0, &parts.1, &parts.2, omega).unwrap();
        assert!(operator.contact_rank().is_some(), "compressed");
        let found = compare_block(parts.clone(), omega);
        assert!(found >= 4, "{found} exponents");
    }
}

#[test]
fn a_contour_whose_moments_are_full_is_drawn_again() {
    // The 3-dof block at ω = 7 rad/s: 12 linear poles inside the ellipse,
    // 9 contact positions. One moment of 9 probes cannot hold 12 poles
    // (`poles_inside` says so: `None`); the redraw with one more moment and
    // twice the nodes finds every exponent of the region, each estimate
    // within 1e-6 ω of the dense eigenproblem's.
    let omega = 7.0;
    let (groups, coupling, damping) = block(4, 80.0, false);
    let operator = ClassOperator::new(&groups, &coupling, &damping, omega).unwrap();
    let region = Region::default();
    let poles = linear_poles(&operator, omega).unwrap();
    let ellipse = contour_for(&poles, 1.0, &region);
    let inside = poles
        .iter()
        .filter(|(p, _)| ellipse.level(*p) < 1.0)
        .count();
    let r = operator.positions();
    assert!(inside > r, "{inside} poles inside, {r} positions");
    assert!(poles_inside(&operator, &ellipse, NODES, 1, r).is_none());
    let contour = drawn(&operator, &ellipse, NODES, 1, r, inside, 0).expect("drawn again");
    let dense = dense_in_region(&groups, &coupling, &damping, omega, 1.0, &region).unwrap();
    assert!(!dense.is_empty());
    for p in &dense {
        let mu = p.exponent / omega;
        let nearest = contour
            .estimates
            .iter()
            .map(|(estimate, _)| (estimate - mu).norm())
            .fold(f64::INFINITY, f64::min);
        assert!(nearest < 1e-6, "{mu}: nearest estimate {nearest:e}");
    }
    // A count the contour cannot meet (one exponent more than inside) is
    // refused after the redraw: the class then goes to the dense solve.
    assert!(drawn(&operator, &ellipse, NODES, 2, r, inside + 1, 0).is_none());
}
