//! Mistuning on finite-element sectors (issue 44): the coarse open fan
//! (16 sectors, Craig–Bampton per nodal diameter, 53 reduced dofs a
//! sector), its blade the node set `blade` of `cyclorub mesh fan`, each
//! sector's stiffness entries between two blade nodes scaled by `1 + δ_j`
//! and projected on the tuned bases. Checked against oracles that do not
//! share the library's assembly of the perturbation: the wheel assembled
//! here in the wave domain and solved densely, the tuned wheel whose
//! per-diameter stiffness holds the scaled blade (δ the same on every
//! sector), δ = 0 bit for bit, and the finite-element sector whose blade
//! entries are scaled before the reduction (what the projection
//! approximates).

use cyclorub::case::{BasisChoice, Case};
use cyclorub::forced_response::prepare;
use cyclorub::mesh::{assemble, fan, write_fan, FanGeometry};
use cyclorub::model::{Damping, ReducedBlade, SectorModel};
use faer::linalg::solvers::Solve;
use faer::{c64, Mat};
use std::f64::consts::PI;
use std::path::{Path, PathBuf};

const SECTORS: usize = 16;

/// A mistuning pattern of a few percent, no two sectors alike.
const DEVIATIONS: [f64; SECTORS] = [
    0.031, -0.024, 0.012, 0.047, -0.038, 0.0, 0.019, -0.011, -0.045, 0.026, 0.008, -0.017, 0.036,
    -0.03, 0.014, -0.006,
];

/// The coarse fan written to a fresh folder; with `scale`, the stiffness
/// entries between two nodes of its blade set multiplied by it.
fn folder(tag: &str, scale: Option<f64>) -> PathBuf {
    let dir = std::env::temp_dir().join(format!(
        "cyclorub-mistuned-fan-{tag}-{}",
        std::process::id()
    ));
    let _ = std::fs::remove_dir_all(&dir);
    let mesh = fan(SECTORS, 1, &FanGeometry::default()).unwrap();
    let mut matrices = assemble(&mesh.mesh).unwrap();
    if let Some(scale) = scale {
        let mut blade = vec![false; mesh.mesh.nodes.len()];
        for &n in &mesh.sets.blade {
            blade[n] = true;
        }
        let k = &mut matrices.stiffness;
        for j in 0..k.size {
            for p in k.starts[j]..k.starts[j + 1] {
                if blade[k.rows[p] / 3] && blade[j / 3] {
                    k.values[p] *= scale;
                }
            }
        }
    }
    write_fan(&mesh, &matrices, &dir, false).unwrap();
    dir
}

/// The fan's case: engine order 4 (the first family near 282 Hz), one
/// harmonic (the linear checks need no more).
fn case(dir: &Path) -> Case {
    let mut case = Case::from_file_checked(&dir.join("fan16.toml")).unwrap();
    case.excitation.engine_order = 4;
    case.harmonic_balance.harmonics = 1;
    case.harmonic_balance.time_samples = 16;
    case.stability.enabled = false;
    case
}

/// The blade's stiffness entries acting on the rows of `v`: `K_blade v`.
fn blade_times(blade: &ReducedBlade, v: &Mat<c64>) -> Mat<c64> {
    let mut out = Mat::<c64>::zeros(v.nrows(), v.ncols());
    for &(a, b, k) in &blade.stiffness {
        for c in 0..v.ncols() {
            out[(a, c)] += v[(b, c)] * k;
        }
    }
    out
}

/// `V(s)` of any signed diameter from those of `0..=N/2`.
fn basis(blade: &ReducedBlade, s: usize) -> Mat<c64> {
    let s = s % SECTORS;
    if 2 * s <= SECTORS {
        blade.bases[s].clone()
    } else {
        let v = &blade.bases[SECTORS - s];
        Mat::from_fn(v.nrows(), v.ncols(), |i, j| v[(i, j)].conj())
    }
}

/// The full-wheel perturbation `Σ_j δ_j u_jᵀ K_blade u_j` assembled in
/// the wave domain: `P̂(s, t) = δ̂(s − t) V(s)ᴴ K_blade V(t)` with
/// `δ̂(r) = (1/N) Σ_j δ_j e^{iαrj}`, then `P = Fᴴ P̂ F`, block `(j, l) =
/// (1/N) Σ_{s,t} e^{−iαsj} P̂(s, t) e^{iαtl}` (the sector coordinates
/// `x_j = (1/√N) Σ_s e^{−iαsj} q_s`). Returns `P` and the largest
/// imaginary part met (zero up to round-off).
fn wave_domain_perturbation(blade: &ReducedBlade, deviations: &[f64]) -> (Mat<f64>, f64) {
    let n = SECTORS;
    let alpha = 2.0 * PI / n as f64;
    let size = blade.bases[0].ncols();
    let v: Vec<Mat<c64>> = (0..n).map(|s| basis(blade, s)).collect();
    let kv: Vec<Mat<c64>> = v.iter().map(|v| blade_times(blade, v)).collect();
    let delta_hat: Vec<c64> = (0..n)
        .map(|r| {
            deviations
                .iter()
                .enumerate()
                .map(|(j, d)| c64::cis(alpha * (r * j) as f64) * *d)
                .sum::<c64>()
                / n as f64
        })
        .collect();
    // Q(s, l) = Σ_t P̂(s, t) e^{iαtl}.
    let mut q: Vec<Mat<c64>> = vec![Mat::zeros(size, size); n * n];
    for s in 0..n {
        for t in 0..n {
            let p = v[s].adjoint() * &kv[t];
            let weight = delta_hat[(s + n - t) % n];
            for l in 0..n {
                let phase = c64::cis(alpha * (t * l) as f64) * weight;
                add_scaled(&mut q[s * n + l], &p, phase);
            }
        }
    }
    let mut full = Mat::<f64>::zeros(n * size, n * size);
    let mut imaginary = 0.0_f64;
    for j in 0..n {
        for l in 0..n {
            let mut block = Mat::<c64>::zeros(size, size);
            for s in 0..n {
                add_scaled(&mut block, &q[s * n + l], c64::cis(-alpha * (s * j) as f64));
            }
            for c in 0..size {
                for r in 0..size {
                    let x = block[(r, c)] / n as f64;
                    full[(j * size + r, l * size + c)] = x.re;
                    imaginary = imaginary.max(x.im.abs());
                }
            }
        }
    }
    (full, imaginary)
}

/// `out += a · w`.
fn add_scaled(out: &mut Mat<c64>, a: &Mat<c64>, w: c64) {
    for c in 0..a.ncols() {
        for r in 0..a.nrows() {
            out[(r, c)] += a[(r, c)] * w;
        }
    }
}

fn largest(a: &Mat<f64>) -> f64 {
    (0..a.ncols()).fold(0.0_f64, |m, c| {
        (0..a.nrows()).fold(m, |m, r| m.max(a[(r, c)].abs()))
    })
}

fn largest_difference(a: &Mat<f64>, b: &Mat<f64>) -> f64 {
    (0..a.ncols()).fold(0.0_f64, |m, c| {
        (0..a.nrows()).fold(m, |m, r| m.max((a[(r, c)] - b[(r, c)]).abs()))
    })
}

/// Item 1 of issue 44's tests on the fan: the linear response of the
/// mistuned physical problem (harmonic 1 of the 27 condensed dofs of every
/// sector) against `(K − ω²M + iωC) X = F` solved densely, `K` the tuned
/// wheel plus the wave-domain perturbation, `F_j = (A/2) e^{ihαj}` on the
/// excitation dof (`A cos(ωt + hαj)`).
///
/// Measured: the library's stiffness is the wave-domain one to 2.1e-16 of
/// its largest entry (asserted to 1e-13); the responses agree to 2.2e-10
/// – 3.3e-9 of the largest contact amplitude (asserted to 1e-8). The 1e-10
/// of the academic test is out of reach here, and not for the mistuning:
/// in the reduced coordinates (stiff retained dofs beside modal ones) `Z`
/// has condition numbers 9.4e7 (270 Hz) to 1.6e9 (281 Hz), and two dense
/// solves whose `K` differ by those 2e-16 already differ by 3e-11 – 9e-10.
#[test]
fn the_fans_linear_mistuned_response_is_the_dense_solve_of_its_assembled_wheel() {
    let started = std::time::Instant::now();
    let dir = folder("dense", None);
    let mut case = case(&dir);
    case.mistuning.deviations = DEVIATIONS.to_vec();
    let prepared = prepare(&case, &dir, BasisChoice::Physical).unwrap();
    let (mut problem, model) = (prepared.problem, prepared.model);
    let (_, blade) = case
        .model
        .build_with_blade(&dir, "blade", "mistuning.blade_node_set")
        .unwrap();
    let _ = std::fs::remove_dir_all(&dir);
    let tuned = model.tuned().full_wheel().unwrap();
    let (perturbation, imaginary) = wave_domain_perturbation(&blade, &DEVIATIONS);
    let scale = largest(&tuned.stiffness);
    assert!(imaginary < 1e-12 * scale, "{imaginary:e}");
    let mut stiffness = tuned.stiffness.clone();
    stiffness += &perturbation;
    let library = model.full_wheel().unwrap();
    let assembly = largest_difference(&library.stiffness, &stiffness) / scale;
    assert!(
        assembly < 1e-13,
        "the assembled stiffness differs by {assembly:e}"
    );

    let dofs = model.dofs_per_sector();
    let size = SECTORS * dofs;
    let h = case.excitation.engine_order as f64;
    let alpha = 2.0 * PI / SECTORS as f64;
    let mut load = Mat::<c64>::zeros(size, 1);
    for j in 0..SECTORS {
        for &d in &case.excitation.dofs {
            load[(j * dofs + d - 1, 0)] =
                c64::cis(h * alpha * j as f64) * (case.excitation.amplitude / 2.0);
        }
    }
    // The condensed dofs: every dof of the 9 contact nodes (the reduced
    // sector's first 27), contact.dofs (their radial ones) first.
    let coordinates = 3; // a0, Re 1, Im 1
    let mut contact = case.contact_dofs();
    contact.extend((0..27).filter(|d| !case.contact_dofs().contains(d)));
    assert_eq!(
        problem.layout().unknowns,
        SECTORS * contact.len() * coordinates
    );
    let mut worst = 0.0_f64;
    for f in [270.0, 278.0, 281.0, 283.0, 290.0] {
        let omega = 2.0 * PI * f;
        let z = Mat::from_fn(size, size, |r, c| {
            c64::new(
                stiffness[(r, c)] - omega * omega * tuned.mass[(r, c)],
                omega * tuned.damping[(r, c)],
            )
        });
        let expected = z.partial_piv_lu().solve(&load);
        let solved = problem.linear_solution(omega).unwrap();
        let mut scale = 0.0_f64;
        let mut error = 0.0_f64;
        for j in 0..SECTORS {
            for (c, &d) in contact.iter().enumerate() {
                let entry = (j * contact.len() + c) * coordinates;
                let x = c64::new(solved[entry + 1], solved[entry + 2]);
                let e = expected[(j * dofs + d, 0)];
                scale = scale.max(e.norm());
                error = error.max((x - e).norm());
            }
        }
        worst = worst.max(error / scale);
        assert!(error < 1e-8 * scale, "{f} Hz: {:e}", error / scale);
    }
    eprintln!(
        "fan, dense: assembly {assembly:.2e}, response {worst:.2e}, imaginary {:.2e}, {:.1?}",
        imaginary / scale,
        started.elapsed()
    );
}

/// The natural frequencies (Hz) of the first family, nodal diameters
/// `0..=N/2`.
fn first_family(model: &SectorModel) -> Vec<f64> {
    model
        .natural_frequencies()
        .unwrap()
        .into_iter()
        .map(|(_, f)| f[0])
        .collect()
}

/// δ the same on every sector: the mistuned full wheel is the tuned wheel
/// whose per-diameter stiffness holds the scaled blade, `K_r(s) + δ V(s)ᴴ
/// K_blade V(s)` (assembled here per diameter, through no mistuning code),
/// to round-off. And what the projection on the tuned bases approximates:
/// the sector whose blade entries are scaled before the reduction (its
/// own Craig–Bampton bases).
#[test]
fn a_cyclic_fan_mistuning_is_the_tuned_wheel_with_the_scaled_blade() {
    let started = std::time::Instant::now();
    let delta = 0.05;
    let dir = folder("cyclic", None);
    let mut case = case(&dir);
    let tuned = case.model.build(&dir).unwrap();
    case.mistuning.deviations = vec![delta; SECTORS];
    let mistuned = case.mistuned(tuned.clone(), &dir).unwrap();
    let (_, blade) = case
        .model
        .build_with_blade(&dir, "blade", "mistuning.blade_node_set")
        .unwrap();
    let _ = std::fs::remove_dir_all(&dir);
    let (mut masses, mut stiffnesses) = (Vec::new(), Vec::new());
    for s in 0..=SECTORS / 2 {
        let m = tuned.nodal_diameter_matrices(s as i64).unwrap();
        let v = &blade.bases[s];
        let projected = v.adjoint() * blade_times(&blade, v);
        let mut k = m.stiffness.clone();
        add_scaled(&mut k, &projected, c64::new(delta, 0.0));
        masses.push(m.mass);
        stiffnesses.push(k);
    }
    let scaled =
        SectorModel::per_nodal_diameter(SECTORS, masses, stiffnesses, Damping::None).unwrap();
    let expected = scaled.full_wheel().unwrap().stiffness;
    let library = mistuned.full_wheel().unwrap().stiffness;
    let difference = largest_difference(&library, &expected) / largest(&expected);
    assert!(difference < 1e-12, "{difference:e}");

    // The blade scaled before the reduction.
    let scaled_dir = folder("scaled", Some(1.0 + delta));
    let reduced_again = Case::from_file_checked(&scaled_dir.join("fan16.toml"))
        .unwrap()
        .model
        .build(&scaled_dir)
        .unwrap();
    let _ = std::fs::remove_dir_all(&scaled_dir);
    let (tuned_family, projected, exact) = (
        first_family(&tuned),
        first_family(&scaled),
        first_family(&reduced_again),
    );
    let projection = projected
        .iter()
        .zip(&exact)
        .fold(0.0_f64, |m, (p, e)| m.max((p - e).abs() / e));
    assert!(projection < 1e-4, "projection error {projection:e}");
    // What scaling the entries between blade nodes approximates: the blade
    // material's modulus scaled (every blade element, the root layer's
    // coupling to the disk included), whose first family (blade-dominated
    // on every diameter here: 281.7 to 281.9 Hz) rises by nearly √(1 + δ).
    let material = {
        let dir = std::env::temp_dir().join(format!(
            "cyclorub-mistuned-fan-material-{}",
            std::process::id()
        ));
        let _ = std::fs::remove_dir_all(&dir);
        let mut geometry = FanGeometry::default();
        geometry.blade.young *= 1.0 + delta;
        let mesh = fan(SECTORS, 1, &geometry).unwrap();
        write_fan(&mesh, &assemble(&mesh.mesh).unwrap(), &dir, false).unwrap();
        let model = Case::from_file_checked(&dir.join("fan16.toml"))
            .unwrap()
            .model
            .build(&dir)
            .unwrap();
        let _ = std::fs::remove_dir_all(&dir);
        first_family(&model)
    };
    let ratio = |family: &[f64]| -> Vec<f64> {
        family
            .iter()
            .zip(&tuned_family)
            .map(|(f, t)| f / t)
            .collect()
    };
    let (entries, modulus) = (ratio(&exact), ratio(&material));
    let root = (1.0 + delta).sqrt();
    for (d, (e, m)) in entries.iter().zip(&modulus).enumerate() {
        assert!(
            (e - root).abs() < 0.05 * delta,
            "ND {d}: {e} against √(1+δ) = {root}"
        );
        assert!(
            (e - m).abs() < 0.004,
            "ND {d}: {e} against the modulus' {m}"
        );
    }
    eprintln!(
        "fan, cyclic: stiffness {difference:.2e}, projection {projection:.2e}, first family \
         ×{:.5}–{:.5} (blade entries), ×{:.5}–{:.5} (blade modulus), √(1+δ) = {root:.5}, {:.1?}",
        entries.iter().cloned().fold(f64::INFINITY, f64::min),
        entries.iter().cloned().fold(0.0, f64::max),
        modulus.iter().cloned().fold(f64::INFINITY, f64::min),
        modulus.iter().cloned().fold(0.0, f64::max),
        started.elapsed()
    );
}

/// δ = 0 on every sector: the tuned wheel, bit for bit (its full wheel and
/// its linear response on the physical basis).
#[test]
fn zero_deviations_on_the_fan_give_the_tuned_wheel_bit_for_bit() {
    let dir = folder("zero", None);
    let tuned_case = case(&dir);
    let mut zero_case = tuned_case.clone();
    zero_case.mistuning.deviations = vec![0.0; SECTORS];
    let tuned = prepare(&tuned_case, &dir, BasisChoice::Physical).unwrap();
    let zero = prepare(&zero_case, &dir, BasisChoice::Physical).unwrap();
    let _ = std::fs::remove_dir_all(&dir);
    assert!(zero.model.is_mistuned() && !tuned.model.is_mistuned());
    let (a, b) = (
        tuned.model.full_wheel().unwrap(),
        zero.model.full_wheel().unwrap(),
    );
    for (x, y) in [
        (&a.mass, &b.mass),
        (&a.stiffness, &b.stiffness),
        (&a.damping, &b.damping),
    ] {
        assert_eq!(largest_difference(x, y), 0.0);
    }
    let (mut p, mut q) = (tuned.problem, zero.problem);
    for f in [275.0, 282.0] {
        let omega = 2.0 * PI * f;
        assert_eq!(
            p.linear_solution(omega).unwrap(),
            q.linear_solution(omega).unwrap()
        );
    }
}

/// A missing blade node set, blade dofs on a finite-element sector and a
/// blade node set on the academic model are refused, naming the key, the
/// value and what is allowed.
#[test]
fn a_missing_blade_node_set_is_refused_naming_the_key() {
    let dir = folder("refusals", None);
    let sets = dir.join("node_sets.toml");
    let text = std::fs::read_to_string(&sets).unwrap();
    let without: String = text[..text.find("# Every blade node").unwrap()].to_string();
    std::fs::write(&sets, without).unwrap();
    let mut case = case(&dir);
    case.mistuning.standard_deviation = Some(0.01);
    let any = Case::default().model.build(Path::new(".")).unwrap();
    let message = case.mistuned(any.clone(), &dir).unwrap_err().to_string();
    for part in [
        "mistuning.blade_node_set = \"blade\"",
        "no list named \"blade\"",
        "contact",
    ] {
        assert!(message.contains(part), "{message}");
    }
    case.mistuning.blade_node_set = Some("vane".into());
    std::fs::write(&sets, format!("{text}\nroot = [1]\n")).unwrap();
    let message = case.mistuned(any.clone(), &dir).unwrap_err().to_string();
    for part in ["mistuning.blade_node_set = \"vane\"", "blade, root"] {
        assert!(message.contains(part), "{message}");
    }
    case.mistuning.blade_node_set = None;
    case.mistuning.blade_dofs = Some(vec![1, 2]);
    let message = case.mistuned(any.clone(), &dir).unwrap_err().to_string();
    assert!(
        message.starts_with("mistuning.blade_dofs = [1, 2]") && message.contains("blade_node_set"),
        "{message}"
    );
    let _ = std::fs::remove_dir_all(&dir);
    let mut academic = Case::default();
    academic.mistuning.standard_deviation = Some(0.01);
    academic.mistuning.blade_node_set = Some("blade".into());
    let message = academic
        .mistuned(any, Path::new("."))
        .unwrap_err()
        .to_string();
    assert!(
        message.starts_with("mistuning.blade_node_set = \"blade\"")
            && message.contains("finite_element"),
        "{message}"
    );
}

/// A mistuned fan run (`cyclorub run`'s path, the case in its own folder):
/// its record's tuned reference is solved from the case's folder, and the
/// amplification factor follows (away from the casing: the linear
/// response, measured 1.0083 at 282 Hz). One frequency: with two, the run's linear
/// response (results.h5) is solved densely on the full wheel at 300 more
/// (60 s here, against 7 s).
#[test]
fn a_mistuned_fan_run_solves_its_tuned_reference_from_the_case_folder() {
    use cyclorub::run::{run, RunOptions};
    let started = std::time::Instant::now();
    let dir = folder("run", None);
    let mut case = case(&dir);
    case.mistuning.deviations = DEVIATIONS.to_vec();
    // Away from the casing: the point is the linear response.
    case.casing.gap = cyclorub::case::PerContactDof::One(1.0);
    let output = dir.join("results");
    let options = RunOptions {
        output: output.clone(),
        basis: BasisChoice::Physical,
        at_hz: Some(vec![282.0]),
        stability: None,
        overwrite: true,
        interrupt: Default::default(),
    };
    let record = run(&case, &dir, &options, |_| {}).unwrap();
    let _ = std::fs::remove_dir_all(&dir);
    let m = record.mistuning.expect("a mistuned run has a record");
    assert!(m.tuned_peak_m.is_some(), "{}", m.tuned_reference);
    let factor = m.amplification_factor.unwrap();
    assert!(factor.is_finite() && factor > 0.0, "{factor}");
    eprintln!(
        "fan run: amplification factor {factor:.4} (sector {}), {:.1?}",
        m.most_responding_sector,
        started.elapsed()
    );
}
