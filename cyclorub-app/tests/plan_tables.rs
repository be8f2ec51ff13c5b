//! The paper's Tables 2 (N = 24), 4 (N = 16, 27 contact dofs) and 5
//! (N = 45), row by row, from the library side of `cyclorub plan`, and the
//! means the paper quotes for them and over N ≤ 150.

use cyclorub_app::plan::{
    plan_row, sweep, ExcitationKind, PlanCase, PlanError, PlanRule, SectorClass,
};

/// One column of a paper table: engine order, K, reduced size, sectors for
/// AFT-CP, reduction in percent (as printed, one decimal).
type Column = (usize, usize, usize, usize, f64);

const TABLE_2: [Column; 13] = [
    (0, 1, 21, 1, 95.8),
    (1, 12, 252, 12, 50.0),
    (2, 6, 126, 6, 75.0),
    (3, 4, 84, 4, 83.3),
    (4, 3, 63, 3, 87.5),
    (5, 12, 252, 12, 50.0),
    (6, 2, 42, 2, 91.7),
    (7, 12, 252, 12, 50.0),
    (8, 3, 63, 3, 87.5),
    (9, 4, 84, 4, 83.3),
    (10, 6, 126, 6, 75.0),
    (11, 12, 252, 12, 50.0),
    (12, 1, 21, 1, 95.8),
];

const TABLE_4: [Column; 9] = [
    (0, 1, 567, 1, 93.8),
    (1, 8, 4536, 8, 50.0),
    (2, 4, 2268, 4, 75.0),
    (3, 8, 4536, 8, 50.0),
    (4, 2, 1134, 2, 87.5),
    (5, 8, 4536, 8, 50.0),
    (6, 4, 2268, 4, 75.0),
    (7, 8, 4536, 8, 50.0),
    (8, 1, 567, 1, 93.8),
];

const TABLE_5: [Column; 23] = [
    (0, 1, 21, 1, 97.8),
    (1, 45, 945, 45, 0.0),
    (2, 45, 945, 45, 0.0),
    (3, 15, 315, 15, 66.7),
    (4, 45, 945, 45, 0.0),
    (5, 9, 189, 9, 80.0),
    (6, 15, 315, 15, 66.7),
    (7, 45, 945, 45, 0.0),
    (8, 45, 945, 45, 0.0),
    (9, 5, 105, 5, 88.9),
    (10, 9, 189, 9, 80.0),
    (11, 45, 945, 45, 0.0),
    (12, 15, 315, 15, 66.7),
    (13, 45, 945, 45, 0.0),
    (14, 45, 945, 45, 0.0),
    (15, 3, 63, 3, 93.3),
    (16, 45, 945, 45, 0.0),
    (17, 45, 945, 45, 0.0),
    (18, 5, 105, 5, 88.9),
    (19, 45, 945, 45, 0.0),
    (20, 9, 189, 9, 80.0),
    (21, 15, 315, 15, 66.7),
    (22, 45, 945, 45, 0.0),
];

fn case(sectors: usize, contact_dofs: usize, engine_order: usize) -> PlanCase {
    PlanCase {
        sectors,
        harmonics: 10,
        contact_dofs,
        engine_order,
        excitation: ExcitationKind::Standing,
        casing_order: None,
    }
}

fn check_table(sectors: usize, contact_dofs: usize, full_size: usize, table: &[Column]) {
    assert_eq!(table.len(), sectors / 2 + 1);
    for &(h, k, reduced, aft, reduction) in table {
        let c = case(sectors, contact_dofs, h);
        let paper = plan_row(&c, PlanRule::Paper).unwrap();
        let what = format!("N = {sectors}, engine order {h}");
        assert_eq!(paper.k, Some(k), "{what}: K");
        assert_eq!(paper.reduced_size, reduced, "{what}: reduced size");
        assert_eq!(paper.full_size, full_size, "{what}: full size");
        assert_eq!(paper.sectors_for_aft, aft, "{what}: sectors for AFT-CP");
        assert!(
            (paper.reduction_percent - reduction).abs() <= 0.05,
            "{what}: reduction {} vs {reduction}",
            paper.reduction_percent
        );
        // The symmetry rule reproduces the sizes (docs/design.md §3).
        let symmetry = plan_row(&c, PlanRule::Symmetry).unwrap();
        assert_eq!(symmetry.k, None);
        assert_eq!(symmetry.reduced_size, reduced, "{what}: symmetry size");
        assert_eq!(symmetry.sectors_for_aft, aft, "{what}: symmetry sectors");
    }
}

#[test]
fn table_2_n24() {
    check_table(24, 1, 504, &TABLE_2);
}

#[test]
fn table_4_n16_with_27_contact_dofs() {
    // Caption: N × 3 n_nl × (2 N_h + 1) = 16 × 27 × 21 = 9072.
    check_table(16, 27, 9072, &TABLE_4);
}

#[test]
fn table_5_n45() {
    check_table(45, 1, 945, &TABLE_5);
}

fn mean_reduction(sectors: usize, rule: PlanRule, excitation: ExcitationKind) -> f64 {
    let rows: Vec<f64> = (0..=sectors / 2)
        .map(|h| {
            let c = PlanCase {
                excitation,
                ..case(sectors, 1, h)
            };
            plan_row(&c, rule).unwrap().reduction_percent
        })
        .collect();
    rows.iter().sum::<f64>() / rows.len() as f64
}

/// Sec. 4.3: "the mean over all engine orders of the expected reduction is
/// 75 %"; C: "the mean reduction only reaches 38.1 %".
#[test]
fn table_means_quoted_by_the_paper() {
    assert!((mean_reduction(24, PlanRule::Paper, ExcitationKind::Standing) - 75.0).abs() < 0.05);
    assert!((mean_reduction(45, PlanRule::Paper, ExcitationKind::Standing) - 38.1).abs() < 0.05);
    // Sec. 4.3: 51.3 % without the parity rule, for N = 24.
    let without: Vec<f64> = (0..=12)
        .map(|h| {
            cyclorub::basis::SpectralBasis::nodal_diameter_rule(24, 10, &[h], false)
                .unwrap()
                .reduction_percent()
        })
        .collect();
    let mean = without.iter().sum::<f64>() / without.len() as f64;
    assert!((mean - 51.3).abs() < 0.05, "{mean}");
    // Sec. 4.3 and Eq. (89): a traveling excitation is reduced by 100 (1 − 1/N).
    for n in [16, 24, 45] {
        let m = mean_reduction(n, PlanRule::Paper, ExcitationKind::Traveling);
        assert!((m - 100.0 * (1.0 - 1.0 / n as f64)).abs() < 1e-9);
        let s = mean_reduction(n, PlanRule::Symmetry, ExcitationKind::Traveling);
        assert!((s - m).abs() < 1e-9);
    }
}

/// The conclusion's means over N ≤ 150 (Fig. 21). Where our rules agree
/// with the quoted value the test holds it to the printed digit; the
/// others are reported findings (see the final assertions' comments).
#[test]
fn sweep_up_to_150_sectors() {
    let result = sweep(2, 150, 10, ExcitationKind::Standing, None).unwrap();
    assert_eq!(result.rows.len(), 149);
    let group = |class| {
        result
            .groups
            .iter()
            .find(|g| g.class == class)
            .unwrap()
            .clone()
    };
    let even = group(SectorClass::Even);
    let odd = group(SectorClass::OddNonPrime);
    let prime = group(SectorClass::Prime);
    let all = group(SectorClass::All);
    assert_eq!(
        (even.count, odd.count, prime.count, all.count),
        (75, 40, 34, 149)
    );
    // Paper: 62.4 % for even N with the parity rule; 23.4 % for odd
    // non-prime N. Both hold over the engine orders h = 1..N−1.
    assert!((even.over_engine_orders.with_parity - 62.4).abs() < 0.05);
    assert!((odd.over_engine_orders.with_parity - 23.4).abs() < 0.05);
    // Our prime N get nothing (K = N), where the paper quotes 12.5 %; the
    // mean over every odd N is 12.6 %.
    assert!(prime.over_engine_orders.with_parity.abs() < 1e-9);
    // The symmetry rule equals the parity rule for standing loads.
    for g in [&even, &odd, &prime, &all] {
        let (e, d) = (g.over_engine_orders, g.over_nodal_diameters);
        assert!((e.symmetry - e.with_parity).abs() < 1e-9);
        assert!((d.symmetry - d.with_parity).abs() < 1e-9);
    }
    // Paper: 37.6 % over all N, 37.7 % for even N without parity and
    // 25.2 % over all N without parity; ours are within one point.
    assert!((all.over_engine_orders.with_parity - 37.6).abs() < 1.0);
    assert!((even.over_engine_orders.without_parity - 37.7).abs() < 1.0);
    assert!((all.over_engine_orders.without_parity - 25.2).abs() < 1.0);
}

#[test]
fn bad_requests_name_the_argument() {
    let bad = PlanCase {
        engine_order: 24,
        ..case(24, 1, 0)
    };
    let e = plan_row(&bad, PlanRule::Paper).unwrap_err();
    assert!(matches!(
        e,
        PlanError::EngineOrderOutOfRange { max: 23, .. }
    ));
    assert!(e.to_string().contains("0..=23"));
    assert_eq!(
        plan_row(&case(0, 1, 0), PlanRule::Paper).unwrap_err(),
        PlanError::NoSectors(0)
    );
    let no_harmonics = PlanCase {
        harmonics: 0,
        ..case(24, 1, 0)
    };
    assert_eq!(
        plan_row(&no_harmonics, PlanRule::Symmetry).unwrap_err(),
        PlanError::NoHarmonics
    );
    assert!(sweep(5, 4, 10, ExcitationKind::Standing, None).is_err());
    assert!(sweep(0, 4, 10, ExcitationKind::Standing, None).is_err());
    // One sector is valid: a single blade, a single pair per harmonic.
    let one = plan_row(&case(1, 1, 0), PlanRule::Paper).unwrap();
    assert_eq!(
        (one.reduced_size, one.full_size, one.sectors_for_aft),
        (21, 21, 1)
    );
}
