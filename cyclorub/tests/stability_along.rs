//! Stability along a branch (docs/design.md §10): the markers of the
//! default branch and where they are located, the exponents followed from
//! point to point against the contour's, a refined orbit, and a branch
//! through grazing, one class followed from trial to trial. The spectra at
//! single points are in `stability.rs`.

use crate::common;
use crate::stability::{solve, stiffest_contact, SMALL};
use common::spectra::{largest_mismatch, values};
use cyclorub::case::BasisChoice;
use cyclorub::stability::{HillSolver, PointStability, StabilitySettings};
use std::f64::consts::PI;
use std::path::Path;

#[test]
fn every_marker_of_the_default_branch_is_a_sign_change_of_an_exponent_of_its_class() {
    // The default case (N = 24, traveling h = 1, R-HBM): its contact
    // onset destabilizes many classes at once and the plateau regains some.
    // Each marker is a tracked exponent whose real part changes sign
    // between the marker's two points, both exponents found again in the
    // spectra of those points (the growing one in the marker's class or
    // its conjugate).
    let solution = solve("", BasisChoice::Symmetry);
    let check = solution
        .stability_check(&StabilitySettings::default())
        .unwrap();
    let branch = check.branch(&solution.branch.points).unwrap();
    assert!(!branch.markers.is_empty());
    let near = |point: &PointStability, class: i64, e: cyclorub::stability::Exponent| {
        [class, -class].iter().any(|&c| {
            point.class(c).is_some_and(|s| {
                s.exponents.iter().any(|x| {
                    let conjugate = if c == class { e.im } else { -e.im };
                    (x.re - e.re).abs() + (x.im - conjugate).abs() < 1e-9 * point.omega
                })
            })
        })
    };
    for m in &branch.markers {
        let (before, after) = (m.before.unwrap(), m.after.unwrap());
        if m.loses_stability {
            assert!(before.re <= 0.0 && after.re > 0.0, "{m:?}");
        } else {
            assert!(before.re > 0.0 && after.re <= 0.0, "{m:?}");
        }
        let (a, b) = (&branch.points[m.index], &branch.points[m.index + 1]);
        let class = m.nodal_diameter.unwrap();
        let growing = if m.loses_stability {
            (b, after)
        } else {
            (a, before)
        };
        assert!(near(growing.0, class, growing.1), "{m:?}");
        let all = |p: &PointStability, e: cyclorub::stability::Exponent| {
            p.classes.iter().any(|c| near(p, c.nodal_diameter, e))
        };
        assert!(all(a, before) && all(b, after), "{m:?}");
        let hz = (a.omega / (2.0 * PI), b.omega / (2.0 * PI));
        assert!(m.frequency_hz >= hz.0.min(hz.1) && m.frequency_hz <= hz.0.max(hz.1));
    }
    // Stability is lost at the contact onset and regained before the end.
    assert!(branch.markers[0].loses_stability);
    assert!(branch.markers.iter().any(|m| !m.loses_stability));
    // A class's events are never two at one step: no lost/regained pair
    // from a swap of the matching or from noise. (They need not alternate:
    // an exponent near the strip's edge passes from one class's strip to
    // another's, the same multiplier, without crossing.)
    let mut classes: Vec<i64> = branch
        .markers
        .iter()
        .filter_map(|m| m.nodal_diameter)
        .collect();
    classes.sort_unstable();
    classes.dedup();
    for class in classes {
        let events: Vec<_> = branch
            .markers
            .iter()
            .filter(|m| m.nodal_diameter == Some(class) && m.class_changes)
            .collect();
        for pair in events.windows(2) {
            assert!(pair[1].index > pair[0].index, "class {class}: {pair:?}");
        }
    }
    // Far fewer events than crossings: the contact onset is one event.
    let events = branch.markers.iter().filter(|m| m.is_event()).count();
    println!("{} markers, {events} events", branch.markers.len());
    assert!(events < 60, "{events} events");
    // Located on the branch (forced_response::locate_markers): each
    // located event's exponent, on the branch re-solved where the marker
    // now sits, has a real part within the markers' band (1e-6 ω; below
    // the growth tolerance 1e-8 ω unless the bracket closed to 1e-6 of the
    // chord first), and its bracket is below 1e-4 Hz (or 1e-6 of the
    // chord); the marker stays between its two points.
    let mut located = branch.clone();
    let report = solution
        .locate_markers(&StabilitySettings::default(), &mut located)
        .unwrap();
    println!("{report:?}");
    // Measured: 43 of the 45 events (33 by the followed exponent, 10 by
    // the class's count where it jumps); one left, a Newton failure on the
    // chord at the 129.99 Hz fold (a kink of the branch), and one removed:
    // at 128.102 Hz the tracking paired a growing exponent of class 10 with
    // a damped one, the class growing one exponent at both points.
    assert!(report.located + 2 >= report.events, "{report:?}");
    assert_eq!(report.unmatched.len(), 1, "{report:?}");
    assert_eq!(
        report.located + report.failed.len() + report.unmatched.len(),
        report.events
    );
    // A removed event: its two exponents far apart in multiplier (not one
    // exponent moving), both outside the band, its class's stability
    // unchanged, and the class growing as many exponents at both points.
    for (i, _) in &report.unmatched {
        let m = &branch.markers[*i];
        let (a, b) = (&branch.points[m.index], &branch.points[m.index + 1]);
        let (before, after) = (m.before.unwrap(), m.after.unwrap());
        assert!(!m.class_changes, "{m:?}");
        assert!(before.re.abs() > 1e-6 * a.omega && after.re.abs() > 1e-6 * b.omega);
        let apart = (before.multiplier(a.omega) - after.multiplier(b.omega)).norm();
        assert!(apart > 0.1, "{apart} {m:?}");
        let class = m.nodal_diameter.expect("classes are known");
        let growing = |p: &cyclorub::stability::PointStability| {
            let omega = p.omega;
            p.classes
                .iter()
                .filter(|c| c.nodal_diameter == class)
                .flat_map(|c| &c.exponents)
                .filter(|e| e.re > 1e-6 * omega)
                .count()
        };
        assert_eq!(
            growing(&branch.points[m.index]),
            growing(&branch.points[m.index + 1]),
            "{m:?}"
        );
    }
    let kept: Vec<_> = (0..branch.markers.len())
        .filter(|i| !report.unmatched.iter().any(|(u, _)| u == i))
        .map(|i| &branch.markers[i])
        .collect();
    assert_eq!(located.markers.len(), kept.len());
    let mut worst: f64 = 0.0;
    for (m, before) in located.markers.iter().zip(kept) {
        let Some(location) = m.located else {
            assert_eq!(m, before, "a marker not located is left as it was");
            continue;
        };
        let omega = 2.0 * PI * m.frequency_hz;
        if location.by_count {
            // Located by the class's count of growing exponents (the
            // followed exponent jumps inside the bracket): the growing
            // side's slowest exponent, just past 0 at a bracket this narrow.
            assert!(
                m.exponent.re > 0.0 && m.exponent.re <= 1e-4 * omega,
                "{m:?}"
            );
        } else {
            assert!(m.exponent.re.abs() <= 1e-6 * omega, "{m:?}");
            assert!(
                m.exponent.re.abs() <= 1e-8 * omega || location.bracket_fraction <= 1e-6,
                "{m:?}"
            );
            worst = worst.max(m.exponent.re.abs() / omega);
        }
        assert!(
            location.bracket_hz <= 1e-4 || location.bracket_fraction <= 1e-6,
            "{m:?}"
        );
        assert!(m.fraction > 0.0 && m.fraction < 1.0, "{m:?}");
        assert_eq!(
            (m.index, m.nodal_diameter),
            (before.index, before.nodal_diameter)
        );
    }
}

#[test]
fn a_refined_orbit_solves_the_finer_problem_from_the_truncated_one() {
    // A contact point of the 6-sector chain (N_h = 3) refined to N_h = 6:
    // Newton converges from the truncated solution, the refined unknowns
    // solve the finer problem, and its harmonics up to 3 move by far less
    // than the solution's size (the truncation, not another orbit).
    use cyclorub::continuation::{Evaluation, Problem};
    use cyclorub::forced_response::{prepare, refined_point};
    let solution = solve(SMALL, BasisChoice::Symmetry);
    let index = stiffest_contact(&solution);
    let point = &solution.branch.points[index];
    let prepared = prepare(&solution.case, Path::new("."), BasisChoice::Symmetry).unwrap();
    let mut refined = refined_point(
        &prepared,
        Path::new("."),
        BasisChoice::Symmetry,
        &point.unknowns,
        point.omega,
        2,
    )
    .unwrap()
    .expect("Newton converges on the refined orbit");
    assert_eq!(refined.prepared.problem.layout().harmonics(), 6);
    let mut out = Evaluation::default();
    let unknowns = refined.unknowns.clone();
    let problem = &mut refined.prepared.problem;
    problem
        .evaluate(&unknowns, point.omega, false, &mut out)
        .unwrap();
    let residual = out.residual.iter().map(|r| r * r).sum::<f64>().sqrt() / problem.force_scale();
    let fine = &refined.prepared.problem;
    assert!(residual < 1e-7, "{residual:e}");
    // Back on the coarse layout's blocks: the embedding read backwards.
    let coarse = prepared.problem.layout();
    let back = coarse
        .embed(&point.unknowns, fine.layout())
        .expect("the coarse blocks are in the fine layout");
    let size = back.iter().map(|x| x * x).sum::<f64>().sqrt();
    let moved = back
        .iter()
        .zip(&refined.unknowns)
        .filter(|(b, _)| **b != 0.0)
        .map(|(b, r)| (b - r) * (b - r))
        .sum::<f64>()
        .sqrt();
    assert!(moved < 0.2 * size, "moved {moved:e} of {size:e}");
    assert!(moved > 0.0, "the refinement changes the orbit");
}

#[test]
fn exponents_followed_along_the_default_branch_are_those_the_contour_finds() {
    // The default branch point by point, each class's exponents followed
    // from the previous point where they moved little: at every point,
    // every class holds the same exponents as the contour run afresh
    // there (same count, each within 1e-7 ω: both accept an exponent at a
    // residual of 1e-9 of the terms, which places the strongly growing,
    // ill-conditioned ones of the plateau to about 1e-8 ω, measured
    // against the dense oracle), or, in the few classes where the two
    // differ by more, the followed ones equal the dense eigenproblem's to
    // 1e-7 ω (at the 130 Hz fold the contour placed a real exponent near
    // a collision 1e-4 rad/s off the dense one, the cluster's following to
    // 5e-9); and a good share of the contact points' classes were followed
    // (else the test checks nothing).
    let solution = solve("", BasisChoice::Symmetry);
    let check = solution
        .stability_check(&StabilitySettings::default())
        .unwrap();
    let dense = solution
        .stability_check(&StabilitySettings {
            solver: HillSolver::DenseRegion,
            ..StabilitySettings::default()
        })
        .unwrap();
    let (mut followed, mut solved, mut arbitrated) = (0, 0, 0);
    let mut following = None;
    for p in &solution.branch.points {
        let (point, next) = check
            .point_following(&p.unknowns, p.omega, following.as_ref())
            .unwrap();
        followed += next.followed();
        solved += next.len();
        following = Some(next);
        let afresh = check.point(&p.unknowns, p.omega).unwrap();
        for (a, b) in point.classes.iter().zip(&afresh.classes) {
            assert_eq!(a.nodal_diameter, b.nodal_diameter);
            let class = a.nodal_diameter;
            let (a, b) = (values(&a.exponents), values(&b.exponents));
            if a.len() == b.len() && largest_mismatch(&a, &b) < 1e-7 * p.omega {
                continue;
            }
            // Where the two differ (an ill-conditioned exponent near a
            // collision, which either may place less well), the dense
            // eigenproblem says which: the followed one must be right.
            arbitrated += 1;
            let oracle = dense.point(&p.unknowns, p.omega).unwrap();
            let oracle = oracle
                .classes
                .iter()
                .find(|c| c.nodal_diameter == class)
                .unwrap();
            let oracle = values(&oracle.exponents);
            assert_eq!(a.len(), oracle.len(), "class counts at {} rad/s", p.omega);
            let worst = largest_mismatch(&a, &oracle);
            assert!(worst < 1e-7 * p.omega, "{worst} at {} rad/s", p.omega);
        }
    }
    eprintln!("{followed} of {solved} followed, {arbitrated} classes checked against the dense eigenproblem");
    assert!(
        arbitrated < 10,
        "{arbitrated} classes differ from the contour"
    );
    assert!(3 * followed > solved, "{followed} of {solved} followed");
}

#[test]
fn a_branch_through_grazing_gives_no_lost_and_regained_pair_within_the_tracking_resolution() {
    // The 6-sector chain's branch goes through grazing (the blade first
    // touching the casing) and back off it. Markers come from exponents
    // tracked from point to point with the hysteresis band: a class never
    // loses and regains stability (or the reverse) within one step or at
    // two neighbouring steps (the tracking's resolution), which is what
    // exponents hovering at the tolerance at grazing would give.
    let solution = solve(SMALL, BasisChoice::Symmetry);
    let check = solution
        .stability_check(&StabilitySettings::default())
        .unwrap();
    let branch = check.branch(&solution.branch.points).unwrap();
    let touching = branch
        .points
        .iter()
        .filter(|p| p.off_contact_bound.is_none())
        .count();
    assert!(
        touching > 0 && touching < branch.points.len(),
        "the branch goes through grazing: {touching} of {} points in contact",
        branch.points.len()
    );
    let mut classes: Vec<i64> = branch
        .markers
        .iter()
        .filter_map(|m| m.nodal_diameter)
        .collect();
    classes.sort_unstable();
    classes.dedup();
    for class in classes {
        let events: Vec<_> = branch
            .markers
            .iter()
            .filter(|m| m.nodal_diameter == Some(class) && m.class_changes)
            .collect();
        for pair in events.windows(2) {
            if pair[0].loses_stability != pair[1].loses_stability {
                assert!(
                    pair[1].index >= pair[0].index + 2,
                    "class {class}: a pair within the tracking resolution {pair:?}"
                );
            }
        }
    }
    println!("{} markers", branch.markers.len());
}

#[test]
fn a_class_followed_from_trial_to_trial_holds_the_exponents_the_contour_finds() {
    // What locating a marker by its class's count asks at each trial point
    // (`Stability::class_exponents_following`): one class's exponents
    // followed from the previous call's. Along the default branch's contact
    // points, for a class solved directly and one mirrored from its
    // conjugate, each equals the class solved afresh (same count, each
    // within 1e-7 ω, as for the whole point's following) and most calls
    // were followed, not contoured.
    let solution = solve("", BasisChoice::Symmetry);
    let check = solution
        .stability_check(&StabilitySettings::default())
        .unwrap();
    let contact: Vec<_> = solution
        .branch
        .points
        .iter()
        .filter(|p| {
            check
                .point(&p.unknowns, p.omega)
                .is_ok_and(|s| s.off_contact_bound.is_none())
        })
        .take(24)
        .collect();
    assert!(contact.len() >= 20, "{} contact points", contact.len());
    for class in [5, -3] {
        let (mut following, mut followed) = (None, 0);
        for p in &contact {
            let (exponents, next) = check
                .class_exponents_following(&p.unknowns, p.omega, class, following.as_ref())
                .unwrap();
            followed += next.followed();
            following = Some(next);
            let afresh = check.class_exponents(&p.unknowns, p.omega, class).unwrap();
            let (a, b) = (values(&exponents), values(&afresh));
            assert_eq!(a.len(), b.len(), "class {class} at {} rad/s", p.omega);
            let worst = largest_mismatch(&a, &b);
            assert!(
                worst < 1e-7 * p.omega,
                "class {class}: {worst} at {} rad/s",
                p.omega
            );
        }
        assert!(
            2 * followed > contact.len(),
            "class {class}: {followed} of {} followed",
            contact.len()
        );
    }
}
