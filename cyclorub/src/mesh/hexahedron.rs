//! The 20-node serendipity hexahedron (quadratic, "hex20"): isotropic linear
//! elasticity, element stiffness and consistent mass by 3×3×3 Gauss
//! integration (exact for the mass of an undistorted element, and the usual
//! full integration of the stiffness).
//!
//! Node `a` of an element sits at the natural coordinates
//! [`HEX20_NATURAL`]`[a]`: the eight corners first, then the twelve
//! mid-edge nodes. Dofs of an element are 3 per node in node order (x, y, z).

use super::MeshError;

/// Nodes of one element.
pub const HEX20_NODES: usize = 20;
/// Dofs of one element (3 per node).
pub const HEX20_DOFS: usize = 3 * HEX20_NODES;

/// Natural coordinates `(ξ, η, ζ)` of the 20 nodes: corners, then mid-edges.
pub const HEX20_NATURAL: [[f64; 3]; HEX20_NODES] = [
    [-1.0, -1.0, -1.0],
    [1.0, -1.0, -1.0],
    [1.0, 1.0, -1.0],
    [-1.0, 1.0, -1.0],
    [-1.0, -1.0, 1.0],
    [1.0, -1.0, 1.0],
    [1.0, 1.0, 1.0],
    [-1.0, 1.0, 1.0],
    [0.0, -1.0, -1.0],
    [1.0, 0.0, -1.0],
    [0.0, 1.0, -1.0],
    [-1.0, 0.0, -1.0],
    [0.0, -1.0, 1.0],
    [1.0, 0.0, 1.0],
    [0.0, 1.0, 1.0],
    [-1.0, 0.0, 1.0],
    [-1.0, -1.0, 0.0],
    [1.0, -1.0, 0.0],
    [1.0, 1.0, 0.0],
    [-1.0, 1.0, 0.0],
];

/// Three-point Gauss–Legendre rule on [−1, 1]: abscissae and weights.
pub const GAUSS3: [(f64, f64); 3] = [
    (-0.774_596_669_241_483_4, 5.0 / 9.0),
    (0.0, 8.0 / 9.0),
    (0.774_596_669_241_483_4, 5.0 / 9.0),
];

/// An isotropic linear elastic material.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Material {
    /// Young's modulus (Pa).
    pub young: f64,
    /// Poisson's ratio (−1 < ν < 1/2).
    pub poisson: f64,
    /// Density (kg/m³).
    pub density: f64,
}

impl Material {
    /// The 6×6 elasticity matrix `D` in Voigt order (xx, yy, zz, xy, yz, zx),
    /// engineering shear strains.
    pub fn elasticity(&self) -> [[f64; 6]; 6] {
        let (e, nu) = (self.young, self.poisson);
        let lambda = e * nu / ((1.0 + nu) * (1.0 - 2.0 * nu));
        let mu = e / (2.0 * (1.0 + nu));
        let mut d = [[0.0; 6]; 6];
        for (i, row) in d.iter_mut().enumerate().take(3) {
            for (j, value) in row.iter_mut().enumerate().take(3) {
                *value = if i == j { lambda + 2.0 * mu } else { lambda };
            }
        }
        for (i, row) in d.iter_mut().enumerate().skip(3) {
            row[i] = mu;
        }
        d
    }

    /// Refuses non-physical values, naming `what` (e.g. `blade material`).
    pub fn check(&self, what: &str) -> Result<(), MeshError> {
        let fine = self.young.is_finite()
            && self.young > 0.0
            && self.density.is_finite()
            && self.density > 0.0
            && self.poisson > -1.0
            && self.poisson < 0.5;
        if fine {
            Ok(())
        } else {
            Err(MeshError::Invalid {
                what: what.into(),
                message: format!(
                    "E = {:e} Pa, ν = {}, ρ = {:e} kg/m³: need E > 0, ρ > 0 and −1 < ν < 1/2",
                    self.young, self.poisson, self.density
                ),
            })
        }
    }
}

/// Shape functions and their natural derivatives at `(ξ, η, ζ)`.
pub fn shape_functions(p: [f64; 3]) -> ([f64; HEX20_NODES], [[f64; 3]; HEX20_NODES]) {
    let mut n = [0.0; HEX20_NODES];
    let mut dn = [[0.0; 3]; HEX20_NODES];
    for (a, c) in HEX20_NATURAL.iter().enumerate() {
        // Linear factors (1 + ξ ξ_a) etc.; a zero natural coordinate marks
        // the direction in which a mid-edge function is quadratic.
        let l = [1.0 + p[0] * c[0], 1.0 + p[1] * c[1], 1.0 + p[2] * c[2]];
        match c.iter().position(|&v| v == 0.0) {
            None => {
                let s = p[0] * c[0] + p[1] * c[1] + p[2] * c[2] - 2.0;
                n[a] = 0.125 * l[0] * l[1] * l[2] * s;
                for d in 0..3 {
                    let (e, f) = ((d + 1) % 3, (d + 2) % 3);
                    // ∂/∂p_d of l_d·s: c_d·s + l_d·c_d.
                    dn[a][d] = 0.125 * l[e] * l[f] * c[d] * (s + l[d]);
                }
            }
            Some(q) => {
                let (e, f) = ((q + 1) % 3, (q + 2) % 3);
                let bubble = 1.0 - p[q] * p[q];
                n[a] = 0.25 * bubble * l[e] * l[f];
                dn[a][q] = 0.25 * (-2.0 * p[q]) * l[e] * l[f];
                dn[a][e] = 0.25 * bubble * c[e] * l[f];
                dn[a][f] = 0.25 * bubble * l[e] * c[f];
            }
        }
    }
    (n, dn)
}

/// Shape function values and Cartesian derivatives at one point of an element,
/// with the Jacobian determinant.
pub struct PointGeometry {
    /// Shape function values.
    pub values: [f64; HEX20_NODES],
    /// `∂N_a/∂x`, `∂N_a/∂y`, `∂N_a/∂z`.
    pub gradients: [[f64; 3]; HEX20_NODES],
    /// `det(∂x/∂ξ)`, positive for a well-oriented element.
    pub jacobian: f64,
}

/// Geometry of the element with node coordinates `coords` at natural point `p`;
/// an inverted or degenerate element (det J ≤ 0) is refused.
pub fn point_geometry(
    coords: &[[f64; 3]; HEX20_NODES],
    p: [f64; 3],
) -> Result<PointGeometry, MeshError> {
    let (values, dn) = shape_functions(p);
    // J[i][j] = ∂x_j/∂ξ_i.
    let mut j = [[0.0; 3]; 3];
    for a in 0..HEX20_NODES {
        for i in 0..3 {
            for k in 0..3 {
                j[i][k] += dn[a][i] * coords[a][k];
            }
        }
    }
    let det = j[0][0] * (j[1][1] * j[2][2] - j[1][2] * j[2][1])
        - j[0][1] * (j[1][0] * j[2][2] - j[1][2] * j[2][0])
        + j[0][2] * (j[1][0] * j[2][1] - j[1][1] * j[2][0]);
    if !(det.is_finite() && det > 0.0) {
        return Err(MeshError::BadElement {
            jacobian: det,
            at: p,
        });
    }
    let inv = [
        [
            (j[1][1] * j[2][2] - j[1][2] * j[2][1]) / det,
            (j[0][2] * j[2][1] - j[0][1] * j[2][2]) / det,
            (j[0][1] * j[1][2] - j[0][2] * j[1][1]) / det,
        ],
        [
            (j[1][2] * j[2][0] - j[1][0] * j[2][2]) / det,
            (j[0][0] * j[2][2] - j[0][2] * j[2][0]) / det,
            (j[0][2] * j[1][0] - j[0][0] * j[1][2]) / det,
        ],
        [
            (j[1][0] * j[2][1] - j[1][1] * j[2][0]) / det,
            (j[0][1] * j[2][0] - j[0][0] * j[2][1]) / det,
            (j[0][0] * j[1][1] - j[0][1] * j[1][0]) / det,
        ],
    ];
    // ∂N/∂x_k = Σ_i (J⁻¹)[k][i] ∂N/∂ξ_i.
    let mut gradients = [[0.0; 3]; HEX20_NODES];
    for a in 0..HEX20_NODES {
        for k in 0..3 {
            gradients[a][k] = (0..3).map(|i| inv[k][i] * dn[a][i]).sum();
        }
    }
    Ok(PointGeometry {
        values,
        gradients,
        jacobian: det,
    })
}

/// Engineering strain (Voigt: xx, yy, zz, xy, yz, zx) at natural point `p`
/// for element displacements `u` (3 per node, node order).
pub fn strain(
    coords: &[[f64; 3]; HEX20_NODES],
    u: &[f64; HEX20_DOFS],
    p: [f64; 3],
) -> Result<[f64; 6], MeshError> {
    let g = point_geometry(coords, p)?;
    let mut e = [0.0; 6];
    for a in 0..HEX20_NODES {
        let [gx, gy, gz] = g.gradients[a];
        let (ux, uy, uz) = (u[3 * a], u[3 * a + 1], u[3 * a + 2]);
        e[0] += gx * ux;
        e[1] += gy * uy;
        e[2] += gz * uz;
        e[3] += gy * ux + gx * uy;
        e[4] += gz * uy + gy * uz;
        e[5] += gx * uz + gz * ux;
    }
    Ok(e)
}

/// Element matrices, dense row-major `HEX20_DOFS × HEX20_DOFS`.
pub struct ElementMatrices {
    /// Stiffness `∫ Bᵀ D B dV`.
    pub stiffness: Vec<f64>,
    /// Consistent mass `∫ ρ Nᵀ N dV`.
    pub mass: Vec<f64>,
}

/// Stiffness and consistent mass of one element (3×3×3 Gauss points).
pub fn element_matrices(
    coords: &[[f64; 3]; HEX20_NODES],
    material: &Material,
) -> Result<ElementMatrices, MeshError> {
    let d = material.elasticity();
    let mut stiffness = vec![0.0; HEX20_DOFS * HEX20_DOFS];
    let mut scalar_mass = [[0.0; HEX20_NODES]; HEX20_NODES];
    for &(x, wx) in &GAUSS3 {
        for &(y, wy) in &GAUSS3 {
            for &(z, wz) in &GAUSS3 {
                let g = point_geometry(coords, [x, y, z])?;
                let w = wx * wy * wz * g.jacobian;
                // B (6 × 60), column 3a + i is node a, direction i.
                let mut b = [[0.0; HEX20_DOFS]; 6];
                for a in 0..HEX20_NODES {
                    let [gx, gy, gz] = g.gradients[a];
                    let c = 3 * a;
                    b[0][c] = gx;
                    b[1][c + 1] = gy;
                    b[2][c + 2] = gz;
                    b[3][c] = gy;
                    b[3][c + 1] = gx;
                    b[4][c + 1] = gz;
                    b[4][c + 2] = gy;
                    b[5][c] = gz;
                    b[5][c + 2] = gx;
                }
                // DB (6 × 60) then Bᵀ(DB).
                let mut db = [[0.0; HEX20_DOFS]; 6];
                for (i, row) in db.iter_mut().enumerate() {
                    for (k, bk) in b.iter().enumerate() {
                        if d[i][k] != 0.0 {
                            for (value, bv) in row.iter_mut().zip(bk.iter()) {
                                *value += d[i][k] * bv;
                            }
                        }
                    }
                }
                for r in 0..HEX20_DOFS {
                    for (bk, dbk) in b.iter().zip(db.iter()) {
                        let brw = bk[r] * w;
                        if brw != 0.0 {
                            let row = &mut stiffness[r * HEX20_DOFS..(r + 1) * HEX20_DOFS];
                            for (value, dv) in row.iter_mut().zip(dbk.iter()) {
                                *value += brw * dv;
                            }
                        }
                    }
                }
                let wm = w * material.density;
                for (row, na) in scalar_mass.iter_mut().zip(g.values.iter()) {
                    for (value, nc) in row.iter_mut().zip(g.values.iter()) {
                        *value += wm * na * nc;
                    }
                }
            }
        }
    }
    // Exact symmetry (the products above are symmetric only to round-off).
    for r in 0..HEX20_DOFS {
        for c in 0..r {
            let mean = 0.5 * (stiffness[r * HEX20_DOFS + c] + stiffness[c * HEX20_DOFS + r]);
            stiffness[r * HEX20_DOFS + c] = mean;
            stiffness[c * HEX20_DOFS + r] = mean;
        }
    }
    let mut mass = vec![0.0; HEX20_DOFS * HEX20_DOFS];
    for a in 0..HEX20_NODES {
        for c in 0..HEX20_NODES {
            let m = 0.5 * (scalar_mass[a][c] + scalar_mass[c][a]);
            for i in 0..3 {
                mass[(3 * a + i) * HEX20_DOFS + 3 * c + i] = m;
            }
        }
    }
    Ok(ElementMatrices { stiffness, mass })
}
