//! Property tests of the symmetry rule against a brute-force closure of the
//! load pairs and against the paper's rules.

use cyclorub::basis::{PaperRule, SpectralBasis};
use cyclorub::cyclic::{fold_nodal_diameter, ExcitationPattern, LoadCase, SignedPair};
use proptest::prelude::*;
use std::collections::{HashSet, VecDeque};

/// The load kinds drawn by the tests.
#[derive(Clone, Debug)]
enum Kind {
    Traveling,
    Standing,
    Mixed(f64),
    /// A per-sector excitation repeating with period `p | N`: it excites
    /// the diameters that are multiples of `N / p`.
    PerSector(Vec<f64>, Vec<f64>),
    None,
}

fn load_strategy() -> impl Strategy<Value = (LoadCase, usize)> {
    (1usize..=60, 1usize..=10)
        .prop_flat_map(|(n, nh)| {
            let divisors: Vec<usize> = (1..=n).filter(|p| n % p == 0).collect();
            let kind = prop_oneof![
                Just(Kind::Traveling),
                Just(Kind::Standing),
                (0.05f64..0.95).prop_map(Kind::Mixed),
                proptest::sample::select(divisors).prop_flat_map(|p| {
                    (
                        proptest::collection::vec(0.1f64..2.0, p),
                        proptest::collection::vec(-3.0f64..3.0, p),
                    )
                        .prop_map(|(a, phi)| Kind::PerSector(a, phi))
                }),
                Just(Kind::None),
            ];
            let casing = prop_oneof![Just(None), (0usize..2 * n).prop_map(Some)];
            (Just(n), Just(nh), 0..n, kind, casing)
        })
        .prop_map(|(n, nh, h, kind, casing_order)| {
            let excitation = match kind {
                Kind::Traveling => Some(ExcitationPattern::Traveling { engine_order: h }),
                Kind::Standing => Some(ExcitationPattern::Standing { engine_order: h }),
                Kind::Mixed(w) => Some(ExcitationPattern::Mixed {
                    engine_order: h,
                    backward_weight: w,
                    forward_weight: 1.0 - w,
                }),
                Kind::PerSector(a, phi) => {
                    let p = a.len();
                    Some(ExcitationPattern::PerSector {
                        amplitudes: (0..n).map(|j| a[j % p]).collect(),
                        phases: (0..n).map(|j| phi[j % p]).collect(),
                    })
                }
                Kind::None => None,
            };
            (
                LoadCase {
                    sectors: n,
                    excitation,
                    casing_order,
                },
                nh,
            )
        })
}

/// Brute force: every pair reachable from `(0, 0)` by adding or subtracting
/// generators, with `|k|` kept within `N_h + max |k_gen|` (enough: steps of
/// at most that size can be ordered to stay in the band), restricted to
/// `0 ≤ k ≤ N_h`.
fn brute_force_closure(n: usize, generators: &[SignedPair], nh: usize) -> Vec<Vec<i64>> {
    let nn = n as i64;
    let band = nh as i64
        + generators
            .iter()
            .map(|g| g.harmonic.abs())
            .max()
            .unwrap_or(0);
    let mut seen: HashSet<(i64, i64)> = HashSet::new();
    let mut queue = VecDeque::from([(0i64, 0i64)]);
    seen.insert((0, 0));
    while let Some((s, k)) = queue.pop_front() {
        for g in generators {
            for sign in [1, -1] {
                let next = (
                    (s + sign * g.nodal_diameter).rem_euclid(nn),
                    k + sign * g.harmonic,
                );
                if next.1.abs() <= band && seen.insert(next) {
                    queue.push_back(next);
                }
            }
        }
    }
    (0..=nh as i64)
        .map(|k| {
            let mut set: Vec<i64> = seen
                .iter()
                .filter(|p| p.1 == k)
                .map(|p| fold_nodal_diameter(p.0, n))
                .collect();
            set.sort_unstable();
            set
        })
        .collect()
}

fn sets(b: &SpectralBasis) -> Vec<Vec<i64>> {
    (0..=b.harmonics())
        .map(|k| b.nodal_diameters(k).to_vec())
        .collect()
}

fn subset(a: &SpectralBasis, b: &SpectralBasis) -> bool {
    (0..=a.harmonics()).all(|k| {
        a.nodal_diameters(k)
            .iter()
            .all(|s| b.nodal_diameters(k).contains(s))
    })
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 256, ..ProptestConfig::default() })]

    /// Closed: sums and differences of kept pairs within the harmonic range
    /// are kept; harmonic 0 is closed under negation.
    #[test]
    fn symmetry_rule_is_closed((load, nh) in load_strategy()) {
        let n = load.sectors;
        let b = SpectralBasis::symmetry(&load, nh).unwrap();
        for &s in b.nodal_diameters(0) {
            prop_assert!(b.nodal_diameters(0).contains(&fold_nodal_diameter(-s, n)));
        }
        for k1 in 0..=nh {
            for k2 in 0..=k1 {
                for &s1 in b.nodal_diameters(k1) {
                    for &s2 in b.nodal_diameters(k2) {
                        if k1 + k2 <= nh {
                            let sum = fold_nodal_diameter(s1 + s2, n);
                            prop_assert!(b.nodal_diameters(k1 + k2).contains(&sum),
                                "({s1},{k1}) + ({s2},{k2}) = ({sum},{}) missing", k1 + k2);
                        }
                        let difference = fold_nodal_diameter(s1 - s2, n);
                        prop_assert!(b.nodal_diameters(k1 - k2).contains(&difference));
                    }
                }
            }
        }
    }

    /// Minimal and complete: exactly the pairs generated by the loads.
    #[test]
    fn symmetry_rule_is_the_closure_of_the_loads((load, nh) in load_strategy()) {
        let b = SpectralBasis::symmetry(&load, nh).unwrap();
        let mut generators = load.pairs();
        generators.push(SignedPair::new(load.sectors as i64, 0, load.sectors));
        prop_assert_eq!(sets(&b), brute_force_closure(load.sectors, &generators, nh));
    }

    /// Against the paper: equal sizes (and sets) for one traveling or one
    /// standing load on a circular casing; never larger, and inside the
    /// paper's sets, for combined loads.
    #[test]
    fn symmetry_rule_against_the_papers_rules((load, nh) in load_strategy()) {
        let sym = SpectralBasis::symmetry(&load, nh).unwrap();
        let paper = SpectralBasis::paper(&load, nh).unwrap();
        let nodal = SpectralBasis::nodal_diameter(&load, nh).unwrap();
        prop_assert!(subset(&sym, &paper), "symmetry {:?} not in paper {:?}", sets(&sym), sets(&paper));
        prop_assert!(subset(&sym, &nodal));
        prop_assert!(sym.real_unknowns_per_contact_dof() <= paper.real_unknowns_per_contact_dof());
        prop_assert!(sym.sampled_sectors() <= paper.sampled_sectors());
        let circular = load.casing_order.unwrap_or(0) == 0;
        match (&load.excitation, circular) {
            (Some(ExcitationPattern::Traveling { engine_order }), true) => {
                prop_assert_eq!(PaperRule::for_load(&load).unwrap(),
                    PaperRule::TravelingWave { engine_order: *engine_order });
                prop_assert_eq!(sets(&sym), sets(&paper));
            }
            (Some(ExcitationPattern::Standing { .. }), true)
            | (Some(ExcitationPattern::Mixed { .. }), true) => {
                prop_assert_eq!(sym.real_unknowns_per_contact_dof(),
                    paper.real_unknowns_per_contact_dof());
                prop_assert_eq!(sets(&sym), sets(&paper));
            }
            _ => {}
        }
    }
}
