//! The paper's nodal-diameter rule (Sec. 2.4, Eq. 33) and parity rule
//! (Sec. 3.2.1, Appendix B).

use super::{BasisError, BasisKind, SpectralBasis};
use crate::cyclic::{ExcitationPattern, HarmonicSet, LoadCase};

fn gcd(a: usize, b: usize) -> usize {
    let (mut a, mut b) = (a, b);
    while b != 0 {
        (a, b) = (b, a % b);
    }
    a
}

/// `K` of Eq. (33): `lcm(2h, N) / (2h)`, the smallest `K ≥ 1` with
/// `2 K h ≡ 0 (mod N)`; `K = 1` for `h ≡ 0 (mod N)`. `sectors` must be ≥ 1.
pub fn paper_k(sectors: usize, engine_order: usize) -> usize {
    let n = sectors.max(1);
    if engine_order.is_multiple_of(n) {
        1
    } else {
        n / gcd(n, 2 * (engine_order % n))
    }
}

/// The order the paper's rule uses for several excited diameters
/// (Sec. 2.4, 4.3.3, C.3): their greatest common divisor (0 if all are 0
/// or none is given). Coprime orders give 1, hence the full set.
pub fn combined_order(engine_orders: &[usize]) -> usize {
    engine_orders.iter().fold(0, |g, &h| gcd(g, h))
}

/// Whether the parity rule applies to the order `h` (Sec. 3.2.1):
/// `K h ≡ N/2 (mod N)`, which needs an even `N`.
pub fn parity_applies(sectors: usize, engine_order: usize) -> bool {
    let n = sectors.max(1);
    let k = paper_k(n, engine_order);
    n.is_multiple_of(2) && (k * (engine_order % n)) % n == n / 2
}

/// The paper's list `D = [d_0, d_1, …, d_K]` (Eq. 34 and the steps after it):
/// `d_q` is `q h mod N` folded to `0..=⌊N/2⌋`; repeats are kept, as the
/// paper lists them (Eq. 96).
pub fn paper_nodal_diameters(sectors: usize, engine_order: usize) -> Vec<usize> {
    let n = sectors.max(1);
    let h = engine_order % n;
    (0..=paper_k(n, h))
        .map(|q| {
            let r = (q * h) % n;
            r.min(n - r)
        })
        .collect()
}

impl SpectralBasis {
    /// The paper's nodal-diameter rule for the excited orders
    /// `engine_orders`, combined through their gcd `h` (Sec. 2.4): the set
    /// `D = {d_q}` of [`paper_nodal_diameters`] on every harmonic, each
    /// `d` entering as `+d` and `−d`. With `parity` and `K h ≡ N/2 (mod N)`
    /// (Sec. 3.2.1), the `d_q` of even `q` (`D^e`) go on even harmonics
    /// and those of odd `q` (`D^o`) on odd ones.
    ///
    /// The parity rule is proved for one order excited on harmonic 1; the
    /// caller decides whether it holds for its loads.
    pub fn nodal_diameter_rule(
        sectors: usize,
        harmonics: usize,
        engine_orders: &[usize],
        parity: bool,
    ) -> Result<Self, BasisError> {
        super::check_size(sectors, harmonics)?;
        let h = combined_order(engine_orders) % sectors;
        // The paper's steps: d_q from q h mod N for q = 0..=K, each entering
        // as +d and −d; marked on the N residues, read back in order.
        let signed = |keep: &dyn Fn(usize) -> bool| -> Vec<i64> {
            let mut member = vec![false; sectors];
            for q in (0..=paper_k(sectors, h)).filter(|&q| keep(q)) {
                let r = (q * h) % sectors;
                member[r] = true;
                member[(sectors - r) % sectors] = true;
            }
            let lowest = (sectors / 2) as i64 + 1 - sectors as i64;
            (lowest..=(sectors / 2) as i64)
                .filter(|&s| member[s.rem_euclid(sectors as i64) as usize])
                .collect()
        };
        let sets = if parity && parity_applies(sectors, h) {
            let even = signed(&|q: usize| q.is_multiple_of(2));
            let odd = signed(&|q: usize| !q.is_multiple_of(2));
            HarmonicSet::up_to(harmonics)
                .iter()
                .map(|k| {
                    if k.is_multiple_of(2) {
                        even.clone()
                    } else {
                        odd.clone()
                    }
                })
                .collect()
        } else {
            vec![signed(&|_| true); HarmonicSet::up_to(harmonics).count()]
        };
        Self::new(BasisKind::NodalDiameter, sectors, sets)
    }

    /// The nodal-diameter rule applied to a load's orders (excitation and
    /// casing), even for a traveling excitation; the parity rule is used
    /// where the paper applies it: one order excited on harmonic 1
    /// (traveling, standing or mixed) and a circular casing. Per-sector
    /// excitations use the gcd of their excited diameters, without parity.
    pub fn nodal_diameter(load: &LoadCase, harmonics: usize) -> Result<Self, BasisError> {
        let (orders, parity) = load_orders(load)?;
        Self::nodal_diameter_rule(load.sectors, harmonics, &orders, parity)
    }
}

/// The orders a load excites (excitation diameters and casing order) and
/// whether the parity rule may be used for it.
pub fn load_orders(load: &LoadCase) -> Result<(Vec<usize>, bool), BasisError> {
    if load.sectors == 0 {
        return Err(BasisError::NoSectors(0));
    }
    let casing = load.casing_order.filter(|&h| h > 0);
    let mut orders: Vec<usize> = Vec::new();
    let mut single_first_harmonic = false;
    if let Some(excitation) = &load.excitation {
        excitation.validate(load.sectors)?;
        match excitation {
            ExcitationPattern::Traveling { engine_order }
            | ExcitationPattern::Standing { engine_order }
            | ExcitationPattern::Mixed { engine_order, .. } => {
                orders.push(*engine_order);
                single_first_harmonic = true;
            }
            ExcitationPattern::PerSector { .. } => orders.extend(
                excitation
                    .pair_coefficients(load.sectors)
                    .iter()
                    .map(|(pair, _)| pair.nodal_diameter.unsigned_abs() as usize),
            ),
        }
    }
    orders.extend(casing);
    Ok((orders, single_first_harmonic && casing.is_none()))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn k_of_eq_33() {
        assert_eq!(paper_k(24, 0), 1);
        assert_eq!(paper_k(24, 1), 12);
        assert_eq!(paper_k(24, 8), 3);
        assert_eq!(paper_k(45, 9), 5);
        assert_eq!(paper_k(1, 0), 1);
    }

    #[test]
    fn parity_condition() {
        assert!(parity_applies(24, 1) && parity_applies(24, 4) && parity_applies(24, 12));
        assert!(!parity_applies(24, 8) && !parity_applies(24, 0) && !parity_applies(45, 9));
    }

    #[test]
    fn paper_list_keeps_repeats() {
        assert_eq!(paper_nodal_diameters(24, 8), vec![0, 8, 8, 0]);
        assert_eq!(paper_nodal_diameters(24, 4), vec![0, 4, 8, 12]);
    }
}
