//! Time integration of the full wheel against closed-form oracles: the
//! block-circulant operators against the assembled full wheel, and the
//! steady state of a wheel that never touches its casing against the
//! linear forced response (harmonic balance of a linear system is exact),
//! in time and in the spectrum of its last periods.

use cyclorub::case::{BasisChoice, Case};
use cyclorub::forced_response::prepare;
use cyclorub::simulate::circulant::CirculantFactorization;
use cyclorub::simulate::spectrum::Window;
use cyclorub::simulate::start::from_harmonic_balance;
use cyclorub::simulate::{Drive, Ending, Simulation, SimulationSettings, State, WheelSetup};
use std::f64::consts::PI;
use std::path::Path;

fn case(text: &str) -> Case {
    Case::from_toml(text, Path::new("case.toml")).expect("a valid case")
}

/// A small wheel (N = 6) of the academic sector, heavily damped so that
/// transients die in tens of periods, with a casing out of reach.
const FAR_CASING: &str = r#"
[model]
sectors = 6
[model.damping]
ratio = 0.05
[casing]
gap = 1.0
[contact]
regularization = 0.0
"#;

#[test]
fn the_circulant_operators_are_the_assembled_full_wheel() {
    let case = case(FAR_CASING);
    let setup = WheelSetup::from_case(&case, Path::new(".")).unwrap();
    let full = setup.model.full_wheel().unwrap();
    let size = setup.wheel.size();
    let x: Vec<f64> = (0..size).map(|i| ((i * 7 + 3) % 11) as f64 - 5.0).collect();
    for (operator, dense) in [
        (&setup.wheel.mass, &full.mass),
        (&setup.wheel.stiffness, &full.stiffness),
        (&setup.wheel.damping, &full.damping),
    ] {
        let mut y = vec![0.0; size];
        operator.apply_add(1.0, &x, &mut y);
        let scale = (0..size)
            .flat_map(|i| (0..size).map(move |j| (i, j)))
            .fold(0.0_f64, |m, (i, j)| m.max(dense[(i, j)].abs()));
        for (i, yi) in y.iter().enumerate() {
            let expected: f64 = (0..size).map(|j| dense[(i, j)] * x[j]).sum();
            assert!((yi - expected).abs() <= 1e-12 * scale * 10.0, "row {i}");
        }
    }
    // The lumped chain couples neighbours only; modal damping every sector.
    assert_eq!(setup.wheel.stiffness.offsets(), vec![0, 1, 5]);
    // Solving with K + 3 C + 5 M inverts the assembled matrix.
    let mut factorization = CirculantFactorization::new(&setup.wheel, 1.0, 3.0, 5.0).unwrap();
    let mut solution = vec![0.0; size];
    factorization.solve(&x, &mut solution);
    for (i, xi) in x.iter().enumerate() {
        let back: f64 = (0..size)
            .map(|j| {
                (full.stiffness[(i, j)] + 3.0 * full.damping[(i, j)] + 5.0 * full.mass[(i, j)])
                    * solution[j]
            })
            .sum();
        assert!((back - xi).abs() < 1e-9 * 5.0, "row {i}: {back} vs {xi}");
    }
}

#[test]
fn the_dispersion_correction_makes_the_steady_state_exact_and_the_plain_scheme_is_of_order_2() {
    // 32 steps a period: the trapezoidal rule's frequency error (Ωh)²/12 is
    // 3e-3, which moves the steady state by about that much; on the wheel
    // warped at the excitation frequency the displacement at each period's
    // end is the closed form to the steady tolerance.
    let case = case(FAR_CASING);
    let setup = WheelSetup::from_case(&case, Path::new(".")).unwrap();
    let frequency_hz = 125.0;
    let omega = 2.0 * PI * frequency_hz;
    let mut prepared = prepare(&case, Path::new("."), BasisChoice::Symmetry).unwrap();
    let linear = prepared.problem.linear_solution(omega).unwrap();
    let contacts = setup.loads.contact_count();
    let reference =
        from_harmonic_balance(&prepared.problem, &linear, omega, &setup.wheel, contacts).unwrap();
    let error_with = |steps_per_period: usize, dispersion_correction: bool| {
        let settings = SimulationSettings {
            steps_per_period,
            periods: 400,
            steady_tolerance: Some(1e-11),
            history_periods: 0,
            dispersion_correction,
            ..SimulationSettings::default()
        };
        let simulation = Simulation::new(
            setup.wheel.clone(),
            setup.loads.clone(),
            setup.law(),
            Drive::Fixed { omega },
            settings,
            State::at_rest(setup.wheel.size(), contacts),
            None,
        )
        .unwrap();
        assert_eq!(
            simulation.dispersion_ratio().is_some(),
            dispersion_correction
        );
        let outcome = simulation.run(|_| {}).unwrap();
        assert!(matches!(outcome.ending, Ending::Steady { .. }));
        let (x, reference) = (&outcome.last_state.displacement, &reference.displacement);
        let largest = reference.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
        x.iter()
            .zip(reference)
            .fold(0.0_f64, |m, (a, b)| m.max((a - b).abs()))
            / largest
    };
    let (corrected, plain) = (error_with(32, true), error_with(32, false));
    println!("relative displacement error at 32 steps a period: corrected {corrected:.2e}, plain {plain:.2e}");
    assert!(corrected < 1e-8, "{corrected:e}");
    assert!(plain > 1e-4, "{plain:e}");
    // The scheme as given is of order 2: halving the step divides the
    // steady state's error by 4.
    let errors: Vec<f64> = [16, 32, 64].iter().map(|&n| error_with(n, false)).collect();
    for pair in errors.windows(2) {
        let order = (pair[0] / pair[1]).log2();
        println!("order {order:.3}");
        assert!((order - 2.0).abs() < 0.05, "{errors:?}");
    }
}

#[test]
fn the_linear_steady_state_is_the_closed_form_forced_response() {
    let case = case(FAR_CASING);
    let setup = WheelSetup::from_case(&case, Path::new(".")).unwrap();
    // Below the first family's ND 1 resonance (about 128 Hz).
    let frequency_hz = 110.0;
    let omega = 2.0 * PI * frequency_hz;
    let mut prepared = prepare(&case, Path::new("."), BasisChoice::Symmetry).unwrap();
    let linear = prepared.problem.linear_solution(omega).unwrap();
    let contacts = setup.loads.contact_count();
    // The reference: the forced response at phase 0 on every dof.
    let reference =
        from_harmonic_balance(&prepared.problem, &linear, omega, &setup.wheel, contacts).unwrap();
    let settings = SimulationSettings {
        steps_per_period: 4000,
        periods: 200,
        steady_tolerance: Some(1e-9),
        history_periods: 2,
        ..SimulationSettings::default()
    };
    let start = State::at_rest(setup.wheel.size(), contacts);
    let outcome = Simulation::new(
        setup.wheel.clone(),
        setup.loads.clone(),
        setup.law(),
        Drive::Fixed { omega },
        settings,
        start,
        None,
    )
    .unwrap()
    .run(|_| {})
    .unwrap();
    assert!(
        matches!(outcome.ending, Ending::Steady { .. }),
        "{:?} after {} periods",
        outcome.ending,
        outcome.periods.len()
    );
    // The state at a period's end is the forced response at phase 0; the
    // trapezoidal rule's error is (ωh)²/12 ≈ 2e-7 at 4000 steps a period.
    let error = |a: &[f64], b: &[f64]| {
        let largest = b.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
        a.iter()
            .zip(b)
            .fold(0.0_f64, |m, (x, y)| m.max((x - y).abs()))
            / largest
    };
    let x_error = error(&outcome.last_state.displacement, &reference.displacement);
    let v_error = error(&outcome.last_state.velocity, &reference.velocity);
    println!(
        "steady after {} periods; relative error: displacement {x_error:.2e}, velocity {v_error:.2e}; {:.0} steps/s",
        outcome.periods.len(),
        outcome.steps_per_second()
    );
    assert!(x_error < 1e-6 && v_error < 1e-6);
    // The spectrum of the last two periods: the closed-form amplitude
    // `√(x² + (v/ω)²)` of the observed dof on its bin (the excitation is
    // bin 2), nothing on the others.
    let sectors = setup.model.sectors();
    let dofs = setup.model.dofs_per_sector();
    let observed = settings.observed_dof;
    let spectra = outcome
        .history
        .observed_spectra(sectors, outcome.step, Window::Rectangular);
    assert!((spectra.frequency_hz[2] - frequency_hz).abs() < 1e-9 * frequency_hz);
    for j in 0..sectors {
        let i = j * dofs + observed;
        let expected = reference.displacement[i].hypot(reference.velocity[i] / omega);
        let amplitude = &spectra.amplitude[j];
        assert!(
            (amplitude[2] - expected).abs() < 1e-6 * expected,
            "sector {j}: {} vs {expected}",
            amplitude[2]
        );
        let elsewhere = amplitude
            .iter()
            .enumerate()
            .filter(|(k, _)| *k != 2)
            .fold(0.0_f64, |m, (_, a)| m.max(*a));
        assert!(elsewhere < 1e-6 * expected, "sector {j}: {elsewhere}");
    }
    // simulation.h5 holds the recorded steps bit for bit, in its layout.
    #[cfg(feature = "hdf5")]
    {
        let path = std::env::temp_dir().join(format!(
            "cyclorub-simulate-linear-{}.h5",
            std::process::id()
        ));
        cyclorub::simulate::hdf5::write(&path, &outcome, observed + 1).unwrap();
        let file = hdf5_pure::File::open(&path).unwrap();
        let h = &outcome.history;
        let steps = h.time.len();
        let contacts = setup.loads.contact_dofs().len();
        for (name, values, shape) in [
            ("history/time_s", &h.time, vec![steps]),
            (
                "history/displacement",
                &h.observed_displacement,
                vec![steps, sectors],
            ),
            (
                "history/contact_velocity",
                &h.contact_velocity,
                vec![steps, sectors, contacts],
            ),
            (
                "history/contact_force",
                &h.contact_force,
                vec![steps, sectors, contacts],
            ),
        ] {
            let dataset = file.dataset(name).unwrap();
            let read: Vec<usize> = dataset
                .shape()
                .unwrap()
                .iter()
                .map(|&d| d as usize)
                .collect();
            assert_eq!(read, shape, "{name}");
            assert_eq!(&dataset.read_f64().unwrap(), values, "{name}");
        }
        // The contact dof's velocity is the state's, at the last step.
        let last =
            outcome.last_state.velocity[setup.loads.contact_index(sectors - 1, contacts - 1)];
        assert_eq!(h.contact_velocity.last(), Some(&last));
        std::fs::remove_file(&path).ok();
    }
}
