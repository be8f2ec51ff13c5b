//! The explicit scheme with Lagrange multipliers (`law = "dlft"`, rigid
//! casing): a single mass hitting a rigid wall against the closed form,
//! no penetration at any step of a rubbing wheel, and a node pressed on a
//! sliding casing with friction against the closed form.

use cyclorub::case::Case;
use cyclorub::simulate::lagrange::CentralDifference;
use cyclorub::simulate::{Drive, Simulation, SimulationSettings, State, WheelSetup};
use std::f64::consts::PI;
use std::path::Path;
use std::sync::Arc;

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

#[test]
fn too_few_steps_for_the_explicit_scheme_are_raised_to_its_stable_count() {
    // 8 steps a period of the 6-sector wheel at 208 Hz: far above the
    // bound 2/ω_max. The integration takes the bound's count (a multiple of
    // the sectors) and runs; the count it takes is stable (a few periods
    // stay bounded) and not far above what the bound asks.
    let setup =
        setup("[model]\nsectors = 6\n[excitation]\namplitude = 20.0\n[contact]\nlaw = \"dlft\"\n");
    let omega = 2.0 * PI * 208.1;
    let settings = SimulationSettings {
        steps_per_period: 8,
        periods: 5,
        steady_tolerance: None,
        history_periods: 0,
        ..SimulationSettings::default()
    };
    let start = State::at_rest(setup.wheel.size(), setup.loads.contact_count());
    let simulation = Simulation::new(
        setup.wheel.clone(),
        setup.loads.clone(),
        setup.law(),
        Drive::Fixed { omega },
        settings,
        start.clone(),
        None,
    )
    .expect("a stable count is taken");
    let steps = simulation.steps_per_period();
    assert_eq!(simulation.steps_raised_from(), Some(8));
    assert_eq!(steps % 6, 0);
    // One fewer block of sectors is refused: the count is the least one.
    let fewer = SimulationSettings {
        steps_per_period: steps - 6,
        ..settings
    };
    let below = CentralDifference::new(
        setup.wheel.clone(),
        setup.loads.clone(),
        None,
        Drive::Fixed { omega },
        2.0 * PI / omega / fewer.steps_per_period as f64,
        start,
    );
    assert!(
        matches!(
            below,
            Err(cyclorub::simulate::SimulateError::StepTooLong { .. })
        ),
        "{steps} steps a period"
    );
    let outcome = simulation.run(|_| {}).unwrap();
    assert_eq!(outcome.steps, 5 * steps as u64);
    assert!(outcome
        .last_state
        .displacement
        .iter()
        .all(|x| x.is_finite() && x.abs() < 1.0));
}

/// A node pressed on a rigid casing by a static force `P` while the casing
/// slides past it at `ρΩ` (far above the node's own velocity, so that the
/// sliding direction stays circumferential): with the mass coupling `m_c`
/// between its normal and circumferential dofs, the constraint `x_N = g`
/// gives `(m_θ − μ m_c) ẍ_θ + k_θ x_θ = −μ λ0` and the multiplier
/// `λ = λ0 − m_c ẍ_θ`, `λ0 = P − k_N g`. The explicit scheme holds both
/// (the friction's coupling enters its complementarity problem). With a
/// wall `κ` in series (and `m_c = 0`) the node rests at
/// `x_N = (P + κ g)/(k_N + κ)` under `λ0 = κ (x_N − g)`.
fn pressed_node_slides_as_the_closed_form_says(coupling: f64, wall: Option<f64>) {
    let (m_theta, k_normal, k_theta, gap, mu) = (0.5_f64, 1e4, 2e4, 1e-3, 0.2);
    let setup = setup(&format!(
        "[model]\nkind = \"matrices\"\nsectors = 1\n\
         mass = [[1.0, {coupling}, 0.0], [{coupling}, {m_theta}, 0.0], [0.0, 0.0, 0.5]]\n\
         stiffness = [[{k_normal}, 0.0, 0.0], [0.0, {k_theta}, 0.0], [0.0, 0.0, 2e4]]\n\
         [model.damping]\nkind = \"none\"\n[excitation]\nkind = \"none\"\n\
         [casing]\ngap = {gap}\n[contact]\nlaw = \"dlft\"\ndofs = [1]\nfriction = {mu}\n\
         circumferential_dofs = [2]\naxial_dofs = [3]\nradius = 0.5\n{}[rotation]\nspeed = 100.0\n",
        wall.map_or(String::new(), |kappa| format!("wall_stiffness = {kappa}\n"))
    ));
    let push = 2.0 * k_normal * gap;
    let rest = wall.map_or(gap, |kappa| (push + kappa * gap) / (k_normal + kappa));
    let loads = (*setup.loads)
        .clone()
        .with_preload(vec![push, 0.0, 0.0])
        .unwrap();
    let lambda0 = push - k_normal * rest;
    let amplitude = mu * lambda0 / k_theta;
    let frequency = (k_theta / (m_theta - mu * coupling)).sqrt();
    let x_theta = |t: f64| -amplitude * (1.0 - (frequency * t).cos());
    let a_theta = |t: f64| -amplitude * frequency * frequency * (frequency * t).cos();
    let h = 1e-5;
    // At rest on the casing; the velocity is the scheme's v(−h/2).
    let mut start = State::at_rest(3, 1);
    start.displacement[0] = rest;
    start.velocity[1] = -0.5 * h * a_theta(0.0);
    let mut scheme = CentralDifference::new(
        setup.wheel.clone(),
        Arc::new(loads),
        wall,
        Drive::Fixed { omega: frequency },
        h,
        start,
    )
    .unwrap();
    let (mut error_theta, mut error_lambda, mut off) = (0.0_f64, 0.0_f64, 0.0_f64);
    let mut axial = 0.0_f64;
    for n in 0..(2.0 * 2.0 * PI / frequency / h) as usize {
        // λ of the step from t_n acts at t_n.
        let t = n as f64 * h;
        scheme.advance().unwrap();
        let s = scheme.state();
        error_lambda =
            error_lambda.max((s.contact_force[0] - (lambda0 - coupling * a_theta(t))).abs());
        error_theta = error_theta.max((s.displacement[1] - x_theta(t + h)).abs());
        // On the casing at every step's end, neither in nor off it.
        off = off.max((s.displacement[0] - rest).abs());
        axial = axial.max(s.displacement[2].abs());
    }
    println!(
        "m_c = {coupling}, wall {wall:?}: circumferential error {:.2e} of its amplitude, multiplier error {:.2e} \
         of λ0, largest distance to the casing {:.1e} of the gap",
        error_theta / amplitude,
        error_lambda / lambda0,
        off / gap
    );
    assert!(off <= 1e-13 * gap, "off the casing by {off:e} m");
    assert!(
        error_theta < 2e-5 * amplitude,
        "x_θ off by {error_theta:e} m"
    );
    assert!(error_lambda < 1e-6 * lambda0, "λ off by {error_lambda:e} N");
    assert_eq!(axial, 0.0, "no axial sliding, no axial force");
}

#[test]
fn a_pressed_node_slides_on_the_casing_as_the_closed_form_says() {
    pressed_node_slides_as_the_closed_form_says(0.0, None);
}

#[test]
fn with_a_wall_in_series_a_pressed_node_slides_as_the_closed_form_says() {
    pressed_node_slides_as_the_closed_form_says(0.0, Some(1e6));
}

#[test]
fn with_mass_coupling_the_friction_enters_the_multipliers_as_the_closed_form_says() {
    pressed_node_slides_as_the_closed_form_says(0.1, None);
}
