//! The two-stage condensation against the dense Schur complement of the
//! assembled mistuned wheel (`condensation::condense`, which knows nothing
//! of diameters or kept dofs).

use super::super::super::layout::{Block, BlockKind};
use super::super::condensation::{condense, dynamic_stiffness, submatrix, with_wall};
use super::super::{BlockMatrices, Condensed, LocalBlock};
use super::PerturbedWheel;
use crate::hbm::linear::diameters::tests::value;
use crate::model::SectorModel;
use crate::model::{generate_deviations, DeviationDistribution, LumpedSector, Mistuning};
use faer::linalg::solvers::Solve;
use faer::{c64, Mat};
use std::sync::Arc;

/// A symmetric block-circulant wheel (first block row pseudo-random,
/// `B(−t) = B(t)ᵀ`, the stiffness's diagonal dominant).
fn tuned_wheel(sectors: usize, dofs: usize, seed: usize) -> BlockMatrices {
    let size = sectors * dofs;
    let matrix = |kind: usize, diagonal: f64| {
        Arc::new(Mat::from_fn(size, size, |r, c| {
            let (j, p) = (r / dofs, r % dofs);
            let (k, q) = (c / dofs, c % dofs);
            let t = (k + sectors - j) % sectors;
            // Entry (p, q) of B(t) with B(N − t) = B(t)ᵀ.
            let (t, p, q) = if t <= sectors / 2 {
                (t, p, q)
            } else {
                (sectors - t, q, p)
            };
            let (p, q) = if t == 0 { (p.min(q), p.max(q)) } else { (p, q) };
            let dominant = if t == 0 && p == q { diagonal } else { 0.0 };
            let v = value(seed + 1000 * kind + (t * dofs + p) * dofs + q);
            c64::new(dominant + v, 0.0)
        }))
    };
    BlockMatrices {
        mass: matrix(1, 3.0),
        stiffness: matrix(2, 40.0),
        damping: matrix(3, 0.5),
    }
}

/// `tuned` with sector `j`'s stiffness changed by `δ_j B` on `dofs`
/// (`B` symmetric, pseudo-random).
fn mistuned(
    tuned: &BlockMatrices,
    sectors: usize,
    changed: &[usize],
    seed: usize,
) -> BlockMatrices {
    let mut stiffness = (*tuned.stiffness).clone();
    let dofs = stiffness.nrows() / sectors;
    for j in 0..sectors {
        let delta = 0.05 * value(seed + j);
        for (a, &p) in changed.iter().enumerate() {
            for (b, &q) in changed.iter().enumerate() {
                let entry = value(seed + 100 + a.min(b) * 10 + a.max(b));
                stiffness[(j * dofs + p, j * dofs + q)] += c64::new(delta * entry, 0.0);
            }
        }
    }
    BlockMatrices {
        mass: tuned.mass.clone(),
        stiffness: Arc::new(stiffness),
        damping: tuned.damping.clone(),
    }
}

fn block(harmonic: usize) -> Block {
    Block {
        harmonic,
        kind: BlockKind::Wheel,
        slots: Vec::new(),
    }
}

/// The dense block of the wheel: sector-major contact dofs, the others.
fn dense(matrices: &BlockMatrices, sectors: usize, contact: &[usize], load: &[c64]) -> LocalBlock {
    let dofs = matrices.mass.nrows() / sectors;
    LocalBlock {
        matrices: matrices.clone(),
        contact: (0..sectors)
            .flat_map(|j| contact.iter().map(move |&d| j * dofs + d))
            .collect(),
        interior: (0..sectors * dofs)
            .filter(|e| !contact.contains(&(e % dofs)))
            .collect(),
        load: load.to_vec(),
        structure: crate::hbm::linear::WheelStructure::Dense,
    }
}

/// The largest relative difference of `Z`, `∂Z/∂ω`, `F`, `∂F/∂ω` (a zero
/// reference, as `∂/∂ω` on harmonic 0, must be matched exactly).
fn relative_difference(a: &Condensed, b: &Condensed) -> [f64; 4] {
    let matrix = |x: &Mat<c64>, y: &Mat<c64>| {
        let (mut d, mut s) = (0.0_f64, 0.0_f64);
        for r in 0..y.nrows() {
            for c in 0..y.ncols() {
                d = d.max((x[(r, c)] - y[(r, c)]).norm());
                s = s.max(y[(r, c)].norm());
            }
        }
        d / s.max(f64::MIN_POSITIVE)
    };
    let vector = |x: &[c64], y: &[c64]| {
        let d = x
            .iter()
            .zip(y)
            .map(|(p, q)| (p - q).norm())
            .fold(0.0, f64::max);
        d / y
            .iter()
            .map(|q| q.norm())
            .fold(0.0, f64::max)
            .max(f64::MIN_POSITIVE)
    };
    [
        matrix(&a.dynamic, &b.dynamic),
        matrix(&a.dynamic_derivative, &b.dynamic_derivative),
        vector(&a.load, &b.load),
        vector(&a.load_derivative, &b.load_derivative),
    ]
}

/// `x_i = Z_ii⁻¹ (f_i − Z_ic x_c)` of the dense wheel, with `x_c`.
fn dense_recover(local: &LocalBlock, harmonic: usize, omega: f64, x_c: &[c64]) -> Vec<c64> {
    let (z, _) = dynamic_stiffness(&local.matrices, harmonic, omega);
    let rhs = Mat::from_fn(local.interior.len(), 1, |r, _| {
        let i = local.interior[r];
        local
            .contact
            .iter()
            .zip(x_c)
            .fold(local.load[i], |s, (&c, v)| s - z[(i, c)] * v)
    });
    let solved = submatrix(&z, &local.interior, &local.interior)
        .partial_piv_lu()
        .solve(&rhs);
    let mut x = vec![c64::new(0.0, 0.0); z.nrows()];
    for (&c, &v) in local.contact.iter().zip(x_c) {
        x[c] = v;
    }
    for (r, &i) in local.interior.iter().enumerate() {
        x[i] = solved[(r, 0)];
    }
    x
}

/// Both stages give the dense Schur complement of the assembled wheel, its
/// derivative and both loads to 1e-12 (also in series with a wall), and
/// the recovered dofs of the dense solve, on odd and even wheels, with the
/// contact dofs among the changed ones or not, on harmonics 0 and 3.
#[test]
fn two_stages_equal_the_dense_condensation_of_the_mistuned_wheel() {
    for (sectors, dofs, contact, changed, harmonic) in [
        (5, 5, vec![0], vec![0, 1, 2], 3),
        (6, 6, vec![4, 1], vec![2, 3], 0),
        (6, 5, vec![2], vec![0, 3], 2),
    ] {
        let tuned = tuned_wheel(sectors, dofs, 31 * sectors + harmonic);
        let wheel = mistuned(&tuned, sectors, &changed, 7 * dofs);
        let load: Vec<c64> = (0..sectors * dofs)
            .map(|d| c64::new(value(3 * d + 1), value(3 * d + 2)))
            .collect();
        let two = PerturbedWheel::new(&wheel, &tuned, sectors, &contact).expect("two stages");
        let local = dense(&wheel, sectors, &contact, &load);
        let (block, omega) = (block(harmonic), 1.3);
        let reference = condense(&block, &local, omega).unwrap();
        let staged = two.condense(&block, &load, omega, None).unwrap();
        let case = format!("N = {sectors}, contact {contact:?}, changed {changed:?}");
        for (name, e) in ["Z", "dZ", "F", "dF"]
            .iter()
            .zip(relative_difference(&staged, &reference))
        {
            assert!(e < 1e-12, "{case}: {name} {e:e}");
        }
        let kappa = 30.0;
        let walled = with_wall(&block, reference, kappa, omega).unwrap();
        let staged = two.condense(&block, &load, omega, Some(kappa)).unwrap();
        for (name, e) in ["Z", "dZ", "F", "dF"]
            .iter()
            .zip(relative_difference(&staged, &walled))
        {
            assert!(e < 1e-12, "{case}, wall: {name} {e:e}");
        }
        let x_c: Vec<c64> = (0..local.contact.len())
            .map(|e| c64::new(value(5 * e + 8), value(5 * e + 9)))
            .collect();
        let expected = dense_recover(&local, harmonic, omega, &x_c);
        let got = two.recover(&block, &load, omega, &x_c).unwrap();
        let scale = expected.iter().map(|v| v.norm()).fold(0.0, f64::max);
        let error = got
            .iter()
            .zip(&expected)
            .map(|(a, b)| (a - b).norm())
            .fold(0.0, f64::max);
        assert!(
            error < 1e-12 * scale,
            "{case}: recovered {error:e} of {scale:e}"
        );
    }
}

/// The default academic wheel (N = 24) mistuned at 1 % (seed 1): on every
/// harmonic of the default case at 128 Hz, the two stages give the dense
/// Schur complement to 1e-12; the tuned wheel and a changed mass are left
/// to the other condensations.
#[test]
fn the_mistuned_academic_wheel_condenses_in_two_stages_as_densely() {
    let sectors = 24;
    let blade = LumpedSector::academic()
        .blade_stiffness(&[0, 1, 2], "blade_dofs")
        .unwrap();
    let deviations = generate_deviations(sectors, 0.01, 1, DeviationDistribution::Normal);
    let mistuning = Mistuning::new(deviations, blade, "deviations").unwrap();
    let tuned_model = SectorModel::academic(sectors).unwrap();
    let model = tuned_model.clone().with_mistuning(mistuning).unwrap();
    let complex = |m: &Mat<f64>| {
        Arc::new(Mat::from_fn(m.nrows(), m.ncols(), |r, c| {
            c64::new(m[(r, c)], 0.0)
        }))
    };
    let matrices = |model: &SectorModel| {
        let w = model.full_wheel().unwrap();
        BlockMatrices {
            mass: complex(&w.mass),
            stiffness: complex(&w.stiffness),
            damping: complex(&w.damping),
        }
    };
    let (wheel, tuned) = (matrices(&model), matrices(&tuned_model));
    let two = PerturbedWheel::new(&wheel, &tuned, sectors, &[0]).expect("two stages");
    assert_eq!(two.kept, 3, "m1 (contact), m2, m3");
    let load: Vec<c64> = (0..5 * sectors)
        .map(|e| {
            if e % 5 == 0 {
                c64::cis(0.3 * e as f64)
            } else {
                c64::new(0.0, 0.0)
            }
        })
        .collect();
    let omega = 2.0 * std::f64::consts::PI * 128.0;
    let local = dense(&wheel, sectors, &[0], &load);
    for harmonic in 0..=10 {
        let reference = condense(&block(harmonic), &local, omega).unwrap();
        let staged = two.condense(&block(harmonic), &load, omega, None).unwrap();
        for (name, e) in ["Z", "dZ", "F", "dF"]
            .iter()
            .zip(relative_difference(&staged, &reference))
        {
            assert!(e < 1e-12, "harmonic {harmonic}: {name} {e:e}");
        }
    }
    assert!(PerturbedWheel::new(&tuned, &tuned, sectors, &[0]).is_none());
    let heavier = BlockMatrices {
        mass: Arc::new(Mat::from_fn(5 * sectors, 5 * sectors, |r, c| {
            tuned.mass[(r, c)] * 1.01
        })),
        ..wheel.clone()
    };
    assert!(PerturbedWheel::new(&heavier, &tuned, sectors, &[0]).is_none());
}
