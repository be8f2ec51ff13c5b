//! Benchmark: one residual and Jacobian evaluation (the cost of a Newton
//! iteration before its factorization) on the open fan with 3D contact and
//! sliding friction, the paper's Sec. 5 settings (`N_h = 10`, `N_t = 2000`,
//! DLFT ε = 1e7, μ = 0.15, Ω = 1151.9 rad/s, traveling wave h = 4): on the
//! symmetry basis and on the physical full wheel, with and without the
//! friction, at the same frequency and at a new one (the linear part
//! condensed again), and the factorization of the Jacobian (each the
//! fastest of 20 repeats on the symmetry basis, of one on the full wheel:
//! the machine may be shared; the full wheel's Jacobian is structured from
//! 2000 unknowns: its
//! wave-frame factorization and one GMRES solve are timed instead of the
//! LU). The fan is written to a temporary folder (`FAN_REFINE`,
//! default 1: the coarse mesh; the reduced model has 53 dofs per diameter
//! whatever the mesh). Run with `cargo bench -p cyclorub --bench friction`.

use cyclorub::case::{BasisChoice, Case};
use cyclorub::continuation::{solve_structured, Evaluation, Problem};
use cyclorub::mesh::{assemble, fan, write_fan, FanGeometry};
use cyclorub::run::prepare;
use faer::linalg::solvers::Solve;
use std::f64::consts::PI;
use std::time::Instant;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let refine: usize = std::env::var("FAN_REFINE")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(1);
    let dir = std::env::temp_dir().join(format!("cyclorub-bench-friction-{}", std::process::id()));
    let mesh = fan(16, refine, &FanGeometry::default())?;
    write_fan(&mesh, &assemble(&mesh.mesh)?, &dir, true)?;
    let mut case = Case::from_file_checked(&dir.join("fan16.toml"))?;
    case.excitation.engine_order = 4;
    case.casing.gap = cyclorub::case::PerContactDof::One(6e-5);
    println!(
        "open fan, refine {refine}, N = 16, traveling h = 4, N_h = 10, N_t = 2000, DLFT, μ = 0.15"
    );
    for basis in [BasisChoice::Symmetry, BasisChoice::Physical] {
        for friction in [true, false] {
            let mut case = case.clone();
            if !friction {
                case.contact.friction = None;
                case.contact.circumferential_dofs.clear();
                case.contact.axial_dofs.clear();
            }
            let prepared = prepare(&case, &dir, basis)?;
            let mut problem = prepared.problem;
            let omega = 2.0 * PI * prepared.case.continuation.start_hz.unwrap_or(270.0) / 0.95;
            // A point in contact: the linear response at the resonance.
            let x = problem.linear_solution(omega)?;
            let mut out = Evaluation::default();
            problem.evaluate(&x, omega, true, &mut out)?;
            let repeats = if basis == BasisChoice::Symmetry {
                20
            } else {
                1
            };
            // The fastest of the repeats: the machine may be shared.
            let mut evaluation = f64::INFINITY;
            for _ in 0..repeats {
                let clock = Instant::now();
                problem.evaluate(&x, omega, true, &mut out)?;
                evaluation = evaluation.min(clock.elapsed().as_secs_f64());
            }
            // The same at a new frequency each time: with the linear part's
            // condensation (per pair, or per harmonic of the full wheel).
            let mut moved = f64::INFINITY;
            for repeat in 0..repeats {
                let shifted = omega * (1.0 + 1e-6 * (repeat + 1) as f64);
                let clock = Instant::now();
                problem.evaluate(&x, shifted, true, &mut out)?;
                moved = moved.min(clock.elapsed().as_secs_f64());
            }
            problem.evaluate(&x, omega, true, &mut out)?;
            // The dense LU, or for the structured full wheel its wave-frame
            // factorization and one GMRES solve.
            let mut factorization = f64::INFINITY;
            for _ in 0..repeats {
                let clock = Instant::now();
                match &out.structured {
                    Some(jacobian) => {
                        jacobian.approximation()?;
                        let rhs: Vec<f64> = (0..x.len()).map(|i| (i as f64).sin()).collect();
                        solve_structured(&out, &rhs).ok_or("no structured solve")?;
                    }
                    None => {
                        let lu = out.jacobian.partial_piv_lu();
                        let _ = lu.solve(faer::Mat::<f64>::zeros(x.len(), 1));
                    }
                }
                factorization = factorization.min(clock.elapsed().as_secs_f64());
            }
            println!(
                "{:<9} friction {:<5} unknowns {:>5}  residual + Jacobian {:>9.2} ms (at a new frequency {:>9.2} ms)  {} {:>9.2} ms",
                basis.name(),
                friction,
                problem.layout().unknowns,
                1e3 * evaluation,
                1e3 * moved,
                if out.structured.is_some() {
                    "wave-frame factors + GMRES"
                } else {
                    "LU"
                },
                1e3 * factorization
            );
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
    Ok(())
}
