//! The fan sector against its geometry: rigid-body modes of the free sector,
//! its mass against independently computed volumes, cyclic conformity and
//! node sets.

use super::super::{assemble, fan, shape_functions, FanGeometry, FanMesh, Mesh, GAUSS3};
use super::dense;
use faer::Side;

fn coarse() -> FanMesh {
    fan(16, 1, &FanGeometry::default()).unwrap()
}

/// The six rigid motions at the nodes: translations x, y, z and rotations
/// about x, y, z (`ω × x`).
fn rigid_motions(mesh: &Mesh) -> Vec<Vec<f64>> {
    let mut out = Vec::new();
    for d in 0..3 {
        out.push(
            (0..3 * mesh.nodes.len())
                .map(|i| if i % 3 == d { 1.0 } else { 0.0 })
                .collect(),
        );
    }
    for axis in 0..3 {
        let mut w = [0.0; 3];
        w[axis] = 1.0;
        out.push(
            mesh.nodes
                .iter()
                .flat_map(|x| {
                    [
                        w[1] * x[2] - w[2] * x[1],
                        w[2] * x[0] - w[0] * x[2],
                        w[0] * x[1] - w[1] * x[0],
                    ]
                })
                .collect(),
        );
    }
    out
}

#[test]
fn the_free_coarse_sector_has_exactly_six_rigid_body_modes() {
    let fan = coarse();
    let k = assemble(&fan.mesh).unwrap().stiffness;
    let k_max = k.values.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    for (which, r) in rigid_motions(&fan.mesh).iter().enumerate() {
        let kr = k.multiply(r);
        let r_max = r.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        let worst = kr.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        assert!(
            worst <= 1e-11 * k_max * r_max,
            "rigid motion {which}: |K r| = {worst:e}"
        );
    }
    let mut values = dense(&k).self_adjoint_eigenvalues(Side::Lower).unwrap();
    values.sort_by(|a, b| a.abs().total_cmp(&b.abs()));
    let largest = values.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    println!(
        "|λ|/λmax: {:?}",
        values[..8].iter().map(|v| v / largest).collect::<Vec<_>>()
    );
    for (i, v) in values[..6].iter().enumerate() {
        assert!(v.abs() < 1e-10 * largest, "eigenvalue {i}: {v:e}");
    }
    assert!(values[6] > 1e-8 * largest, "seventh: {:e}", values[6]);
}

/// The disk's area in the (r, θ) plane for element boundaries `angles`:
/// each circumferential division is bounded by straight radial edges and by
/// the parabolic arcs the quadratic element puts through the arc's ends and
/// mid-point (a triangle plus a parabolic segment of 2/3 chord × height).
fn disk_area(fan: &FanMesh) -> f64 {
    let g = &fan.geometry;
    fan.disk_angles
        .windows(2)
        .map(|w| {
            let d = w[1] - w[0];
            let unit = 0.5 * d.sin() + 4.0 / 3.0 * (0.5 * d).sin() * (1.0 - (0.5 * d).cos());
            unit * (g.rim_radius.powi(2) - g.bore_radius.powi(2))
        })
        .sum()
}

/// The volume of the blade's discrete shape by the divergence theorem over
/// its block's outer faces, `V = ⅓ ∮ x·n dA` (3×3 Gauss points are exact on
/// the quadratic faces), independent of the element volume integrals.
fn blade_volume_by_its_surface(fan: &FanMesh) -> f64 {
    let [ns, nt, nc] = fan.blade_divisions;
    let first = fan.disk_elements();
    let mut volume = 0.0;
    for (e, element) in fan.mesh.elements[first..].iter().enumerate() {
        let idx = [e / (nt * nc), (e / nc) % nt, e % nc];
        let coords = element.nodes.map(|n| fan.mesh.nodes[n]);
        for axis in 0..3 {
            let last = [ns, nt, nc][axis] - 1;
            for (side, sign) in [(0usize, -1.0f64), (last, 1.0)] {
                if idx[axis] != side {
                    continue;
                }
                let (u, v) = ((axis + 1) % 3, (axis + 2) % 3);
                for &(a, wa) in &GAUSS3 {
                    for &(b, wb) in &GAUSS3 {
                        let mut p = [0.0; 3];
                        p[axis] = sign;
                        p[u] = a;
                        p[v] = b;
                        let (n, dn) = shape_functions(p);
                        let (mut x, mut xu, mut xv) = ([0.0; 3], [0.0; 3], [0.0; 3]);
                        for k in 0..20 {
                            for d in 0..3 {
                                x[d] += n[k] * coords[k][d];
                                xu[d] += dn[k][u] * coords[k][d];
                                xv[d] += dn[k][v] * coords[k][d];
                            }
                        }
                        let normal = [
                            xu[1] * xv[2] - xu[2] * xv[1],
                            xu[2] * xv[0] - xu[0] * xv[2],
                            xu[0] * xv[1] - xu[1] * xv[0],
                        ];
                        let flux: f64 = (0..3).map(|d| x[d] * normal[d]).sum();
                        volume += sign * wa * wb * flux / 3.0;
                    }
                }
            }
        }
    }
    volume
}

fn mass_of(fan: &FanMesh, material: usize) -> f64 {
    let mesh = Mesh {
        elements: fan
            .mesh
            .elements
            .iter()
            .filter(|e| e.material == material)
            .cloned()
            .collect(),
        ..fan.mesh.clone()
    };
    let m = assemble(&mesh).unwrap().mass;
    let ones: Vec<f64> = (0..m.size)
        .map(|i| if i % 3 == 0 { 1.0 } else { 0.0 })
        .collect();
    m.bilinear(&ones, &ones)
}

#[test]
fn the_sector_mass_is_density_times_the_independently_computed_volume() {
    for refine in [1, 2] {
        let fan = fan(16, refine, &FanGeometry::default()).unwrap();
        let g = &fan.geometry;
        let m = assemble(&fan.mesh).unwrap().mass;
        let disk_volume = g.chord * disk_area(&fan);
        let blade_volume = blade_volume_by_its_surface(&fan);
        let expected = g.disk.density * disk_volume + g.blade.density * blade_volume;
        for d in 0..3 {
            let u: Vec<f64> = (0..m.size)
                .map(|i| if i % 3 == d { 1.0 } else { 0.0 })
                .collect();
            let total = m.bilinear(&u, &u);
            assert!(
                (total - expected).abs() <= 1e-10 * expected,
                "refine {refine}, direction {d}: {total} kg against {expected} kg"
            );
        }
        let disk = mass_of(&fan, 0);
        let blade = mass_of(&fan, 1);
        assert!((disk - g.disk.density * disk_volume).abs() <= 1e-10 * disk);
        assert!((blade - g.blade.density * blade_volume).abs() <= 1e-10 * blade);
        // The discrete shapes against the exact ones: the annular sector
        // (arcs approximated by parabolas) and span × chord × thickness
        // (the twisted, wrapped blade interpolated quadratically).
        let annulus = g.chord
            * (std::f64::consts::PI / fan.sectors as f64)
            * (g.rim_radius.powi(2) - g.bore_radius.powi(2));
        let plate = g.span() * g.chord * g.thickness;
        println!(
            "refine {refine}: disk {disk} kg, blade {blade} kg; volume errors: disk {:e}, blade {:e}",
            disk_volume / annulus - 1.0,
            blade_volume / plate - 1.0
        );
        assert!((disk_volume / annulus - 1.0).abs() < 1e-6);
        assert!((blade_volume / plate - 1.0).abs() < 1e-4);
    }
}

#[test]
fn every_right_boundary_node_is_its_left_twin_rotated_by_the_sector_angle() {
    for sectors in [3, 16, 23] {
        let fan = fan(sectors, 1, &FanGeometry::default()).unwrap();
        let s = &fan.sets;
        assert_eq!(s.left_boundary.len(), s.right_boundary.len());
        assert!(!s.left_boundary.is_empty());
        let alpha = 2.0 * std::f64::consts::PI / sectors as f64;
        let (sa, ca) = alpha.sin_cos();
        for (&l, &r) in s.left_boundary.iter().zip(&s.right_boundary) {
            let [x, y, z] = fan.mesh.nodes[l];
            let rotated = [ca * x - sa * y, sa * x + ca * y, z];
            let right = fan.mesh.nodes[r];
            let gap = (0..3)
                .map(|d| (rotated[d] - right[d]).abs())
                .fold(0.0, f64::max);
            assert!(
                gap <= 1e-12,
                "N = {sectors}: nodes {l} and {r} differ by {gap:e} m"
            );
        }
        // No node lies on a cyclic face other than the boundary nodes.
        let half = std::f64::consts::PI / sectors as f64;
        let on_faces = fan
            .mesh
            .nodes
            .iter()
            .filter(|p| (p[1].atan2(p[0]).abs() - half).abs() < 1e-9)
            .count();
        assert_eq!(on_faces, 2 * s.left_boundary.len());
    }
}

#[test]
fn the_node_sets_are_where_the_geometry_says() {
    let fan = coarse();
    let g = &fan.geometry;
    let s = &fan.sets;
    let nodes = &fan.mesh.nodes;
    let radius = |n: usize| nodes[n][0].hypot(nodes[n][1]);
    let all: Vec<usize> = s
        .clamped
        .iter()
        .chain(&s.left_boundary)
        .chain(&s.right_boundary)
        .chain(&s.contact)
        .chain([&s.excitation, &s.observation])
        .copied()
        .collect();
    assert!(all.iter().all(|&n| n < nodes.len()));
    assert!(s
        .clamped
        .iter()
        .all(|&n| (radius(n) - g.bore_radius).abs() < 1e-12));
    let bore_nodes = nodes
        .iter()
        .filter(|p| (p[0].hypot(p[1]) - g.bore_radius).abs() < 1e-9)
        .count();
    assert_eq!(bore_nodes, s.clamped.len());
    // Nine distinct contact nodes at the tip radius, evenly spaced (a helix
    // on the tip cylinder: equal chords between neighbours).
    assert_eq!(s.contact.len(), 9);
    assert!(s
        .contact
        .iter()
        .all(|&n| (radius(n) - g.tip_radius).abs() < 1e-12));
    let step = |a: usize, b: usize| {
        let (p, q) = (nodes[a], nodes[b]);
        (0..3).map(|d| (p[d] - q[d]).powi(2)).sum::<f64>().sqrt()
    };
    let first = step(s.contact[0], s.contact[1]);
    for w in s.contact.windows(2) {
        assert!((step(w[0], w[1]) - first).abs() <= 1e-12 * first);
    }
    // The whole chord: ends 8 steps apart along the helix.
    let end_to_end = step(s.contact[0], s.contact[8]);
    assert!(end_to_end < 8.0 * first && end_to_end > 0.99 * g.chord);
    // Excitation at tip mid-chord, mid-thickness: (tip, 0, 0).
    let e = nodes[s.excitation];
    assert!((e[0] - g.tip_radius).abs() < 1e-15 && e[1].abs() < 1e-15 && e[2].abs() < 1e-15);
    let o = nodes[s.observation];
    let expected = g.rim_radius + 0.75 * g.span();
    assert!((o[0] - expected).abs() < 1e-15 && o[1].abs() < 1e-15 && o[2].abs() < 1e-15);
    // The blade set: exactly the nodes that no disk element holds (the
    // root section belongs to the disk), every one in a blade element,
    // holding the contact, excitation and observation nodes.
    let mut in_disk = vec![false; nodes.len()];
    let mut in_blade = vec![false; nodes.len()];
    for e in &fan.mesh.elements {
        let flags = if e.material == 0 {
            &mut in_disk
        } else {
            &mut in_blade
        };
        for &n in &e.nodes {
            flags[n] = true;
        }
    }
    let expected: Vec<usize> = (0..nodes.len())
        .filter(|&n| in_blade[n] && !in_disk[n])
        .collect();
    assert_eq!(s.blade, expected);
    assert!(s
        .contact
        .iter()
        .chain([&s.excitation, &s.observation])
        .all(|n| s.blade.contains(n)));
}

#[test]
fn bad_sector_counts_and_refine_levels_are_refused_naming_the_flag() {
    let g = FanGeometry::default();
    for (sectors, refine, flag) in [
        (2, 1, "--sectors"),
        (24, 1, "--sectors"),
        (16, 0, "--refine"),
        (16, 9, "--refine"),
    ] {
        let error = fan(sectors, refine, &g).unwrap_err();
        assert!(error.is_input_error());
        assert!(error.to_string().starts_with(flag), "{error}");
    }
    assert_eq!(g.max_sectors(), 23);
}
