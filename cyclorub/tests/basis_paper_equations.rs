//! The bases the paper writes out: Eqs. (76)–(82), (85), (87), (88),
//! (104)–(107), and the symmetry rule's prediction of docs/design.md §3.

use cyclorub::basis::{BasisKind, PaperRule, SpectralBasis};
use cyclorub::cyclic::{ExcitationPattern, LoadCase};

const NH: usize = 10;

fn traveling(n: usize, h: usize) -> LoadCase {
    LoadCase {
        sectors: n,
        excitation: Some(ExcitationPattern::Traveling { engine_order: h }),
        casing_order: None,
    }
}

fn standing(n: usize, h: usize) -> LoadCase {
    LoadCase {
        sectors: n,
        excitation: Some(ExcitationPattern::Standing { engine_order: h }),
        casing_order: None,
    }
}

/// Eq. (86): 90 % backward, 10 % forward.
fn mixed(n: usize, h: usize) -> LoadCase {
    LoadCase {
        sectors: n,
        excitation: Some(ExcitationPattern::Mixed {
            engine_order: h,
            backward_weight: 0.9,
            forward_weight: 0.1,
        }),
        casing_order: None,
    }
}

/// The signed set `{+d, −d}` of unsigned diameters, folded and sorted.
fn signed(n: usize, unsigned: &[i64]) -> Vec<i64> {
    let mut v: Vec<i64> = unsigned
        .iter()
        .flat_map(|&d| [d, -d])
        .map(|s| cyclorub::cyclic::fold_nodal_diameter(s, n))
        .collect();
    v.sort_unstable();
    v.dedup();
    v
}

fn sets(b: &SpectralBasis) -> Vec<Vec<i64>> {
    (0..=b.harmonics())
        .map(|k| b.nodal_diameters(k).to_vec())
        .collect()
}

/// A traveling-wave list `[D^k]` as the paper prints it: one signed
/// diameter per harmonic.
fn singletons(list: &[i64]) -> Vec<Vec<i64>> {
    list.iter().map(|&s| vec![s]).collect()
}

/// `D^e` on even harmonics and `D^o` on odd ones (Eqs. 78, 79, 80, 87, 88).
fn parity_sets(n: usize, even: &[i64], odd: &[i64]) -> Vec<Vec<i64>> {
    (0..=NH)
        .map(|k| signed(n, if k % 2 == 0 { even } else { odd }))
        .collect()
}

#[test]
fn eq_76_and_77_traveling_n24() {
    let eq76 = singletons(&[0, -1, -2, -3, -4, -5, -6, -7, -8, -9, -10]);
    let eq77 = singletons(&[0, -3, -6, -9, 12, 9, 6, 3, 0, -3, -6]);
    for (h, expected) in [(1, eq76), (3, eq77)] {
        let paper = SpectralBasis::paper(&traveling(24, h), NH).unwrap();
        assert_eq!(sets(&paper), expected, "h = {h}");
        assert_eq!(paper.kind(), BasisKind::Paper);
        let tw = SpectralBasis::traveling_wave(24, NH, h).unwrap();
        assert_eq!(sets(&tw), expected);
        assert_eq!(tw.kind(), BasisKind::TravelingWave);
        // The symmetry rule finds the traveling-wave hypothesis by itself.
        let sym = SpectralBasis::symmetry(&traveling(24, h), NH).unwrap();
        assert_eq!(sets(&sym), expected);
        assert_eq!(sym.kind(), BasisKind::Symmetry);
        assert_eq!(
            (
                paper.real_unknowns_per_contact_dof(),
                paper.sampled_sectors()
            ),
            (21, 1)
        );
    }
}

#[test]
fn eq_78_and_79_standing_n24() {
    let b = SpectralBasis::paper(&standing(24, 1), NH).unwrap();
    assert_eq!(
        sets(&b),
        parity_sets(24, &[0, 2, 4, 6, 8, 10, 12], &[1, 3, 5, 7, 9, 11])
    );
    assert_eq!(
        PaperRule::for_load(&standing(24, 1)).unwrap(),
        PaperRule::NodalDiameter {
            engine_order: 1,
            k: 12,
            parity: true
        }
    );
    let b = SpectralBasis::paper(&standing(24, 4), NH).unwrap();
    assert_eq!(sets(&b), parity_sets(24, &[0, 8], &[4, 12]));
    assert_eq!(b.real_unknowns_per_contact_dof(), 63);
    // The symmetry rule gives the same sets for a standing load.
    for h in [1, 4] {
        let p = SpectralBasis::paper(&standing(24, h), NH).unwrap();
        let s = SpectralBasis::symmetry(&standing(24, h), NH).unwrap();
        assert_eq!(sets(&p), sets(&s), "h = {h}");
    }
}

#[test]
fn eq_80_81_82_mixed_scenario_n24() {
    // Eq. (80): the excitation h = 6 alone by the nodal-diameter rule.
    let b = SpectralBasis::nodal_diameter(&traveling(24, 6), NH).unwrap();
    assert_eq!(sets(&b), parity_sets(24, &[0, 12], &[6]));
    assert_eq!(b.kind(), BasisKind::NodalDiameter);
    // Eq. (81): the casing h_c = 8 alone, no parity.
    let casing = LoadCase {
        sectors: 24,
        excitation: None,
        casing_order: Some(8),
    };
    let expected81 = vec![signed(24, &[0, 8]); NH + 1];
    assert_eq!(
        sets(&SpectralBasis::nodal_diameter(&casing, NH).unwrap()),
        expected81
    );
    assert_eq!(
        sets(&SpectralBasis::paper(&casing, NH).unwrap()),
        expected81
    );
    // Eq. (82): both, through gcd(6, 8) = 2, no parity: 252 unknowns.
    let both = LoadCase {
        casing_order: Some(8),
        ..traveling(24, 6)
    };
    let b = SpectralBasis::paper(&both, NH).unwrap();
    assert_eq!(sets(&b), vec![signed(24, &[0, 2, 4, 6, 8, 10, 12]); NH + 1]);
    assert_eq!(
        (b.real_unknowns_per_contact_dof(), b.sampled_sectors()),
        (252, 12)
    );
    assert_eq!(
        PaperRule::for_load(&both).unwrap(),
        PaperRule::NodalDiameter {
            engine_order: 2,
            k: 6,
            parity: false
        }
    );
}

/// docs/design.md §3: the symmetry rule for N = 24, h = 6 traveling, h_c = 8.
#[test]
fn symmetry_rule_on_the_mixed_scenario_n24() {
    let both = LoadCase {
        casing_order: Some(8),
        ..traveling(24, 6)
    };
    let b = SpectralBasis::symmetry(&both, NH).unwrap();
    for k in 0..=NH {
        let expected: Vec<i64> = match k {
            0 | 4 | 8 => vec![-8, 0, 8],
            2 | 6 | 10 => vec![-4, 4, 12],
            1 | 5 | 9 => vec![-6, 2, 10],
            _ => vec![-10, -2, 6],
        };
        assert_eq!(b.nodal_diameters(k), expected.as_slice(), "harmonic {k}");
    }
    assert_eq!(b.real_unknowns_per_contact_dof(), 63);
    assert_eq!(b.sampled_sectors(), 3);
    // The observed parity of Sec. 4.3.3 (Fig. 12): {0, 4, 8, 12} on even
    // harmonics, {2, 6, 10} on odd ones, as unsigned diameters.
    for k in 0..=NH {
        for &s in b.nodal_diameters(k) {
            let d = s.unsigned_abs();
            assert_eq!(d % 4 == 0, k % 2 == 0, "harmonic {k}, diameter {s}");
        }
    }
}

#[test]
fn eq_85_traveling_n16() {
    let expected = singletons(&[0, -1, -2, -3, -4, -5, -6, -7, 8, 7, 6]);
    assert_eq!(
        sets(&SpectralBasis::paper(&traveling(16, 1), NH).unwrap()),
        expected
    );
    assert_eq!(
        sets(&SpectralBasis::symmetry(&traveling(16, 1), NH).unwrap()),
        expected
    );
}

#[test]
fn eq_87_and_88_partly_standing_n16() {
    let b = SpectralBasis::paper(&mixed(16, 4), NH).unwrap();
    assert_eq!(sets(&b), parity_sets(16, &[0, 8], &[4]));
    assert_eq!(
        PaperRule::for_load(&mixed(16, 4)).unwrap(),
        PaperRule::NodalDiameter {
            engine_order: 4,
            k: 2,
            parity: true
        }
    );
    let b = SpectralBasis::paper(&mixed(16, 7), NH).unwrap();
    assert_eq!(sets(&b), parity_sets(16, &[0, 2, 4, 6, 8], &[1, 3, 5, 7]));
    // Table 4: 50 % for h = 7.
    assert!((b.reduction_percent() - 50.0).abs() < 1e-12);
    for h in [4, 7] {
        let s = SpectralBasis::symmetry(&mixed(16, h), NH).unwrap();
        assert_eq!(
            sets(&s),
            sets(&SpectralBasis::paper(&mixed(16, h), NH).unwrap())
        );
    }
}

#[test]
fn eq_104_and_105_traveling_n45() {
    let eq104 = singletons(&[0, -2, -4, -6, -8, -10, -12, -14, -16, -18, -20]);
    let eq105 = singletons(&[0, -17, 11, -6, 22, 5, -12, 16, -1, -18, 10]);
    for (h, expected) in [(2, eq104), (17, eq105)] {
        let b = SpectralBasis::paper(&traveling(45, h), NH).unwrap();
        assert_eq!(sets(&b), expected, "h = {h}");
        // C.1: 100 (1 − 1/N) = 97.7 %.
        assert!((b.reduction_percent() - 100.0 * (1.0 - 1.0 / 45.0)).abs() < 1e-12);
        assert_eq!(
            sets(&SpectralBasis::symmetry(&traveling(45, h), NH).unwrap()),
            expected
        );
    }
}

#[test]
fn eq_106_standing_n45() {
    for (h, unsigned, k) in [(9, vec![0, 9, 18], 5), (15, vec![0, 15], 3)] {
        let b = SpectralBasis::paper(&standing(45, h), NH).unwrap();
        assert_eq!(sets(&b), vec![signed(45, &unsigned); NH + 1], "h = {h}");
        assert_eq!(PaperRule::for_load(&standing(45, h)).unwrap().k(), Some(k));
        assert_eq!(b.sampled_sectors(), k);
    }
}

#[test]
fn eq_107_mixed_scenario_n45() {
    let both = LoadCase {
        casing_order: Some(3),
        ..traveling(45, 12)
    };
    let b = SpectralBasis::paper(&both, NH).unwrap();
    assert_eq!(
        sets(&b),
        vec![signed(45, &[0, 3, 6, 9, 12, 15, 18, 21]); NH + 1]
    );
    // C.3: 66.7 %.
    assert!((b.reduction_percent() - 100.0 * 2.0 / 3.0).abs() < 1e-12);
    let s = SpectralBasis::symmetry(&both, NH).unwrap();
    assert!(s.real_unknowns_per_contact_dof() <= b.real_unknowns_per_contact_dof());
}

#[test]
fn one_sector_keeps_a_single_pair_per_harmonic() {
    for load in [traveling(1, 0), standing(1, 0), mixed(1, 0)] {
        for b in [
            SpectralBasis::paper(&load, NH).unwrap(),
            SpectralBasis::symmetry(&load, NH).unwrap(),
            SpectralBasis::nodal_diameter(&load, NH).unwrap(),
        ] {
            assert_eq!(sets(&b), vec![vec![0]; NH + 1]);
            assert_eq!(b.real_unknowns_per_contact_dof(), 2 * NH + 1);
            assert!(b.reduction_percent().abs() < 1e-12);
        }
    }
}

#[test]
fn bad_loads_are_errors_not_panics() {
    assert!(SpectralBasis::paper(&traveling(24, 24), NH).is_err());
    assert!(SpectralBasis::symmetry(&standing(24, 30), NH).is_err());
    assert!(SpectralBasis::nodal_diameter(&traveling(0, 0), NH).is_err());
    assert!(SpectralBasis::traveling_wave(0, NH, 0).is_err());
    let per_sector = LoadCase {
        sectors: 4,
        excitation: Some(ExcitationPattern::PerSector {
            amplitudes: vec![1.0; 3],
            phases: vec![0.0; 3],
        }),
        casing_order: None,
    };
    assert!(SpectralBasis::symmetry(&per_sector, NH).is_err());
    assert!(SpectralBasis::paper(&per_sector, NH).is_err());
}
