//! Solves with `A − sI` by the structure of a Hill block: a small
//! factorization of each group's dynamic stiffness and a Schur complement
//! on the contact dofs (Woodbury).

use super::Block;
use crate::stability::small_lu::SmallLu;
use faer::c64;

/// `A − sI` factorized by the block's structure.
pub(in crate::stability::targeted) struct Solver {
    /// The shift `s`.
    pub(in crate::stability::targeted) shift: c64,
    /// `Z_g(s)` per group.
    groups: Vec<SmallLu>,
    /// `Z⁻¹ e_j` for each contact dof `j`, on its group's dofs.
    columns: Vec<Vec<c64>>,
    /// `I + D Eᵀ Z⁻¹ E` on the contact dofs.
    schur: SmallLu,
}

impl Solver {
    /// `A − sI` at `shift`, or `None` when a factorization meets a zero pivot.
    pub(in crate::stability::targeted) fn at(block: &Block, shift: c64) -> Option<Self> {
        let omega = block.omega;
        let mut groups = Vec::with_capacity(block.groups.len());
        for g in block.groups {
            let d = g.dynamics.as_ref();
            let n = d.dofs();
            let z = shift + c64::new(0.0, g.harmonic as f64);
            let (a2, a1) = (z * z * (omega * omega), z * omega);
            let mut matrix = Vec::with_capacity(n * n);
            for r in 0..n {
                for c in 0..n {
                    matrix.push(
                        d.mass()[(r, c)] * a2 + d.damping()[(r, c)] * a1 + d.stiffness()[(r, c)],
                    );
                }
            }
            groups.push(SmallLu::new(matrix, n)?);
        }
        let columns: Vec<Vec<c64>> = block
            .contact
            .iter()
            .zip(&block.contact_group)
            .map(|(&d, &g)| {
                let n = block.groups[g].dynamics.dofs();
                let mut e = vec![c64::new(0.0, 0.0); n];
                e[d - block.offsets[g]] = c64::new(1.0, 0.0);
                groups[g].solve(&mut e);
                e
            })
            .collect();
        let n = block.contact.len();
        let mut schur = vec![c64::new(0.0, 0.0); n * n];
        for i in 0..n {
            schur[i * n + i] = c64::new(1.0, 0.0);
        }
        // (D G)_ij = Σ_l D_il G_lj, G_lj nonzero only in j's group.
        for j in 0..n {
            let g = block.contact_group[j];
            for l in 0..n {
                if block.contact_group[l] != g {
                    continue;
                }
                let gl = columns[j][block.contact[l] - block.offsets[g]];
                for i in 0..n {
                    schur[i * n + j] += block.coupling[i * n + l] * gl;
                }
            }
        }
        Some(Self {
            shift,
            groups,
            columns,
            schur: SmallLu::new(schur, n)?,
        })
    }

    /// `(A − sI)⁻¹ b` for the state `b = [b₁; b₂]`.
    pub(in crate::stability::targeted) fn apply(&self, block: &Block, b: &[c64]) -> Vec<c64> {
        let (m, omega, s) = (block.m, block.omega, self.shift);
        let (b1, b2) = b.split_at(m);
        // Q(s) x = −ω² M b₂ − ω² (s + 2ik) M b₁ − ω C b₁, per group.
        let mut x = vec![c64::new(0.0, 0.0); m];
        for ((g, &o), lu) in block.groups.iter().zip(&block.offsets).zip(&self.groups) {
            let d = g.dynamics.as_ref();
            let n = d.dofs();
            let factor = (s + c64::new(0.0, 2.0 * g.harmonic as f64)) * (omega * omega);
            for r in 0..n {
                let mut sum = c64::new(0.0, 0.0);
                for c in 0..n {
                    sum -= d.mass()[(r, c)] * (b2[o + c] * (omega * omega) + b1[o + c] * factor)
                        + d.damping()[(r, c)] * b1[o + c] * omega;
                }
                x[o + r] = sum;
            }
            lu.solve(&mut x[o..o + n]);
        }
        // Woodbury on the contact dofs: x −= Z⁻¹E (I + D G)⁻¹ D Eᵀ y.
        let n = block.contact.len();
        let mut t: Vec<c64> = (0..n)
            .map(|i| {
                (0..n)
                    .map(|l| block.coupling[i * n + l] * x[block.contact[l]])
                    .sum()
            })
            .collect();
        self.schur.solve(&mut t);
        for (j, &u) in t.iter().enumerate() {
            let o = block.offsets[block.contact_group[j]];
            for (r, &value) in self.columns[j].iter().enumerate() {
                x[o + r] -= value * u;
            }
        }
        let mut out = Vec::with_capacity(2 * m);
        out.extend_from_slice(&x);
        out.extend(b1.iter().zip(&x).map(|(&b, &x)| b + s * x));
        out
    }
}
