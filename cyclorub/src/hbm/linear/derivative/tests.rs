use super::super::super::layout::{Block, BlockKind};
use super::super::condensation::{condense, condense_for_products, with_wall};
use super::super::diameters::tests::value;
use super::super::{BlockMatrices, Condensed, LocalBlock, WheelStructure};
use faer::{c64, Mat};
use std::sync::Arc;

/// A symmetric block of `size` dofs (stiffness diagonally dominant, mass
/// and damping pseudo-random symmetric), its contact dofs in an unsorted
/// order and a complex load.
fn local(size: usize, contact: &[usize], seed: usize) -> LocalBlock {
    let symmetric = |kind: usize, diagonal: f64| {
        Arc::new(Mat::from_fn(size, size, |r, c| {
            let (a, b) = (r.min(c), r.max(c));
            let dominant = if r == c { diagonal } else { 0.0 };
            c64::new(dominant + value(seed + 1000 * kind + a * size + b), 0.0)
        }))
    };
    LocalBlock {
        matrices: BlockMatrices {
            mass: symmetric(1, 3.0),
            stiffness: symmetric(2, 40.0),
            damping: symmetric(3, 0.5),
        },
        contact: contact.to_vec(),
        interior: (0..size).filter(|d| !contact.contains(d)).collect(),
        load: (0..size)
            .map(|d| c64::new(value(seed + 7 * d + 1), value(seed + 7 * d + 2)))
            .collect(),
        structure: WheelStructure::Dense,
    }
}

fn block(harmonic: usize) -> Block {
    Block {
        harmonic,
        kind: BlockKind::Wheel,
        slots: Vec::new(),
    }
}

/// The largest entry of `a − b` over the largest of `b`.
fn relative(a: &[c64], b: &[c64]) -> f64 {
    let difference = a
        .iter()
        .zip(b)
        .map(|(x, y)| (x - y).norm())
        .fold(0.0, f64::max);
    difference / b.iter().map(|y| y.norm()).fold(f64::MIN_POSITIVE, f64::max)
}

fn dynamic_column(condensed: &Condensed, x: &[c64]) -> Vec<c64> {
    condensed.multiply(x, false)
}

/// Kept as products, the condensed block's `∂Z/∂ω x` and `∂F/∂ω` equal
/// the matrix form's (to round-off) and a central difference of `Z x` and
/// `F` in `ω` (to the difference's own error), with and without a wall,
/// with and without interior dofs; `Z` and `F` are the matrix form's.
#[test]
#[allow(clippy::float_cmp)] // harmonic 0: exactly zero
fn a_derivative_kept_as_products_equals_the_matrix_and_a_finite_difference() {
    for (size, contact, harmonic, wall) in [
        (12, vec![7, 2, 9, 0, 4], 1, None),
        (12, vec![7, 2, 9, 0, 4], 3, Some(25.0)),
        (9, vec![5, 1], 2, None),
        (4, vec![3, 0, 1, 2], 2, Some(8.0)),
        (10, vec![6, 3, 8], 0, Some(30.0)),
    ] {
        let local = local(size, &contact, 31 * size + harmonic);
        let (block, omega) = (block(harmonic), 1.7);
        let condensed = |omega: f64, products: bool| {
            let plain = if products {
                condense_for_products(&block, &local, omega)
            } else {
                condense(&block, &local, omega)
            }
            .expect("a regular block");
            match wall {
                Some(kappa) => with_wall(&block, plain, kappa, omega).expect("a regular wall"),
                None => plain,
            }
        };
        let (matrix, products) = (condensed(omega, false), condensed(omega, true));
        assert!(products.dynamic_derivative.nrows() == 0 && products.derivative_products.is_some());
        let case = format!("size {size}, k = {harmonic}, wall {wall:?}");
        let x: Vec<c64> = (0..contact.len())
            .map(|e| c64::new(value(5 * e + 8), value(5 * e + 9)))
            .collect();
        for (name, a, b, tolerance) in [
            (
                "Z x",
                dynamic_column(&products, &x),
                dynamic_column(&matrix, &x),
                1e-14,
            ),
            ("F", products.load.clone(), matrix.load.clone(), 1e-14),
            (
                "dZ/dω x",
                products.multiply(&x, true),
                matrix.multiply(&x, true),
                1e-12,
            ),
            (
                "dF/dω",
                products.load_derivative.clone(),
                matrix.load_derivative.clone(),
                1e-12,
            ),
        ] {
            let error = relative(&a, &b);
            assert!(
                error < tolerance,
                "{case}: {name} off the matrix form by {error:e}"
            );
        }
        // Central differences, h = 1e-5: error ~ h² ‖Z'''‖ ≈ 1e-10.
        let h = 1e-5;
        let (above, below) = (condensed(omega + h, true), condensed(omega - h, true));
        let difference = |f: &dyn Fn(&Condensed) -> Vec<c64>| -> Vec<c64> {
            f(&above)
                .iter()
                .zip(f(&below))
                .map(|(p, m)| (p - m) / (2.0 * h))
                .collect()
        };
        let product = difference(&|c| dynamic_column(c, &x));
        let load = difference(&|c| c.load.clone());
        if harmonic == 0 {
            // Nothing depends on ω: the derivatives vanish exactly.
            let largest = |v: &[c64]| v.iter().map(|e| e.norm()).fold(0.0, f64::max);
            assert!(largest(&products.multiply(&x, true)) == 0.0, "{case}");
            assert!(largest(&products.load_derivative) == 0.0, "{case}");
            continue;
        }
        let error = relative(&products.multiply(&x, true), &product);
        assert!(
            error < 1e-7,
            "{case}: dZ/dω x off the difference by {error:e}"
        );
        let error = relative(&products.load_derivative, &load);
        assert!(
            error < 1e-7,
            "{case}: dF/dω off the difference by {error:e}"
        );
    }
}
