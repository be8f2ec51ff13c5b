//! The tracking's markers on synthetic spectra.

use super::*;
use crate::stability::markers::MarkerKind;
use crate::stability::spectrum::ClassSpectrum;

const OMEGA: f64 = 100.0;

/// A point with one class per entry of `classes`: `(σ, exponents)`.
fn point(omega: f64, classes: &[(i64, Vec<(f64, f64)>)]) -> PointStability {
    PointStability {
        omega,
        classes: classes
            .iter()
            .map(|(sigma, exponents)| ClassSpectrum {
                nodal_diameter: *sigma,
                exponents: exponents
                    .iter()
                    .map(|&(re, im)| Exponent { re, im })
                    .collect(),
                truncation: 0.0,
                dense: false,
            })
            .collect(),
        tolerance: 1e-8 * omega,
        peak_contact_stiffness: 1.0,
        off_contact_bound: None,
    }
}

/// An exponent's real part along a branch of points 1 rad/s apart, in
/// class 2, with a second, steady exponent beside it.
fn branch(real_parts: &[f64], im: f64) -> Vec<PointStability> {
    real_parts
        .iter()
        .enumerate()
        .map(|(i, &re)| {
            point(
                OMEGA + i as f64,
                &[(0, vec![(-1.0, 20.0)]), (2, vec![(re, im), (-3.0, -30.0)])],
            )
        })
        .collect()
}

#[test]
fn a_crossing_is_placed_where_the_tracked_real_part_vanishes() {
    let found = markers(&branch(&[-2.0, -1.0, 3.0, 4.0], 10.0), true);
    assert_eq!(found.len(), 1, "{found:?}");
    let m = &found[0];
    assert_eq!((m.index, m.nodal_diameter), (1, Some(2)));
    assert!(m.loses_stability);
    assert_eq!(m.kind, MarkerKind::NeimarkSacker);
    assert!((m.fraction - 0.25).abs() < 1e-12);
    assert!((m.frequency_hz - (OMEGA + 1.25) / (2.0 * PI)).abs() < 1e-12);
    assert!(m.before.unwrap().re < 0.0 && m.after.unwrap().re > 0.0);
}

#[test]
fn an_exponent_hovering_in_the_band_gives_no_marker() {
    // ±1e-5 1/s against a band of 1e-6 ω = 1e-4 1/s: noise, not a crossing.
    let noise = [-1e-5, 1e-5, -1e-5, 2e-5, -5e-6, 1e-5, -1e-5];
    assert!(markers(&branch(&noise, 10.0), true).is_empty());
}

#[test]
fn a_crossing_through_the_band_is_one_marker_where_it_last_changed_sign() {
    // Down to the band, wavering in it, then out above: one marker, at
    // the last sign change (between points 4 and 5).
    let found = markers(
        &branch(&[-1.0, -1e-5, 1e-5, 2e-5, -1e-5, 5e-5, 2.0], 10.0),
        true,
    );
    assert_eq!(found.len(), 1, "{found:?}");
    assert_eq!(found[0].index, 4);
    // Out and back beyond the band both ways: a pair.
    let found = markers(&branch(&[-1.0, 1.0, -1.0], 10.0), true);
    assert_eq!(found.len(), 2);
    assert!(found[0].loses_stability && !found[1].loses_stability);
}

#[test]
fn the_nearest_first_matching_is_the_whole_list_sorted() {
    // Pseudo-random distances with ties, against the stable sort of
    // the whole list and the same greedy pass.
    let mut state = 12345_u64;
    let mut next = || {
        state = state
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (state >> 33) as f64 / (1u64 << 31) as f64
    };
    for (a, b) in [(1, 1), (3, 7), (20, 20), (40, 9), (60, 61)] {
        let distances: Vec<(f64, usize, usize)> = (0..a)
            .flat_map(|i| (0..b).map(move |j| (i, j)))
            .map(|(i, j)| ((8.0 * next()).floor() / 8.0, i, j))
            .collect();
        let mut sorted = distances.clone();
        sorted.sort_by(|p, q| p.0.total_cmp(&q.0));
        let (mut used_a, mut used_b) = (vec![false; a], vec![false; b]);
        let mut expected = Vec::new();
        for (_, i, j) in sorted {
            if !used_a[i] && !used_b[j] {
                used_a[i] = true;
                used_b[j] = true;
                expected.push((i, j));
            }
        }
        assert_eq!(super::nearest_first(distances, a, b), expected, "{a} × {b}");
    }
}

#[test]
fn the_frequency_turns_where_the_steps_about_a_step_go_opposite_ways() {
    let turns = |omegas: &[f64], index: usize| {
        super::super::frequency_turns(omegas.len(), |i| omegas[i], index)
    };
    assert!(turns(&[0.0, 1.0, 2.0, 1.0], 1));
    assert!(!turns(&[0.0, 1.0, 2.0, 3.0], 1));
    // A step between two turns (a zig-zag): a turn at either end.
    assert!(turns(&[0.0, 2.0, 1.0, 3.0], 1));
    // At the ends, the step itself and its one neighbour.
    assert!(turns(&[0.0, 1.0, 0.0], 0));
    assert!(!turns(&[0.0, 1.0, 2.0], 0));
    assert!(turns(&[0.0, 1.0, 0.0], 1));
    assert!(!turns(&[0.0, 1.0, 2.0], 1));
    // Two points: nothing tells, a turn.
    assert!(turns(&[0.0, 1.0], 0));
}

#[test]
fn a_real_crossing_is_a_fold_in_class_0_and_a_branch_point_elsewhere() {
    let found = markers(&branch(&[-1.0, 1.0], 0.0), true);
    assert_eq!(found[0].kind, MarkerKind::BranchPoint);
    let fold: Vec<PointStability> = [-1.0, 1.0]
        .iter()
        .enumerate()
        .map(|(i, &re)| point(OMEGA + i as f64, &[(0, vec![(re, 0.0)])]))
        .collect();
    assert_eq!(markers(&fold, true)[0].kind, MarkerKind::Fold);
    assert_eq!(markers(&fold, false)[0].kind, MarkerKind::RealCrossing);
    // Class 0 where the branch goes on in frequency through the
    // crossing: a branch point; where it turns about it: a fold.
    let class_zero = |omegas: &[f64], res: &[f64]| {
        let points: Vec<PointStability> = omegas
            .iter()
            .zip(res)
            .map(|(&w, &re)| point(w, &[(0, vec![(re, 0.0)])]))
            .collect();
        markers(&points, true)[0].kind
    };
    let through = [OMEGA, OMEGA + 1.0, OMEGA + 2.0, OMEGA + 3.0];
    let turning = [OMEGA, OMEGA + 2.0, OMEGA + 3.0, OMEGA + 1.0];
    let res = [-2.0, -1.0, 1.0, 2.0];
    assert_eq!(class_zero(&through, &res), MarkerKind::BranchPoint);
    assert_eq!(class_zero(&turning, &res), MarkerKind::Fold);
    // At −1: period doubling.
    let found = markers(&branch(&[-1.0, 1.0], 0.5 * OMEGA), true);
    assert_eq!(found[0].kind, MarkerKind::PeriodDoubling);
}

#[test]
fn an_exponent_is_followed_across_classes_by_its_multiplier() {
    // The exponent leaves class 2's strip at its top edge and comes back
    // in class 3 at the bottom (the same multiplier): no crossing is
    // made up by pairing it with class 2's other exponent.
    let half = 0.5 * OMEGA;
    let points = vec![
        point(
            OMEGA,
            &[(2, vec![(0.5, half - 0.5), (-3.0, -30.0)]), (3, vec![])],
        ),
        point(
            OMEGA,
            &[(2, vec![(-3.0, -30.0)]), (3, vec![(0.6, -half + 0.5)])],
        ),
    ];
    assert!(markers(&points, true).is_empty());
}

#[test]
fn a_conjugate_pair_crosses_as_one_marker() {
    // Class 0 holds λ and λ̄; classes 1 and −1 hold conjugate copies.
    let points: Vec<PointStability> = [-1.0, 1.0]
        .iter()
        .enumerate()
        .map(|(i, &re)| {
            point(
                OMEGA + i as f64,
                &[
                    (-1, vec![(re, -7.0)]),
                    (0, vec![(re, 12.0), (re, -12.0)]),
                    (1, vec![(re, 7.0)]),
                ],
            )
        })
        .collect();
    let found = markers(&points, true);
    let classes: Vec<Option<i64>> = found.iter().map(|m| m.nodal_diameter).collect();
    assert_eq!(classes, vec![Some(0), Some(1)], "{found:?}");
}

#[test]
fn a_swap_of_the_matching_within_one_step_gives_no_marker() {
    // Two exponents of class 2 close in the multiplier plane trade
    // places: tracking may read one rising and one falling through 0
    // at the same step; the class keeps one growing exponent.
    let points = vec![
        point(OMEGA, &[(2, vec![(0.3, 10.0), (-0.3, 11.0)])]),
        point(OMEGA + 1.0, &[(2, vec![(-0.05, 10.0), (0.6, 11.0)])]),
    ];
    // Tracked alone, that is a regain and a loss.
    let tracked = tracked_crossings(&points, true);
    assert_eq!(tracked.len(), 2);
    let found = markers(&points, true);
    assert!(found.is_empty(), "{found:?}");
}

#[test]
fn a_second_growing_exponent_does_not_change_its_class() {
    // Class 2: one exponent grows at the first step, a second at the
    // third, the first falls back at the fifth; the class is stable
    // again only when the second does too.
    let points: Vec<PointStability> = [
        (-1.0, -2.0),
        (1.0, -2.0),
        (1.5, -1.0),
        (1.5, 1.0),
        (1.2, 1.5),
        (-1.0, 1.5),
        (-1.0, -1.0),
    ]
    .iter()
    .enumerate()
    .map(|(i, &(x, y))| point(OMEGA + i as f64, &[(2, vec![(x, 10.0), (y, 30.0)])]))
    .collect();
    let found = markers(&points, true);
    let read: Vec<(usize, bool, bool)> = found
        .iter()
        .map(|m| (m.index, m.loses_stability, m.class_changes))
        .collect();
    assert_eq!(
        read,
        vec![
            (0, true, true),
            (2, true, false),
            (4, false, false),
            (5, false, true)
        ],
        "{found:?}"
    );
}
