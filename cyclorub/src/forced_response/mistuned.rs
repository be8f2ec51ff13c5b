//! The linear forced response of a mistuned wheel (issue 44, docs/design.md
//! §12): every sector's amplitude of one dof, from a dense solve of the
//! assembled full wheel on harmonic 1 (a small wheel: `N · dofs` rows), and
//! the amplification factor against the tuned wheel. The linear anchor of
//! a mistuning study (Whitehead's bound `(1 + √N)/2`).

use crate::hbm::Forcing;
use crate::model::{ModelError, SectorModel};
use faer::linalg::solvers::Solve;
use faer::{c64, Mat};
use rayon::prelude::*;
use std::f64::consts::PI;

/// The full wheel's first-harmonic load of `forcing`: `X_j = Σ_s c_s
/// e^{−i s α j}` on the forced dofs of sector `j` (0-based), as the
/// physical formulation builds it (`x(t) = 2 Re(X e^{iωt})`).
pub fn wheel_load(model: &SectorModel, forcing: &Forcing) -> Vec<c64> {
    let (n, dofs) = (model.sectors(), model.dofs_per_sector());
    let alpha = 2.0 * PI / n as f64;
    let coefficients = forcing.pattern.pair_coefficients(n);
    let mut load = vec![c64::new(0.0, 0.0); n * dofs];
    for j in 0..n {
        let value: c64 = coefficients
            .iter()
            .map(|(p, (re, im))| {
                c64::new(*re, *im)
                    * forcing.amplitude
                    * c64::cis(-(p.nodal_diameter as f64) * alpha * j as f64)
            })
            .sum();
        for &d in &forcing.dofs {
            load[j * dofs + d] += value;
        }
    }
    load
}

/// The linear response of the assembled wheel `model` (mistuned or not) to
/// `load` on harmonic 1 at `omega` (rad/s): `(K − ω² M + i ω C) X = F`,
/// solved densely; complex coefficients, sector-major.
pub fn wheel_response(
    model: &SectorModel,
    load: &[c64],
    omega: f64,
) -> Result<Vec<c64>, ModelError> {
    let wheel = model.full_wheel()?;
    Ok(solve_at(&wheel, load, omega))
}

fn solve_at(wheel: &crate::model::FullWheelMatrices, load: &[c64], omega: f64) -> Vec<c64> {
    let size = load.len();
    let z = Mat::from_fn(size, size, |r, c| {
        c64::new(
            wheel.stiffness[(r, c)] - omega * omega * wheel.mass[(r, c)],
            omega * wheel.damping[(r, c)],
        )
    });
    let x = z
        .partial_piv_lu()
        .solve(Mat::from_fn(size, 1, |r, _| load[r]));
    (0..size).map(|r| x[(r, 0)]).collect()
}

/// Each sector's largest amplitude (`2|X|`, m) of sector dof `dof`
/// (0-based) over `frequencies_hz`, the wheel `model` driven by `forcing`
/// on harmonic 1 (no contact). Frequencies are solved in parallel.
pub fn linear_sector_peaks(
    model: &SectorModel,
    forcing: &Forcing,
    dof: usize,
    frequencies_hz: &[f64],
) -> Result<Vec<f64>, ModelError> {
    let (n, dofs) = (model.sectors(), model.dofs_per_sector());
    if dof >= dofs {
        return Err(ModelError::invalid(
            "output.observed_dof",
            format!(
                "dof {} is out of range: a sector has dofs 1..={dofs}",
                dof + 1
            ),
        ));
    }
    let wheel = model.full_wheel()?;
    let load = wheel_load(model, forcing);
    let amplitudes: Vec<Vec<f64>> = frequencies_hz
        .par_iter()
        .map(|f| {
            let x = solve_at(&wheel, &load, 2.0 * PI * f);
            (0..n).map(|j| 2.0 * x[j * dofs + dof].norm()).collect()
        })
        .collect();
    Ok((0..n)
        .map(|j| amplitudes.iter().fold(0.0_f64, |m, a| m.max(a[j])))
        .collect())
}

/// The linear amplification factor of the mistuned `model`: its largest
/// sector peak of `dof` over `frequencies_hz` over the tuned wheel's
/// ([`SectorModel::tuned`]) on the same frequencies.
pub fn linear_amplification_factor(
    model: &SectorModel,
    forcing: &Forcing,
    dof: usize,
    frequencies_hz: &[f64],
) -> Result<f64, ModelError> {
    let largest = |peaks: Vec<f64>| peaks.into_iter().fold(0.0_f64, f64::max);
    let mistuned = largest(linear_sector_peaks(model, forcing, dof, frequencies_hz)?);
    let tuned = largest(linear_sector_peaks(
        &model.tuned(),
        forcing,
        dof,
        frequencies_hz,
    )?);
    Ok(mistuned / tuned)
}
