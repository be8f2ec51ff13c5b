//! `cyclorub stability RESULTS [--point P | --at-hz F] [--harmonics H] [--largest-eigenproblem S]
//! [--solver S] [--full-wheel] [--json] [--case-dir DIR]`: the Floquet exponents of one
//! point of a results folder, per symmetry class (Hill's method, see
//! `cyclorub::stability`), as a table or as JSON.
//!
//! The case and its basis come from `run.json`, the point's unknowns from
//! `results.h5`; the problem is rebuilt from the case, so a case whose
//! model lives in matrix files needs them where `--case-dir` says.

use super::results_folder::{open_point, OpenedPoint};
use super::{outln, CliError};
use cyclorub::forced_response::{Convergence, RefineError, Refinement};
use cyclorub::stability::{
    ClassSpectrum, HillSolver, PointStability, Stability, StabilityError, StabilitySettings,
};
use serde::Serialize;
use std::f64::consts::PI;
use std::path::PathBuf;

mod sizes;
use sizes::{print_convergence, refine};

/// How many exponents of each class the table shows (largest real part
/// first); `--json` gives them all.
const SHOWN: usize = 4;

/// A class whose truncation indicator is above this asks for more harmonics.
const TRUNCATION_WARNING: f64 = 1e-3;

/// Arguments of `cyclorub stability`.
#[derive(clap::Args)]
pub struct StabilityArgs {
    /// Results folder written by `cyclorub run` (its run.json and results.h5).
    results: PathBuf,
    /// Point (index along the branch, as in branch.csv) (default: the
    /// point of largest amplitude).
    #[arg(long, conflicts_with = "at_hz")]
    point: Option<usize>,
    /// Take the point nearest to this frequency (Hz), within the branch's
    /// range (refused beyond it, with the range); the table says how far
    /// the point is.
    #[arg(long)]
    at_hz: Option<f64>,
    /// Harmonics of Hill's truncation (default: the case's [stability]
    /// harmonics, as the run took them, else harmonic_balance.harmonics).
    #[arg(long)]
    harmonics: Option<usize>,
    /// The largest eigenproblem (`2 · dofs · pairs` of one class) solved;
    /// a larger one is refused (≥ 1; default 2000; its time grows as the
    /// cube of the size: about a minute of CPU per class at 3150).
    #[arg(long)]
    largest_eigenproblem: Option<usize>,
    /// How each class is solved: `condensed` (the default: every exponent
    /// in the strip |Im λ| ≤ gω/2 (g the class's harmonic step), Re λ ≥ −0.05 ω, by a contour integral on
    /// the contact dofs), `dense-region` (the same region from the dense
    /// eigenproblem: its check), `dense` (the dense eigenproblem, each
    /// family's copy centred on harmonic 0) or `targeted` (that pick,
    /// faster where it can vouch for it).
    #[arg(long, value_enum, default_value_t = SolverArg::Condensed)]
    solver: SolverArg,
    /// Skip the refined orbit: by default the point is also solved with
    /// twice the harmonics (Newton at its frequency from the truncated
    /// solution) and checked with twice Hill's harmonics, and each class's
    /// leading exponent is printed with its change between the two: the
    /// estimate of how converged it is.
    #[arg(long)]
    no_refine: bool,
    /// Refinements at most: the orbit and Hill's truncation are doubled
    /// (2, 4, 8, … times the run's harmonics) until the leading real part
    /// moves by less than --converge-within between two of them.
    #[arg(long, default_value_t = 3)]
    refinements: u32,
    /// The relative change of the leading real part between two
    /// refinements below which the sizes count as converged.
    #[arg(long, default_value_t = 0.01)]
    converge_within: f64,
    /// Hill's method on the whole wheel in physical coordinates, without
    /// symmetry classes (the reference; refused when its eigenproblem is
    /// too large).
    #[arg(long)]
    full_wheel: bool,
    /// Print the whole spectrum of every class as JSON (with the point's
    /// index and frequency) instead of the table.
    #[arg(long)]
    json: bool,
    /// Folder the case's relative paths (matrix files) start from
    /// (default: the working directory; `cyclorub run` took them from the
    /// case file's folder, which run.json does not record).
    #[arg(long, default_value = ".")]
    case_dir: PathBuf,
}

/// `--solver`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
enum SolverArg {
    Condensed,
    DenseRegion,
    Dense,
    Targeted,
}

impl SolverArg {
    fn solver(self) -> HillSolver {
        match self {
            SolverArg::Condensed => HillSolver::Condensed,
            SolverArg::DenseRegion => HillSolver::DenseRegion,
            SolverArg::Dense => HillSolver::Dense,
            SolverArg::Targeted => HillSolver::Targeted,
        }
    }

    /// The argument's spelling.
    fn name(self) -> &'static str {
        match self {
            SolverArg::Condensed => "condensed",
            SolverArg::DenseRegion => "dense-region",
            SolverArg::Dense => "dense",
            SolverArg::Targeted => "targeted",
        }
    }

    /// What the table's header says of the method.
    fn describe(self) -> &'static str {
        match self {
            SolverArg::Condensed => {
                "condensed (contour integral of the contact resolvent, refined on the class's problem): every exponent with |Im λ| ≤ gω/2 (g the class's harmonic step) and Re λ ≥ −0.05 ω"
            }
            SolverArg::DenseRegion => {
                "dense eigenproblem, every exponent with |Im λ| ≤ gω/2 (g the class's harmonic step) and Re λ ≥ −0.05 ω"
            }
            SolverArg::Dense => "dense eigenproblem, each family's copy centred on harmonic 0",
            SolverArg::Targeted => {
                "targeted (the dense pick where it can vouch for it, the dense eigenproblem elsewhere)"
            }
        }
    }
}

/// What `--json` prints: the point, how it was checked, and the whole
/// [`PointStability`] (its fields at the top level).
#[derive(Serialize)]
struct Report<'a> {
    /// The results folder.
    results: String,
    /// The point's index along the branch.
    point: usize,
    /// Its frequency, Hz.
    frequency_hz: f64,
    /// Whether Newton converged at the point.
    converged: bool,
    /// The basis the branch was solved on.
    basis: &'a str,
    /// `symmetry_classes` or `full_wheel`.
    method: &'static str,
    /// How each class was solved (`--solver`).
    solver: &'static str,
    /// Hill's harmonics.
    harmonics: usize,
    /// Whether no exponent grows.
    stable: bool,
    /// How many exponents grow.
    unstable_exponents: usize,
    /// The classes with a growing exponent.
    unstable_classes: Vec<i64>,
    #[serde(flatten)]
    stability: &'a PointStability,
    /// The refinements until the sizes converged, when computed.
    convergence: Option<ConvergenceReport<'a>>,
    /// The point on the refined orbit (twice the harmonics), when computed.
    #[serde(skip_serializing_if = "Option::is_none")]
    refined: Option<RefinedReport<'a>>,
}

/// The refinements of `--json`: each doubles the orbit's harmonics and
/// Hill's truncation.
#[derive(Serialize)]
struct ConvergenceReport<'a> {
    /// Harmonics of each refinement.
    harmonics: Vec<usize>,
    /// Each refinement's leading exponent: its class and real part, 1/s.
    leading: Vec<Option<(i64, f64)>>,
    /// Each refinement's change of the leading real part from the one
    /// before (the run's orbit for the first), relative.
    changes: Vec<Option<f64>>,
    /// The last change: the error estimate of the last refinement.
    estimate: Option<f64>,
    /// Whether it fell below `--converge-within`.
    converged: bool,
    /// The last refinement's exponents.
    stability: Option<&'a PointStability>,
    /// Why the refinements stopped short (the next one too large).
    stopped: Option<&'a str>,
}

/// The refined orbit's exponents in `--json`.
#[derive(Serialize)]
struct RefinedReport<'a> {
    /// Harmonics of the refined orbit and of its Hill truncation.
    harmonics: usize,
    /// Newton's iterations from the truncated solution.
    newton_iterations: usize,
    /// The change of the wheel's leading real part, relative to it on the
    /// refined orbit: the error estimate.
    estimate: Option<f64>,
    /// Per class: the change of its leading real part, relative to the
    /// refined orbit's leading real part.
    class_changes: Vec<(i64, f64)>,
    /// The refined point's stability.
    stability: &'a PointStability,
}

/// Runs `cyclorub stability`.
pub fn execute(args: StabilityArgs) -> Result<(), CliError> {
    if !(args.converge_within > 0.0 && args.converge_within < 1.0) {
        return Err(CliError::usage(format!(
            "--converge-within {}: give a relative change between 0 and 1 (e.g. 0.01)",
            args.converge_within
        )));
    }
    if args.refinements > 6 {
        return Err(CliError::usage(format!(
            "--refinements {}: give 0 to 6 (each doubles the harmonics: 6 is 64 times the run's)",
            args.refinements
        )));
    }
    if args.largest_eigenproblem == Some(0) {
        return Err(CliError::usage(format!(
            "--largest-eigenproblem 0: give a size ≥ 1 (the rows of one class's eigenproblem, \
             2 · dofs · pairs, above which the check is refused; default {}): 0 would refuse \
             every class",
            StabilitySettings::default().largest_eigenproblem
        )));
    }
    if args.harmonics == Some(0) {
        return Err(CliError::usage(
            "--harmonics 0: give an integer ≥ 1 (Hill's truncation)",
        ));
    }
    let folder = &args.results;
    let OpenedPoint {
        prepared,
        basis,
        data,
        index,
        choice,
    } = open_point(folder, args.point, args.at_hz, &args.case_dir)?;
    let point = &data.points[index];
    let defaults = StabilitySettings::default();
    let settings = StabilitySettings {
        // The run's truncation unless told otherwise: the same point gives
        // the same exponents here and in results.h5.
        harmonics: args.harmonics.or(prepared.case.stability.harmonics),
        largest_eigenproblem: args
            .largest_eigenproblem
            .unwrap_or(defaults.largest_eigenproblem),
        solver: args.solver.solver(),
        ..defaults
    };
    let contact_dofs = prepared.case.contact_dofs();
    let check = if args.full_wheel {
        Stability::full_wheel(&prepared.model, &prepared.problem, &contact_dofs, &settings)
    } else {
        Stability::new(&prepared.model, &prepared.problem, &contact_dofs, &settings)
    }
    .map_err(|e| stability_error(e, &args))?;
    let omega = 2.0 * PI * point.frequency_hz;
    let stability = check
        .point(&point.unknowns, omega)
        .map_err(|e| stability_error(e, &args))?;
    let whole_wheel = check.classes().is_empty();
    let convergence = if args.no_refine || args.refinements == 0 {
        None
    } else {
        Some(refine(
            &prepared,
            basis,
            &point.unknowns,
            omega,
            &settings,
            &stability,
            &args,
        )?)
    };
    // The first refinement (twice the harmonics): the run's own estimate.
    let refined = convergence.as_ref().and_then(|c| c.steps.first());
    if args.json {
        let report = Report {
            results: folder.display().to_string(),
            point: index,
            frequency_hz: point.frequency_hz,
            converged: point.converged,
            basis: basis.name(),
            method: if whole_wheel {
                "full_wheel"
            } else {
                "symmetry_classes"
            },
            harmonics: check.harmonics(),
            solver: args.solver.name(),
            stable: stability.stable(),
            unstable_exponents: stability.unstable_exponents(),
            unstable_classes: stability.unstable_classes(),
            stability: &stability,
            convergence: convergence.as_ref().map(|c| ConvergenceReport {
                harmonics: c.steps.iter().map(|s| s.harmonics).collect(),
                leading: c
                    .steps
                    .iter()
                    .map(|s| s.stability.leading().map(|(class, e)| (class, e.re)))
                    .collect(),
                changes: c.changes.clone(),
                estimate: c.estimate,
                converged: c.converged,
                stopped: c.stopped.as_deref(),
                stability: c.last().map(|s| &s.stability),
            }),
            refined: refined.map(|r| RefinedReport {
                harmonics: r.harmonics,
                newton_iterations: r.iterations,
                estimate: r.leading_change(&stability),
                class_changes: r.class_changes(&stability),
                stability: &r.stability,
            }),
        };
        let text = serde_json::to_string_pretty(&report)
            .map_err(|e| CliError::failure(format!("cannot write the JSON report: {e}")))?;
        outln!("{text}");
        return Ok(());
    }
    let amplitude = point.amplitude.iter().copied().fold(0.0, f64::max);
    let how = choice.text();
    outln!(
        "{}: {} basis, {} points",
        folder.display(),
        basis.name(),
        data.points.len()
    );
    outln!(
        "point {index} at {:.6} Hz, amplitude {amplitude:.4e} m{how}",
        point.frequency_hz
    );
    outln!(
        "Hill's method with {} harmonics, {}; growth when Re λ > {:.2e} 1/s",
        check.harmonics(),
        if whole_wheel && prepared.case.mistuning.is_set() {
            "on the whole wheel (mistuned: its one symmetry class)".to_string()
        } else if whole_wheel {
            "on the whole wheel (no symmetry: the reference)".to_string()
        } else {
            format!("per symmetry class ({} classes)", stability.classes.len())
        },
        stability.tolerance
    );
    if stability.off_contact_bound == Some(0.0) {
        outln!("no contact (the linearized contact vanishes): the linear wheel's exponents");
    } else if let Some(bound) = stability.off_contact_bound {
        outln!(
            "weak contact (peak contact stiffness {:.3e} N/m): the linear wheel's exponents, which the contact moves by at most {bound:.3e} rad/s",
            stability.peak_contact_stiffness
        );
    } else {
        outln!(
            "peak contact stiffness {:.3e} N/m",
            stability.peak_contact_stiffness
        );
    }
    outln!("solved by: {}", args.solver.describe());
    outln!(
        "truncation: the largest share of an exponent's eigenvector on the highest harmonics (above {TRUNCATION_WARNING:.0e}: raise --harmonics)"
    );
    for class in &stability.classes {
        print_class(class, &stability, whole_wheel)?;
    }
    outln!("{}", verdict(&stability, whole_wheel));
    if let Some(refined) = refined {
        outln!(
            "refined orbit: {} harmonics (Newton {} iterations from this point), Hill with {} harmonics",
            refined.harmonics,
            refined.iterations,
            refined.harmonics
        );
        if let (Some(estimate), Some((class, e))) = (
            refined.leading_change(&stability),
            refined.stability.leading(),
        ) {
            let place = if whole_wheel {
                "of the whole wheel".to_string()
            } else {
                format!("in class σ = {class}")
            };
            outln!(
                "error estimate: the leading real part moves by {:.1} % ({:+.4e} 1/s {place} on the refined orbit)",
                100.0 * estimate,
                e.re
            );
        }
        outln!("    class  leading Re λ (1/s): this orbit  refined   change (of the leading)");
        for (class, change) in refined.class_changes(&stability) {
            let fine = refined.stability.class(class).and_then(|c| c.leading());
            let coarse = stability.class(class).and_then(|c| c.leading());
            if let (Some(a), Some(b)) = (fine, coarse) {
                outln!(
                    "    {class:>5}  {:>+25.4e}  {:>+9.4e}   {:>6.1} %",
                    b.re,
                    a.re,
                    100.0 * change
                );
            }
        }
        outln!("refined: {}", verdict(&refined.stability, whole_wheel));
    }
    if let Some(convergence) = convergence.as_ref().filter(|c| c.steps.len() > 1) {
        print_convergence(convergence, &stability, args.converge_within, whole_wheel)?;
    }
    Ok(())
}

/// One class's lines of the table.
fn print_class(
    class: &ClassSpectrum,
    stability: &PointStability,
    whole_wheel: bool,
) -> Result<(), CliError> {
    let growing = class.unstable(stability.tolerance);
    let name = if whole_wheel {
        "whole wheel".to_string()
    } else {
        format!("class σ = {}", class.nodal_diameter)
    };
    let state = if growing > 0 {
        format!(
            "unstable ({growing} of {} exponents grow)",
            class.exponents.len()
        )
    } else {
        format!("stable ({} exponents)", class.exponents.len())
    };
    let raise = if class.truncation > TRUNCATION_WARNING {
        " (raise --harmonics)"
    } else {
        ""
    };
    outln!(
        "{name}: {state}, truncation {:.1e}{raise}",
        class.truncation
    );
    outln!(
        "    {:>12}  {:>12}  {:>11}",
        "Re λ (1/s)",
        "Im λ (rad/s)",
        "|e^{λT}|"
    );
    for exponent in class.exponents.iter().take(SHOWN) {
        let modulus = exponent.multiplier(stability.omega).norm();
        outln!(
            "    {:>+12.4e}  {:>+12.4e}  {:>11.6}",
            exponent.re,
            exponent.im,
            modulus
        );
    }
    Ok(())
}

/// The last line: stable, or which classes are not and the fastest growth.
fn verdict(stability: &PointStability, whole_wheel: bool) -> String {
    let growing = stability.unstable_exponents();
    if growing == 0 {
        return format!(
            "stable: no exponent with Re λ > {:.2e} 1/s{}",
            stability.tolerance,
            if whole_wheel { "" } else { " in any class" }
        );
    }
    let whole = if whole_wheel {
        " of the whole wheel"
    } else {
        ""
    };
    let grow = if growing == 1 {
        format!("1 exponent{whole} grows")
    } else {
        format!("{growing} exponents{whole} grow")
    };
    let classes: Vec<String> = stability
        .unstable_classes()
        .iter()
        .map(i64::to_string)
        .collect();
    let fastest = stability
        .leading()
        .map(|(sigma, e)| {
            let modulus = e.multiplier(stability.omega).norm();
            let class = if whole_wheel {
                String::new()
            } else {
                format!(" in class σ = {sigma}")
            };
            format!(
                "; fastest λ = {:+.4e} {:+.4e}i{class} (|e^{{λT}}| = {modulus:.6})",
                e.re, e.im
            )
        })
        .unwrap_or_default();
    if whole_wheel {
        format!("unstable: {grow}{fastest}")
    } else {
        format!(
            "unstable: {grow}, in class{} σ = {}{fastest}",
            if classes.len() == 1 { "" } else { "es" },
            classes.join(", ")
        )
    }
}

/// A stability error as a CLI error: a setting or a size refused is bad
/// input (exit 2), the rest a failure (exit 1).
fn stability_error(error: StabilityError, args: &StabilityArgs) -> CliError {
    match error {
        StabilityError::TooLarge { .. } => CliError::usage(format!(
            "{}{error} (here: --harmonics, or --largest-eigenproblem to accept it)",
            if args.full_wheel {
                "--full-wheel: "
            } else {
                ""
            }
        )),
        StabilityError::Setting { .. } => CliError::usage(error.to_string()),
        other => CliError::failure(other.to_string()),
    }
}
