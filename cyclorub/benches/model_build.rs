//! Benchmark: a finite-element sector of a few hundred dofs builds all its
//! per-diameter matrices (with modal damping, one Hermitian eigenproblem per
//! diameter). Run with `cargo bench -p cyclorub --bench model_build`.

use cyclorub::model::{Damping, FiniteElementSector, ModalDamping, SectorModel};
use faer::Mat;
use std::time::{Duration, Instant};

/// A banded symmetric positive definite matrix standing for an FE sector.
fn banded(n: usize, bandwidth: usize, diagonal: f64, seed: u64) -> Mat<f64> {
    let mut state = seed;
    let mut next = move || {
        state = state
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (state >> 11) as f64 / (1u64 << 53) as f64 - 0.5
    };
    let mut a = Mat::<f64>::zeros(n, n);
    for i in 0..n {
        for j in i.saturating_sub(bandwidth)..i {
            let v = next();
            a[(i, j)] = v;
            a[(j, i)] = v;
        }
    }
    for i in 0..n {
        a[(i, i)] = diagonal * (1.0 + 0.1 * next().abs()) + 2.0 * bandwidth as f64;
    }
    a
}

fn time<T>(f: impl Fn() -> T) -> (Duration, T) {
    let mut best = Duration::MAX;
    let mut result = None;
    for _ in 0..5 {
        let start = Instant::now();
        let r = f();
        best = best.min(start.elapsed());
        result = Some(r);
    }
    (best, result.expect("ran"))
}

fn main() {
    let sectors = 24;
    for size in [100usize, 300] {
        let boundary = 20;
        let sector = FiniteElementSector {
            mass: banded(size, 6, 1.0, 1),
            stiffness: banded(size, 6, 1e3, 2),
            left_boundary: (0..boundary).collect(),
            right_boundary: (size - boundary..size).collect(),
            boundary_frame: Default::default(),
        };
        let damping = Damping::Modal(ModalDamping {
            ratios: vec![1e-3; 5],
            others: 5e-3,
        });
        let (build, model) = time(|| {
            SectorModel::finite_element(sectors, sector.clone(), damping.clone()).expect("model")
        });
        let half = sectors as i64 / 2;
        // A fresh model each time: modal damping is cached once computed.
        let (all, count) = time(|| {
            let model = SectorModel::finite_element(sectors, sector.clone(), damping.clone())
                .expect("model");
            (-half + 1..=half)
                .map(|s| model.nodal_diameter_matrices(s).expect("matrices"))
                .collect::<Vec<_>>()
                .len()
        });
        let (distinct, _) = time(|| {
            let model = SectorModel::finite_element(sectors, sector.clone(), damping.clone())
                .expect("model");
            let diameters: Vec<i64> = (-half + 1..=half).collect();
            model
                .nodal_diameter_matrices_for(&diameters)
                .expect("matrices")
                .len()
        });
        let (cached, _) = time(|| {
            (-half + 1..=half)
                .map(|s| model.nodal_diameter_matrices(s).expect("matrices"))
                .collect::<Vec<_>>()
                .len()
        });
        let (frequencies, _) = time(|| model.natural_frequencies().expect("frequencies"));
        println!(
            "FE sector {size} dofs ({} independent), N = {sectors}, modal damping: build {:.1} ms; \
             build + all {count} signed diameters {:.1} ms (sequential), {:.1} ms (parallel); \
             again once cached {:.1} ms; natural frequencies {:.1} ms",
            model.dofs_per_sector(),
            build.as_secs_f64() * 1e3,
            all.as_secs_f64() * 1e3,
            distinct.as_secs_f64() * 1e3,
            cached.as_secs_f64() * 1e3,
            frequencies.as_secs_f64() * 1e3,
        );
    }
}
