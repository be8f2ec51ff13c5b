//! The explicit scheme with Lagrange multipliers (`law = "dlft"`, rigid
//! casing): a single mass hitting a rigid wall against the closed form,
//! and no penetration at any step of a rubbing wheel.

use cyclorub::case::Case;
use cyclorub::simulate::{Drive, Simulation, SimulationSettings, State, WheelSetup};
use std::path::Path;

fn setup(text: &str) -> WheelSetup {
    let case = Case::from_toml(text, Path::new("case.toml")).expect("a valid case");
    WheelSetup::from_case(&case, Path::new(".")).expect("a wheel")
}

#[test]
fn a_mass_on_a_spring_hits_the_wall_plastically_as_the_closed_form_says() {
    // m = 1 kg, k = 1e4 N/m (ω = 100 rad/s), launched at 0.2 m/s toward a
    // rigid wall 1 mm away: x = (v0/ω) sin ωt until it touches at
    // t1 = asin(g ω / v0) / ω; the impact is plastic, so it leaves the wall
    // at rest: x = g cos ω(t − t1), back to the wall without impact at
    // t1 + 2π/ω.
    let setup = setup(
        "[model]\nkind = \"matrices\"\nsectors = 1\nmass = [[1.0]]\nstiffness = [[1e4]]\n\
         [model.damping]\nkind = \"none\"\n[excitation]\nkind = \"none\"\n\
         [casing]\ngap = 1e-3\n[contact]\nlaw = \"dlft\"\n",
    );
    let (omega, v0, gap) = (100.0_f64, 0.2, 1e-3);
    let mut start = State::at_rest(1, 1);
    start.velocity[0] = v0;
    let settings = SimulationSettings {
        steps_per_period: 20_000,
        periods: 2,
        steady_tolerance: None,
        history_periods: 2,
        ..SimulationSettings::default()
    };
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
    let t1 = (gap * omega / v0).asin() / omega;
    let exact = |t: f64| {
        if t < t1 {
            v0 / omega * (omega * t).sin()
        } else {
            gap * (omega * (t - t1)).cos()
        }
    };
    let h = &outcome.history;
    let mut error = 0.0_f64;
    let mut highest = f64::NEG_INFINITY;
    for (t, x) in h.time.iter().zip(&h.observed_displacement) {
        highest = highest.max(*x);
        if *t < t1 + 1.9 * std::f64::consts::PI / omega {
            error = error.max((x - exact(*t)).abs());
        }
    }
    println!(
        "largest error {:.2e} of the gap at h = {:.2e} s; highest position {:.3e} m",
        error / gap,
        outcome.step,
        highest
    );
    assert!(highest <= gap * (1.0 + 1e-12), "no penetration: {highest}");
    assert!(error < 1e-3 * gap, "error {error:.3e} m");
}

#[test]
fn a_rubbing_wheel_never_enters_its_casing() {
    // Five times the default excitation on 6 sectors at the first family's ND 1
    // resonance: the blades would swing far past the 1 mm gap.
    let setup =
        setup("[model]\nsectors = 6\n[excitation]\namplitude = 20.0\n[contact]\nlaw = \"dlft\"\n");
    let settings = SimulationSettings {
        steps_per_period: 1024,
        periods: 40,
        steady_tolerance: None,
        history_periods: 40,
        ..SimulationSettings::default()
    };
    let start = State::at_rest(setup.wheel.size(), setup.loads.contact_count());
    let outcome = Simulation::new(
        setup.wheel.clone(),
        setup.loads.clone(),
        setup.law(),
        Drive::Fixed {
            omega: 2.0 * std::f64::consts::PI * 208.1,
        },
        settings,
        start,
        None,
    )
    .unwrap()
    .run(|_| {})
    .unwrap();
    let h = &outcome.history;
    let deepest = h
        .contact_displacement
        .iter()
        .fold(f64::NEG_INFINITY, |m, x| m.max(*x));
    let contacts = h.contact_force.iter().filter(|f| **f > 0.0).count();
    println!(
        "{} steps, {contacts} sector-steps in contact, deepest position {deepest:.6e} m, {:.0} steps/s",
        h.time.len(),
        outcome.steps_per_second()
    );
    assert!(contacts > 100, "the blades reach the casing");
    assert!(deepest <= 1e-3 * (1.0 + 1e-12), "penetration: {deepest}");
}
