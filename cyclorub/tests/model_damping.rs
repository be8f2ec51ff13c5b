//! Damping: the per-diameter damped responses equal the full wheel's
//! (closed-form linear solves), and modal damping holds its ratios.

use crate::support;

use cyclorub::model::{Damping, FiniteElementSector, ModalDamping, SectorModel};
use faer::{c64, Mat};
use support::{cis, complex, dynamic_stiffness, hermitian_modes, max_abs_c, solve, Lcg};

/// Solves the damped forced response on the full wheel and, wave by wave,
/// with the per-diameter matrices; they must agree.
fn check_responses(model: &SectorModel, omegas: &[f64], seed: u64) {
    let sectors = model.sectors();
    let n = model.dofs_per_sector();
    let alpha = 2.0 * std::f64::consts::PI / sectors as f64;
    let full = model.full_wheel().expect("full wheel");
    let (m, k, c) = (
        complex(&full.mass),
        complex(&full.stiffness),
        complex(&full.damping),
    );
    let mut rng = Lcg(seed);
    // A force on every dof of every sector (complex amplitudes).
    let force = Mat::from_fn(sectors * n, 1, |_, _| {
        c64::new(rng.range(-1.0, 1.0), rng.range(-1.0, 1.0))
    });
    let per_diameter: Vec<_> = (0..sectors as i64)
        .map(|s| model.nodal_diameter_matrices(s).expect("per diameter"))
        .collect();
    for &omega in omegas {
        let x_full = solve(&dynamic_stiffness(&k, &m, &c, omega), &force);
        // x_j = Σ_s X_s·exp(−isα(j−1)), F_s = (1/N) Σ_j f_j·exp(isα(j−1)).
        let mut x_waves = Mat::<c64>::zeros(sectors * n, 1);
        for (s, nd) in per_diameter.iter().enumerate() {
            let f_s = Mat::from_fn(n, 1, |d, _| {
                (0..sectors)
                    .map(|j| force[(j * n + d, 0)] * cis(s as f64 * alpha * j as f64))
                    .sum::<c64>()
                    / sectors as f64
            });
            let x_s = solve(
                &dynamic_stiffness(&nd.stiffness, &nd.mass, &nd.damping, omega),
                &f_s,
            );
            for j in 0..sectors {
                let phase = cis(-(s as f64) * alpha * j as f64);
                for d in 0..n {
                    x_waves[(j * n + d, 0)] += x_s[(d, 0)] * phase;
                }
            }
        }
        let scale = max_abs_c(&x_full);
        for i in 0..sectors * n {
            let diff = (x_full[(i, 0)] - x_waves[(i, 0)]).norm();
            assert!(
                diff <= 1e-8 * scale,
                "ω = {omega}: dof {i}: {} vs {}",
                x_full[(i, 0)],
                x_waves[(i, 0)]
            );
        }
    }
}

/// Frequencies near resonances (and between them) in rad/s.
fn probe_frequencies(model: &SectorModel) -> Vec<f64> {
    let freqs = model.natural_frequencies().expect("frequencies");
    let two_pi = 2.0 * std::f64::consts::PI;
    let mut omegas = Vec::new();
    let (_, f0) = &freqs[0];
    omegas.push(two_pi * f0[0] * 1.0003);
    let (_, f1) = &freqs[freqs.len() / 2];
    omegas.push(two_pi * f1[0]);
    omegas.push(two_pi * f1[f1.len() - 1] * 0.999);
    omegas.push(two_pi * 0.5 * (f1[0] + f1[f1.len() - 1]));
    omegas
}

fn academic_with(sectors: usize, damping: Damping) -> SectorModel {
    SectorModel::lumped(sectors, &cyclorub::model::LumpedSector::academic(), damping)
        .expect("academic")
}

#[test]
fn modal_damping_responses_agree_academic() {
    for sectors in [24, 45, 1, 2] {
        let model = SectorModel::academic(sectors).expect("academic");
        check_responses(&model, &probe_frequencies(&model), 1);
        // By mode index, as the paper's Sec. 5.1 (first modes 1e-3, others 5e-3).
        let model = academic_with(
            sectors,
            Damping::Modal(ModalDamping {
                ratios: vec![1e-3, 1e-3],
                others: 5e-3,
            }),
        );
        check_responses(&model, &probe_frequencies(&model), 2);
    }
}

#[test]
fn viscous_damping_responses_agree() {
    for sectors in [24, 3] {
        let model = academic_with(
            sectors,
            Damping::Rayleigh {
                alpha: 5.0,
                beta: 2e-6,
            },
        );
        check_responses(&model, &probe_frequencies(&model), 3);
        let mut rng = Lcg(9);
        let c = rng.spd(5, 1.0);
        let c1 = rng.matrix(5, 5);
        let model = academic_with(
            sectors,
            Damping::Matrix {
                matrix: c,
                coupling: Some(c1),
            },
        );
        check_responses(&model, &probe_frequencies(&model), 4);
    }
}

#[test]
fn modal_damping_responses_agree_fe_sector() {
    let mut rng = Lcg(21);
    for sectors in [6, 7, 1] {
        let fe = FiniteElementSector {
            mass: rng.spd(6, 3.0),
            stiffness: rng.spd(6, 1.0),
            left_boundary: vec![0, 1],
            right_boundary: vec![4, 5],
            boundary_frame: Default::default(),
        };
        for damping in [
            Damping::Modal(ModalDamping {
                ratios: vec![1e-3, 2e-3, 4e-3],
                others: 1e-2,
            }),
            Damping::Matrix {
                matrix: rng.spd(6, 0.1),
                coupling: None,
            },
        ] {
            let model = SectorModel::finite_element(sectors, fe.clone(), damping).expect("fe");
            check_responses(&model, &probe_frequencies(&model), 5);
        }
    }
}

/// `Φᴴ C(s) Φ = diag(2 ξ_r ω_r)` per diameter.
#[test]
fn modal_damping_holds_its_ratios_per_diameter() {
    let ratios = ModalDamping {
        ratios: vec![1e-3, 2e-3, 3e-3],
        others: 5e-3,
    };
    let model = academic_with(24, Damping::Modal(ratios.clone()));
    for s in [-12, -5, 0, 1, 7, 12] {
        let nd = model.nodal_diameter_matrices(s).expect("per diameter");
        let (values, phi) = hermitian_modes(&nd.stiffness, &nd.mass);
        let projected = phi.adjoint() * &nd.damping * &phi;
        for r in 0..5 {
            for q in 0..5 {
                let expected = if r == q {
                    2.0 * ratios.ratio(r) * values[r].sqrt()
                } else {
                    0.0
                };
                let got = projected[(r, q)];
                assert!(
                    (got - c64::new(expected, 0.0)).norm()
                        <= 1e-9 * (2.0 * 5e-3 * values[4].sqrt()),
                    "s = {s}, ({r}, {q}): {got} vs {expected}"
                );
            }
        }
    }
}

/// With one ratio on all modes, the full wheel's damping is the modal
/// damping of the full wheel's own modes.
#[test]
fn uniform_modal_damping_is_full_wheel_modal_damping() {
    let xi = 2e-3;
    let model = academic_with(8, Damping::Modal(ModalDamping::uniform(xi)));
    let full = model.full_wheel().expect("full wheel");
    let (values, phi) = hermitian_modes(&complex(&full.stiffness), &complex(&full.mass));
    let projected = phi.adjoint() * complex(&full.damping) * &phi;
    let top = 2.0 * xi * values[values.len() - 1].sqrt();
    for r in 0..values.len() {
        for q in 0..values.len() {
            let expected = if r == q {
                2.0 * xi * values[r].sqrt()
            } else {
                0.0
            };
            assert!(
                (projected[(r, q)] - c64::new(expected, 0.0)).norm() <= 1e-9 * top,
                "({r}, {q})"
            );
        }
    }
}
