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

/// The same check on the open fan (coarse mesh, Craig–Bampton per nodal
/// diameter, 16 × 53 dofs, 27 contact dofs a sector with friction, the
/// regularized law, centrifugal preload) at one contact frequency.
mod fan {
    use super::*;
    use cyclorub::case::{LawKind, PerContactDof};
    use cyclorub::mesh::{assemble, fan, write_fan, FanGeometry};
    use std::path::PathBuf;

    fn folder() -> PathBuf {
        let dir =
            std::env::temp_dir().join(format!("cyclorub-accuracy-fan-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        let mesh = fan(16, 1, &FanGeometry::default()).unwrap();
        let matrices = assemble(&mesh.mesh).unwrap();
        write_fan(&mesh, &matrices, &dir, false).unwrap();
        dir
    }

    /// Engine order 4 near the first family (282 Hz), a 20 µm gap, and
    /// modal damping 1e-2 (ten times the paper's) so that the wheel settles
    /// in tens of periods: the test's length, not its physics.
    fn case(dir: &Path, harmonics: usize) -> Case {
        let mut case = Case::from_file_checked(&dir.join("fan16.toml")).unwrap();
        case.excitation.engine_order = 4;
        case.contact.law = LawKind::Regularized;
        case.casing.gap = PerContactDof::One(2e-5);
        case.harmonic_balance.harmonics = harmonics;
        case.harmonic_balance.time_samples = 512;
        case.stability.enabled = false;
        case.model.damping.ratios = Some(vec![1e-2; 5]);
        case.model.damping.others = Some(1e-2);
        case
    }

    /// The branch swept up to 283.5 Hz (in contact from about 281 Hz).
    fn solved(dir: &Path, harmonics: usize) -> (Case, Solution) {
        let case = case(dir, harmonics);
        let frequencies = vec![
            270.0, 274.0, 277.0, 279.0, 280.0, 281.0, 282.0, 283.0, 283.5,
        ];
        let solution = ForcedResponse::from_case(&case)
            .unwrap()
            .case_dir(dir)
            .at_frequencies_hz(frequencies)
            .build()
            .unwrap()
            .run(&mut [])
            .unwrap();
        assert!(solution.branch.points.iter().all(|p| p.converged));
        (case, solution)
    }

    /// Measured: N_h = 12 and 24 give 1.62262e-4 and 1.62172e-4 m (5.5e-4
    /// apart, 2.0e-3 from N_h = 6: the series converges by a factor ~3.7,
    /// so N_h = 24 is within ~2e-4 of its limit); 30 periods from the
    /// N_h = 24 point settle at 1.62206e-4 m (2.1e-4 from it); the plain
    /// scheme (40 periods) at 1.6224e-4 (4.2e-4: the contact's stiffening makes the
    /// period error matter less here than on the academic lower sheet).
    /// 70 of the 512 × 27 samples touch the casing.
    #[test]
    fn at_default_settings_the_fans_steady_amplitude_in_contact_is_the_converged_harmonic_balances()
    {
        let dir = folder();
        let (_, coarse) = solved(&dir, 12);
        let (case, mut fine) = solved(&dir, 24);
        let reference = amplitude(&fine);
        assert!(
            (amplitude(&coarse) - reference).abs() < 1e-3 * reference,
            "N_h = 12: {:.6e} m, N_h = 24: {reference:.6e} m",
            amplitude(&coarse)
        );
        let point = fine.branch.points.last().unwrap().clone();
        let samples = fine
            .problem
            .contact_samples(&point.unknowns, point.omega)
            .unwrap();
        let touching = samples
            .penetration
            .iter()
            .flatten()
            .filter(|&&p| p > 0.0)
            .count();
        assert!(touching > 0, "the fan does not touch its casing");
        let setup = WheelSetup::from_case(&case, &dir).unwrap();
        let contacts = setup.loads.contact_count();
        let start = from_harmonic_balance(
            &fine.problem,
            &point.unknowns,
            point.omega,
            &setup.wheel,
            contacts,
        )
        .unwrap();
        let settings = SimulationSettings {
            periods: 30,
            steady_tolerance: None,
            history_periods: 0,
            observed_dof: case.output.observed_index(),
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
        let _ = std::fs::remove_dir_all(&dir);
        let settled = outcome
            .periods
            .last()
            .unwrap()
            .maxima
            .iter()
            .fold(0.0_f64, |m, a| m.max(*a));
        let error = (settled - reference).abs() / reference;
        println!("reference {reference:.6e} m, settled {settled:.6e} m ({error:.2e}), {touching} samples touching");
        assert!(
            error < 1e-3,
            "settled {settled:.6e} m against {reference:.6e} m: {error:.3e}"
        );
    }
}
