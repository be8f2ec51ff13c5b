//! The contact Jacobian, formed through the maps' nonzeros (cyclic) or band
//! by band (physical), against the dense formula
//! `Z + G̃ (T_law (a Ḡ + b Ḡ Z) + T_displacement Ḡ)` with every matrix
//! formed in full.

use super::*;
use crate::basis::SpectralBasis;
use crate::contact::{
    ContactModel, DynamicLagrangian, FrictionNode, RegularizedPenalty, RotationSpeed,
};
use crate::cyclic::ExcitationPattern;
use crate::hbm::layout::SectorMaps;
use crate::hbm::{Forcing, Formulation, ProblemSpec};
use crate::model::{BlockCirculantSector, Damping, SectorModel};
use std::f64::consts::PI;

const SECTORS: usize = 6;
const GAP: f64 = 1e-3;

/// A sector of seven dofs: two contact nodes' normal dofs (0, 1), their
/// circumferential and axial dofs (2, 3 and 4, 5), and a blade dof (6)
/// that holds them; coupled to the next sector through the blade and
/// normal dofs.
fn two_node_model() -> SectorModel {
    let stiffness = Mat::from_fn(7, 7, |r, c| {
        if r == c {
            3.0e5 + 2.0e4 * r as f64
        } else {
            -1.0e4 * (((r + c) % 5) as f64 + 1.0) / 5.0
        }
    });
    let masses = [0.3, 0.3, 0.25, 0.28, 0.25, 0.28, 1.0];
    let coupling = Mat::from_fn(7, 7, |r, c| match (r, c) {
        (6, 6) => -5.0e4,
        (0, 0) | (1, 1) => -1.0e4,
        _ => 0.0,
    });
    SectorModel::block_circulant(
        SECTORS,
        BlockCirculantSector {
            mass: Mat::from_fn(7, 7, |r, c| if r == c { masses[r] } else { 0.0 }),
            stiffness,
            mass_coupling: None,
            stiffness_coupling: Some(coupling),
        },
        Damping::Rayleigh {
            alpha: 2.0,
            beta: 1e-6,
        },
    )
    .unwrap()
}

/// The dense formula at the problem's last evaluation.
fn dense_jacobian(problem: &HarmonicBalance) -> Mat<f64> {
    let layout = problem.layout();
    let (n, rows, size) = (
        layout.unknowns,
        layout.sector_coordinates(),
        layout.coordinates(),
    );
    let (to_sectors, from_sectors) = match &layout.maps {
        SectorMaps::Identity => (Mat::identity(n, n), Mat::identity(n, n)),
        SectorMaps::Dense {
            to_sectors,
            from_sectors,
        } => (to_sectors.clone(), from_sectors.clone()),
    };
    let (mut law, mut displacement) = (Mat::zeros(rows, rows), Mat::zeros(rows, rows));
    for block in problem.contact_blocks() {
        let target: &mut Mat<f64> = if block.law {
            &mut law
        } else {
            &mut displacement
        };
        for r in 0..size {
            for c in 0..size {
                target[(block.row + r, block.column + c)] += block.values[r * size + c];
            }
        }
    }
    let input = problem.law().input();
    let (a, b) = (input.penetration, input.residual);
    let z = &problem.linear().dynamic;
    let mapped_z = &to_sectors * z;
    let operand = Mat::from_fn(rows, n, |r, c| {
        a * to_sectors[(r, c)] + b * mapped_z[(r, c)]
    });
    let inner = &law * &operand + &displacement * &to_sectors;
    z + &from_sectors * &inner
}

/// The largest difference between the Jacobian evaluated at a point in
/// contact and the dense formula, relative to the largest entry of the
/// formula's contact part (`J − Z`).
fn disagreement(spec: &ProblemSpec<'_>, formulation: &Formulation, omega: f64) -> f64 {
    let mut problem = spec.build(formulation).unwrap();
    // The linear response scaled to reach 1.5 times the gap: some instants
    // in contact, some not.
    let linear = problem.linear_solution(omega).unwrap();
    let samples = problem.contact_samples(&linear, omega).unwrap();
    let reach = samples
        .penetration
        .iter()
        .flatten()
        .fold(f64::MIN, |m, p| m.max(p + GAP));
    let x: Vec<f64> = linear.iter().map(|v| v * 1.5 * GAP / reach).collect();
    let samples = problem.contact_samples(&x, omega).unwrap();
    let penetration = samples.penetration.iter().flatten();
    let touching = penetration.clone().filter(|&&p| p > 0.0).count();
    assert!(
        touching > 0 && touching < penetration.count(),
        "the point touches the casing at some instants"
    );
    let mut out = Evaluation::default();
    problem.evaluate(&x, omega, true, &mut out).unwrap();
    let expected = dense_jacobian(&problem);
    let n = x.len();
    let z = &problem.linear().dynamic;
    let (mut worst, mut contact): (f64, f64) = (0.0, 0.0);
    for r in 0..n {
        for c in 0..n {
            worst = worst.max((out.jacobian[(r, c)] - expected[(r, c)]).abs());
            contact = contact.max((expected[(r, c)] - z[(r, c)]).abs());
        }
    }
    // The maps alone, as the residual uses them.
    if let SectorMaps::Dense { to_sectors, .. } = &problem.layout().maps {
        let mut mapped = vec![0.0; to_sectors.nrows()];
        problem.to_sectors(&x, &mut mapped);
        let scale = x.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
        for (r, m) in mapped.iter().enumerate() {
            let dense: f64 = (0..n).map(|c| to_sectors[(r, c)] * x[c]).sum();
            assert!((m - dense).abs() <= 1e-13 * scale, "Ḡ x row {r}");
        }
    }
    assert!(contact > 0.0, "the contact part is not empty");
    worst / contact
}

#[test]
fn contact_jacobian_equals_the_dense_formula() {
    let model = two_node_model();
    let omega = 1.002 * 2.0 * PI * model.natural_frequencies().unwrap()[1].1[0];
    let casing = Casing {
        gaps: vec![GAP, GAP],
        order: 0,
        amplitudes: vec![0.0, 0.0],
    };
    let friction = SlidingFriction::new(
        0.3,
        RotationSpeed::Fixed(30.0),
        vec![
            FrictionNode {
                circumferential: 2,
                axial: 3,
                radius: 0.4,
            },
            FrictionNode {
                circumferential: 4,
                axial: 5,
                radius: 0.45,
            },
        ],
    )
    .unwrap();
    let patterns = [
        (
            "partly standing h = 1 (Eq. 86 weights)",
            ExcitationPattern::Mixed {
                engine_order: 1,
                backward_weight: 0.9,
                forward_weight: 0.1,
            },
        ),
        (
            "traveling h = 1",
            ExcitationPattern::Traveling { engine_order: 1 },
        ),
    ];
    let laws = [
        (
            "regularized",
            ContactModel::Regularized(RegularizedPenalty::new(2e6, 0.5).unwrap()),
        ),
        (
            "dlft",
            ContactModel::Lagrangian(DynamicLagrangian::new(2e6, None).unwrap()),
        ),
    ];
    for (pattern_name, pattern) in patterns {
        let forcing = Forcing {
            pattern,
            amplitude: 40.0,
            dofs: vec![6],
            static_force: 0.0,
        };
        for (law_name, law) in &laws {
            for with_friction in [true, false] {
                let spec = ProblemSpec {
                    model: &model,
                    contact_dofs: &[0, 1],
                    forcing: Some(&forcing),
                    casing: &casing,
                    contact: law.clone(),
                    friction: with_friction.then_some(&friction),
                    preload: None,
                    harmonics: 3,
                    time_samples: 8 * SECTORS,
                };
                let basis = SpectralBasis::symmetry(&spec.load_case(), spec.harmonics).unwrap();
                let pairs = basis.nodal_diameters(1).len();
                for (basis_name, formulation) in [
                    ("symmetry", Formulation::Cyclic(basis)),
                    ("physical", Formulation::Physical),
                ] {
                    let relative = disagreement(&spec, &formulation, omega);
                    println!(
                        "{pattern_name} ({pairs} pairs on k = 1), {law_name}, friction \
                         {with_friction}, {basis_name}: {relative:.2e}"
                    );
                    assert!(
                        relative < 1e-12,
                        "{pattern_name} {law_name} friction {with_friction} {basis_name}: \
                         {relative:e}"
                    );
                }
            }
        }
    }
}
