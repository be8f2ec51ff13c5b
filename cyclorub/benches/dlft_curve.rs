//! Benchmark: whole DLFT-HBM forced response curves with the paper's
//! parameters (Sec. 4.1: `N_h = 10`, `N_t = 10000`, wall `κ = 1e8 N/m`,
//! `ε = 1e9 N/m`), academic model N = 24, traveling wave h = 1 of 4 N, from
//! 0.95 to 1.10 times the first 1-diameter resonance: the symmetry
//! (traveling-wave) basis and the physical full model.
//! Run with `cargo bench -p cyclorub --bench dlft_curve`.

use cyclorub::basis::SpectralBasis;
use cyclorub::contact::{ContactModel, DynamicLagrangian};
use cyclorub::continuation::{continue_branch, ArcLengthSettings, NewtonSettings, Problem};
use cyclorub::cyclic::ExcitationPattern;
use cyclorub::hbm::{Casing, Forcing, Formulation, ProblemSpec};
use cyclorub::model::SectorModel;
use std::f64::consts::PI;
use std::time::Instant;

fn curve(
    spec: &ProblemSpec<'_>,
    name: &str,
    formulation: &Formulation,
    resonance_hz: f64,
) -> Result<(), Box<dyn std::error::Error>> {
    let clock = Instant::now();
    let mut problem = spec.build(formulation)?;
    let setup = clock.elapsed().as_secs_f64();
    // The case file's defaults.
    let settings = ArcLengthSettings {
        start: 2.0 * PI * 0.95 * resonance_hz,
        end: 2.0 * PI * 1.10 * resonance_hz,
        initial_step: 0.01,
        min_step: 1e-7,
        max_step: 0.1,
        length_scale: 1e-3,
        newton: NewtonSettings {
            tolerance: 1e-8,
            max_iterations: 15,
            ..Default::default()
        },
        max_points: 5000,
    };
    let clock = Instant::now();
    let guess = problem.linear_solution(settings.start)?;
    let branch = continue_branch(&mut problem, guess, &settings, |_, _| {});
    let wall = clock.elapsed().as_secs_f64();
    println!(
        "{name:<9} unknowns {:>4}  set-up {setup:>7.3} s  curve {wall:>8.3} s  points {:>4}  Newton iterations {:>5}  {:>8.3} ms/iteration  stop {:?}",
        problem.unknowns(),
        branch.points.len(),
        branch.total_iterations,
        1e3 * wall / branch.total_iterations.max(1) as f64,
        branch.stop
    );
    Ok(())
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let model = SectorModel::academic(24)?;
    let resonance_hz = model
        .natural_frequencies()?
        .iter()
        .find(|(d, _)| *d == 1)
        .and_then(|(_, f)| f.first().copied())
        .ok_or("no 1-diameter mode")?;
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
        contact: ContactModel::Lagrangian(DynamicLagrangian::new(1e9, Some(1e8))?),
        friction: None,
        preload: None,
        harmonics: 10,
        time_samples: 10_000,
    };
    println!(
        "forced response, N = 24, traveling wave h = 1, 4 N, N_h = 10, N_t = 10000, DLFT-HBM (κ = 1e8 N/m, ε = 1e9 N/m)"
    );
    let basis = SpectralBasis::symmetry(&spec.load_case(), spec.harmonics)?;
    curve(&spec, "symmetry", &Formulation::Cyclic(basis), resonance_hz)?;
    curve(&spec, "physical", &Formulation::Physical, resonance_hz)?;
    Ok(())
}
