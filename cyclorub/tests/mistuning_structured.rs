//! A mistuned wheel's Jacobian kept structured (issue 44; what the fan's
//! mistuned full wheel solves with, above `STRUCTURED_UNKNOWNS`): against
//! the dense Jacobian of the same mistuned problem on six sectors in
//! contact, its products agree, and GMRES, preconditioned by the tuned
//! wave frame built from the sectors' average, solves the exact Jacobian
//! though the approximation is not exact there.

use cyclorub::case::{BasisChoice, Case};
use cyclorub::continuation::{Evaluation, Problem};
use cyclorub::forced_response::{prepare, ForcedResponse};
use std::path::Path;

use crate::full_wheel_structured::{dense_solve, distance, largest};

#[test]
fn a_mistuned_wheels_structured_jacobian_is_its_dense_one() {
    // Six sectors of the default wheel, N_h = 3, N_t = 96 (a multiple of
    // N), blade stiffness mistuned by up to 3 %, traveling h = 1 (the
    // default load), at 212 Hz: every sector in contact.
    let text = "[model]\nsectors = 6\n[harmonic_balance]\nharmonics = 3\ntime_samples = 96\n\
                [mistuning]\ndeviations = [0.03, -0.01, 0.02, 0.0, -0.03, 0.01]\n";
    let case = Case::from_toml(text, Path::new("case.toml")).unwrap();
    case.validate().unwrap();
    let solution = ForcedResponse::from_case(&case)
        .unwrap()
        .basis(BasisChoice::Physical)
        .at_frequencies_hz(vec![204.0, 208.0, 210.0, 212.0])
        .build()
        .unwrap()
        .run(&mut [])
        .unwrap();
    let point = solution.branch.points.last().unwrap();
    assert!(point.converged);
    let (x, omega) = (point.unknowns.clone(), point.omega);
    let build = || {
        prepare(&case, Path::new("."), BasisChoice::Physical)
            .unwrap()
            .problem
    };
    let mut dense = build();
    let mut structured = build().with_structured_jacobian(1);
    let n = x.len();
    let (mut full, mut kept) = (Evaluation::default(), Evaluation::default());
    dense.evaluate(&x, omega, true, &mut full).unwrap();
    structured.evaluate(&x, omega, true, &mut kept).unwrap();
    // In contact: with the casing moved away the residual is not small.
    let mut away = case.clone();
    away.casing.gap = cyclorub::case::PerContactDof::One(1.0);
    let mut free = Evaluation::default();
    prepare(&away, Path::new("."), BasisChoice::Physical)
        .unwrap()
        .problem
        .evaluate(&x, omega, false, &mut free)
        .unwrap();
    assert!(distance(&free.residual, &full.residual) > 1e-2 * dense.force_scale());
    assert_eq!(kept.jacobian.nrows(), 0, "no dense Jacobian");
    let operator = kept.structured.clone().expect("a structured Jacobian");
    assert!(distance(&full.residual, &kept.residual) <= 1e-12 * dense.force_scale());
    // The same products.
    let v: Vec<f64> = (0..n).map(|i| (i as f64 * 0.731).sin()).collect();
    let mut product = vec![0.0; n];
    operator.apply(&v, &mut product);
    let reference: Vec<f64> = (0..n)
        .map(|r| (0..n).map(|c| full.jacobian[(r, c)] * v[c]).sum())
        .collect();
    let product_error = distance(&product, &reference) / largest(&reference);
    // The tuned frame is only an approximation of a mistuned wheel; GMRES
    // solves the exact Jacobian from it.
    let rhs: Vec<f64> = (0..n).map(|i| (i as f64 * 1.37).cos()).collect();
    let exact = dense_solve(&full.jacobian, &rhs);
    let mut approximate = rhs.clone();
    operator
        .approximation()
        .unwrap()
        .solve_in_place(&mut approximate);
    let approximation_error = distance(&approximate, &exact) / largest(&exact);
    let step = cyclorub::continuation::solve_structured(&kept, &rhs).expect("a structured solve");
    let gmres_error = distance(&step, &exact) / largest(&exact);
    println!(
        "products {product_error:.1e}, the tuned frame alone {approximation_error:.1e}, GMRES {gmres_error:.1e}"
    );
    assert!(
        product_error < 1e-13,
        "products differ by {product_error:e}"
    );
    assert!(
        approximation_error > 1e-8,
        "a mistuned wheel is not the tuned frame's: {approximation_error:e}"
    );
    assert!(gmres_error < 1e-9, "GMRES: {gmres_error:e}");
}
