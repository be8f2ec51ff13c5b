//! Time integration at its default settings against the converged
//! harmonic balance, near resonance on the default case: what the
//! dispersion correction guarantees (docs/time-integration.md).

use cyclorub::case::Case;
use cyclorub::forced_response::{ForcedResponse, Solution};
use cyclorub::simulate::start::from_harmonic_balance;
use cyclorub::simulate::{Drive, Simulation, SimulationSettings, WheelSetup};
use std::path::Path;

/// The default case's lower branch swept down to 128.3 Hz (between the
/// folds at 127.92 and 129.99 Hz: the sweep stays on the lower sheet,
/// about 0.414 mm at the blade tip) with `harmonics` harmonics.
fn lower_branch_at_128_3_hz(harmonics: usize) -> (Case, Solution) {
    let text =
        format!("[harmonic_balance]\nharmonics = {harmonics}\n[stability]\nenabled = false\n");
    let case = Case::from_toml(&text, Path::new("case.toml")).unwrap();
    let frequencies = vec![
        135.0, 131.0, 130.0, 129.5, 129.0, 128.75, 128.5, 128.4, 128.3,
    ];
    let solution = ForcedResponse::from_case(&case)
        .unwrap()
        .at_frequencies_hz(frequencies)
        .build()
        .unwrap()
        .run(&mut [])
        .unwrap();
    assert!(solution.branch.points.iter().all(|p| p.converged));
    (case, solution)
}

/// The largest blade-tip amplitude over the sectors at the branch's last
/// point, m.
fn amplitude(solution: &Solution) -> f64 {
    let summary = solution.point_summaries().pop().unwrap().unwrap();
    summary.observed.peak.iter().fold(0.0_f64, |m, a| m.max(*a))
}

/// The largest sector maximum over the last period after `periods`
/// periods from the harmonic balance point, m.
fn settled(case: &Case, solution: &Solution, periods: usize, dispersion_correction: bool) -> f64 {
    let point = solution.branch.points.last().unwrap();
    let setup = WheelSetup::from_case(case, Path::new(".")).unwrap();
    let contacts = setup.loads.contact_count();
    let start = from_harmonic_balance(
        &solution.problem,
        &point.unknowns,
        point.omega,
        &setup.wheel,
        contacts,
    )
    .unwrap();
    let settings = SimulationSettings {
        periods,
        steady_tolerance: None,
        history_periods: 0,
        dispersion_correction,
        ..SimulationSettings::default()
    };
    let outcome = Simulation::new(
        setup.wheel.clone(),
        setup.loads.clone(),
        setup.law(),
        Drive::Fixed { omega: point.omega },
        settings,
        start,
        None,
    )
    .unwrap()
    .run(|_| {})
    .unwrap();
    let last = outcome.periods.last().unwrap();
    last.maxima.iter().fold(0.0_f64, |m, a| m.max(*a))
}

#[test]
fn at_default_settings_the_steady_amplitude_near_resonance_is_the_converged_harmonic_balances() {
    // The reference: the harmonic balance with 10 and with 20 harmonics
    // agree to 1e-4 there (converged).
    let (case, coarse) = lower_branch_at_128_3_hz(10);
    let (_, fine) = lower_branch_at_128_3_hz(20);
    let reference = amplitude(&fine);
    assert!(
        (amplitude(&coarse) - reference).abs() < 1e-4 * reference,
        "N_h = 10: {:.6e} m, N_h = 20: {reference:.6e} m",
        amplitude(&coarse)
    );
    // Started on the harmonic balance point, the wheel drifts to the
    // scheme's own steady state with the light damping's time constant
    // (a few hundred periods): after 500 periods most of any bias shows.
    // At the default 256 steps a period with the dispersion correction,
    // it settles within 0.1 % of the converged amplitude; the plain
    // average-acceleration scheme drifts by more (the check can fail).
    let periods = 500;
    let corrected = settled(&case, &coarse, periods, true);
    let plain = settled(&case, &coarse, periods, false);
    let error = |a: f64| (a - reference).abs() / reference;
    println!(
        "reference {reference:.6e} m; corrected {corrected:.6e} m ({:.2e}); plain {plain:.6e} m ({:.2e})",
        error(corrected),
        error(plain)
    );
    assert!(
        error(corrected) < 1e-3,
        "corrected: {:.3e}",
        error(corrected)
    );
    assert!(error(plain) > 2e-3, "plain: {:.3e}", error(plain));
}
