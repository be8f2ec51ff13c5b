//! Benchmark: the default academic case (N = 24, R-HBM, one contact dof a
//! sector, `N_h = 10`, `N_t = 10000`) mistuned at 1 % (seed 1), solved on
//! the physical full wheel (issue 44): milliseconds a point and a Newton
//! iteration over the first `CYCLORUB_BENCH_POINTS` points (default 400),
//! and the time the whole default run (`max_points = 5000`) would take at
//! that rate. Run with `cargo bench -p cyclorub --bench mistuned_curve`.

use cyclorub::case::{BasisChoice, Case};
use cyclorub::continuation::Problem;
use cyclorub::forced_response::ForcedResponse;
use std::path::Path;
use std::time::Instant;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let points: usize = std::env::var("CYCLORUB_BENCH_POINTS")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(400);
    let text = format!(
        "[mistuning]\nstandard_deviation = 0.01\nseed = 1\n\
         [continuation]\nmax_points = {points}\n"
    );
    let case = Case::from_toml(&text, Path::new("case.toml"))?;
    case.validate()?;
    let clock = Instant::now();
    let solver = ForcedResponse::from_case(&case)?
        .basis(BasisChoice::Physical)
        .stability(None)
        .build()?;
    let unknowns = solver.problem().unknowns();
    let solution = solver.run(&mut [])?;
    let wall = clock.elapsed().as_secs_f64();
    let branch = &solution.branch;
    let per_point = 1e3 * solution.solve_s / branch.points.len().max(1) as f64;
    println!(
        "mistuned default case 1 %: unknowns {unknowns}  set-up {:.3} s  solve {:.3} s  \
         (wall {wall:.3} s)  points {}  Newton iterations {}  {per_point:.2} ms/point  \
         {:.2} ms/iteration  stop {:?}",
        solution.setup_s,
        solution.solve_s,
        branch.points.len(),
        branch.total_iterations,
        1e3 * solution.solve_s / branch.total_iterations.max(1) as f64,
        branch.stop
    );
    // The whole default run's curve has 18742 points (docs/mistuning.md,
    // "A long branch"): what it takes at this rate.
    println!(
        "the whole curve (18742 points) at this rate: {:.0} s",
        18742.0 * per_point / 1e3
    );
    Ok(())
}
