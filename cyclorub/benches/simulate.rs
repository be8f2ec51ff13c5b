//! Benchmark: time integration of the full wheel with the implicit scheme
//! (Newmark average acceleration, Newton on the contact unknowns) and the
//! explicit one (central differences, Lagrange multipliers).
//! - the paper's default case (academic sector, N = 24, traveling wave
//!   h = 1 of 4 N, R-HBM law) over 1000 excitation periods at 127.7 Hz from
//!   rest, 256 steps a period: the issue asks for under 10 s; the same
//!   with the unilateral contact (law = "dlft"), explicit;
//! - a finite-element sector of 300 dofs (banded matrices, 20 boundary
//!   dofs, modal damping), N = 24, 20 periods;
//! - the coarse open fan (Craig–Bampton, 16 × 53 dofs, 432 contact
//!   unknowns with friction), engine order 4 at 290 Hz from rest, 0.1 mm
//!   gap: the regularized law (implicit, 512 steps a period, Newton's
//!   matrix kept and, for comparison, factorized at every iteration) and
//!   the DLFT law (explicit, at its stable step).
//!
//! Run with `cargo bench -p cyclorub --bench simulate` (`-- fan`: the fan
//! alone).
//!
//! Measured (2 cores shared with other jobs, 27 November 2026): the coarse
//! fan, regularized, 3,783 steps/s (5,135 Newton iterations, 22
//! factorizations; 831 steps/s factorizing at every iteration, the final
//! states 1.1e-11 apart); DLFT, explicit, 9,783 steps/s at 5,392 steps a
//! period. Before this (issue 43, the same machine, `cyclorub simulate` of
//! `fan16-traveling-h4` at 290 Hz, 512 steps, 10 periods, gap 0.1 mm):
//! 324 steps/s regularized, 2,246 DLFT; after, 1,744 and 6,883. The
//! default case, 1000 periods in 5.02 s (51,000 steps/s, 83,277
//! iterations: chord iterations are cheap, 0 halvings); with law =
//! "dlft" 2.55 s; the finite-element sector 111 steps/s.
//! Earlier (25 November 2026): the default case, 1000 periods in
//! 5.33 s (48 000 steps/s; contact in 361 periods, 37 391 Newton
//! iterations, no halving); with law = "dlft", the explicit scheme, 2.88 s
//! (88 800 steps/s); the finite-element sector, 97 steps/s: its blocks are
//! stored dense (`n²` per block and per nodal diameter's Cholesky factor).

use cyclorub::case::{Case, LawKind, PerContactDof};
use cyclorub::contact::{Casing, ContactModel, RegularizedPenalty};
use cyclorub::cyclic::ExcitationPattern;
use cyclorub::hbm::Forcing;
use cyclorub::mesh::{assemble, fan, write_fan, FanGeometry};
use cyclorub::model::{Damping, FiniteElementSector, ModalDamping, SectorModel};
use cyclorub::simulate::{
    Drive, NewtonSettings, Simulation, SimulationOutcome, SimulationSettings, State, WheelLoads,
    WheelMatrices, WheelSetup,
};
use faer::Mat;
use std::f64::consts::PI;
use std::path::Path;
use std::sync::Arc;
use std::time::Instant;

fn banded(n: usize, bandwidth: usize, diagonal: f64, seed: u64) -> Mat<f64> {
    let mut state = seed;
    let mut next = move || {
        state = state
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (state >> 11) as f64 / (1u64 << 53) as f64 - 0.5
    };
    let mut a = Mat::<f64>::zeros(n, n);
    for i in 0..n {
        for j in i.saturating_sub(bandwidth)..i {
            let v = next();
            a[(i, j)] = v;
            a[(j, i)] = v;
        }
    }
    for i in 0..n {
        a[(i, i)] = diagonal * (1.0 + 0.1 * next().abs()) + 2.0 * bandwidth as f64;
    }
    a
}

/// The coarse open fan (`cyclorub mesh fan --refine 1`: Craig–Bampton,
/// 53 dofs a sector, N = 16) under engine order 4 with friction, `law`,
/// a gap of 0.1 mm after the centrifugal preload (from rest the preload,
/// applied at once, throws the blades onto the casing in the first
/// period; then they vibrate near it).
fn coarse_fan(law: LawKind) -> WheelSetup {
    let dir = std::env::temp_dir().join(format!("cyclorub-bench-fan-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let mesh = fan(16, 1, &FanGeometry::default()).expect("fan");
    let matrices = assemble(&mesh.mesh).expect("assembly");
    write_fan(&mesh, &matrices, &dir, false).expect("fan files");
    let mut case = Case::from_file_checked(&dir.join("fan16.toml")).expect("fan case");
    case.excitation.engine_order = 4;
    case.contact.law = law;
    case.casing.gap = PerContactDof::One(1e-4);
    let setup = WheelSetup::from_case(&case, &dir).expect("fan setup");
    let _ = std::fs::remove_dir_all(&dir);
    setup
}

/// `periods` periods of `setup` at `hz` from rest, `steps` a period.
fn fan_run(
    setup: &WheelSetup,
    hz: f64,
    periods: usize,
    steps: usize,
    newton: NewtonSettings,
) -> SimulationOutcome {
    let settings = SimulationSettings {
        periods,
        steps_per_period: steps,
        steady_tolerance: None,
        history_periods: 0,
        newton,
        ..SimulationSettings::default()
    };
    Simulation::new(
        setup.wheel.clone(),
        setup.loads.clone(),
        setup.law(),
        Drive::Fixed {
            omega: 2.0 * PI * hz,
        },
        settings,
        State::at_rest(setup.wheel.size(), setup.loads.contact_count()),
        None,
    )
    .expect("fan simulation")
    .run(|_| {})
    .expect("fan run")
}

/// The coarse fan with both laws: steps/s with Newton's matrix kept
/// (chord iterations) and factorized at every iteration.
fn fan_benches() {
    let clock = Instant::now();
    let setup = coarse_fan(LawKind::Regularized);
    println!(
        "coarse fan: {} sectors × {} dofs, {} contact unknowns with friction, set-up {:.2} s",
        setup.wheel.sectors(),
        setup.wheel.dofs_per_sector(),
        3 * setup.loads.contact_count(),
        clock.elapsed().as_secs_f64()
    );
    let (hz, periods, steps) = (290.0, 10, 512);
    let mut last = Vec::new();
    for keep_jacobian in [true, false] {
        let newton = NewtonSettings {
            keep_jacobian,
            ..NewtonSettings::default()
        };
        let outcome = fan_run(&setup, hz, periods, steps, newton);
        // The regularized force is never exactly 0: contact where it
        // reaches a thousandth of its largest.
        let largest = outcome
            .periods
            .iter()
            .flat_map(|p| &p.peak_force)
            .fold(0.0_f64, |m, f| m.max(*f));
        let touched = outcome
            .periods
            .iter()
            .filter(|p| p.peak_force.iter().any(|f| *f > 1e-3 * largest))
            .count();
        println!(
            "coarse fan, law = \"regularized\" (implicit), {hz} Hz from rest, {periods} periods × \
             {steps} steps, Newton's matrix {}: {:.2} s, {:.0} steps/s, {} iterations, {} \
             factorizations, {} halvings, {touched} periods with contact",
            if keep_jacobian {
                "kept"
            } else {
                "factorized every iteration"
            },
            outcome.wall_seconds,
            outcome.steps_per_second(),
            outcome.newton_iterations,
            outcome.factorizations,
            outcome.halvings,
        );
        last.push(outcome.last_state.displacement);
    }
    let scale = last[1].iter().fold(0.0_f64, |m, v| m.max(v.abs()));
    let difference = last[0]
        .iter()
        .zip(&last[1])
        .fold(0.0_f64, |m, (a, b)| m.max((a - b).abs()));
    println!(
        "  kept against factorized: largest displacement difference {:.2e} of the largest",
        difference / scale
    );
    let setup = coarse_fan(LawKind::Dlft);
    let outcome = fan_run(&setup, hz, 2, 256, NewtonSettings::default());
    println!(
        "coarse fan, law = \"dlft\" (explicit), {hz} Hz from rest, 2 periods at {} steps a \
         period (the stable step): {:.2} s, {:.0} steps/s",
        outcome.steps / 2,
        outcome.wall_seconds,
        outcome.steps_per_second()
    );
}

fn main() {
    if std::env::args().any(|a| a == "fan") {
        // `cargo bench --bench simulate -- fan`: the fan alone.
        fan_benches();
        return;
    }
    fan_benches();
    // The default case.
    let clock = Instant::now();
    let setup = WheelSetup::from_case(&Case::default(), Path::new(".")).expect("default case");
    let settings = SimulationSettings {
        periods: 1000,
        steady_tolerance: None,
        ..SimulationSettings::default()
    };
    let start = State::at_rest(setup.wheel.size(), setup.loads.contact_count());
    let simulation = Simulation::new(
        setup.wheel.clone(),
        setup.loads.clone(),
        setup.law(),
        Drive::Fixed {
            omega: 2.0 * PI * 127.7,
        },
        settings,
        start,
        None,
    )
    .expect("simulation");
    let set_up = clock.elapsed().as_secs_f64();
    let outcome = simulation.run(|_| {}).expect("run");
    let touched = outcome
        .periods
        .iter()
        .filter(|p| p.peak_force.iter().any(|f| *f > 2.5))
        .count();
    println!(
        "default case (N = 24, 5 dofs a sector), 1000 periods × 256 steps: set-up {set_up:.3} s, \
         integration {:.2} s, {:.0} steps/s, {} Newton iterations, {} halvings, {touched} periods with contact",
        outcome.wall_seconds,
        outcome.steps_per_second(),
        outcome.newton_iterations,
        outcome.halvings
    );

    // The same wheel with the unilateral contact (law = "dlft", the wall of
    // 1e8 N/m in series): the explicit scheme, whose step is bounded by the
    // highest natural frequency, not by accuracy.
    let mut case = Case::default();
    case.contact.law = cyclorub::case::LawKind::Dlft;
    let setup = WheelSetup::from_case(&case, Path::new(".")).expect("dlft case");
    let settings = SimulationSettings {
        periods: 1000,
        steady_tolerance: None,
        ..SimulationSettings::default()
    };
    let start = State::at_rest(setup.wheel.size(), setup.loads.contact_count());
    let outcome = Simulation::new(
        setup.wheel.clone(),
        setup.loads.clone(),
        setup.law(),
        Drive::Fixed {
            omega: 2.0 * PI * 127.7,
        },
        settings,
        start,
        None,
    )
    .expect("explicit simulation")
    .run(|_| {})
    .expect("explicit run");
    println!(
        "default case with law = \"dlft\" (explicit central differences, Lagrange multipliers), \
         1000 periods × 256 steps: integration {:.2} s, {:.0} steps/s",
        outcome.wall_seconds,
        outcome.steps_per_second(),
    );

    // A finite-element sector.
    let (size, boundary, sectors) = (300, 20, 24);
    let sector = FiniteElementSector {
        mass: banded(size, 6, 1.0, 1),
        stiffness: banded(size, 6, 1e3, 2),
        left_boundary: (0..boundary).collect(),
        right_boundary: (size - boundary..size).collect(),
        boundary_frame: Default::default(),
    };
    let damping = Damping::Modal(ModalDamping {
        ratios: vec![1e-3; 5],
        others: 5e-3,
    });
    let clock = Instant::now();
    let model = SectorModel::finite_element(sectors, sector, damping).expect("model");
    let wheel = Arc::new(WheelMatrices::new(&model).expect("wheel"));
    let dofs = model.dofs_per_sector();
    let forcing = Forcing {
        pattern: ExcitationPattern::Traveling { engine_order: 1 },
        amplitude: 1.0,
        dofs: vec![dofs / 2],
        static_force: 0.0,
    };
    let casing = Casing {
        gaps: vec![1e-3],
        order: 0,
        amplitudes: vec![0.0],
    };
    let loads = Arc::new(
        WheelLoads::new(sectors, dofs, Some(&forcing), casing, &[dofs / 2]).expect("loads"),
    );
    let law = ContactModel::Regularized(RegularizedPenalty::new(1e6, 0.1).expect("law")).law();
    let set_up = clock.elapsed().as_secs_f64();
    let settings = SimulationSettings {
        periods: 20,
        steady_tolerance: None,
        history_periods: 0,
        ..SimulationSettings::default()
    };
    let outcome = Simulation::new(
        wheel.clone(),
        loads,
        law,
        Drive::Fixed { omega: 5.0 },
        settings,
        State::at_rest(wheel.size(), sectors),
        None,
    )
    .expect("simulation")
    .run(|_| {})
    .expect("run");
    println!(
        "finite-element sector ({dofs} dofs, N = {sectors}: {} dofs, damping blocks at {} sector offsets), \
         20 periods × 256 steps: set-up {set_up:.2} s, {:.0} steps/s",
        wheel.size(),
        wheel.damping.offsets().len(),
        outcome.steps_per_second()
    );
}
