//! Time integration of the full wheel against harmonic balance points with
//! the regularized law: a stable point stays where the integration starts
//! it, and its energy balances over a period.

use cyclorub::case::Case;
use cyclorub::forced_response::ForcedResponse;
use cyclorub::simulate::start::from_harmonic_balance;
use cyclorub::simulate::{Drive, Ending, Simulation, SimulationSettings, State, WheelSetup};
use std::path::Path;

/// The default case (traveling wave h = 1 of 4 N, R-HBM, gap 1 mm) on a
/// wheel of N = 6 sectors, N_h = 10.
const SMALL_WHEEL: &str =
    "[model]\nsectors = 6\n[harmonic_balance]\nharmonics = 10\ntime_samples = 1200\n";

#[test]
fn a_stable_point_of_the_lower_branch_stays_on_it() {
    let case = Case::from_toml(SMALL_WHEEL, Path::new("case.toml")).unwrap();
    // The lower branch after the jump, followed down from 230 Hz to 5.6 µm
    // below the casing, 3 mHz above its fold (209.234 Hz): the regularized
    // law's force reaches 0.011 N there.
    let frequencies = vec![
        230.0, 220.0, 215.0, 212.0, 210.5, 209.8, 209.5, 209.32, 209.27, 209.237,
    ];
    let solution = ForcedResponse::from_case(&case)
        .unwrap()
        .at_frequencies_hz(frequencies)
        .build()
        .unwrap()
        .run(&mut [])
        .unwrap();
    let point = solution.branch.points.last().unwrap();
    assert!(point.converged);
    let summary = solution.point_summaries().pop().unwrap().unwrap();
    let amplitude = summary.observed.peak.clone();
    assert!(amplitude.iter().all(|a| (0.99e-3..1e-3).contains(a)));

    let setup = WheelSetup::from_case(&case, Path::new(".")).unwrap();
    let contacts = setup.loads.contact_count();
    let start = from_harmonic_balance(
        &solution.problem,
        &point.unknowns,
        point.omega,
        &setup.wheel,
        contacts,
    )
    .unwrap();
    // 4096 steps a period: the trapezoidal rule shifts frequencies by
    // (ωh)²/12 = 2e-7, which the resonance amplifies 500 times.
    let settings = SimulationSettings {
        steps_per_period: 4096,
        periods: 30,
        steady_tolerance: None,
        history_periods: 0,
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
    let deviation = outcome
        .periods
        .iter()
        .flat_map(|p| p.maxima.iter().zip(&amplitude))
        .fold(0.0_f64, |m, (x, a)| m.max((x - a).abs() / a));
    let last = outcome.periods.last().unwrap();
    let peak_force = last.peak_force.iter().fold(0.0_f64, |m, f| m.max(*f));
    println!(
        "{} periods: per-period maxima within {deviation:.2e} of the HBM amplitude; \
         peak contact force {peak_force:.3e} N; {:.0} steps/s",
        outcome.periods.len(),
        outcome.steps_per_second()
    );
    assert!(deviation < 1e-4, "deviation {deviation:.3e}");
    assert!(peak_force > 1e-2, "the law acts: {peak_force} N");
}

#[test]
fn at_steady_state_the_excitation_feeds_damping_and_contact() {
    // A heavily damped wheel of 6 sectors against an oval casing (order 2)
    // 10 µm away that it touches every period: the rotating casing does
    // work on the blades through the contact forces.
    let text = "[model]\nsectors = 6\n[model.damping]\nratio = 0.05\n\
                [casing]\ngap = 1e-5\norder = 2\namplitude = 3e-6\n";
    let case = Case::from_toml(text, Path::new("case.toml")).unwrap();
    let setup = WheelSetup::from_case(&case, Path::new(".")).unwrap();
    let settings = SimulationSettings {
        steps_per_period: 1024,
        periods: 300,
        steady_tolerance: Some(1e-10),
        history_periods: 0,
        ..SimulationSettings::default()
    };
    let start = State::at_rest(setup.wheel.size(), setup.loads.contact_count());
    let outcome = Simulation::new(
        setup.wheel.clone(),
        setup.loads.clone(),
        setup.law(),
        Drive::Fixed {
            omega: 2.0 * std::f64::consts::PI * 120.0,
        },
        settings,
        start,
        None,
    )
    .unwrap()
    .run(|_| {})
    .unwrap();
    assert!(matches!(outcome.ending, Ending::Steady { .. }));
    let last = outcome.periods.last().unwrap();
    let e = last.energy;
    let balance = (e.input - e.damping - e.contact).abs() / e.input;
    println!(
        "steady after {} periods; over the last: input {:.6e} J, damping {:.6e} J, \
         contact {:.6e} J, peak forces {:.2?} N; balance {balance:.1e}",
        outcome.periods.len(),
        e.input,
        e.damping,
        e.contact,
        last.peak_force
    );
    let rubbing = last.peak_force.iter().filter(|f| **f > 1.0).count();
    assert!(rubbing >= 2, "{rubbing} blades rub: {:?}", last.peak_force);
    assert!(
        e.contact.abs() > 0.1 * e.input,
        "the contact exchanges work"
    );
    assert!(balance < 1e-6, "balance {balance:.3e}");
}
