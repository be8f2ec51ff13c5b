//! A finite-element sector whose cyclic boundary dofs are Cartesian
//! (`u_R = e^{−iαs} R(α) u_L`): its per-diameter frequencies against the
//! full wheel assembled independently, node by node in global coordinates.
//!
//! The structure is a 3D truss (springs along the bars, lumped masses,
//! springs to the ground along given directions): each sector's nodes are
//! the first sector's turned by `jα` about the axis, the right boundary
//! nodes of sector `j` being the left ones of sector `j + 1`. The full
//! wheel never uses `R(α)` on dofs: each bar's direction comes from the
//! global positions of its ends.

use crate::support;

use cyclorub::model::{Axis, BoundaryFrame, Damping, FiniteElementSector, ModelSpec, SectorModel};
use faer::Mat;
use std::f64::consts::PI;
use support::frequencies_hz;

/// A node of the first sector: position (m), lumped mass (kg).
struct Node {
    at: [f64; 3],
    mass: f64,
}

/// A bar between two nodes (indices into the sector's node list, the
/// right boundary nodes after the others), or to the ground along a
/// direction (`to: None`).
struct Bar {
    from: usize,
    to: Option<usize>,
    direction: [f64; 3],
    stiffness: f64,
}

/// The sector: nodes 0, 1 on the left boundary, 2, 3 inside, 4, 5 on the
/// right boundary (nodes 0, 1 turned by α); the boundary masses are split
/// half on each side.
struct Truss {
    sectors: usize,
    axis: Axis,
    nodes: Vec<Node>,
    bars: Vec<Bar>,
}

fn rotate(r: &[[f64; 3]; 3], v: [f64; 3]) -> [f64; 3] {
    [0, 1, 2].map(|i| (0..3).map(|j| r[i][j] * v[j]).sum())
}

fn unit(v: [f64; 3]) -> [f64; 3] {
    let n = v.iter().map(|x| x * x).sum::<f64>().sqrt();
    v.map(|x| x / n)
}

/// In the frame where `axis` is the third coordinate, a point at radius
/// `r`, angle `theta` and height `h`.
fn point(axis: Axis, r: f64, theta: f64, h: f64) -> [f64; 3] {
    let (x, y, z) = (r * theta.cos(), r * theta.sin(), h);
    match axis {
        Axis::Z => [x, y, z],
        Axis::X => [z, x, y],
        Axis::Y => [y, z, x],
    }
}

impl Truss {
    fn new(sectors: usize, axis: Axis) -> Self {
        let alpha = 2.0 * PI / sectors as f64;
        let at = |r, t, h| point(axis, r, t, h);
        let left = [at(0.30, 0.0, 0.00), at(0.45, 0.0, 0.02)];
        let r = axis.rotation(alpha);
        let nodes = vec![
            Node {
                at: left[0],
                mass: 1.5,
            },
            Node {
                at: left[1],
                mass: 0.7,
            },
            Node {
                at: at(0.35, 0.4 * alpha, 0.03),
                mass: 2.0,
            },
            Node {
                at: at(0.52, 0.6 * alpha, -0.01),
                mass: 0.9,
            },
            Node {
                at: rotate(&r, left[0]),
                mass: 1.5,
            },
            Node {
                at: rotate(&r, left[1]),
                mass: 0.7,
            },
        ];
        let bar = |from, to, stiffness| Bar {
            from,
            to: Some(to),
            direction: [0.0; 3],
            stiffness,
        };
        let ground = |from, direction, stiffness| Bar {
            from,
            to: None,
            direction: unit(direction),
            stiffness,
        };
        let bars = vec![
            bar(0, 1, 3.0e6),
            bar(0, 2, 2.0e6),
            bar(1, 3, 1.5e6),
            bar(2, 3, 2.5e6),
            bar(1, 2, 0.8e6),
            bar(2, 4, 2.2e6),
            bar(3, 5, 1.1e6),
            bar(3, 4, 0.6e6),
            // Held to the ground in three independent directions at node
            // 0 and in two at node 2, so that no mode is rigid.
            ground(0, at(1.0, 0.0, 0.0), 4.0e6),
            ground(0, at(0.0, 0.0, 1.0), 3.0e6),
            ground(0, at(1.0, PI / 2.0, 0.3), 2.0e6),
            ground(2, at(1.0, 0.4 * alpha + 0.5, 0.2), 1.0e6),
            ground(2, at(0.2, 0.4 * alpha, 1.0), 1.7e6),
        ];
        Self {
            sectors,
            axis,
            nodes,
            bars,
        }
    }

    /// The 3 × 3 stiffness block `k n nᵀ` of a bar along `n`.
    fn block(n: [f64; 3], k: f64) -> [[f64; 3]; 3] {
        [0, 1, 2].map(|i| [0, 1, 2].map(|j| k * n[i] * n[j]))
    }

    /// Adds a bar between global dofs `3a..3a+3` and `3b..3b+3` (`b`
    /// `None`: the ground) along `n`.
    fn add(k: &mut Mat<f64>, a: usize, b: Option<usize>, n: [f64; 3], stiffness: f64) {
        let block = Self::block(n, stiffness);
        for i in 0..3 {
            for j in 0..3 {
                let v = block[i][j];
                k[(3 * a + i, 3 * a + j)] += v;
                if let Some(b) = b {
                    k[(3 * b + i, 3 * b + j)] += v;
                    k[(3 * a + i, 3 * b + j)] -= v;
                    k[(3 * b + i, 3 * a + j)] -= v;
                }
            }
        }
    }

    /// The sector's mass and stiffness on its six nodes (18 dofs) in the
    /// first sector's frame.
    fn sector(&self) -> FiniteElementSector {
        let size = 3 * self.nodes.len();
        let mut k = Mat::<f64>::zeros(size, size);
        for bar in &self.bars {
            let n = match bar.to {
                Some(to) => {
                    let (a, b) = (self.nodes[bar.from].at, self.nodes[to].at);
                    unit([b[0] - a[0], b[1] - a[1], b[2] - a[2]])
                }
                None => bar.direction,
            };
            Self::add(&mut k, bar.from, bar.to, n, bar.stiffness);
        }
        let mass = Mat::from_fn(size, size, |i, j| {
            let node = &self.nodes[i / 3];
            let boundary = i / 3 != 2 && i / 3 != 3;
            match (i == j, boundary) {
                (false, _) => 0.0,
                (true, true) => 0.5 * node.mass,
                (true, false) => node.mass,
            }
        });
        FiniteElementSector {
            mass,
            stiffness: k,
            left_boundary: (0..6).collect(),
            right_boundary: (12..18).collect(),
            boundary_frame: BoundaryFrame::Cartesian { axis: self.axis },
        }
    }

    /// The full wheel in global coordinates: four nodes per sector
    /// (sector `j`'s nodes 4, 5 are sector `j + 1`'s nodes 0, 1).
    fn full_wheel(&self) -> (Mat<f64>, Mat<f64>) {
        let n = self.sectors;
        let size = 12 * n;
        let alpha = 2.0 * PI / n as f64;
        let mut k = Mat::<f64>::zeros(size, size);
        let mut m = Mat::<f64>::zeros(size, size);
        let global = |j: usize, node: usize| match node {
            0..=3 => 4 * j + node,
            _ => 4 * ((j + 1) % n) + node - 4,
        };
        for j in 0..n {
            let r = self.axis.rotation(j as f64 * alpha);
            let at = |node: usize| rotate(&r, self.nodes[node].at);
            for bar in &self.bars {
                let direction = match bar.to {
                    Some(to) => {
                        let (a, b) = (at(bar.from), at(to));
                        unit([b[0] - a[0], b[1] - a[1], b[2] - a[2]])
                    }
                    None => rotate(&r, bar.direction),
                };
                Self::add(
                    &mut k,
                    global(j, bar.from),
                    bar.to.map(|to| global(j, to)),
                    direction,
                    bar.stiffness,
                );
            }
            for node in 0..4 {
                for d in 0..3 {
                    let i = 3 * global(j, node) + d;
                    m[(i, i)] = self.nodes[node].mass;
                }
            }
        }
        (k, m)
    }
}

/// Every frequency of the wheel from the diameters (0 < d < N/2 counted
/// twice), sorted.
fn union(model: &SectorModel) -> Vec<f64> {
    let sectors = model.sectors();
    let mut all = Vec::new();
    for (d, freqs) in model.natural_frequencies().expect("frequencies") {
        let twice = d != 0 && 2 * d != sectors;
        for f in freqs {
            all.push(f);
            if twice {
                all.push(f);
            }
        }
    }
    all.sort_by(f64::total_cmp);
    all
}

fn largest_relative_difference(a: &[f64], b: &[f64]) -> f64 {
    assert_eq!(a.len(), b.len());
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y).abs() / y.abs())
        .fold(0.0, f64::max)
}

#[test]
fn cartesian_boundaries_give_the_frequencies_of_the_wheel_assembled_in_global_coordinates() {
    for (sectors, axis) in [(5, Axis::Z), (6, Axis::Z), (7, Axis::X), (4, Axis::Y)] {
        let truss = Truss::new(sectors, axis);
        let model = SectorModel::finite_element(sectors, truss.sector(), Damping::None)
            .expect("a Cartesian FE sector");
        assert_eq!(model.dofs_per_sector(), 12);
        let (k, m) = truss.full_wheel();
        let reference = frequencies_hz(&k, &m);
        let cyclic = union(&model);
        let difference = largest_relative_difference(&cyclic, &reference);
        assert!(
            difference <= 1e-10,
            "N = {sectors}, axis {axis:?}: largest relative difference {difference:e}"
        );
        // The rotation matters: the same dofs taken as turning with the
        // sector give another wheel.
        let mut plain = truss.sector();
        plain.boundary_frame = BoundaryFrame::Cylindrical;
        let wrong = SectorModel::finite_element(sectors, plain, Damping::None).expect("model");
        assert!(largest_relative_difference(&union(&wrong), &reference) > 1e-3);
    }
}

#[test]
fn the_case_file_keys_build_the_same_model_and_refuse_what_does_not_fit() {
    let truss = Truss::new(6, Axis::Z);
    let sector = truss.sector();
    let rows = |a: &Mat<f64>| -> String {
        let lines: Vec<String> = (0..a.nrows())
            .map(|i| {
                let row: Vec<String> = (0..a.ncols()).map(|j| format!("{:e}", a[(i, j)])).collect();
                format!("[{}]", row.join(", "))
            })
            .collect();
        format!("[{}]", lines.join(",\n"))
    };
    let text = |frame: &str| {
        format!(
            "[model]\nkind = \"matrices\"\nsectors = 6\nmass = {}\nstiffness = {}\n\
             left_boundary = [1, 2, 3, 4, 5, 6]\nright_boundary = [13, 14, 15, 16, 17, 18]\n{frame}\n\
             [model.damping]\nkind = \"none\"\n",
            rows(&sector.mass),
            rows(&sector.stiffness)
        )
    };
    let build = |frame: &str| {
        ModelSpec::from_case_toml(&text(frame))
            .expect("a model table")
            .build(std::path::Path::new("."))
    };
    let from_case = build("boundary_frame = \"cartesian\"\naxis = \"z\"").expect("model");
    let direct = SectorModel::finite_element(6, sector.clone(), Damping::None).expect("model");
    assert_eq!(union(&from_case), union(&direct));
    // An axis without Cartesian dofs, and boundaries that are not node
    // triples, are refused naming the key.
    let error = build("axis = \"x\"").expect_err("axis alone").to_string();
    assert!(error.contains("model.axis"), "{error}");
    let odd = text("boundary_frame = \"cartesian\"")
        .replace("[1, 2, 3, 4, 5, 6]", "[1, 2, 3, 4]")
        .replace("[13, 14, 15, 16, 17, 18]", "[13, 14, 15, 16]");
    let error = ModelSpec::from_case_toml(&odd)
        .expect("a model table")
        .build(std::path::Path::new("."))
        .expect_err("not triples")
        .to_string();
    assert!(
        error.contains("model.left_boundary") && error.contains("multiple of 3"),
        "{error}"
    );
}
