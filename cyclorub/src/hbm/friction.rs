//! The sliding friction of the residual (Eqs. 83–84, see
//! [`crate::contact::SlidingFriction`]): per friction node, from the normal
//! force samples the law gave and the velocities of the node's tangential
//! dofs, the tangential forces' coordinates and their derivative blocks.
//!
//! With `w = (ω x'_θ + ρΩ, ω x'_z)` (`x' = dx/dτ`, `τ = ωt`), `t = w/|w|`,
//! the residual gains `R_θ = μ f_N t_θ`, `R_z = μ f_N t_z`. Its derivatives:
//! through `f_N` (the law's blocks, which read `q = a p + b ρ`), and through
//! the velocities, `μ f_N (∂t/∂w) ω D` with `D` the derivative in `τ` of the
//! real harmonic coordinates; along `ω`, `μ f_N (∂t/∂w) ∂w/∂ω` with
//! `∂w/∂ω = (x'_θ + ρ ∂Ω/∂ω, x'_z)`.

use super::aft::{derivative_coordinates, Aft};
use super::layout::Layout;
use crate::contact::{sliding_direction, SlidingFriction};

/// Which column signal a friction block multiplies and how.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Column {
    /// The normal dof's law input (`a x + b r`, as the law's own block).
    Normal,
    /// The circumferential dof's displacement (a velocity block).
    Circumferential,
    /// The axial dof's displacement (a velocity block).
    Axial,
}

/// The six blocks of a friction node, in storage order: row (0:
/// circumferential, 1: axial) and column.
pub(super) const BLOCKS: [(usize, Column); 6] = [
    (0, Column::Normal),
    (1, Column::Normal),
    (0, Column::Circumferential),
    (0, Column::Axial),
    (1, Column::Circumferential),
    (1, Column::Axial),
];

/// The friction of one problem, with its buffers.
#[derive(Clone, Debug)]
pub(super) struct FrictionPart {
    pub(super) spec: SlidingFriction,
    /// Six `H × H` row-major blocks per friction node (sampled sector-major),
    /// in the order of [`BLOCKS`].
    pub(super) blocks: Vec<f64>,
    /// `∂R/∂ω` of the friction forces through the velocities, in sector
    /// coordinates (the tangential bands; zero elsewhere).
    pub(super) frequency_derivative: Vec<f64>,
    rate: [Vec<f64>; 2],
    force: [Vec<f64>; 2],
    /// Time samples of the six blocks' derivatives, then of `∂R/∂ω`'s two.
    samples: Vec<Vec<f64>>,
    coordinates: Vec<f64>,
}

impl FrictionPart {
    pub(super) fn new(spec: &SlidingFriction, layout: &Layout, time_samples: usize) -> Self {
        let size = layout.coordinates();
        let nodes = layout.sampled_sectors * spec.nodes().len();
        Self {
            spec: spec.clone(),
            blocks: vec![0.0; nodes * BLOCKS.len() * size * size],
            frequency_derivative: vec![0.0; layout.sector_coordinates()],
            rate: [vec![0.0; time_samples], vec![0.0; time_samples]],
            force: [vec![0.0; time_samples], vec![0.0; time_samples]],
            samples: vec![vec![0.0; time_samples]; BLOCKS.len() + 2],
            coordinates: vec![0.0; size],
        }
    }

    /// The block `b` (index in [`BLOCKS`]) of friction node `index`.
    pub(super) fn block(&self, index: usize, b: usize, size: usize) -> &[f64] {
        let at = (index * BLOCKS.len() + b) * size * size;
        &self.blocks[at..at + size * size]
    }

    /// Friction node `index` (`j · n_n + c`) of tangential signals at
    /// `bands` (circumferential, axial offsets in the sector coordinates):
    /// writes its forces' coordinates into `forces` and, if `jacobian`,
    /// its blocks and `∂R/∂ω`, from the displacements' coordinates and the
    /// normal force `normal_force` (with its slope `df/dq`) at each instant.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn node(
        &mut self,
        aft: &mut Aft,
        index: usize,
        bands: [usize; 2],
        displacements: &[f64],
        normal_force: &[f64],
        slope: &[f64],
        omega: f64,
        jacobian: bool,
        forces: &mut [f64],
    ) {
        let size = self.coordinates.len();
        let node = self.spec.nodes()[index % self.spec.nodes().len()];
        let mu = self.spec.coefficient();
        let speed = self.spec.speed();
        let sliding = node.radius * speed.at(omega);
        let sliding_derivative = node.radius * speed.derivative();
        for (rate, &band) in self.rate.iter_mut().zip(&bands) {
            derivative_coordinates(&displacements[band..band + size], &mut self.coordinates);
            aft.to_time(&self.coordinates, rate);
        }
        for n in 0..normal_force.len() {
            let (rate_theta, rate_axial) = (self.rate[0][n], self.rate[1][n]);
            let (t, dt) = sliding_direction(omega * rate_theta + sliding, omega * rate_axial);
            let force = mu * normal_force[n];
            self.force[0][n] = force * t[0];
            self.force[1][n] = force * t[1];
            if jacobian {
                let dw = [rate_theta + sliding_derivative, rate_axial];
                for (b, &(row, column)) in BLOCKS.iter().enumerate() {
                    self.samples[b][n] = match column {
                        Column::Normal => mu * t[row] * slope[n],
                        Column::Circumferential => force * dt[row][0] * omega,
                        Column::Axial => force * dt[row][1] * omega,
                    };
                }
                for (row, derivative) in dt.iter().enumerate() {
                    self.samples[BLOCKS.len() + row][n] =
                        force * (derivative[0] * dw[0] + derivative[1] * dw[1]);
                }
            }
        }
        for (force, &band) in self.force.iter().zip(&bands) {
            aft.to_frequency(force, &mut forces[band..band + size]);
        }
        if !jacobian {
            return;
        }
        for (b, &(_, column)) in BLOCKS.iter().enumerate() {
            let at = (index * BLOCKS.len() + b) * size * size;
            let block = &mut self.blocks[at..at + size * size];
            aft.derivative_block(&self.samples[b], block);
            if column != Column::Normal {
                times_derivative(block, size);
            }
        }
        for (row, &band) in bands.iter().enumerate() {
            aft.to_frequency(
                &self.samples[BLOCKS.len() + row],
                &mut self.frequency_derivative[band..band + size],
            );
        }
    }
}

/// `B ← B D` for a row-major `size × size` block, `D` the derivative in `τ`
/// of [`derivative_coordinates`].
fn times_derivative(block: &mut [f64], size: usize) {
    for row in block.chunks_exact_mut(size) {
        row[0] = 0.0;
        for k in 1..=(size - 1) / 2 {
            let (re, im) = (row[2 * k - 1], row[2 * k]);
            row[2 * k - 1] = k as f64 * im;
            row[2 * k] = -(k as f64) * re;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_derivative_block_product_is_the_block_of_the_derivative() {
        // B D u = B (D u) for any u.
        let size = 7;
        let block: Vec<f64> = (0..size * size).map(|i| (i as f64 * 0.37).sin()).collect();
        let u: Vec<f64> = (0..size).map(|i| (i as f64 * 1.3).cos()).collect();
        let mut du = vec![0.0; size];
        derivative_coordinates(&u, &mut du);
        let mut product = block.clone();
        times_derivative(&mut product, size);
        for r in 0..size {
            let left: f64 = (0..size).map(|c| product[r * size + c] * u[c]).sum();
            let right: f64 = (0..size).map(|c| block[r * size + c] * du[c]).sum();
            assert!((left - right).abs() < 1e-14, "row {r}: {left} vs {right}");
        }
    }

    #[test]
    fn derivative_coordinates_differentiate_the_signal() {
        let (h, n_t) = (4, 64);
        let mut aft = Aft::new(h, n_t);
        let u: Vec<f64> = (0..2 * h + 1)
            .map(|i| 0.1 * (i as f64 + 1.0).sqrt())
            .collect();
        let mut du = vec![0.0; 2 * h + 1];
        derivative_coordinates(&u, &mut du);
        let (mut samples, mut rate) = (vec![0.0; n_t], vec![0.0; n_t]);
        aft.to_time(&u, &mut samples);
        aft.to_time(&du, &mut rate);
        let step = 2.0 * std::f64::consts::PI / n_t as f64;
        // Against the closed-form derivative of the trigonometric sum.
        for (n, r) in rate.iter().enumerate() {
            let tau = n as f64 * step;
            let exact: f64 = (1..=h)
                .map(|k| {
                    let (s, c) = (k as f64 * tau).sin_cos();
                    -2.0 * k as f64 * (u[2 * k - 1] * s + u[2 * k] * c)
                })
                .sum();
            assert!((r - exact).abs() < 1e-13, "τ_{n}: {r} vs {exact}");
        }
    }
}
