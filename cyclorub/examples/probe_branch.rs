use cyclorub::basis::SpectralBasis;
use cyclorub::contact::{ContactModel, RegularizedPenalty};
use cyclorub::continuation::{continue_branch, ArcLengthSettings, NewtonSettings};
use cyclorub::cyclic::ExcitationPattern;
use cyclorub::hbm::{Casing, Forcing, Formulation, ProblemSpec};
use cyclorub::model::SectorModel;
use std::f64::consts::PI;
fn main() {
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
        time_samples: std::env::args().nth(1).map_or(128, |a| a.parse().unwrap()),
    };
    let basis = SpectralBasis::symmetry(&spec.load_case(), 10).unwrap();
    let mut p = spec.build(&Formulation::Cyclic(basis)).unwrap();
    let start = 2.0 * PI * f * 0.9;
    let s = ArcLengthSettings {
        start,
        end: 2.0 * PI * f * 1.3,
        initial_step: 0.01,
        min_step: 1e-6,
        max_step: 0.2,
        length_scale: 1e-3,
        newton: NewtonSettings {
            tolerance: 1e-8,
            max_iterations: 12,
        },
        max_points: 400,
    };
    let g = p.linear_solution(start).unwrap();
    let t = std::time::Instant::now();
    let b = continue_branch(&mut p, g, &s, |pt, pr| {
        if pr.points % 1 == 0 {
            println!(
                "{} {:.4} Hz it {} step {:.3e} x1 {:.3e}",
                pr.points,
                pr.frequency_hz,
                pt.iterations,
                pr.step,
                pt.unknowns[1].hypot(pt.unknowns[2])
            )
        }
    });
    println!(
        "{:?} {} pts {} its {:?}",
        b.stop,
        b.points.len(),
        b.total_iterations,
        t.elapsed()
    );
}
