//! The first stage of a perturbed wheel's condensation: the tuned wheel on
//! its kept dofs, diameter by diameter, in small fixed loops (a sector's
//! few dofs: faer's general routines and their allocations cost more than
//! the arithmetic here), then back to the sectors as dense matrices.
//!
//! With `x_j = Σ_s x̂(s) e^{i s α j}` and `x̂(s) = (1/N) Σ_j x_j e^{−i s α j}`
//! (as `diameters.rs`), diameter `s` condenses as a sector:
//! `Ŝ = Ẑ_kk − Ẑ_ki Ẑ_ii⁻¹ Ẑ_ik`, `ĝ = f̂_k − Ẑ_ki Ẑ_ii⁻¹ f̂_i`, with their
//! `ω`-derivatives; the wheel's kept block `(j, l)` is `S(0, l − j)` with
//! `S(0, t) = (1/N) Σ_s Ŝ(s) e^{−i s α t}`, its load `g_j = Σ_s ĝ(s) e^{i s α j}`.

use super::super::BlockMatrices;
use faer::{c64, Mat};

/// The tuned wheel condensed on the kept dofs at one frequency: `Z`,
/// `∂Z/∂ω` (dense, sector-major) and the loads `F`, `∂F/∂ω`.
pub(super) struct FirstStage {
    pub(super) dynamic: Mat<c64>,
    pub(super) derivative: Mat<c64>,
    pub(super) load: Vec<c64>,
    pub(super) load_derivative: Vec<c64>,
}

/// What the first stage needs of the wheel: one sector's kept and other
/// dofs, and `e^{i α t}`.
pub(super) struct Split<'a> {
    pub(super) kept: &'a [usize],
    pub(super) inner: &'a [usize],
    pub(super) twiddles: &'a [c64],
}

/// `Z = K − (kω)² M + i kω C`, `∂Z/∂ω` of one diameter at `(a, b)`.
fn entries(m: &BlockMatrices, k: f64, omega: f64, a: usize, b: usize) -> (c64, c64) {
    let (mass, stiffness, damping) = (m.mass[(a, b)], m.stiffness[(a, b)], m.damping[(a, b)]);
    let z = stiffness - mass * (k * k * omega * omega) + damping * c64::new(0.0, k * omega);
    let dz = mass * (-2.0 * k * k * omega) + damping * c64::new(0.0, k);
    (z, dz)
}

/// LU with partial pivoting of the `n × n` row-major `a`, in place: the
/// row swaps, or `None` when a pivot is zero or not finite.
fn factor(a: &mut [c64], n: usize) -> Option<Vec<usize>> {
    let mut pivots = Vec::with_capacity(n);
    for c in 0..n {
        let p = (c..n).max_by(|&x, &y| a[x * n + c].norm().total_cmp(&a[y * n + c].norm()))?;
        let pivot = a[p * n + c];
        if !(pivot.norm() > 0.0 && pivot.norm().is_finite()) {
            return None;
        }
        pivots.push(p);
        if p != c {
            for col in 0..n {
                a.swap(c * n + col, p * n + col);
            }
        }
        for r in c + 1..n {
            let l = a[r * n + c] / a[c * n + c];
            a[r * n + c] = l;
            for col in c + 1..n {
                let u = a[c * n + col];
                a[r * n + col] -= l * u;
            }
        }
    }
    Some(pivots)
}

/// Solves `A X = B` for the `n × cols` row-major `b`, in place, from
/// [`factor`]'s result.
fn solve(lu: &[c64], pivots: &[usize], n: usize, b: &mut [c64], cols: usize) {
    for (c, &p) in pivots.iter().enumerate() {
        if p != c {
            for col in 0..cols {
                b.swap(c * cols + col, p * cols + col);
            }
        }
    }
    for r in 0..n {
        for c in 0..r {
            let l = lu[r * n + c];
            for col in 0..cols {
                let v = b[c * cols + col];
                b[r * cols + col] -= l * v;
            }
        }
    }
    for r in (0..n).rev() {
        for c in r + 1..n {
            let u = lu[r * n + c];
            for col in 0..cols {
                let v = b[c * cols + col];
                b[r * cols + col] -= u * v;
            }
        }
        let d = lu[r * n + r];
        for col in 0..cols {
            b[r * cols + col] /= d;
        }
    }
}

/// The first stage of harmonic `harmonic` at `omega` from the tuned
/// wheel's `diameters` (`N` of them) and the wheel's `load` (sector-major,
/// all dofs); `None` when a diameter's other dofs are singular there.
pub(super) fn first_stage(
    diameters: &[&BlockMatrices],
    split: &Split<'_>,
    harmonic: usize,
    omega: f64,
    load: &[c64],
) -> Option<FirstStage> {
    let n = diameters.len();
    let (kept, inner) = (split.kept, split.inner);
    let (r, m) = (kept.len(), inner.len());
    let dofs = r + m;
    let k = harmonic as f64;
    let zero = c64::new(0.0, 0.0);
    let scale = 1.0 / n as f64;
    // S(0, t) and ∂S(0, t)/∂ω, row-major r × (N r); the loads by sector.
    let mut row = vec![zero; r * n * r];
    let mut d_row = vec![zero; r * n * r];
    let mut g = vec![zero; n * r];
    let mut dg = vec![zero; n * r];
    let cols = r + 1;
    for (s, matrices) in diameters.iter().enumerate() {
        let z = |a: usize, b: usize| entries(matrices, k, omega, a, b);
        // f̂(s) on every dof of the sector.
        let hat: Vec<c64> = (0..dofs)
            .map(|d| {
                (0..n).fold(zero, |sum, j| {
                    sum + load[j * dofs + d] * split.twiddles[(s * j) % n].conj()
                }) * scale
            })
            .collect();
        let (mut w, mut q) = (vec![zero; m * cols], vec![zero; m * cols]);
        if m > 0 {
            let mut zii = vec![zero; m * m];
            let mut dzii = vec![zero; m * m];
            for (a, &ia) in inner.iter().enumerate() {
                for (b, &ib) in inner.iter().enumerate() {
                    (zii[a * m + b], dzii[a * m + b]) = z(ia, ib);
                }
            }
            let pivots = factor(&mut zii, m)?;
            // W = Z_ii⁻¹ [Z_ik | f̂_i].
            for (a, &ia) in inner.iter().enumerate() {
                for (b, &kb) in kept.iter().enumerate() {
                    w[a * cols + b] = z(ia, kb).0;
                }
                w[a * cols + r] = hat[ia];
            }
            solve(&zii, &pivots, m, &mut w, cols);
            // Q = Z_ii⁻¹ ([∂Z_ik | 0] − ∂Z_ii W).
            for (a, &ia) in inner.iter().enumerate() {
                for col in 0..cols {
                    let mut v = if col < r { z(ia, kept[col]).1 } else { zero };
                    for b in 0..m {
                        v -= dzii[a * m + b] * w[b * cols + col];
                    }
                    q[a * cols + col] = v;
                }
            }
            solve(&zii, &pivots, m, &mut q, cols);
        }
        // Ŝ(s), ∂Ŝ(s) and ĝ(s), ∂ĝ(s), one kept row at a time.
        let mut hat_s = vec![zero; r * r];
        let mut hat_ds = vec![zero; r * r];
        let (mut hat_g, mut hat_dg) = (vec![zero; r], vec![zero; r]);
        for (a, &ka) in kept.iter().enumerate() {
            let coupling: Vec<(c64, c64)> = inner.iter().map(|&ib| z(ka, ib)).collect();
            for col in 0..cols {
                let (mut v, mut dv) = if col < r {
                    z(ka, kept[col])
                } else {
                    (hat[ka], zero)
                };
                for (b, &(zki, dzki)) in coupling.iter().enumerate() {
                    v -= zki * w[b * cols + col];
                    dv -= dzki * w[b * cols + col] + zki * q[b * cols + col];
                }
                if col < r {
                    hat_s[a * r + col] = v;
                    hat_ds[a * r + col] = dv;
                } else {
                    hat_g[a] = v;
                    hat_dg[a] = dv;
                }
            }
        }
        for t in 0..n {
            let back = split.twiddles[(s * t) % n].conj() * scale;
            let forth = split.twiddles[(s * t) % n];
            for a in 0..r {
                for b in 0..r {
                    row[a * n * r + t * r + b] += hat_s[a * r + b] * back;
                    d_row[a * n * r + t * r + b] += hat_ds[a * r + b] * back;
                }
                g[t * r + a] += hat_g[a] * forth;
                dg[t * r + a] += hat_dg[a] * forth;
            }
        }
    }
    let size = n * r;
    // Block (j, l) is S(0, l − j), filled a column at a time (no integer
    // division an entry: it was most of this step's cost).
    let dense = |row: &[c64]| {
        let mut wheel = Mat::<c64>::zeros(size, size);
        for l in 0..n {
            for b in 0..r {
                for j in 0..n {
                    let t = if l >= j { l - j } else { l + n - j };
                    for a in 0..r {
                        wheel[(j * r + a, l * r + b)] = row[a * n * r + t * r + b];
                    }
                }
            }
        }
        wheel
    };
    Some(FirstStage {
        dynamic: dense(&row),
        derivative: dense(&d_row),
        load: g,
        load_derivative: dg,
    })
}
