//! A class's quadratic operator applied to a vector without factorizing
//! it: `Q(μ) q` and `Q'(μ) q` (the Rayleigh functional iteration's
//! products, `super::refine`), and `Q(μ) q` with the scale of its terms
//! (the residual tests). A vector's products with `M`, `C`, `K` and the
//! contact are kept ([`Applied`]), so that both at a second `μ` cost `O(m)`.

use super::{ClassOperator, ZERO};
use faer::c64;

impl ClassOperator<'_> {
    /// `Q(μ) q` and `Q'(μ) q`, each entry built from the matrices (not
    /// through a factorization).
    pub(in crate::stability::condensed) fn times(
        &self,
        mu: c64,
        q: &[c64],
    ) -> (Vec<c64>, Vec<c64>) {
        self.at(&self.applied(q), mu)
    }

    /// The products of the matrices with `q` that `Q(μ) q` and `Q'(μ) q`
    /// combine: both at any `μ` then cost `O(m)` ([`Self::at`]); an
    /// iteration that evaluates one vector at two `μ` (a Newton step, then
    /// the next inverse iteration) pays the products once.
    pub(in crate::stability::condensed) fn applied(&self, q: &[c64]) -> Applied {
        let m = self.m;
        let (mut mass, mut damping, mut stiffness) = (vec![ZERO; m], vec![ZERO; m], vec![ZERO; m]);
        for (&o, &index) in self.offsets.iter().zip(&self.group_matrices) {
            let d = &self.matrices[index];
            let n = d.dofs;
            let x = &q[o..o + n];
            for r in 0..n {
                let row = r * n..(r + 1) * n;
                let (mut mx, mut dx, mut kx) = (ZERO, ZERO, ZERO);
                for (((&mc, &dc), &kc), &xc) in d.mass[row.clone()]
                    .iter()
                    .zip(&d.damping[row.clone()])
                    .zip(&d.stiffness[row])
                    .zip(x)
                {
                    mx += mc * xc;
                    dx += dc * xc;
                    kx += kc * xc;
                }
                mass[o + r] = mx;
                damping[o + r] = dx;
                stiffness[o + r] = kx;
            }
        }
        // C_c(μ) x = D x + ω μ E x + ω E (i k ∘ x), Q' adds ω E x.
        let x: Vec<c64> = self.contact.iter().map(|&d| q[d]).collect();
        let contact_stiffness = self.stiffness_rows.times(&x);
        let (contact_velocity, contact_harmonics) = if self.velocity_terms {
            let shifted: Vec<c64> = x
                .iter()
                .zip(&self.contact_group)
                .map(|(&x, &g)| x * c64::new(0.0, self.groups[g].harmonic as f64))
                .collect();
            (
                self.damping_rows.times(&x),
                self.damping_rows.times(&shifted),
            )
        } else {
            (Vec::new(), Vec::new())
        };
        Applied {
            mass,
            damping,
            stiffness,
            contact_stiffness,
            contact_velocity,
            contact_harmonics,
        }
    }

    /// `Q(μ) q` and `Q'(μ) q` from `q`'s products ([`Self::applied`]).
    pub(in crate::stability::condensed) fn at(
        &self,
        applied: &Applied,
        mu: c64,
    ) -> (Vec<c64>, Vec<c64>) {
        let mut value = vec![ZERO; self.m];
        let mut slope = vec![ZERO; self.m];
        let w = self.omega;
        for ((g, &o), &index) in self
            .groups
            .iter()
            .zip(&self.offsets)
            .zip(&self.group_matrices)
        {
            let n = self.matrices[index].dofs;
            let z = mu + c64::new(0.0, g.harmonic as f64);
            let (a2, a1, b1) = (z * z * (w * w), z * w, z * (2.0 * w * w));
            for i in o..o + n {
                let (mx, dx, kx) = (applied.mass[i], applied.damping[i], applied.stiffness[i]);
                value[i] = mx * a2 + dx * a1 + kx;
                slope[i] = mx * b1 + dx * w;
            }
        }
        for (i, &d) in self.contact.iter().enumerate() {
            let mut sum = applied.contact_stiffness[i];
            if self.velocity_terms {
                let ex = applied.contact_velocity[i];
                sum += (ex * mu + applied.contact_harmonics[i]) * w;
                slope[d] += ex * w;
            }
            value[d] += sum;
        }
        (value, slope)
    }

    /// `Q(μ) q` with the scale of the terms summed (for a relative
    /// residual).
    pub(in crate::stability::condensed) fn residual(&self, mu: c64, q: &[c64]) -> (Vec<c64>, f64) {
        self.products(mu, q)
    }

    /// `Q(μ) q` and the scale of its terms (the sum of their sizes).
    fn products(&self, mu: c64, q: &[c64]) -> (Vec<c64>, f64) {
        let mut value = vec![ZERO; self.m];
        let mut scale = 0.0_f64;
        let w = self.omega;
        for ((g, &o), &index) in self
            .groups
            .iter()
            .zip(&self.offsets)
            .zip(&self.group_matrices)
        {
            let d = &self.matrices[index];
            let n = d.dofs;
            let z = mu + c64::new(0.0, g.harmonic as f64);
            let (a2, a1) = (z * z * (w * w), z * w);
            let x = &q[o..o + n];
            for r in 0..n {
                let row = r * n..(r + 1) * n;
                let (mass, damping, stiffness) = (
                    &d.mass[row.clone()],
                    &d.damping[row.clone()],
                    &d.stiffness[row],
                );
                // Σ M x, Σ C x, Σ K x first: the factors apply once a row.
                let (mut mx, mut dx, mut kx) = (ZERO, ZERO, ZERO);
                for c in 0..n {
                    mx += mass[c] * x[c];
                    dx += damping[c] * x[c];
                    kx += stiffness[c] * x[c];
                    let (ma, da) = (mass[c] * a2, damping[c] * a1);
                    scale += (size(ma) + size(da) + size(stiffness[c])) * size(x[c]);
                }
                value[o + r] = mx * a2 + dx * a1 + kx;
            }
        }
        // C_c(μ) x = D x + E diag(ω(μ + i k_col)) x.
        let r = self.contact.len();
        let x: Vec<c64> = self.contact.iter().map(|&d| q[d]).collect();
        let moved: Vec<c64> = if self.velocity_terms {
            x.iter()
                .zip(&self.contact_group)
                .map(|(&x, &g)| x * (mu + c64::new(0.0, self.groups[g].harmonic as f64)) * w)
                .collect()
        } else {
            Vec::new()
        };
        for i in 0..r {
            let mut sum = ZERO;
            for (column, entry) in self.stiffness_rows.row(i) {
                sum += entry * x[column];
                scale += size(entry) * size(x[column]);
            }
            if self.velocity_terms {
                for (column, entry) in self.damping_rows.row(i) {
                    sum += entry * moved[column];
                    scale += size(entry) * size(moved[column]);
                }
            }
            value[self.contact[i]] += sum;
        }
        (value, scale)
    }
}

/// The products of a class's matrices with one vector
/// ([`ClassOperator::applied`]).
#[derive(Clone)]
pub(in crate::stability::condensed) struct Applied {
    /// `M x`, `C x`, `K x` on the block's dofs, group by group.
    mass: Vec<c64>,
    damping: Vec<c64>,
    stiffness: Vec<c64>,
    /// `D x`, `E x` and `E (i k ∘ x)` on the contact positions (the last
    /// two empty without friction).
    contact_stiffness: Vec<c64>,
    contact_velocity: Vec<c64>,
    contact_harmonics: Vec<c64>,
}

/// `|Re z| + |Im z|`: a norm within `√2` of `|z|`, without `hypot`.
fn size(z: c64) -> f64 {
    z.re.abs() + z.im.abs()
}
