use super::super::super::layout::{Block, BlockKind};
use super::super::condensation::condense;
use super::super::condensation::with_wall;
use super::super::{BlockMatrices, Condensed, LocalBlock};
use super::WheelDiameters;
use faer::linalg::solvers::Solve;
use faer::{c64, Mat};
use std::sync::Arc;

/// A reproducible value in [−1, 1) (the perturbed wheel's tests draw
/// theirs here too).
pub(in crate::hbm::linear) fn value(seed: usize) -> f64 {
    let mut x = (seed as u64)
        .wrapping_mul(6364136223846793005)
        .wrapping_add(1442695040888963407);
    x ^= x >> 33;
    x = x.wrapping_mul(0xff51afd7ed558ccd);
    x ^= x >> 33;
    (x % 2_000_000) as f64 / 1e6 - 1.0
}

/// A block-circulant wheel of `sectors` sectors of `dofs` dofs: first
/// block row `B(t)` pseudo-random, the stiffness's `B(0)` made dominant so
/// that every interior block is regular.
fn wheel(sectors: usize, dofs: usize, seed: usize) -> BlockMatrices {
    let size = sectors * dofs;
    let matrix = |kind: usize, diagonal: f64| {
        Arc::new(Mat::from_fn(size, size, |r, c| {
            let (j, p) = (r / dofs, r % dofs);
            let (k, q) = (c / dofs, c % dofs);
            let t = (k + sectors - j) % sectors;
            let dominant = if t == 0 && p == q { diagonal } else { 0.0 };
            c64::new(
                dominant + value(seed + 1000 * kind + (t * dofs + p) * dofs + q),
                0.0,
            )
        }))
    };
    BlockMatrices {
        mass: matrix(1, 3.0),
        stiffness: matrix(2, 40.0),
        damping: matrix(3, 0.5),
    }
}

/// Sector-major contact and interior dofs of the wheel for one sector's
/// contact dofs (in the condensed order, not sorted).
fn split(sectors: usize, dofs: usize, contact: &[usize]) -> (Vec<usize>, Vec<usize>) {
    let wheel_contact = (0..sectors)
        .flat_map(|j| contact.iter().map(move |&d| j * dofs + d))
        .collect();
    let interior = (0..sectors * dofs)
        .filter(|d| !contact.contains(&(d % dofs)))
        .collect();
    (wheel_contact, interior)
}

fn block(harmonic: usize) -> Block {
    Block {
        harmonic,
        kind: BlockKind::Wheel,
        slots: Vec::new(),
    }
}

/// The largest difference between `Z` (or `∂Z/∂ω`) of `a`, read entry by
/// entry, and `b`'s, and the largest entry of `b`.
fn largest_difference(a: &Condensed, b: &Condensed, derivative: bool) -> (f64, f64) {
    let size = b.dynamic.nrows();
    let mut difference = 0.0_f64;
    let mut scale = 0.0_f64;
    for r in 0..size {
        for c in 0..size {
            let expected = b.entry(r, c, derivative);
            difference = difference.max((a.entry(r, c, derivative) - expected).norm());
            scale = scale.max(expected.norm());
        }
    }
    (difference, scale)
}

fn largest_vector_difference(a: &[c64], b: &[c64]) -> (f64, f64) {
    let difference = a
        .iter()
        .zip(b)
        .map(|(x, y)| (x - y).norm())
        .fold(0.0, f64::max);
    let scale = b.iter().map(|y| y.norm()).fold(0.0, f64::max);
    (difference, scale)
}

/// Condensing the wheel diameter by diameter gives the dense Schur
/// complement, its frequency derivative and both loads, on odd and even
/// wheels and on harmonics 0 and 3; and the recovered interior dofs are
/// those of the dense solve `x_i = Z_ii⁻¹ (f_i − Z_ic x_c)`.
#[test]
fn condensing_by_diameters_equals_the_dense_schur_complement() {
    for (sectors, dofs, contact, harmonic) in [
        (5, 4, vec![2, 0], 3),
        (6, 5, vec![4, 1, 2], 0),
        (6, 5, vec![3], 2),
    ] {
        let matrices = wheel(sectors, dofs, 17 * sectors + harmonic);
        let (wheel_contact, interior) = split(sectors, dofs, &contact);
        let load: Vec<c64> = (0..sectors * dofs)
            .map(|d| c64::new(value(7 * d + 1), value(7 * d + 2)))
            .collect();
        let diameters = WheelDiameters::new(&matrices, sectors, &wheel_contact, &interior)
            .expect("a block-circulant wheel");
        let dense = LocalBlock {
            matrices: matrices.clone(),
            contact: wheel_contact.clone(),
            interior: interior.clone(),
            load: load.clone(),
            structure: crate::hbm::linear::WheelStructure::Dense,
        };
        let omega = 1.3;
        let block = block(harmonic);
        let reference = condense(&block, &dense, omega).unwrap();
        let by_diameters = diameters.condense(&block, &load, omega, None).unwrap();
        let probe: Vec<c64> = (0..wheel_contact.len())
            .map(|e| c64::new(value(5 * e + 8), value(5 * e + 9)))
            .collect();
        let case = format!("N = {sectors}, k = {harmonic}");
        for (name, (difference, scale)) in [
            ("Z", largest_difference(&by_diameters, &reference, false)),
            ("dZ/dω", largest_difference(&by_diameters, &reference, true)),
            (
                "Z x",
                largest_vector_difference(
                    &by_diameters.multiply(&probe, false),
                    &reference.multiply(&probe, false),
                ),
            ),
            (
                "dZ/dω x",
                largest_vector_difference(
                    &by_diameters.multiply(&probe, true),
                    &reference.multiply(&probe, true),
                ),
            ),
            (
                "F",
                largest_vector_difference(&by_diameters.load, &reference.load),
            ),
            (
                "dF/dω",
                largest_vector_difference(
                    &by_diameters.load_derivative,
                    &reference.load_derivative,
                ),
            ),
        ] {
            // Harmonic 0 has no frequency derivative: measured against Z.
            let derivative = name.starts_with('d');
            let vanishes = harmonic == 0 && derivative;
            assert!(vanishes || scale > 1e-3, "{case}: {name} vanishes");
            let scale = if vanishes { 1.0 } else { scale };
            assert!(
                difference <= 1e-12 * scale,
                "{case}: {name} differs by {difference:.2e} (scale {scale:.2e})"
            );
        }
        // A wall κ in series, diameter by diameter, as on the dense block.
        let kappa = 25.0;
        let walled = diameters
            .condense(&block, &load, omega, Some(kappa))
            .unwrap();
        let dense_walled = with_wall(&block, reference.clone(), kappa, omega).unwrap();
        for (name, (difference, scale)) in [
            (
                "Z with a wall",
                largest_difference(&walled, &dense_walled, false),
            ),
            (
                "F with a wall",
                largest_vector_difference(&walled.load, &dense_walled.load),
            ),
        ] {
            assert!(
                scale > 1e-3 && difference <= 1e-12 * scale,
                "{case}: {name} differs by {difference:.2e} (scale {scale:.2e})"
            );
        }
        if harmonic > 0 {
            let (difference, scale) = largest_difference(&walled, &dense_walled, true);
            assert!(
                scale > 1e-3 && difference <= 1e-12 * scale,
                "{case}: dZ/dω with a wall differs by {difference:.2e} (scale {scale:.2e})"
            );
        }
        // Recovery of the interior dofs.
        let contact_values: Vec<c64> = (0..wheel_contact.len())
            .map(|e| c64::new(value(11 * e + 3), value(11 * e + 4)))
            .collect();
        let recovered = diameters
            .recover(&block, &load, omega, &contact_values)
            .unwrap();
        let k = harmonic as f64;
        let z = |r: usize, c: usize| {
            matrices.stiffness[(r, c)] - matrices.mass[(r, c)] * (k * k * omega * omega)
                + matrices.damping[(r, c)] * c64::new(0.0, k * omega)
        };
        let zii = Mat::from_fn(interior.len(), interior.len(), |r, c| {
            z(interior[r], interior[c])
        });
        let rhs = Mat::from_fn(interior.len(), 1, |r, _| {
            wheel_contact
                .iter()
                .zip(&contact_values)
                .fold(load[interior[r]], |sum, (&c, v)| {
                    sum - z(interior[r], c) * v
                })
        });
        let solved = zii.partial_piv_lu().solve(&rhs);
        let expected: Vec<c64> = (0..interior.len()).map(|r| solved[(r, 0)]).collect();
        let got: Vec<c64> = interior.iter().map(|&i| recovered[i]).collect();
        let (difference, scale) = largest_vector_difference(&got, &expected);
        assert!(
            difference <= 1e-12 * scale,
            "{case}: recovery differs by {difference:.2e} (scale {scale:.2e})"
        );
        for (&c, v) in wheel_contact.iter().zip(&contact_values) {
            assert_eq!(recovered[c], *v, "{case}: contact dof {c} kept");
        }
    }
}

/// A wheel whose blocks do not repeat, or whose contact dofs differ
/// between sectors, has no diameters (the dense condensation serves).
#[test]
fn a_wheel_that_is_not_block_circulant_has_no_diameters() {
    let (sectors, dofs) = (4, 3);
    let matrices = wheel(sectors, dofs, 5);
    let (contact, interior) = split(sectors, dofs, &[1]);
    assert!(WheelDiameters::new(&matrices, sectors, &contact, &interior).is_some());
    let mut stiffness = (*matrices.stiffness).clone();
    stiffness[(5, 7)] += c64::new(1e-6, 0.0);
    let perturbed = BlockMatrices {
        stiffness: Arc::new(stiffness),
        ..matrices.clone()
    };
    assert!(WheelDiameters::new(&perturbed, sectors, &contact, &interior).is_none());
    // Sector 2 condenses dof 2 instead of dof 1.
    let mut uneven = contact.clone();
    uneven[2] = 2 * dofs + 2;
    let uneven_interior: Vec<usize> = (0..sectors * dofs)
        .filter(|d| !uneven.contains(d))
        .collect();
    assert!(WheelDiameters::new(&matrices, sectors, &uneven, &uneven_interior).is_none());
    assert!(WheelDiameters::new(&matrices, 1, &contact, &interior).is_none());
}
