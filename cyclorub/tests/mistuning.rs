//! Mistuned wheels (issue 44): the physical full wheel with each sector's
//! blade stiffness scaled by `1 + δ_j`, against oracles that do not share
//! its code: a dense solve of the wheel assembled here spring by spring,
//! the tuned wheel (δ = 0, and δ the same on every sector against the
//! scaled blade), Whitehead's bound on the linear amplification factor,
//! and the full wheel's residual with contact computed here by a naive
//! DFT of the regularized law.

use cyclorub::case::{BasisChoice, Case};
use cyclorub::forced_response::mistuned::linear_amplification_factor;
use cyclorub::forced_response::{prepare, ForcedResponse};
use cyclorub::model::{ACADEMIC_MASSES, ACADEMIC_STIFFNESSES};
use faer::linalg::solvers::Solve;
use faer::{c64, Mat};
use std::f64::consts::PI;
use std::path::Path;

use crate::common::blade::BLADE;

pub(crate) fn case(text: &str) -> Case {
    let case = Case::from_toml(text, Path::new("case.toml")).unwrap();
    case.validate().unwrap();
    case
}

/// The academic wheel of 6 sectors, Rayleigh damping (so that the oracle
/// can assemble it), the traveling wave h = 1, and `extra` appended.
fn academic(extra: &str) -> String {
    format!(
        "[model]\nsectors = 6\n[model.damping]\nkind = \"rayleigh\"\nalpha = 3.0\nbeta = 2e-6\n\
         [harmonic_balance]\nharmonics = 3\ntime_samples = 96\n[basis]\nkind = \"physical\"\n{extra}"
    )
}

const DEVIATIONS: [f64; 6] = [0.03, -0.02, 0.05, 0.0, -0.04, 0.01];

pub(crate) fn deviations_toml(d: &[f64]) -> String {
    let list: Vec<String> = d.iter().map(|x| format!("{x:?}")).collect();
    format!("[mistuning]\ndeviations = [{}]\n", list.join(", "))
}

/// The academic wheel assembled here from Table 1 (docs/design.md §4),
/// springs k1 and k2 of sector j scaled by 1 + δ_j: `(M, K, C)` with
/// `C = α M + β K_tuned` (the damping stays the tuned wheel's).
pub(crate) fn assembled(
    deviations: &[f64],
    alpha: f64,
    beta: f64,
) -> (Mat<f64>, Mat<f64>, Mat<f64>) {
    let n = deviations.len();
    let size = 5 * n;
    let mass = Mat::from_fn(size, size, |r, c| {
        if r == c {
            ACADEMIC_MASSES[r % 5]
        } else {
            0.0
        }
    });
    let k = ACADEMIC_STIFFNESSES;
    let stiffness = |scaled: bool| {
        let mut m = Mat::<f64>::zeros(size, size);
        let mut spring = |a: usize, b: usize, value: f64| {
            m[(a, a)] += value;
            m[(b, b)] += value;
            m[(a, b)] -= value;
            m[(b, a)] -= value;
        };
        for (j, d) in deviations.iter().enumerate() {
            let scale = if scaled { 1.0 + d } else { 1.0 };
            let o = 5 * j;
            spring(o, o + 1, k[0] * scale);
            spring(o + 1, o + 2, k[1] * scale);
            spring(o + 2, o + 3, k[2]);
            spring(o + 3, o + 4, k[4]);
            spring(o + 4, 5 * ((j + 1) % n) + 3, k[4]);
        }
        for j in 0..n {
            m[(5 * j + 3, 5 * j + 3)] += k[3];
        }
        m
    };
    let tuned = stiffness(false);
    let damping = Mat::from_fn(size, size, |r, c| {
        alpha * mass[(r, c)] + beta * tuned[(r, c)]
    });
    (mass, stiffness(true), damping)
}

/// `X` of `(K − ω² M + iω C) X = F`, densely.
fn dense_solve(m: &(Mat<f64>, Mat<f64>, Mat<f64>), load: &[c64], omega: f64) -> Vec<c64> {
    let size = load.len();
    let z = Mat::from_fn(size, size, |r, c| {
        c64::new(
            m.1[(r, c)] - omega * omega * m.0[(r, c)],
            omega * m.2[(r, c)],
        )
    });
    let x = z
        .partial_piv_lu()
        .solve(Mat::from_fn(size, 1, |r, _| load[r]));
    (0..size).map(|r| x[(r, 0)]).collect()
}

/// The traveling wave `h = 1` of 4 N on m1: `F_j = 2 e^{iα j}` (`x(t) = 2 Re(X e^{iωt})`).
fn traveling_load(n: usize) -> Vec<c64> {
    let alpha = 2.0 * PI / n as f64;
    let mut load = vec![c64::new(0.0, 0.0); 5 * n];
    for j in 0..n {
        load[5 * j] = c64::cis(alpha * j as f64) * 2.0;
    }
    load
}

/// Harmonic 1 of contact dof m1 in every sector, from the physical unknowns.
fn first_harmonic(x: &[f64], sectors: usize, harmonics: usize) -> Vec<c64> {
    let size = 2 * harmonics + 1;
    (0..sectors)
        .map(|j| c64::new(x[j * size + 1], x[j * size + 2]))
        .collect()
}

#[test]
fn the_linear_mistuned_response_is_the_dense_solve_of_the_assembled_wheel() {
    let case = case(&academic(&deviations_toml(&DEVIATIONS)));
    let mut problem = prepare(&case, Path::new("."), BasisChoice::Physical)
        .unwrap()
        .problem;
    let oracle = assembled(&DEVIATIONS, 3.0, 2e-6);
    let load = traveling_load(6);
    // Across the first blade family (nodal diameter 1 at 208.7 Hz tuned).
    for f in [190.0, 205.0, 208.5, 211.0, 230.0] {
        let omega = 2.0 * PI * f;
        let solved = first_harmonic(&problem.linear_solution(omega).unwrap(), 6, 3);
        let expected = dense_solve(&oracle, &load, omega);
        let scale = expected
            .iter()
            .step_by(5)
            .fold(0.0_f64, |m, x| m.max(x.norm()));
        for (j, x) in solved.iter().enumerate() {
            let error = (x - expected[5 * j]).norm() / scale;
            assert!(error < 1e-10, "{f} Hz, sector {}: {error:e}", j + 1);
        }
    }
}

/// A short branch through first contact, at fixed frequencies.
fn at_frequencies(case: &Case, basis: BasisChoice) -> Vec<(f64, Vec<f64>)> {
    let solution = ForcedResponse::from_case(case)
        .unwrap()
        .basis(basis)
        .at_frequencies_hz(vec![195.0, 200.0, 204.0, 206.0])
        .build()
        .unwrap()
        .run(&mut [])
        .unwrap();
    solution
        .branch
        .points
        .iter()
        .map(|p| {
            assert!(p.converged);
            (p.omega, p.unknowns.clone())
        })
        .collect()
}

const CONTACT: &str = "[casing]\ngap = 2e-4\n[continuation]\ntolerance = 1e-11\n";

#[test]
fn zero_deviations_give_the_tuned_branch_bit_for_bit() {
    let tuned = case(&academic(CONTACT));
    let zero = case(&academic(&format!(
        "{CONTACT}{}",
        deviations_toml(&[0.0; 6])
    )));
    let a = at_frequencies(&tuned, BasisChoice::Physical);
    let b = at_frequencies(&zero, BasisChoice::Physical);
    assert_eq!(a, b);
    // And the tuned symmetric branch: the sectors' first harmonics of the
    // traveling wave have one modulus.
    let first = first_harmonic(&a[3].1, 6, 3);
    let spread = first
        .iter()
        .fold(0.0_f64, |m, x| m.max((x.norm() - first[0].norm()).abs()));
    assert!(spread < 1e-12 * first[0].norm(), "{spread:e}");
}

#[test]
fn a_cyclic_mistuning_is_the_tuned_wheel_with_the_scaled_blade() {
    let delta = 0.05;
    // Mass-proportional damping only: C does not depend on the blade.
    let text =
        |extra: &str| academic(&format!("{CONTACT}{extra}")).replace("beta = 2e-6", "beta = 0.0");
    let mistuned = case(&text(&deviations_toml(&[delta; 6])));
    let k = ACADEMIC_STIFFNESSES;
    let springs = format!(
        "springs = [\n{{ dofs = [1, 2], stiffness = {:?} }},\n{{ dofs = [2, 3], stiffness = {:?} }},\n\
         {{ dofs = [3, 4], stiffness = {:?} }},\n{{ dofs = [4], stiffness = {:?}, link = \"ground\" }},\n\
         {{ dofs = [4, 5], stiffness = {:?} }},\n{{ dofs = [5, 4], stiffness = {:?}, link = \"next_sector\" }},\n]\n",
        k[0] * (1.0 + delta),
        k[1] * (1.0 + delta),
        k[2],
        k[3],
        k[4],
        k[4]
    );
    let scaled = case(&text("").replace("sectors = 6\n", &format!("sectors = 6\n{springs}")));
    let a = at_frequencies(&mistuned, BasisChoice::Physical);
    let b = at_frequencies(&scaled, BasisChoice::Physical);
    for ((wa, xa), (wb, xb)) in a.iter().zip(&b) {
        assert_eq!(wa, wb);
        let scale = xb.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
        let error = xa
            .iter()
            .zip(xb)
            .fold(0.0_f64, |m, (x, y)| m.max((x - y).abs()));
        assert!(error < 1e-10 * scale, "{wa}: {error:e} of {scale:e}");
    }
}

#[test]
fn linear_amplification_factors_of_a_hundred_patterns_stay_below_whiteheads_bound() {
    let sectors = 6;
    let bound = (1.0 + (sectors as f64).sqrt()) / 2.0;
    let base = case(&format!(
        "[model]\nsectors = {sectors}\n[model.damping]\nratio = 5e-3\n"
    ));
    let model = base.model.build(Path::new(".")).unwrap();
    let forcing = base.forcing().unwrap();
    // The first blade family spans 208.7–212.2 Hz tuned (nodal diameters
    // 1–3; 0 is a disk mode at 67 Hz); steps of 0.04 Hz against a
    // half-power width of about 2 Hz.
    let frequencies: Vec<f64> = (0..=500).map(|i| 200.0 + i as f64 * 0.04).collect();
    let mut largest = 0.0_f64;
    for seed in 0..100 {
        let mut mistuned = base.clone();
        mistuned.mistuning.standard_deviation = Some(0.03);
        mistuned.mistuning.seed = Some(seed);
        let model = mistuned.mistuned(model.clone(), Path::new(".")).unwrap();
        let factor = linear_amplification_factor(&model, &forcing, 0, &frequencies).unwrap();
        assert!(factor <= bound, "seed {seed}: {factor} above {bound}");
        largest = largest.max(factor);
    }
    // Mistuning does amplify (the test would pass vacuously otherwise).
    assert!(largest > 1.05, "largest factor {largest}");
}

/// `f` of the regularized law at penetration `p` (Eq. 70).
fn regularized(p: f64, kappa: f64, gamma: f64) -> f64 {
    let half = 0.5 * kappa * p;
    half + (half * half + gamma * gamma).sqrt()
}

#[test]
fn with_contact_the_mistuned_solution_satisfies_the_full_wheel_residual() {
    let harmonics = 3;
    let samples = 96;
    let case = case(&academic(&format!(
        "{CONTACT}{}",
        deviations_toml(&DEVIATIONS)
    )));
    let points = at_frequencies(&case, BasisChoice::Physical);
    let oracle = assembled(&DEVIATIONS, 3.0, 2e-6);
    let (kappa, gamma, gap) = (1e8, 2.5, 2e-4);
    let n = 6;
    let size = 2 * harmonics + 1;
    let mut touched = false;
    for (omega, x) in &points {
        // Contact forces per sector and harmonic, by a naive DFT.
        let mut force = vec![vec![c64::new(0.0, 0.0); harmonics + 1]; n];
        for (j, per_sector) in force.iter_mut().enumerate() {
            let c = &x[j * size..(j + 1) * size];
            for m in 0..samples {
                let theta = 2.0 * PI * m as f64 / samples as f64;
                let mut u = c[0];
                for k in 1..=harmonics {
                    u += 2.0 * (c64::new(c[2 * k - 1], c[2 * k]) * c64::cis(k as f64 * theta)).re;
                }
                let f = regularized(u - gap, kappa, gamma);
                touched |= u > gap;
                for (k, slot) in per_sector.iter_mut().enumerate() {
                    *slot += c64::cis(-(k as f64) * theta) * (f / samples as f64);
                }
            }
        }
        // Every harmonic of the whole wheel: Z X = F − f_contact on all
        // dofs, m1 of each sector given by the unknowns; the other dofs
        // solved from their own rows, then m1's rows checked.
        for k in 0..=harmonics {
            let w = k as f64 * omega;
            let load = if k == 1 {
                traveling_load(n)
            } else {
                vec![c64::new(0.0, 0.0); 5 * n]
            };
            let rhs: Vec<c64> = (0..5 * n)
                .map(|r| {
                    if r % 5 == 0 {
                        load[r] - force[r / 5][k]
                    } else {
                        load[r]
                    }
                })
                .collect();
            let z = |r: usize, c: usize| {
                c64::new(
                    oracle.1[(r, c)] - w * w * oracle.0[(r, c)],
                    w * oracle.2[(r, c)],
                )
            };
            let contact: Vec<c64> = (0..n)
                .map(|j| {
                    let c = &x[j * size..(j + 1) * size];
                    if k == 0 {
                        c64::new(c[0], 0.0)
                    } else {
                        c64::new(c[2 * k - 1], c[2 * k])
                    }
                })
                .collect();
            let interior: Vec<usize> = (0..5 * n).filter(|r| r % 5 != 0).collect();
            let a = Mat::from_fn(interior.len(), interior.len(), |r, c| {
                z(interior[r], interior[c])
            });
            let b = Mat::from_fn(interior.len(), 1, |r, _| {
                (0..n).fold(rhs[interior[r]], |s, j| {
                    s - z(interior[r], 5 * j) * contact[j]
                })
            });
            let inner = a.partial_piv_lu().solve(b);
            let mut full = vec![c64::new(0.0, 0.0); 5 * n];
            for j in 0..n {
                full[5 * j] = contact[j];
            }
            for (i, &r) in interior.iter().enumerate() {
                full[r] = inner[(i, 0)];
            }
            for j in 0..n {
                let row = 5 * j;
                let residual = (0..5 * n).fold(-rhs[row], |s, c| s + z(row, c) * full[c]);
                // Relative to the load's 4 N (2 N per complex coefficient).
                assert!(
                    residual.norm() < 1e-10 * 2.0,
                    "{} Hz, harmonic {k}, sector {}: {:e}",
                    omega / (2.0 * PI),
                    j + 1,
                    residual.norm()
                );
            }
        }
    }
    assert!(
        touched,
        "no point touches the casing: the test would not check the contact"
    );
}

#[test]
fn friction_and_dlft_run_on_a_mistuned_wheel() {
    let friction = BLADE
        .replace("harmonics = 12", "harmonics = 4")
        .replace("time_samples = 1536", "time_samples = 192");
    let mistuning = "[mistuning]\nstandard_deviation = 0.02\nseed = 3\nblade_dofs = [1, 2, 3]\n[basis]\nkind = \"physical\"\n";
    let dlft = academic(&format!(
        "[contact]\nlaw = \"dlft\"\nepsilon = 1e9\nwall_stiffness = 1e8\n[casing]\ngap = 2e-4\n{}",
        deviations_toml(&DEVIATIONS)
    ));
    for text in [format!("{friction}{mistuning}"), dlft] {
        let case = case(&text);
        let model = case.model.build(Path::new(".")).unwrap();
        let middle = cyclorub::forced_response::excited_frequency(&case, &model).unwrap();
        let solution = ForcedResponse::from_case(&case)
            .unwrap()
            .at_frequencies_hz((0..8).map(|i| (0.95 + 0.005 * i as f64) * middle).collect())
            .build()
            .unwrap()
            .run(&mut [])
            .unwrap();
        assert!(solution.model.is_mistuned());
        assert!(
            solution.branch.points.iter().all(|p| p.converged),
            "{:?}: {:?}",
            case.contact.law,
            solution
                .branch
                .points
                .iter()
                .map(|p| (p.omega / (2.0 * PI), p.residual_norm))
                .collect::<Vec<_>>()
        );
        // The sectors differ: the mistuned wheel is not the traveling wave.
        let last = solution.branch.points.last().unwrap();
        let size = last.unknowns.len() / 6;
        let moduli: Vec<f64> = (0..6)
            .map(|j| c64::new(last.unknowns[j * size + 1], last.unknowns[j * size + 2]).norm())
            .collect();
        let spread = moduli
            .iter()
            .fold(0.0_f64, |m, x| m.max((x - moduli[0]).abs()));
        // In contact: some sector's tip swings beyond the gap.
        let gap = case.casing().unwrap().gaps[0];
        let swing = 2.0 * moduli.iter().fold(0.0_f64, |m, x| m.max(*x));
        assert!(
            swing > gap,
            "{:?}: swing {swing:e}, gap {gap:e}",
            case.contact.law
        );
        assert!(spread > 1e-3 * moduli[0], "{moduli:?}");
    }
}

/// The message of a case refused before any work.
fn refusal(text: &str, basis: BasisChoice) -> String {
    let case = match Case::from_toml(text, Path::new("case.toml")).and_then(|c| {
        c.validate()?;
        Ok(c)
    }) {
        Ok(case) => case,
        Err(error) => return error.to_string(),
    };
    match prepare(&case, Path::new("."), basis) {
        Ok(_) => panic!("{text:?} was accepted"),
        Err(error) => error.to_string(),
    }
}

#[test]
fn deviations_of_the_wrong_length_are_refused() {
    let message = refusal(
        &academic(&deviations_toml(&[0.01, 0.02])),
        BasisChoice::Physical,
    );
    assert!(
        message.contains("mistuning.deviations = 2 values")
            && message.contains("as many as model.sectors = 6"),
        "{message}"
    );
}

#[test]
fn a_deviation_at_or_below_minus_one_is_refused() {
    let message = refusal(
        &academic(&deviations_toml(&[0.0, 0.0, -1.0, 0.0, 0.0, 0.0])),
        BasisChoice::Physical,
    );
    assert!(
        message.contains("mistuning.deviations")
            && message.contains("sector 3")
            && message.contains("> −1"),
        "{message}"
    );
    let drawn = refusal(
        &academic("[mistuning]\nstandard_deviation = 2.0\n"),
        BasisChoice::Physical,
    );
    assert!(
        drawn.contains("mistuning.standard_deviation = 2")
            && drawn.contains("smaller standard deviation"),
        "{drawn}"
    );
}

#[test]
fn a_reduced_basis_is_refused_for_a_mistuned_wheel() {
    for basis in [BasisChoice::Symmetry, BasisChoice::Full] {
        let message = refusal(&academic(&deviations_toml(&DEVIATIONS)), basis);
        assert!(
            message.contains("cannot hold a mistuned wheel")
                && message.contains("do not decouple")
                && message.contains("basis.kind = \"physical\""),
            "{message}"
        );
    }
}

/// Inline matrices with cyclic boundary lists have no blade to scale (a
/// finite-element sector names its blade by a node set:
/// tests/mistuning_fan.rs).
#[test]
fn mistuning_inline_matrices_with_boundary_lists_is_refused_by_name() {
    let text = "[model]\nkind = \"matrices\"\nsectors = 2\n\
                mass = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]\n\
                stiffness = [[2.0, -1.0, 0.0], [-1.0, 2.0, -1.0], [0.0, -1.0, 2.0]]\n\
                left_boundary = [1]\nright_boundary = [3]\n\
                [excitation]\ndofs = [2]\n[contact]\ndofs = [2]\n\
                [mistuning]\ndeviations = [0.0, 0.1]\nblade_dofs = [2]\n";
    let message = refusal(text, BasisChoice::Physical);
    assert!(
        message.starts_with("mistuning = (with model.kind = \"matrices\")")
            && message.contains("cyclic boundary lists, has no blade to scale"),
        "{message}"
    );
}

/// A mistuned run writes its record (the deviations, every sector's peak,
/// the most responding sector, the amplification factor over the tuned
/// branch's peak, computed here again) and its two figures.
#[cfg(feature = "plot")]
#[test]
fn a_mistuned_run_records_its_sector_peaks_and_amplification_factor() {
    use cyclorub::run::{run, RunOptions};
    let case = case(&academic(&format!(
        "{CONTACT}{}",
        deviations_toml(&DEVIATIONS)
    )));
    let output = std::env::temp_dir().join(format!("cyclorub-mistuning-{}", std::process::id()));
    let frequencies = vec![195.0, 200.0, 204.0, 206.0];
    let options = RunOptions {
        output: output.clone(),
        basis: BasisChoice::Physical,
        at_hz: Some(frequencies.clone()),
        stability: Some(Default::default()),
        overwrite: true,
        interrupt: Default::default(),
    };
    let record = run(&case, Path::new("."), &options, |_| {}).unwrap();
    // Its stability is checked on its one class, the whole wheel, and
    // reported as a tuned run's: a verdict per point in branch.csv.
    assert_eq!(
        record.stability.status,
        cyclorub::run::StabilityStatus::Computed
    );
    assert!(record.stability.points_by_hill >= 1);
    let m = record
        .mistuning
        .expect("a mistuned run has a mistuning record");
    assert_eq!(m.deviations, DEVIATIONS);
    // The peaks are branch.csv's columns' largest values.
    let table = std::fs::read_to_string(output.join("branch.csv")).unwrap();
    let header: Vec<&str> = table.lines().next().unwrap().split(',').collect();
    let stable = header.iter().position(|c| *c == "stable").unwrap();
    for line in table.lines().skip(1) {
        let verdict = line.split(',').nth(stable).unwrap();
        assert!(verdict == "1" || verdict == "0", "{line}");
    }
    let rows: Vec<Vec<f64>> = table
        .lines()
        .skip(1)
        .map(|l| {
            l.split(',')
                .skip(2)
                .take(6)
                .map(|v| v.parse().unwrap())
                .collect()
        })
        .collect();
    for j in 0..6 {
        let largest = rows.iter().fold(0.0_f64, |a, r| a.max(r[j]));
        assert!(
            (m.sector_peaks_m[j] - largest).abs() <= 1e-12 * largest,
            "sector {}",
            j + 1
        );
    }
    let most = (0..6)
        .max_by(|&a, &b| m.sector_peaks_m[a].total_cmp(&m.sector_peaks_m[b]))
        .unwrap();
    assert_eq!(m.most_responding_sector, most + 1);
    // The tuned peak: the tuned case solved again here on the full wheel
    // (the record's is on the symmetry basis).
    let mut tuned = case.clone();
    tuned.mistuning = Default::default();
    let solution = ForcedResponse::from_case(&tuned)
        .unwrap()
        .basis(BasisChoice::Physical)
        .at_frequencies_hz(frequencies)
        .build()
        .unwrap()
        .run(&mut [])
        .unwrap();
    let tuned = solution
        .point_summaries()
        .into_iter()
        .map(|s| {
            s.unwrap()
                .observed
                .peak
                .iter()
                .fold(0.0_f64, |m, &a| m.max(a))
        })
        .fold(0.0_f64, f64::max);
    let factor = m.amplification_factor.unwrap();
    assert!(
        (factor - m.sector_peaks_m[most] / tuned).abs() < 1e-8 * factor,
        "{factor} against {}",
        m.sector_peaks_m[most] / tuned
    );
    for figure in ["sector_amplitudes.svg", "sector_peaks.svg"] {
        assert!(output.join("plots").join(figure).exists(), "{figure}");
    }
    let _ = std::fs::remove_dir_all(&output);
}

/// The time integration's operators are block-circulant: a mistuned case
/// is refused there rather than integrated tuned.
#[test]
fn time_integration_refuses_a_mistuned_wheel() {
    let case = case(&academic(&deviations_toml(&DEVIATIONS)));
    let message = match cyclorub::simulate::WheelSetup::from_case(&case, Path::new(".")) {
        Ok(_) => panic!("a mistuned case was accepted by the time integration"),
        Err(error) => error.to_string(),
    };
    assert!(
        message.contains("mistuning") && message.contains("tuned wheel only"),
        "{message}"
    );
}
