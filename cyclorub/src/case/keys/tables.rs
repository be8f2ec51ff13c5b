//! The key table itself: every table of a case file and its keys. A new
//! table (a new capability's settings) is one more [`Table`] entry here.

use super::{Consumer, Key, Rule, Table, When};
use Consumer::{ContactLaw, Model};
use Rule::{
    AboveTwice, AtLeast, AtMost, Below, BelowHalf, CheckedBy, CountOf, Differs, Dofs, Finite,
    NoMoreThan, NonNegative, OneOf, OneTo, Positive,
};

const ACADEMIC: When = When::Is("model.kind", "academic");
const MATRICES: When = When::Is("model.kind", "matrices");
const FINITE_ELEMENT: When = When::Is("model.kind", "finite_element");
const MODAL: When = When::Is("model.damping.kind", "modal");
const RAYLEIGH: When = When::Is("model.damping.kind", "rayleigh");
const MATRIX: When = When::Is("model.damping.kind", "matrix");
const EXCITED: When = When::IsNot("excitation.kind", "none");
const REGULARIZED: When = When::Is("contact.law", "regularized");
const DLFT: When = When::Is("contact.law", "dlft");
const BY_MODEL: &[Rule] = &[CheckedBy(Model)];
const BY_LAW: &[Rule] = &[CheckedBy(ContactLaw)];

/// Every table of a case file, in the order of the file.
#[rustfmt::skip]
pub const TABLES: &[Table] = &[
    Table {
        name: "model",
        doc: "The sector model (one sector; the wheel is N copies of it).",
        keys: &[
            Key::new("kind", "`\"academic\"`", "", "",
                "Sector model: \"academic\" (lumped chain: masses, springs), \"matrices\" (inline \
                 matrices), \"matrix_market\" (Matrix Market files) or \"finite_element\" (sparse \
                 Matrix Market files, node coordinates and node sets, reduced by Craig–Bampton per \
                 nodal diameter)")
                .rules(&[OneOf(&["academic", "matrices", "matrix_market", "finite_element"])]),
            Key::new("sectors", "`24`", "", "integer, 1..=10000", "Number of sectors N")
                .rules(&[AtLeast(1)]),
            Key::new("symmetry_tolerance", "absent: `1e-8`", "", "0..=1e-3",
                "Relative tolerance on the symmetry of the matrices")
                .rules(BY_MODEL),
            Key::new("masses", "absent: the paper's Table 1", "kg", "> 0", "mass of each dof")
                .rules(BY_MODEL).when(ACADEMIC),
            Key::new("springs", "absent: the paper's Table 1", "N/m", "stiffness ≥ 0",
                "springs { dofs = [a, b], stiffness = k, link = \"within\" | \"next_sector\" \
                 (a in sector j, b in j+1) | \"ground\" (dofs = [a]) }")
                .rules(BY_MODEL).when(ACADEMIC),
            Key::new("mass", "required", "kg", "list of rows, symmetric", "sector mass matrix")
                .rules(BY_MODEL).when(MATRICES).example("[[0.2, 0.0], [0.0, 0.3]]"),
            Key::new("stiffness", "required", "N/m", "list of rows, symmetric",
                "sector stiffness matrix")
                .rules(BY_MODEL).when(MATRICES).example("[[2e6, -2e6], [-2e6, 3.6e6]]"),
            Key::new("mass_coupling", "absent: none", "kg",
                "rows; not with left_boundary / right_boundary",
                "mass coupling block to the next sector")
                .rules(BY_MODEL).when(MATRICES).example("[[0.0, 0.0], [0.0, 0.0]]"),
            Key::new("stiffness_coupling", "absent: none", "N/m",
                "rows; not with left_boundary / right_boundary",
                "stiffness coupling block to the next sector")
                .rules(BY_MODEL).when(MATRICES).example("[[0.0, 0.0], [0.0, -5e5]]"),
            Key::new("mass_file", "required by kind = \"matrix_market\", \"finite_element\"", "", "",
                "Sector mass matrix, a Matrix Market file relative to the case file's folder")
                .rules(BY_MODEL).example("\"mass.mtx\""),
            Key::new("stiffness_file", "required by kind = \"matrix_market\", \"finite_element\"", "", "",
                "Sector stiffness matrix, a Matrix Market file relative to the case file's folder")
                .rules(BY_MODEL).example("\"stiffness.mtx\""),
            Key::new("coordinates_file", "required", "m", "CSV lines node,x,y,z; nodes 1..=n",
                "node coordinates, a CSV file relative to the case file's folder; dofs are \
                 dofs_per_node per node in node order")
                .rules(BY_MODEL).when(FINITE_ELEMENT).example("\"nodes.csv\""),
            Key::new("dofs_per_node", "absent: `3`", "", "3",
                "dofs per node: x, y, z in the sector's Cartesian frame")
                .rules(BY_MODEL).when(FINITE_ELEMENT).example("3"),
            Key::new("node_sets_file", "required", "",
                "TOML lists of 1-based nodes, each node once in a list; contact not empty; a node \
                 in one of contact, excitation, observation, and neither clamped nor right_boundary",
                "node sets: clamped, left_boundary, right_boundary (paired by coordinates after a \
                 turn of 2π/N about axis when not given in order), contact, excitation, \
                 observation (all their dofs are kept, in this order, as the model's dofs 1, 2…); \
                 other lists are read by name (blade: mistuning.blade_node_set)")
                .rules(BY_MODEL).when(FINITE_ELEMENT).example("\"node_sets.toml\""),
            Key::new("contact_frame", "absent: \"cartesian\"", "", "\"cartesian\" or \"cylindrical\"",
                "how the contact nodes' dofs are expressed: \"cartesian\" (x, y, z) or \
                 \"cylindrical\" (each node's radial, circumferential and axial directions \
                 about axis, for 3D contact with friction: radial dofs toward the casing)")
                .rules(&[OneOf(&["cartesian", "cylindrical"])]).when(FINITE_ELEMENT)
                .example("\"cylindrical\""),
            Key::new("left_boundary", "absent: none", "", "1-based",
                "Left cyclic boundary dofs of a finite-element sector: kind = \"matrix_market\", \
                 or \"matrices\" without couplings")
                .rules(BY_MODEL).example("[1, 2]"),
            Key::new("right_boundary", "absent: none", "", "1-based, as many as left_boundary",
                "Right cyclic boundary dofs, paired in order with left_boundary")
                .rules(BY_MODEL).example("[7, 8]"),
            Key::new("boundary_frame", "absent: \"cylindrical\"", "",
                "\"cylindrical\" or \"cartesian\"",
                "How the boundary dofs are expressed: \"cylindrical\", they turn with the \
                 sector (u_R = e^{−iαs} u_L); \"cartesian\", node triples (x, y, z) in the \
                 sector's fixed frame, the next sector being this one turned by α = 2π/N \
                 about axis (u_R = e^{−iαs} R(α) u_L)")
                .rules(&[OneOf(&["cylindrical", "cartesian"])]).example("\"cartesian\""),
            Key::new("axis", "absent: \"z\"", "", "\"x\", \"y\" or \"z\"; with boundary_frame = \"cartesian\" \
                (kind = \"finite_element\": also the axis turning the left face onto the right one)",
                "Rotation axis of the wheel in the sector's Cartesian frame: \"x\", \"y\" or \"z\"")
                .rules(&[OneOf(&["x", "y", "z"])]).example("\"z\""),
        ],
    },
    Table {
        name: "model.reduction",
        doc: "Craig–Bampton reduction per nodal diameter of a finite-element sector.",
        keys: &[
            Key::new("internal_modes", "absent: `20`, the paper's", "", "integer ≥ 0",
                "With model.kind = \"finite_element\": fixed-interface modes kept per nodal \
                 diameter, after the retained dofs; the reduced models are cached in \
                 .cyclorub-cache next to the case file")
                .rules(BY_MODEL).example("20"),
        ],
    },
    Table {
        name: "model.damping",
        doc: "Damping of the sector model.",
        keys: &[
            Key::new("kind", "`\"modal\"`", "", "",
                "\"modal\" (ratio, or ratios and others), \"rayleigh\" (alpha, beta), \"matrix\" \
                 (matrix and coupling, or file) or \"none\"")
                .rules(&[OneOf(&["none", "modal", "rayleigh", "matrix"])]),
            Key::new("ratio", "absent: `1e-3`, the paper's", "", "≥ 0",
                "damping ratio of every mode")
                .rules(BY_MODEL).when(MODAL).example("1e-3"),
            Key::new("ratios", "absent: ratio applies", "", "≥ 0",
                "ratios by mode index within each nodal diameter's family, instead of ratio")
                .rules(BY_MODEL).when(MODAL).example("[1e-3, 1e-3, 1e-3, 1e-3, 1e-3]"),
            Key::new("others", "absent: the last of ratios, if it lists every mode", "", "≥ 0",
                "with ratios: ratio of the modes beyond the list")
                .rules(BY_MODEL).when(MODAL).example("5e-3"),
            Key::new("alpha", "absent: `0`", "1/s", "≥ 0", "mass factor of C = alpha M + beta K")
                .rules(BY_MODEL).when(RAYLEIGH).example("0.0"),
            Key::new("beta", "absent: `0`", "s", "≥ 0", "stiffness factor of C = alpha M + beta K")
                .rules(BY_MODEL).when(RAYLEIGH).example("1e-6"),
            Key::new("matrix", "required, or file", "N s/m", "list of rows, symmetric",
                "sector damping matrix, laid out like the stiffness")
                .rules(BY_MODEL).when(MATRIX).example("[[1.0, 0.0], [0.0, 1.0]]"),
            Key::new("coupling", "absent: none", "N s/m", "rows",
                "damping coupling block to the next sector, for block-circulant sectors")
                .rules(BY_MODEL).when(MATRIX).example("[[0.0, 0.0], [0.0, 0.0]]"),
            Key::new("file", "absent: matrix applies", "", "",
                "the damping matrix as a Matrix Market file relative to the case file's folder, \
                 instead of matrix")
                .rules(BY_MODEL).when(MATRIX).example("\"damping.mtx\""),
        ],
    },
    Table {
        name: "excitation",
        doc: "First-harmonic force on sector dofs (Eq. 48, 75, 86).",
        keys: &[
            Key::new("kind", "`\"traveling\"`", "", "",
                "\"traveling\" (Eq. 48, backward in blade numbering), \"standing\" (Eq. 75), \
                 \"mixed\" (Eq. 86), \"per_sector\" (amplitudes, phases) or \"none\"")
                .rules(&[OneOf(&["traveling", "standing", "mixed", "per_sector", "none"])]),
            Key::new("engine_order", "`1`", "", "integer, 0 ≤ h < model.sectors", "Engine order h")
                .rules(&[Below("model.sectors")]).when(EXCITED),
            Key::new("amplitude", "`4.0`", "N", "≥ 0", "Force amplitude f_ex")
                .rules(&[NonNegative]).when(EXCITED),
            Key::new("dofs", "`[1]`", "", "1-based, at least one",
                "Sector dofs where the force acts; 1 is the blade tip m1 of the academic model")
                .rules(&[Dofs]).when(EXCITED),
            Key::new("backward_weight", "`0.9`", "", "≥ 0; not both weights 0",
                "weight of the backward wave (Eq. 86: 0.9)")
                .rules(&[NonNegative]).when(When::Is("excitation.kind", "mixed")),
            Key::new("forward_weight", "`0.1`", "", "≥ 0; not both weights 0",
                "weight of the forward wave (Eq. 86: 0.1)")
                .rules(&[NonNegative]).when(When::Is("excitation.kind", "mixed")),
            Key::new("amplitudes", "`[]`", "", "one per sector",
                "amplitude factor of each sector, multiplies amplitude")
                .rules(&[CountOf("model.sectors")]).when(When::Is("excitation.kind", "per_sector")),
            Key::new("phases", "`[]`", "rad", "one per sector", "phase of each sector")
                .rules(&[CountOf("model.sectors")]).when(When::Is("excitation.kind", "per_sector")),
            Key::new("static_force", "`0.0`", "N", "finite",
                "Static force (harmonic 0) on the same dofs of every sector; 0: no preload")
                .rules(&[Finite]),
        ],
    },
    Table {
        name: "casing",
        doc: "The gap seen by each contact dof, Eq. (74): g0(t) = c + p cos(h_c (Ωt − 2πj/N)), \
              rotating with Ω = ω.",
        keys: &[
            Key::new("gap", "`1e-3`", "m", "≥ 0; one value, or one per contact dof",
                "Mean gap c between blade tip and casing")
                .rules(&[NonNegative, CheckedBy(Consumer::Casing)]),
            Key::new("order", "`0`", "", "integer < harmonic_balance.time_samples / 2",
                "Diametral order h_c of the casing shape; 0: circular")
                .rules(&[BelowHalf(
                    "harmonic_balance.time_samples",
                    "so that its gap is sampled without aliasing",
                )]),
            Key::new("amplitude", "`0.0`", "m",
                "≥ 0, ≤ gap when order > 0; one value, or one per contact dof",
                "Amplitude p of the diametral shape; the paper: 0.05 c")
                .rules(&[NonNegative, CheckedBy(Consumer::Casing)]),
            Key::new("gap_after_preload", "absent: true, the paper's", "", "true or false",
                "With [preload]: true, the gap is measured on the preloaded blade (the paper, \
                 Sec. 5.2: the preload shifts the static position, not the clearance); false, \
                 on the blade at rest (the static tip growth closes it)")
                .example("false"),
        ],
    },
    Table {
        name: "contact",
        doc: "Contact dofs and contact law.",
        keys: &[
            Key::new("law", "`\"regularized\"`", "", "",
                "\"regularized\" (R-HBM, Eq. 70: stiffness, regularization) or \"dlft\" \
                 (DLFT-HBM: epsilon, wall_stiffness)")
                .rules(&[OneOf(&["regularized", "dlft"])]),
            Key::new("dofs", "`[1]`", "", "1-based, at least one",
                "Contact dofs of a sector; positive displacement is toward the casing")
                .rules(&[Dofs]),
            Key::new("stiffness", "`1e8`", "N/m", "> 0", "contact stiffness κ")
                .rules(BY_LAW).when(REGULARIZED),
            Key::new("regularization", "`2.5`", "N", "≥ 0", "regularization γ; 0: the plain penalty law")
                .rules(BY_LAW).when(REGULARIZED),
            Key::new("epsilon", "`1e9`", "N/m", "> 0", "Lagrangian weight ε")
                .rules(BY_LAW).when(DLFT),
            Key::new("wall_stiffness", "absent: a rigid casing", "N/m", "> 0",
                "stiffness of the wall between tip and casing; the paper's academic runs: 1e8")
                .rules(BY_LAW).when(DLFT).example("1e8"),
            Key::new("friction", "absent: frictionless", "", "≥ 0",
                "Sliding friction coefficient μ, Eqs. (83)–(84): the casing rubs each contact \
                 node with μ f_N against its velocity (v_θ + ρΩ, v_z); the paper: 0.15")
                .rules(&[NonNegative]).example("0.15"),
            Key::new("circumferential_dofs", "required with friction", "",
                "1-based, one per contact dof",
                "With friction: the circumferential dof of each contact dof's node, positive \
                 in the direction of rotation")
                .rules(BY_LAW).example("[2]"),
            Key::new("axial_dofs", "required with friction", "", "1-based, one per contact dof",
                "With friction: the axial dof of each contact dof's node")
                .rules(BY_LAW).example("[3]"),
            Key::new("radius", "absent: from the model's node coordinates", "m",
                "≥ 0; one value, or one per contact dof",
                "With friction: the radius ρ of each contact node (finite-element sectors know \
                 it)")
                .rules(&[NonNegative, CheckedBy(ContactLaw)]).example("0.3"),
        ],
    },
    Table {
        name: "rotation",
        doc: "The wheel's rotation, which sets the sliding speed ρΩ of friction (used only \
              with contact.friction).",
        keys: &[
            Key::new("speed", "absent: required with friction unless synchronous", "rad/s",
                "finite; not with synchronous = true",
                "Rotation speed Ω; the paper: 1151.9 (11,000 rpm)")
                .rules(&[Finite, CheckedBy(ContactLaw)]).example("1151.9"),
            Key::new("synchronous", "absent: false, a fixed speed", "", "true or false",
                "Ω = ω along the sweep: the excitation synchronous with the rotation (the \
                 paper's choice, Sec. 5.2)")
                .example("true"),
        ],
    },
    Table {
        name: "preload",
        doc: "A static load on every sector alike (harmonic 0, nodal diameter 0), solved with \
              the response: the centrifugal force of the spinning wheel, or given per dof.",
        keys: &[
            Key::new("centrifugal", "absent: false", "", "true or false",
                "The centrifugal body force Ω² M r of the finite-element sector at preload.speed, \
                 its static response solved on the full sector (model.kind = \"finite_element\")")
                .example("true"),
            Key::new("speed", "absent: rotation.speed", "rad/s", "≥ 0",
                "The speed Ω of the centrifugal force; the paper: 1151.9 (11,000 rpm)")
                .rules(&[NonNegative, CheckedBy(Consumer::Model)]).example("1151.9"),
            Key::new("static_forces", "absent: none", "N", "finite; one per dof of a sector",
                "A static force on each dof of every sector (added to the centrifugal one)")
                .rules(&[CheckedBy(Consumer::Model)]).example("[0.0, 0.0, 0.0, 0.0, 0.0]"),
        ],
    },
    Table {
        name: "harmonic_balance",
        doc: "Harmonic balance discretization.",
        keys: &[
            Key::new("harmonics", "`10`", "", "integer ≥ 1", "Number of harmonics N_h")
                .rules(&[AtLeast(1)]),
            Key::new("time_samples", "`10000`", "", "integer ≥ 2 N_h + 1",
                "Time samples per period N_t; a multiple of N makes reduced and full agree to \
                 round-off")
                .rules(&[AboveTwice("harmonic_balance.harmonics")]),
        ],
    },
    Table {
        name: "continuation",
        doc: "Pseudo-arc-length continuation in frequency; steps are scaled (one gap of \
              displacement and the whole range each count 1).",
        keys: &[
            Key::new("start_hz", "absent: `0.95 f₁`", "Hz", "> 0",
                "Start frequency; f₁ is the first natural frequency of the excited nodal diameter")
                .rules(&[Positive]),
            Key::new("end_hz", "absent: `1.10 f₁`", "Hz", "> 0, ≠ start_hz",
                "End frequency; below the start to sweep down")
                .rules(&[Positive, Differs("continuation.start_hz", "the frequency range is empty")]),
            Key::new("initial_step", "`0.01`", "", "> 0, ≤ max_step", "First step, scaled arc length")
                .rules(&[Positive, AtMost("continuation.max_step")]),
            Key::new("min_step", "`1e-7`", "", "> 0, ≤ max_step",
                "Smallest step; the run stops when it would go below")
                .rules(&[Positive, AtMost("continuation.max_step")]),
            Key::new("max_step", "`0.1`", "", "> 0", "Largest step").rules(&[Positive]),
            Key::new("tolerance", "`1e-8`", "", "> 0, ≤ 1e-3",
                "Newton tolerance on ‖R‖ / f_ex (a looser one would accept predictor points unsolved)")
                .rules(&[Positive, NoMoreThan(1e-3)]),
            Key::new("max_iterations", "`15`", "", "integer ≥ 1", "Newton iterations per step")
                .rules(&[AtLeast(1)]),
            Key::new("max_points", "`5000`", "", "integer ≥ 1",
                "Cap on the number of points, both sweeps together; the run stops there")
                .rules(&[AtLeast(1)]),
            Key::new("dlft_predictor", "`\"tangent\"`", "", "",
                "Prediction on DLFT-HBM branches: \"tangent\" (steps of at most 0.03, every \
                 kink that refuses one located and turned: for sharp nonsmooth folds, the \
                 academic cases) or \"secant\" (along the last chord, up to max_step: for \
                 finely sampled contact, whose short pieces tilt each point's tangent, e.g. \
                 the open fan at 2000 instants)")
                .rules(&[OneOf(&["tangent", "secant"])]),
        ],
    },
    Table {
        name: "basis",
        doc: "Which unknowns are solved for (`cyclorub plan` shows their sizes).",
        keys: &[Key::new("kind", "`\"symmetry\"`", "", "",
            "\"symmetry\" (the smallest exact basis), \"paper\" (the paper's choice), \
             \"nodal_diameter\", \"full\" (every pair) or \"physical\" (the full wheel, the \
             reference); `cyclorub run --basis` overrides it")
            .rules(&[OneOf(&["symmetry", "paper", "nodal_diameter", "full", "physical"])])],
    },
    Table {
        name: "output",
        doc: "Result files: branch.csv, run.json, results.h5 (and observed_harmonics.csv on demand).",
        keys: &[
            Key::new("directory", "`\"results\"`", "", "",
                "Results folder, relative to the working directory; `cyclorub run --output` \
                 overrides it"),
            Key::new("observed_dof", "`1`", "", "1..=the dofs of a sector",
                "Dof whose amplitude branch.csv reports")
                .rules(BY_MODEL),
            Key::new("sectors", "`[]`", "", "1..=model.sectors; [] for all",
                "Sectors reported in branch.csv")
                .rules(&[OneTo("model.sectors")]),
            Key::new("harmonics_csv", "`false`", "", "true or false",
                "Also write observed_harmonics.csv (the observed dof's harmonic coordinates \
                 per point and reported sector, 11 KB per point on the default case; \
                 results.h5 holds them anyway)"),
            Key::new("contact_harmonics", "`false`", "", "true or false",
                "Keep the harmonic coordinates of every contact force per point in \
                 results.h5 (N · n_c · (2N_h + 1) values per point); `cyclorub recover` \
                 gives any dof after the run"),
            Key::new("peak_histories", "`false`", "", "true or false",
                "Keep the time histories (displacement, velocity, contact force, penetration) \
                 of the point of largest amplitude on every sector in results.h5 (/peak: \
                 8 MB on the default case); `cyclorub recover` gives them after the run"),
            Key::new("figures", "`[\"svg\", \"png\"]`", "", "a list of \"svg\", \"png\"",
                "Formats of the figures in plots/: \"svg\" (always written), \"png\" (each \
                 figure also as a PNG at 300 dpi, rasterized from its SVG with an embedded \
                 font, for reports and slides); [\"svg\"] skips the PNGs")
                .rules(&[OneOf(&["svg", "png"])]),
        ],
    },
    Table {
        name: "mistuning",
        doc: "A mistuned wheel (issue 44): the blade stiffness of sector j scaled by 1 + δ_j, \
              solved on the full wheel (basis.kind = \"physical\"); absent: a tuned wheel.",
        keys: &[
            Key::new("deviations", "absent: none", "", "one per sector, each finite and > −1",
                "The deviations δ_1 … δ_N of the sectors' blade stiffness; not with \
                 standard_deviation")
                .rules(&[CountOf("model.sectors")]).example("[0.01, -0.005, 0.0]"),
            Key::new("standard_deviation", "absent: none", "", "≥ 0; not with deviations",
                "Draw the deviations at random with this standard deviation (e.g. 0.01 for 1 %)")
                .rules(&[NonNegative]).example("0.01"),
            Key::new("seed", "absent: `0`", "", "integer ≥ 0",
                "Seed of the drawn deviations: the same seed, the same pattern")
                .example("1"),
            Key::new("distribution", "absent: \"normal\"", "", "",
                "Law of the drawn deviations: \"normal\" (mean 0) or \"uniform\" (on ±√3 σ)")
                .rules(&[OneOf(&["normal", "uniform"])]).example("\"uniform\""),
            Key::new("blade_dofs", "absent: `[1, 2, 3]`", "", "dofs of a sector, from 1",
                "The blade's dofs: on the academic model the springs joining two of them are \
                 scaled (m1 the tip, m2, m3: the root spring m3–m4 is not); on inline matrices \
                 (kind = \"matrices\") the stiffness entries between two of them")
                .rules(&[Dofs]).example("[1, 2, 3]"),
            Key::new("blade_node_set", "absent: \"blade\"", "", "a list of model.node_sets_file",
                "On finite-element sectors (kind = \"finite_element\"), the blade's node set: \
                 the sector stiffness entries between two of its nodes are scaled, projected on \
                 the tuned Craig–Bampton bases (cyclorub mesh fan writes \"blade\": the blade \
                 above its root section)")
                .example("\"blade\""),
        ],
    },
    Table {
        name: "stability",
        doc: "Stability of every point: Floquet exponents by Hill's method in every symmetry \
              class (nodal diameter of the perturbation); branch.csv's stable column, the \
              markers in run.json.",
        keys: &[
            Key::new("enabled", "`true`", "", "true or false",
                "Check every point of the branch; `cyclorub run --no-stability` skips it"),
            Key::new("harmonics", "absent: harmonic_balance.harmonics", "", "integer ≥ 1",
                "Harmonics of Hill's truncation; raise it to check the exponents converge")
                .rules(&[AtLeast(1)])
                .example("20"),
        ],
    },
];
