//! The geometry of the open fan sector and its mesh.
//!
//! Rotation axis z; the sector spans `θ ∈ [−π/N, π/N]` about the x axis.
//! - **Disk**: the annular sector `r ∈ [bore, rim]`, `z ∈ [−chord/2,
//!   chord/2]` (its axial width is the blade's root chord), titanium; the
//!   bore face is clamped. Its circumferential divisions are: sides from
//!   `±π/N` to the blade root, and the blade root itself, so the blade's
//!   root section shares the disk's top-face nodes.
//! - **Blade**: a plate of constant thickness and chord rising radially from
//!   the rim at mid-sector to the tip. A point at radius `r`, chordwise
//!   coordinate `c` and thickness coordinate `t` has, with the stagger
//!   `β(r)` (0 at the hub, linear to the tip), circumferential arc length
//!   `y = c sin β + t cos β` and axial position `z = c cos β − t sin β`, and
//!   sits at `θ = y / r`: every section is a rectangle wrapped on its
//!   cylinder, the chord axial at the hub. Its exact volume is
//!   `span × chord × thickness` (the map has unit Jacobian in `(r, y, z)`).
//!
//! The left and right cyclic faces are the disk's `θ = ∓π/N` faces, built on
//! the same radial and axial divisions: every right node is its left twin
//! rotated by `2π/N` about z.

use super::hexahedron::Material;
use super::lattice::Lattice;
use super::{Element, Mesh, MeshError};
use std::f64::consts::PI;

/// The refine level of the default mesh (17,379 dofs for 16 sectors).
pub const DEFAULT_REFINE: usize = 3;
/// The largest refine level accepted (about 300,000 dofs).
pub const MAX_REFINE: usize = 8;
/// Number of contact nodes along the blade tip.
pub const CONTACT_NODES: usize = 9;

/// Dimensions (m, rad) and materials of the fan sector.
#[derive(Clone, Debug, PartialEq)]
pub struct FanGeometry {
    /// Radius of the clamped bore.
    pub bore_radius: f64,
    /// Radius of the disk's rim, where the blade starts.
    pub rim_radius: f64,
    /// Radius of the blade tip.
    pub tip_radius: f64,
    /// Blade chord, constant along the span; also the disk's axial width.
    pub chord: f64,
    /// Blade thickness, constant.
    pub thickness: f64,
    /// Stagger at the tip: the chord's angle from the axis (0 at the hub).
    pub tip_stagger: f64,
    /// The disk's material.
    pub disk: Material,
    /// The blade's material.
    pub blade: Material,
}

impl Default for FanGeometry {
    fn default() -> Self {
        Self {
            bore_radius: 0.04,
            rim_radius: 0.085,
            tip_radius: 0.25,
            chord: 0.08,
            thickness: 0.008,
            tip_stagger: 50f64.to_radians(),
            // Titanium (the paper's disk material).
            disk: Material {
                young: 114e9,
                poisson: 0.34,
                density: 4430.0,
            },
            // An isotropic equivalent of a carbon-epoxy blade, its modulus
            // chosen to put the first bending family near the paper's
            // Table 3 (263–288 Hz).
            blade: Material {
                young: 53e9,
                poisson: 0.3,
                density: 1600.0,
            },
        }
    }
}

impl FanGeometry {
    /// Radial length of the blade.
    pub fn span(&self) -> f64 {
        self.tip_radius - self.rim_radius
    }

    /// Half the angle the blade root takes on the rim.
    pub fn root_half_angle(&self) -> f64 {
        0.5 * self.thickness / self.rim_radius
    }

    /// Half the angle the blade's tip section takes (stagger included).
    pub fn tip_half_angle(&self) -> f64 {
        let (s, c) = self.tip_stagger.sin_cos();
        (0.5 * self.chord * s + 0.5 * self.thickness * c) / self.tip_radius
    }

    /// The largest sector count for which the blade fits its sector at the
    /// rim and at the tip (blades of neighbouring sectors would overlap).
    pub fn max_sectors(&self) -> usize {
        let widest = self.root_half_angle().max(self.tip_half_angle());
        (PI / widest).ceil() as usize - 1
    }

    /// Stagger at radius `r` (linear from 0 at the rim).
    pub fn stagger(&self, r: f64) -> f64 {
        self.tip_stagger * (r - self.rim_radius) / self.span()
    }

    /// Cartesian position of the blade point at radius `r`, chordwise
    /// coordinate `c` and thickness coordinate `t`.
    pub fn blade_point(&self, r: f64, c: f64, t: f64) -> [f64; 3] {
        let (s, co) = self.stagger(r).sin_cos();
        let arc = c * s + t * co;
        let z = c * co - t * s;
        let theta = arc / r;
        [r * theta.cos(), r * theta.sin(), z]
    }
}

/// Node sets of the fan sector (0-based node numbers).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct NodeSets {
    /// The bore face (every dof fixed).
    pub clamped: Vec<usize>,
    /// The `θ = −π/N` face, in the same order as `right_boundary`.
    pub left_boundary: Vec<usize>,
    /// The `θ = +π/N` face: `right_boundary[i]` is `left_boundary[i]` rotated by `2π/N`.
    pub right_boundary: Vec<usize>,
    /// Nine nodes evenly spaced along the tip's `t = −thickness/2` edge
    /// (pressure side), leading edge first.
    pub contact: Vec<usize>,
    /// The tip node at mid-chord, mid-thickness.
    pub excitation: usize,
    /// Mid-chord, mid-thickness at three quarters of the span: bending
    /// moves it a lot, and it is away from the contact edge.
    pub observation: usize,
    /// Every blade node above its root section (the root's nodes are the
    /// disk's top face): the stiffness entries between two of them come
    /// from blade elements only, and `[mistuning]` scales them.
    pub blade: Vec<usize>,
}

/// The fan sector: mesh, node sets, and how it was divided.
#[derive(Clone, Debug)]
pub struct FanMesh {
    /// Number of sectors of the wheel.
    pub sectors: usize,
    /// Refine level.
    pub refine: usize,
    /// Dimensions and materials.
    pub geometry: FanGeometry,
    /// Nodes and elements (material 0: disk, 1: blade).
    pub mesh: Mesh,
    /// Node sets.
    pub sets: NodeSets,
    /// Disk elements (radial, circumferential, axial).
    pub disk_divisions: [usize; 3],
    /// Blade elements (span, thickness, chord).
    pub blade_divisions: [usize; 3],
    /// Circumferential element boundaries of the disk (rad), left to right.
    pub disk_angles: Vec<f64>,
}

impl FanMesh {
    /// Number of disk elements.
    pub fn disk_elements(&self) -> usize {
        self.disk_divisions.iter().product()
    }

    /// Number of blade elements.
    pub fn blade_elements(&self) -> usize {
        self.blade_divisions.iter().product()
    }

    /// Number of dofs (3 per node).
    pub fn dofs(&self) -> usize {
        3 * self.mesh.nodes.len()
    }
}

/// Values at the `2n + 1` lattice points of `n` equal divisions of `[a, b]`.
fn divide(a: f64, b: f64, n: usize) -> Vec<f64> {
    (0..=2 * n)
        .map(|i| a + (b - a) * i as f64 / (2 * n) as f64)
        .collect()
}

/// Builds the fan sector of `sectors` sectors at refine level `refine`
/// (1: a coarse mesh for tests, [`DEFAULT_REFINE`]: the default).
pub fn fan(sectors: usize, refine: usize, geometry: &FanGeometry) -> Result<FanMesh, MeshError> {
    geometry.disk.check("disk material")?;
    geometry.blade.check("blade material")?;
    let lengths = [
        geometry.bore_radius,
        geometry.rim_radius - geometry.bore_radius,
        geometry.tip_radius - geometry.rim_radius,
        geometry.chord,
        geometry.thickness,
    ];
    if lengths.iter().any(|l| !(l.is_finite() && *l > 0.0)) {
        return Err(MeshError::Invalid {
            what: "fan geometry".into(),
            message: format!(
                "need 0 < bore {} < rim {} < tip {} and a positive chord {} and thickness {} (m)",
                geometry.bore_radius,
                geometry.rim_radius,
                geometry.tip_radius,
                geometry.chord,
                geometry.thickness
            ),
        });
    }
    let max_sectors = geometry.max_sectors();
    if sectors < 3 || sectors > max_sectors {
        return Err(MeshError::Invalid {
            what: "--sectors".into(),
            message: format!(
                "{sectors} sectors: allowed 3 to {max_sectors} (beyond, the blades of neighbouring \
                 sectors would overlap)"
            ),
        });
    }
    if refine == 0 || refine > MAX_REFINE {
        return Err(MeshError::Invalid {
            what: "--refine".into(),
            message: format!(
                "{refine}: allowed 1 (coarse, about 1,300 dofs) to {MAX_REFINE}; the default is {DEFAULT_REFINE}"
            ),
        });
    }
    let half = PI / sectors as f64;
    let root = geometry.root_half_angle();
    // Divisions: the disk sides and the blade span, chord and disk radius
    // grow with `refine`; one element through the blade's thickness (the
    // quadratic element bends well with one layer).
    let (n_r, n_side, n_z) = (2 * refine, 2 * refine, 4 * refine);
    let (n_span, n_thick) = (4 * refine, 1);
    let radii = divide(geometry.bore_radius, geometry.rim_radius, n_r);
    let chord_points = divide(-0.5 * geometry.chord, 0.5 * geometry.chord, n_z);
    let thick_points = divide(-0.5 * geometry.thickness, 0.5 * geometry.thickness, n_thick);
    // θ lattice: left side, the blade root (θ = t / rim, as the blade's own
    // map gives at the hub), right side.
    let mut angles = divide(-half, -root, n_side);
    angles.pop();
    angles.extend(thick_points.iter().map(|t| t / geometry.rim_radius));
    let mut right = divide(root, half, n_side);
    right.remove(0);
    angles.extend(right);
    let n_theta = 2 * n_side + n_thick;

    let mut nodes: Vec<[f64; 3]> = Vec::new();
    let mut elements = Vec::new();
    let mut disk = Lattice::new([n_r, n_theta, n_z]);
    for p in disk.node_points() {
        let (r, th, z) = (radii[p[0]], angles[p[1]], chord_points[p[2]]);
        disk.set(p, nodes.len());
        nodes.push([r * th.cos(), r * th.sin(), z]);
    }
    let number = |lattice: &Lattice, e: [usize; 3]| -> Result<[usize; 20], MeshError> {
        let mut ids = [0; 20];
        for (id, p) in ids.iter_mut().zip(Lattice::element_points(e)) {
            *id = lattice.get(p).ok_or_else(|| MeshError::Invalid {
                what: "fan mesh".into(),
                message: format!("lattice point {p:?} has no node"),
            })?;
        }
        Ok(ids)
    };
    for e in disk.element_indices() {
        elements.push(Element {
            nodes: number(&disk, e)?,
            material: 0,
        });
    }
    // Blade lattice (span, thickness, chord): right-handed like the disk's
    // (r, θ, z) at the hub. Its root layer is the disk's top face.
    let spans = divide(geometry.rim_radius, geometry.tip_radius, n_span);
    let mut blade = Lattice::new([n_span, n_thick, n_z]);
    let top = 2 * n_r;
    let root_offset = 2 * n_side;
    let mut blade_nodes = Vec::new();
    for p in blade.node_points() {
        if p[0] == 0 {
            let shared =
                disk.get([top, root_offset + p[1], p[2]])
                    .ok_or_else(|| MeshError::Invalid {
                        what: "fan mesh".into(),
                        message: format!("blade root point {p:?} is not a disk node"),
                    })?;
            blade.set(p, shared);
        } else {
            blade.set(p, nodes.len());
            blade_nodes.push(nodes.len());
            nodes.push(geometry.blade_point(spans[p[0]], chord_points[p[2]], thick_points[p[1]]));
        }
    }
    for e in blade.element_indices() {
        elements.push(Element {
            nodes: number(&blade, e)?,
            material: 1,
        });
    }

    let missing = |what: &str| MeshError::Invalid {
        what: "fan mesh".into(),
        message: format!("the {what} node is missing from the lattice"),
    };
    let [pr, pt, pz] = disk.points();
    let mut clamped = Vec::new();
    for j in 0..pt {
        for k in 0..pz {
            if let Some(id) = disk.get([0, j, k]) {
                clamped.push(id);
            }
        }
    }
    let (mut left_boundary, mut right_boundary) = (Vec::new(), Vec::new());
    for i in 0..pr {
        for k in 0..pz {
            if let (Some(l), Some(r)) = (disk.get([i, 0, k]), disk.get([i, pt - 1, k])) {
                left_boundary.push(l);
                right_boundary.push(r);
            }
        }
    }
    let tip = 2 * n_span;
    let chord_lattice = 2 * n_z;
    let step = chord_lattice / (CONTACT_NODES - 1);
    let contact = (0..CONTACT_NODES)
        .map(|q| {
            blade
                .get([tip, 0, q * step])
                .ok_or_else(|| missing("contact"))
        })
        .collect::<Result<Vec<_>, _>>()?;
    let excitation = blade
        .get([tip, 1, chord_lattice / 2])
        .ok_or_else(|| missing("excitation"))?;
    let observation = blade
        .get([3 * tip / 4, 1, chord_lattice / 2])
        .ok_or_else(|| missing("observation"))?;

    let mut disk_angles: Vec<f64> = angles.iter().step_by(2).copied().collect();
    disk_angles.shrink_to_fit();
    Ok(FanMesh {
        sectors,
        refine,
        geometry: geometry.clone(),
        mesh: Mesh {
            nodes,
            elements,
            materials: vec![geometry.disk, geometry.blade],
        },
        sets: NodeSets {
            clamped,
            left_boundary,
            right_boundary,
            contact,
            excitation,
            observation,
            blade: blade_nodes,
        },
        disk_divisions: [n_r, n_theta, n_z],
        blade_divisions: [n_span, n_thick, n_z],
        disk_angles,
    })
}
