//! The texts of a fan folder: its case file (`fan<N>.toml`, a
//! `kind = "finite_element"` model) and its README.

use super::assembly::AssembledMatrices;
use super::fan::{FanMesh, CONTACT_NODES};
use std::fmt::Write as _;

/// The case file's name for `sectors` sectors (`fan16.toml`).
pub fn case_file_name(sectors: usize) -> String {
    format!("fan{sectors}.toml")
}

/// First-bending frequencies (Hz) per nodal diameter 0..8 measured on the
/// 16-sector fan (bore clamped, cyclic reduction with Cartesian boundaries
/// rotated, sparse Cholesky of `K(s)` and subspace iteration, checked
/// against the dense solver on refine 1), per refine level (1, 2 and the
/// default 3).
pub const MEASURED_FIRST_FAMILY: [(usize, [f64; 9]); 3] = [
    (
        1,
        [
            281.73, 281.92, 281.98, 281.94, 281.90, 281.88, 281.86, 281.85, 281.85,
        ],
    ),
    (
        2,
        [
            275.97, 276.14, 276.20, 276.17, 276.13, 276.11, 276.09, 276.09, 276.08,
        ],
    ),
    (
        3,
        [
            274.83, 275.00, 275.05, 275.02, 274.98, 274.96, 274.95, 274.94, 274.94,
        ],
    ),
];

/// The case file: a finite-element `[model]` table and the paper's Sec. 5
/// settings, its dof numbers counting the reduced model's retained dofs.
pub fn case_text(fan: &FanMesh) -> String {
    let s = &fan.sets;
    // The reduced model's dofs (kind = "finite_element"): every dof of the
    // contact nodes, then of the excitation and observation nodes (a node
    // kept once), 1-based, then the modal coordinates.
    let mut retained = s.contact.clone();
    for node in [s.excitation, s.observation] {
        if !retained.contains(&node) {
            retained.push(node);
        }
    }
    let first_dof = |node: usize| 3 * retained.iter().position(|&n| n == node).unwrap_or(0) + 1;
    let excitation_y = first_dof(s.excitation) + 1;
    let observation_y = first_dof(s.observation) + 1;
    let dofs_from = |offset: usize| -> String {
        s.contact
            .iter()
            .map(|&n| (first_dof(n) + offset).to_string())
            .collect::<Vec<_>>()
            .join(", ")
    };
    let retained_dofs = 3 * retained.len();
    let mut t = String::new();
    let _ = write!(
        t,
        r#"# Open fan stage, {n} sectors (cyclorub mesh fan --sectors {n} --refine {r}):
# the paper's Sec. 5 studies on an open model (see README.md).
#
# The sector is reduced by Craig–Bampton per nodal diameter; the reduced
# model's dofs, which the dof numbers below count from 1, are the {retained_dofs}
# dofs of the contact nodes (radial, circumferential, axial: contact_frame),
# then (x, y, z) of the excitation node, then of the observation node
# (node_sets.toml), then the modal coordinates. The reduced models are
# cached in .cyclorub-cache next to this file.

[model]
kind = "finite_element"
sectors = {n}
mass_file = "sector_mass.mtx"
stiffness_file = "sector_stiffness.mtx"
coordinates_file = "nodes.csv"
dofs_per_node = 3
axis = "z"
# Boundary dofs in the global Cartesian frame: u_R = exp(−iαs) R(α) u_L.
boundary_frame = "cartesian"
# clamped, left_boundary, right_boundary, contact, excitation, observation.
node_sets_file = "node_sets.toml"
# The contact nodes' dofs in each node's own (radial, circumferential,
# axial) directions: the normal of 3D contact is radial at every node.
contact_frame = "cylindrical"

# Craig–Bampton per nodal diameter (Sec. 5.1): boundary = every dof of the
# contact, excitation and observation nodes (11 nodes), 20 internal modes.
[model.reduction]
internal_modes = 20

# The paper's modal damping: 1e-3 on the first five modes, 5e-3 beyond.
[model.damping]
kind = "modal"
ratios = [1e-3, 1e-3, 1e-3, 1e-3, 1e-3]
others = 5e-3

# Sec. 5.2: f_ex = 2 N on the tip node at mid-chord, circumferential, in
# every sector. Dof {excitation_y} is the y dof of the excitation node {exc}
# (node set "excitation"), circumferential there (θ = 0).
[excitation]
kind = "traveling"
engine_order = 1
amplitude = 2.0
dofs = [{excitation_y}]

# Sec. 5.2: a rigid casing at c = 4e-4 m from each contact node (the gap
# after the centrifugal preload).
[casing]
gap = 4e-4
order = 0
amplitude = 0.0

# Sec. 5.2: DLFT-HBM with ε = 1e7 at the {cn} nodes of node set "contact",
# normal along each node's radius (dofs {contact_list}), and sliding friction
# μ = 0.15 (Eqs. 83, 84) along its circumferential (dofs {circumferential})
# and axial (dofs {axial}) dofs; radii from nodes.csv.
[contact]
law = "dlft"
epsilon = 1e7
dofs = [{contact_list}]
friction = 0.15
circumferential_dofs = [{circumferential}]
axial_dofs = [{axial}]

# Ω = 1151.9 rad/s (11,000 rpm), the sliding speed ρΩ of friction;
# `synchronous = true` instead takes Ω = ω along the sweep.
[rotation]
speed = 1151.9

# Sec. 5.2: the centrifugal force Ω² M r at that speed, solved on the full
# sector (nodal diameter 0) on harmonic 0; the gap above is measured after it.
[preload]
centrifugal = true

# Off: Hill's check costs about 60 times the solve on this fan (a class has
# 567 contact positions: the traveling h = 4 branch about 10 min against
# 10 s, docs/stability.md); enabled = true checks every point, and
# cyclorub stability RESULTS --point P checks chosen ones.
[stability]
enabled = false

# N_h = 10 harmonics, N_t = 2000 time samples (Sec. 5).
[harmonic_balance]
harmonics = 10
time_samples = 2000

# DLFT's pieces are short at 2000 instants and tilt each point's tangent:
# the secant predictor follows the branch with steps up to 0.2 (traveling
# h = 4: 416 points instead of 4398 along the tangent, on the same curve).
[continuation]
max_step = 0.2
dlft_predictor = "secant"

# The observation node's circumferential (y) displacement, as in the paper's
# forced response curves: dof {observation_y} of node {obs}.
[output]
directory = "results-fan{n}"
observed_dof = {observation_y}
"#,
        n = fan.sectors,
        r = fan.refine,
        exc = s.excitation + 1,
        cn = CONTACT_NODES,
        obs = s.observation + 1,
        contact_list = dofs_from(0),
        circumferential = dofs_from(1),
        axial = dofs_from(2),
    );
    t
}

/// The README of the folder: geometry, materials, element, mesh counts,
/// node sets and measured frequencies.
pub fn readme_text(fan: &FanMesh, matrices: &AssembledMatrices) -> String {
    let g = &fan.geometry;
    let mm = |v: f64| format!("{:.1} mm", v * 1e3);
    let mut t = String::new();
    let _ = writeln!(t, "# Open fan sector ({} sectors)\n", fan.sectors);
    let _ = writeln!(
        t,
        "Written by `cyclorub mesh fan --sectors {} --refine {}`: one sector of a fan stage of \
         the class of the paper's ECL5/Catana (Sec. 5.1), built from simple shapes so that it \
         can be shipped and rebuilt. `cyclorub run {}` runs the case: the sector is reduced \
         by Craig–Bampton per nodal diameter (20 internal modes) and the reduced models are \
         cached in `.cyclorub-cache`.\n",
        fan.sectors,
        fan.refine,
        case_file_name(fan.sectors)
    );
    let _ = writeln!(t, "## Geometry (SI units, rotation axis z)\n");
    let _ = writeln!(
        t,
        "- Sector: θ ∈ [−π/N, π/N] = ±{:.4}° about the x axis; the blade at θ = 0.",
        180.0 / fan.sectors as f64
    );
    let _ = writeln!(
        t,
        "- Disk: annular sector from the bore r = {} (clamped) to the rim r = {}, axial width {} \
         (z ∈ ±{}), titanium.",
        mm(g.bore_radius),
        mm(g.rim_radius),
        mm(g.chord),
        mm(g.chord / 2.0)
    );
    let _ = writeln!(
        t,
        "- Blade: a plate of constant thickness {} and chord {} from the rim to the tip r = {} \
         (span {}). Stagger (chord angle from the axis) 0 at the hub, rising linearly to {:.1}° \
         at the tip. A section point (r, chordwise c, thickness t) has circumferential arc \
         y = c sin β + t cos β, axial z = c cos β − t sin β, at θ = y / r: each section is a \
         rectangle wrapped on its cylinder. The root section shares the disk's top-face nodes.",
        mm(g.thickness),
        mm(g.chord),
        mm(g.tip_radius),
        mm(g.span()),
        g.tip_stagger.to_degrees()
    );
    let _ = writeln!(
        t,
        "- Materials (isotropic): disk E = {:e} Pa, ν = {}, ρ = {} kg/m³ (titanium); blade \
         E = {:e} Pa, ν = {}, ρ = {} kg/m³ (an isotropic equivalent of a carbon-epoxy blade, \
         its modulus set so the first bending family lies near the paper's Table 3).\n",
        g.disk.young,
        g.disk.poisson,
        g.disk.density,
        g.blade.young,
        g.blade.poisson,
        g.blade.density
    );
    let _ = writeln!(t, "## Mesh\n");
    let [dr, dt, dz] = fan.disk_divisions;
    let [bs, bt, bc] = fan.blade_divisions;
    let _ = writeln!(
        t,
        "20-node serendipity hexahedra (quadratic), consistent mass and stiffness by 3×3×3 \
         Gauss points.\n\n\
         - Disk: {dr} radial × {dt} circumferential × {dz} axial = {} elements.\n\
         - Blade: {bs} spanwise × {bt} through the thickness × {bc} chordwise = {} elements.\n\
         - {} nodes, {} dofs (3 per node in node order: x, y, z).\n\
         - Stored entries (lower triangle): mass {}, stiffness {}.\n",
        fan.disk_elements(),
        fan.blade_elements(),
        fan.mesh.nodes.len(),
        fan.dofs(),
        matrices.mass.stored_entries(),
        matrices.stiffness.stored_entries()
    );
    let s = &fan.sets;
    let _ = writeln!(t, "## Files\n");
    let _ = writeln!(
        t,
        "- `sector_mass.mtx`, `sector_stiffness.mtx`: Matrix Market `coordinate real \
         symmetric`, lower triangle, 1-based, 17 significant digits; the free sector (the \
         clamped nodes are a node set, not removed).\n\
         - `nodes.csv`: `node,x,y,z` (m), 1-based.\n\
         - `node_sets.toml`: clamped ({} nodes: the bore face), left_boundary and \
         right_boundary ({} nodes each, paired in order; right = left rotated by 2π/N about z; \
         the bore nodes are in both the boundary and the clamped sets), contact ({} nodes \
         evenly spaced along the tip's pressure-side edge t = −thickness/2, leading edge \
         first), excitation (node {}: tip, mid-chord, mid-thickness), observation (node {}: \
         mid-chord, mid-thickness at three quarters of the span, where bending moves it a lot, \
         away from the contact edge), blade ({} nodes: the blade above its root section, which \
         is the disk's top face; `[mistuning]` scales the stiffness entries between two of \
         them).\n\
         - `{}`: the case (the paper's Sec. 5 settings, contact frictionless along x for now).\n",
        s.clamped.len(),
        s.left_boundary.len(),
        s.contact.len(),
        s.excitation + 1,
        s.observation + 1,
        s.blade.len(),
        case_file_name(fan.sectors)
    );
    let _ = writeln!(t, "## First bending family\n");
    let _ = writeln!(
        t,
        "Measured with the bore clamped, per nodal diameter by the cyclic reduction with the \
         Cartesian boundary dofs rotated (u_R = e^(−iαs) R(α) u_L), 16 sectors (paper's Table 3: \
         263.2, 284.1, 285.5, 285.6, 286.1, 286.8, 287.4, 287.7, 287.9 Hz):\n"
    );
    let _ = writeln!(t, "| refine | ND 0 | 1 | 2 | 3 | 4 | 5 | 6 | 7 | 8 |");
    let _ = writeln!(t, "|---|---|---|---|---|---|---|---|---|---|");
    for (refine, values) in MEASURED_FIRST_FAMILY.iter() {
        let cells: Vec<String> = values.iter().map(|v| format!("{v:.2}")).collect();
        let _ = writeln!(t, "| {refine} | {} |", cells.join(" | "));
    }
    let _ = writeln!(
        t,
        "\nThe family is lowest at nodal diameter 0 and rises to diameter 2; beyond, it is \
         flat within 0.05 % (the stiff full-width titanium disk barely takes part), flatter \
         than the ECL5's. The next modes are near 1230 Hz and 1480 Hz (refine 3). The coarse \
         mesh (refine 1) is 2.5 % stiffer than the default."
    );
    if fan.sectors != 16 {
        let _ = writeln!(
            t,
            "\nThese figures are for 16 sectors; this folder has {} sectors.",
            fan.sectors
        );
    }
    t
}
