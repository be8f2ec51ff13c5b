//! Per-diameter matrices against the assembled full wheel: the sign
//! convention, Hermitian structure, and the frequency unions.

use crate::support;

use cyclorub::model::{
    BlockCirculantSector, Damping, FiniteElementSector, LumpedSector, SectorModel, Spring,
    SpringLink,
};
use faer::{c64, Mat};
use support::{cis, frequencies_hz, max_abs_c, Lcg};

/// For the pattern `x_j = X·exp(−isα(j−1))`, the full wheel applied to it
/// gives `A(s)·X·exp(−isα(j−1))` on every sector `j`.
fn check_pattern(model: &SectorModel, s: i64) {
    let n = model.dofs_per_sector();
    let sectors = model.sectors();
    let alpha = 2.0 * std::f64::consts::PI / sectors as f64;
    let full = model.full_wheel().expect("full wheel");
    let nd = model.nodal_diameter_matrices(s).expect("per diameter");
    let mut rng = Lcg(17u64.wrapping_add(s as u64));
    let x: Vec<c64> = (0..n)
        .map(|_| c64::new(rng.range(-1.0, 1.0), rng.range(-1.0, 1.0)))
        .collect();
    let pattern = Mat::from_fn(sectors * n, 1, |row, _| {
        let (j, d) = (row / n, row % n);
        x[d] * cis(-(s as f64) * alpha * j as f64)
    });
    for (name, full_matrix, per_diameter) in [
        ("mass", &full.mass, &nd.mass),
        ("stiffness", &full.stiffness, &nd.stiffness),
        ("damping", &full.damping, &nd.damping),
    ] {
        let full_c = support::complex(full_matrix);
        let y = &full_c * &pattern;
        let x_col = Mat::from_fn(n, 1, |d, _| x[d]);
        let expected = per_diameter * &x_col;
        let scale = max_abs_c(&expected).max(max_abs_c(per_diameter)) + f64::MIN_POSITIVE;
        for j in 0..sectors {
            let phase = cis(-(s as f64) * alpha * j as f64);
            for d in 0..n {
                let diff = (y[(j * n + d, 0)] - expected[(d, 0)] * phase).norm();
                assert!(
                    diff <= 1e-12 * scale,
                    "N = {sectors}, s = {s}, {name}: sector {} dof {d}: {} vs {}",
                    j + 1,
                    y[(j * n + d, 0)],
                    expected[(d, 0)] * phase
                );
            }
        }
    }
}

fn check_structure(model: &SectorModel) {
    let sectors = model.sectors() as i64;
    for s in -sectors..=sectors {
        let a = model.nodal_diameter_matrices(s).expect("per diameter");
        let b = model.nodal_diameter_matrices(-s).expect("per diameter");
        for (name, m, mc) in [
            ("M", &a.mass, &b.mass),
            ("K", &a.stiffness, &b.stiffness),
            ("C", &a.damping, &b.damping),
        ] {
            let scale = max_abs_c(m) + f64::MIN_POSITIVE;
            let n = m.nrows();
            for i in 0..n {
                for j in 0..n {
                    assert!(
                        (m[(i, j)] - m[(j, i)].conj()).norm() <= 1e-14 * scale,
                        "{name}({s}) not Hermitian"
                    );
                    assert!(
                        (m[(i, j)] - mc[(i, j)].conj()).norm() <= 1e-14 * scale,
                        "{name}(−{s}) ≠ conj"
                    );
                    if s.rem_euclid(sectors) == 0 || 2 * s.rem_euclid(sectors) == sectors {
                        assert!(m[(i, j)].im.abs() <= 1e-14 * scale, "{name}({s}) not real");
                    }
                }
            }
        }
    }
}

/// The union over diameters (0 < d < N/2 twice) against the full wheel.
fn check_frequency_union(model: &SectorModel) {
    let sectors = model.sectors();
    let mut union: Vec<f64> = Vec::new();
    for (d, freqs) in model.natural_frequencies().expect("frequencies") {
        let twice = d != 0 && 2 * d != sectors;
        for f in freqs {
            union.push(f);
            if twice {
                union.push(f);
            }
        }
    }
    union.sort_by(f64::total_cmp);
    let full = model.full_wheel().expect("full wheel");
    let reference = frequencies_hz(&full.stiffness, &full.mass);
    assert_eq!(union.len(), reference.len());
    for (a, b) in union.iter().zip(&reference) {
        assert!(
            (a - b).abs() <= 1e-9 * b.abs().max(1e-300),
            "N = {sectors}: {a} Hz vs full wheel {b} Hz"
        );
    }
}

#[test]
fn academic_sign_convention_and_structure() {
    for sectors in [24, 45, 1, 2, 3] {
        let model = SectorModel::academic(sectors).expect("academic");
        assert_eq!(model.dofs_per_sector(), 5);
        assert_eq!(model.dof_label(0), "m1");
        let n = sectors as i64;
        for s in [0, 1, -1, 2, -3, 5, -7, n / 2, -(n / 2), n - 1, 13, -13] {
            check_pattern(&model, s);
        }
        check_structure(&model);
    }
}

#[test]
fn academic_frequencies_union_equals_full_wheel() {
    for sectors in [24, 45, 1, 2, 7] {
        check_frequency_union(&SectorModel::academic(sectors).expect("academic"));
    }
}

#[test]
fn academic_n24_first_frequencies() {
    let model = SectorModel::academic(24).expect("academic");
    let freqs = model.natural_frequencies().expect("frequencies");
    assert_eq!(freqs.len(), 13);
    for (d, f) in &freqs {
        assert_eq!(f.len(), 5, "nd {d}");
        assert!(f.windows(2).all(|w| w[0] <= w[1]));
        assert!(f[0] > 0.0);
    }
}

/// A block-circulant sector with random couplings (mass coupling too).
#[test]
fn random_block_circulant_sign_convention() {
    let mut rng = Lcg(3);
    for sectors in [1, 2, 5, 6] {
        let n = 4;
        let sector = BlockCirculantSector {
            mass: rng.spd(n, 8.0),
            stiffness: rng.spd(n, 20.0),
            mass_coupling: Some(rng.matrix(n, n)),
            stiffness_coupling: Some(rng.matrix(n, n)),
        };
        let c = rng.spd(n, 1.0);
        let c1 = rng.matrix(n, n);
        for damping in [
            Damping::default(),
            Damping::Rayleigh {
                alpha: 2.0,
                beta: 1e-3,
            },
            Damping::Matrix {
                matrix: c.clone(),
                coupling: Some(c1.clone()),
            },
            Damping::None,
        ] {
            let model =
                SectorModel::block_circulant(sectors, sector.clone(), damping).expect("model");
            for s in -4..=4 {
                check_pattern(&model, s);
            }
            check_structure(&model);
        }
    }
}

/// A spring chain around the wheel written as a finite-element sector: the
/// boundary node is shared between neighbours, its mass split in halves.
/// Sector dofs (FE numbering): 0 = left boundary node, 1, 2 interior,
/// 3 = right boundary node (the next sector's 0); 1 and 2 also carry a blade.
fn chain_fe_sector(rng: &mut Lcg) -> (FiniteElementSector, LumpedSector) {
    let hub = rng.range(1.0, 2.0);
    let (m1, m2, mb) = (
        rng.range(0.5, 1.5),
        rng.range(0.5, 1.5),
        rng.range(0.1, 0.3),
    );
    let (k01, k12, k23, kg, kb) = (
        rng.range(1e5, 2e5),
        rng.range(1e5, 2e5),
        rng.range(1e5, 2e5),
        rng.range(1e3, 1e4),
        rng.range(1e4, 5e4),
    );
    // FE sector: dofs 0..3 chain + dof 4 blade on dof 2.
    let size = 5;
    let mut k = Mat::<f64>::zeros(size, size);
    let mut add = |a: usize, b: Option<usize>, v: f64| {
        k[(a, a)] += v;
        if let Some(b) = b {
            k[(b, b)] += v;
            k[(a, b)] -= v;
            k[(b, a)] -= v;
        }
    };
    add(0, Some(1), k01);
    add(1, Some(2), k12);
    add(2, Some(3), k23);
    add(1, None, kg);
    add(2, Some(4), kb);
    let masses_fe = [hub / 2.0, m1, m2, hub / 2.0, mb];
    let mass = Mat::from_fn(size, size, |i, j| if i == j { masses_fe[i] } else { 0.0 });
    let fe = FiniteElementSector {
        mass,
        stiffness: k,
        left_boundary: vec![0],
        right_boundary: vec![3],
        boundary_frame: Default::default(),
    };
    // The same chain as a lumped sector: dofs hub, m1, m2, blade.
    let lumped = LumpedSector {
        masses: vec![hub, m1, m2, mb],
        springs: vec![
            Spring {
                link: SpringLink::Within(0, 1),
                stiffness: k01,
            },
            Spring {
                link: SpringLink::Within(1, 2),
                stiffness: k12,
            },
            Spring {
                link: SpringLink::NextSector(2, 0),
                stiffness: k23,
            },
            Spring {
                link: SpringLink::Ground(1),
                stiffness: kg,
            },
            Spring {
                link: SpringLink::Within(2, 3),
                stiffness: kb,
            },
        ],
    };
    (fe, lumped)
}

/// Full wheel of an FE sector assembled directly by global numbering (the
/// right boundary of sector j is the left boundary of sector j+1): an oracle
/// independent of the library's block-circulant conversion.
fn fe_full_wheel_oracle(fe: &FiniteElementSector, sectors: usize) -> (Mat<f64>, Mat<f64>) {
    let size = fe.mass.nrows();
    let kept: Vec<usize> = (0..size)
        .filter(|d| !fe.right_boundary.contains(d))
        .collect();
    let n = kept.len();
    let global = |j: usize, o: usize| -> usize {
        if let Some(i) = fe.right_boundary.iter().position(|&r| r == o) {
            let l = fe.left_boundary[i];
            ((j + 1) % sectors) * n + kept.iter().position(|&k| k == l).expect("left kept")
        } else {
            j * n + kept.iter().position(|&k| k == o).expect("kept")
        }
    };
    let mut m = Mat::<f64>::zeros(sectors * n, sectors * n);
    let mut k = Mat::<f64>::zeros(sectors * n, sectors * n);
    for j in 0..sectors {
        for a in 0..size {
            for b in 0..size {
                m[(global(j, a), global(j, b))] += fe.mass[(a, b)];
                k[(global(j, a), global(j, b))] += fe.stiffness[(a, b)];
            }
        }
    }
    (m, k)
}

#[test]
fn fe_chain_sector_matches_lumped_and_full_wheel() {
    let mut rng = Lcg(11);
    for sectors in [24, 45, 1, 2, 5] {
        let (fe, lumped) = chain_fe_sector(&mut rng);
        let fe_model =
            SectorModel::finite_element(sectors, fe.clone(), Damping::default()).expect("fe");
        assert_eq!(fe_model.dofs_per_sector(), 4);
        assert_eq!(fe_model.dof_label(3), "dof 5");
        let lumped_model =
            SectorModel::lumped(sectors, &lumped, Damping::default()).expect("lumped");
        // Same per-diameter matrices (FE dof order 0, 1, 2, 4 = lumped 0..3).
        for s in [-2, -1, 0, 1, 3] {
            let a = fe_model.nodal_diameter_matrices(s).expect("fe nd");
            let b = lumped_model.nodal_diameter_matrices(s).expect("lumped nd");
            for (x, y) in [
                (&a.mass, &b.mass),
                (&a.stiffness, &b.stiffness),
                (&a.damping, &b.damping),
            ] {
                let scale = max_abs_c(y);
                for i in 0..4 {
                    for j in 0..4 {
                        assert!(
                            (x[(i, j)] - y[(i, j)]).norm() <= 1e-12 * scale,
                            "N = {sectors} s = {s}"
                        );
                    }
                }
            }
            check_pattern(&fe_model, s);
        }
        check_structure(&fe_model);
        check_frequency_union(&fe_model);
        // The library's full wheel equals the direct FE assembly.
        let (m, k) = fe_full_wheel_oracle(&fe, sectors);
        let full = fe_model.full_wheel().expect("full");
        let (m_scale, k_scale) = (support::max_abs(&m), support::max_abs(&k));
        for i in 0..m.nrows() {
            for j in 0..m.ncols() {
                assert!((full.mass[(i, j)] - m[(i, j)]).abs() <= 1e-14 * m_scale);
                assert!((full.stiffness[(i, j)] - k[(i, j)]).abs() <= 1e-14 * k_scale);
            }
        }
    }
}

/// A random FE sector with two boundary pairs listed out of order.
#[test]
fn random_fe_sector_sign_convention() {
    let mut rng = Lcg(5);
    for sectors in [1, 2, 3, 8] {
        let size = 7;
        let fe = FiniteElementSector {
            mass: rng.spd(size, 3.0),
            stiffness: rng.spd(size, 1.0),
            left_boundary: vec![4, 0],
            right_boundary: vec![2, 6],
            boundary_frame: Default::default(),
        };
        let model =
            SectorModel::finite_element(sectors, fe.clone(), Damping::default()).expect("fe");
        assert_eq!(model.dofs_per_sector(), 5);
        for s in -3..=3 {
            check_pattern(&model, s);
        }
        check_structure(&model);
        check_frequency_union(&model);
        let (m, k) = fe_full_wheel_oracle(&fe, sectors);
        let full = model.full_wheel().expect("full");
        for i in 0..m.nrows() {
            for j in 0..m.ncols() {
                assert!((full.mass[(i, j)] - m[(i, j)]).abs() <= 1e-12);
                assert!((full.stiffness[(i, j)] - k[(i, j)]).abs() <= 1e-12);
            }
        }
    }
}

/// N = 1 with plain matrices: a 1-dof oscillator.
#[test]
fn single_dof_oscillator() {
    let sector = BlockCirculantSector {
        mass: Mat::from_fn(1, 1, |_, _| 1.0),
        stiffness: Mat::from_fn(1, 1, |_, _| 40.0),
        mass_coupling: None,
        stiffness_coupling: None,
    };
    let model = SectorModel::block_circulant(1, sector, Damping::None).expect("oscillator");
    let freqs = model.natural_frequencies().expect("frequencies");
    assert_eq!(freqs.len(), 1);
    let expected = 40.0_f64.sqrt() / (2.0 * std::f64::consts::PI);
    assert!((freqs[0].1[0] - expected).abs() <= 1e-12 * expected);
    check_pattern(&model, 0);
    check_pattern(&model, 3);
}
