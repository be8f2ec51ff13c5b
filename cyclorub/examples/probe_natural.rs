use cyclorub::basis::SpectralBasis;
use cyclorub::contact::{ContactModel, RegularizedPenalty};
use cyclorub::continuation::{solve_at_frequencies, NewtonSettings};
use cyclorub::cyclic::ExcitationPattern;
use cyclorub::hbm::{Casing, Forcing, Formulation, ProblemSpec};
use cyclorub::model::SectorModel;
use std::f64::consts::PI;
fn main() {
    let nt: usize = std::env::args().nth(1).map_or(240, |a| a.parse().unwrap());
    let model = SectorModel::academic(24).unwrap();
    let f = model.natural_frequencies().unwrap()[1].1[0];
    let forcing = Forcing {
        pattern: ExcitationPattern::Traveling { engine_order: 1 },
        amplitude: 4.0,
        dofs: vec![0],
        static_force: 0.0,
    };
    let casing = Casing {
        gaps: vec![1e-3],
        order: 0,
        amplitudes: vec![0.0],
    };
    let spec = ProblemSpec {
        model: &model,
        contact_dofs: &[0],
        forcing: Some(&forcing),
        casing: &casing,
        contact: ContactModel::Regularized(RegularizedPenalty::new(1e8, 2.5).unwrap()),
        harmonics: 10,
        time_samples: nt,
    };
    let basis = SpectralBasis::symmetry(&spec.load_case(), 10).unwrap();
    let mut p = spec.build(&Formulation::Cyclic(basis)).unwrap();
    let omegas: Vec<f64> = (0..21)
        .map(|i| 2.0 * PI * f * (0.99 + 0.001 * i as f64))
        .collect();
    let g = p.linear_solution(omegas[0]).unwrap();
    let b = solve_at_frequencies(
        &mut p,
        g,
        &omegas,
        &NewtonSettings {
            tolerance: 1e-10,
            max_iterations: 60,
        },
        |pt, _| {
            println!(
                "{:.4} conv {} it {} r {:.2e} x1 {:.4e}",
                pt.omega / 2.0 / PI,
                pt.converged,
                pt.iterations,
                pt.residual_norm,
                pt.unknowns[1].hypot(pt.unknowns[2])
            )
        },
    );
    println!("{:?}", b.stop);
}
