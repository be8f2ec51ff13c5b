//! The stability check of a problem's points: classes and local matrices
//! prepared once, then every point's exponents, class by class in parallel.

use super::classes::{symmetry_classes, SymmetryClass};
use super::condensed::{
    dense_in_region, followed_exponents, linear_in_region, ClassTrack, Following, Region,
};
use super::contact_stiffness::{
    ContactStiffness, ContactTerm, SpaceTimeTable, StiffnessSpectrum, TermKind,
};
use super::hill::{physical_exponents, physical_modes, Group, LocalDynamics, Picked};
use super::markers::{markers, BranchStability};
use super::modes::{normalized, sector_mode, wheel_mode, FloquetMode};
use super::off_contact::OffContact;
use super::settings::{HillSolver, StabilitySettings};
use super::spectrum::{ClassSpectrum, Exponent, PointStability};
use super::targeted::{targeted_classes, ClassBlock};
use super::validated::{with_friction_nodes, Common};
use super::StabilityError;
use crate::basis::PairLattice;
use crate::continuation::{Interrupt, Point};
use crate::cyclic::SignedPair;
use crate::hbm::layout::BlockKind;
use crate::hbm::HarmonicBalance;
use crate::model::SectorModel;
use faer::{c64, Mat};
use rayon::prelude::*;
use std::collections::BTreeMap;
use std::sync::Arc;

enum Wheel {
    /// One block per class, on the sector's matrices of each diameter.
    Classes {
        classes: Vec<SymmetryClass>,
        dynamics: BTreeMap<i64, Arc<LocalDynamics>>,
    },
    /// The whole wheel in physical coordinates: one block (the reference).
    Physical { dynamics: Arc<LocalDynamics> },
}

/// The stability check of the points of one harmonic balance problem.
pub struct Stability<'a> {
    problem: &'a HarmonicBalance,
    contact_dofs: Vec<usize>,
    dofs: usize,
    harmonics: usize,
    time_samples: usize,
    tolerance: f64,
    solver: HillSolver,
    wheel: Wheel,
    off_contact: Option<OffContact>,
}

impl<'a> Stability<'a> {
    /// The check of `problem`'s points on `model` with `contact_dofs` (the
    /// sector's normal contact dofs, 0-based, as the case lists them; with
    /// friction the nodes' tangential dofs are taken from `problem`): by
    /// symmetry classes for a cyclic basis (the subgroup its pairs
    /// generate), on the whole wheel for the physical formulation.
    pub fn new(
        model: &SectorModel,
        problem: &'a HarmonicBalance,
        contact_dofs: &[usize],
        settings: &StabilitySettings,
    ) -> Result<Self, StabilityError> {
        let layout = problem.layout();
        let pairs: Vec<SignedPair> = layout
            .blocks
            .iter()
            .filter_map(|b| match b.kind {
                BlockKind::Pair { nodal_diameter } => Some(SignedPair {
                    nodal_diameter,
                    harmonic: b.harmonic as i64,
                }),
                BlockKind::Wheel => None,
            })
            .collect();
        if pairs.is_empty() {
            return Self::full_wheel(model, problem, contact_dofs, settings);
        }
        let contact_dofs = with_friction_nodes(problem, contact_dofs)?;
        let common = Common::new(model, problem, &contact_dofs, settings)?;
        let lattice = PairLattice::generated_by(layout.sectors, &pairs)?;
        let classes = symmetry_classes(&lattice, common.harmonics);
        let pairs = classes.first().map_or(0, |c| c.pairs.len());
        common.refuse_above(pairs, 1, settings)?;
        let mut dynamics = BTreeMap::new();
        for class in &classes {
            for pair in &class.pairs {
                if dynamics.contains_key(&pair.nodal_diameter) {
                    continue;
                }
                let m = model.nodal_diameter_matrices(pair.nodal_diameter)?;
                let what = format!("nodal diameter {}", pair.nodal_diameter);
                let local = LocalDynamics::new(&m.mass, &m.stiffness, &m.damping, &what)?;
                dynamics.insert(pair.nodal_diameter, Arc::new(local));
            }
        }
        // The weak-contact bound and the targeted solver hold the normal
        // stiffness alone: with friction every point is solved densely.
        let off_contact = if settings.weak_contact_shortcut && problem.friction().is_none() {
            OffContact::new(model, &classes, &common.contact_dofs)?
        } else {
            None
        };
        Ok(common.with(problem, Wheel::Classes { classes, dynamics }, off_contact))
    }

    /// The check on the whole wheel in physical coordinates, one block of
    /// every pair (Hill's method without symmetry: the reference), whatever
    /// basis `problem` was solved on.
    pub fn full_wheel(
        model: &SectorModel,
        problem: &'a HarmonicBalance,
        contact_dofs: &[usize],
        settings: &StabilitySettings,
    ) -> Result<Self, StabilityError> {
        let contact_dofs = with_friction_nodes(problem, contact_dofs)?;
        let common = Common::new(model, problem, &contact_dofs, settings)?;
        common.refuse_above(2 * common.harmonics + 1, model.sectors(), settings)?;
        let wheel = model.full_wheel()?;
        let complex =
            |m: &Mat<f64>| Mat::from_fn(m.nrows(), m.ncols(), |r, c| c64::new(m[(r, c)], 0.0));
        let local = LocalDynamics::new(
            &complex(&wheel.mass),
            &complex(&wheel.stiffness),
            &complex(&wheel.damping),
            "the whole wheel",
        )?;
        Ok(common.with(
            problem,
            Wheel::Physical {
                dynamics: Arc::new(local),
            },
            None,
        ))
    }

    /// Harmonics of Hill's truncation.
    pub fn harmonics(&self) -> usize {
        self.harmonics
    }

    /// The symmetry classes (empty on the whole wheel).
    pub fn classes(&self) -> &[SymmetryClass] {
        match &self.wheel {
            Wheel::Classes { classes, .. } => classes,
            Wheel::Physical { .. } => &[],
        }
    }

    /// The exponents of every class at the converged point `(x, omega)`.
    pub fn point(&self, x: &[f64], omega: f64) -> Result<PointStability, StabilityError> {
        self.point_following(x, omega, None).map(|(point, _)| point)
    }

    /// [`Self::point`] at the next point of a branch, the condensed
    /// solver's exponents followed from `previous` (what the previous
    /// point returned) where they moved little (docs/design.md §10); with
    /// what the next point can follow from.
    pub fn point_following(
        &self,
        x: &[f64],
        omega: f64,
        previous: Option<&Following>,
    ) -> Result<(PointStability, Following), StabilityError> {
        if !(omega.is_finite() && omega > 0.0) {
            return Err(StabilityError::Setting {
                key: "omega",
                value: omega.to_string(),
                allowed: "a finite angular frequency > 0",
            });
        }
        let stiffness = ContactStiffness::sample(self.problem, x, omega, self.time_samples)?;
        let peak = stiffness.peak();
        // The shortcut gives the dense pick's linear exponents; for the
        // condensed solver, the linear wheel's in its region.
        let weak = self.off_contact.as_ref().and_then(|o| o.spectra(peak));
        if let (Some((_, bound)), HillSolver::Condensed, Wheel::Classes { classes, dynamics }) =
            (weak, self.solver, &self.wheel)
        {
            let classes = classes
                .iter()
                .map(|class| {
                    let groups = self.class_groups(class, dynamics);
                    let step = class.harmonic_step.max(1) as f64;
                    linear_in_region(&groups, omega, step, &REGION)
                        .map(|picked| spectrum(class.nodal_diameter, &picked, false, false))
                })
                .collect::<Result<_, _>>()?;
            let point = PointStability {
                omega,
                classes,
                tolerance: self.tolerance * omega,
                peak_contact_stiffness: peak,
                off_contact_bound: Some(bound),
            };
            return Ok((point, Following::default()));
        }
        let linear = match self.solver {
            HillSolver::Condensed | HillSolver::DenseRegion => None,
            _ => weak,
        };
        let mut following = Following::default();
        let (classes, off_contact_bound) = match (linear, &self.wheel) {
            (Some((spectra, bound)), _) => (spectra.to_vec(), Some(bound)),
            (None, Wheel::Classes { classes, dynamics }) => {
                let spectrum = stiffness.spectrum(2 * self.harmonics);
                // The targeted solver rarely vouches where the contact can
                // move the exponents by far more than ω (it then costs
                // about half a dense solve for nothing).
                let solver = match self.off_contact.as_ref() {
                    Some(o)
                        if self.solver == HillSolver::Targeted
                            && o.bound(peak) > TARGETED_UP_TO * omega =>
                    {
                        HillSolver::Dense
                    }
                    _ => self.solver,
                };
                let solved =
                    self.by_class(classes, dynamics, &spectrum, omega, solver, previous)?;
                following = solved.1;
                (solved.0, None)
            }
            (None, Wheel::Physical { dynamics }) => {
                let spectrum = stiffness.spectrum(2 * self.harmonics);
                let (class, track) = self.whole_wheel(dynamics, &spectrum, omega, previous)?;
                if let Some(track) = track {
                    following.insert(0, track);
                }
                (vec![class], None)
            }
        };
        let point = PointStability {
            omega,
            classes,
            tolerance: self.tolerance * omega,
            peak_contact_stiffness: peak,
            off_contact_bound,
        };
        Ok((point, following))
    }

    /// The `count` exponents of largest real part of class `class` (its
    /// nodal diameter `σ`, as in [`Self::classes`]; 0 on the whole wheel)
    /// at the converged point `(x, omega)`, each with its mode on the full
    /// wheel at `t = 0` ([`FloquetMode`]), largest real part first. Always
    /// the dense eigenproblem of the class (Hill's method even where
    /// [`Self::point`] takes the weak-contact shortcut).
    pub fn modes(
        &self,
        x: &[f64],
        omega: f64,
        class: i64,
        count: usize,
    ) -> Result<Vec<FloquetMode>, StabilityError> {
        if !(omega.is_finite() && omega > 0.0) {
            return Err(StabilityError::Setting {
                key: "omega",
                value: omega.to_string(),
                allowed: "a finite angular frequency > 0",
            });
        }
        let available = || match &self.wheel {
            Wheel::Classes { classes, .. } => classes
                .iter()
                .map(|c| c.nodal_diameter.to_string())
                .collect::<Vec<_>>()
                .join(", "),
            Wheel::Physical { .. } => "0 (the whole wheel)".into(),
        };
        let no_class = || StabilityError::NoClass {
            class,
            available: available(),
        };
        let stiffness = ContactStiffness::sample(self.problem, x, omega, self.time_samples)?;
        let spectrum = stiffness.spectrum(2 * self.harmonics);
        // Where each group of the eigenvector sits on the wheel.
        enum Groups {
            Pairs(Vec<(i64, i64)>),
            Harmonics(Vec<i64>, usize),
        }
        let (picked, groups) = match &self.wheel {
            Wheel::Classes { classes, dynamics } => {
                let chosen = classes
                    .iter()
                    .find(|c| c.nodal_diameter == class)
                    .ok_or_else(no_class)?;
                let table = spectrum.space_time_table();
                let b = self.class_block(chosen, dynamics, &table);
                let picked =
                    physical_modes(&b.groups, &b.coupling, &b.damping, omega, b.step, true)?;
                let pairs = chosen
                    .pairs
                    .iter()
                    .map(|p| (p.nodal_diameter, p.harmonic))
                    .collect();
                (picked, Groups::Pairs(pairs))
            }
            Wheel::Physical { dynamics } => {
                if class != 0 {
                    return Err(no_class());
                }
                let (groups, coupling, damping) = self.wheel_block(dynamics, &spectrum);
                let picked = physical_modes(&groups, &coupling, &damping, omega, 1, true)?;
                let harmonics = groups.iter().map(|g| g.harmonic).collect();
                (picked, Groups::Harmonics(harmonics, dynamics.dofs()))
            }
        };
        let sectors = self.problem.layout().sectors;
        let map = |q: &[c64], lambda: c64| match &groups {
            Groups::Pairs(pairs) => sector_mode(q, pairs, self.dofs, sectors, lambda, omega),
            Groups::Harmonics(harmonics, size) => wheel_mode(q, harmonics, *size, lambda, omega),
        };
        picked
            .into_iter()
            .take(count)
            .map(|(p, q)| {
                let (y, v) = map(&q, p.exponent);
                let (displacement, velocity) =
                    normalized(y, v).ok_or_else(|| StabilityError::Eigen {
                        message: format!(
                            "the mode of the exponent {:.6e} {:+.6e}i of class {class} vanishes at t = 0",
                            p.exponent.re, p.exponent.im
                        ),
                    })?;
                Ok(FloquetMode {
                    nodal_diameter: class,
                    exponent: Exponent::new(p.exponent),
                    omega,
                    truncation: p.edge,
                    displacement,
                    velocity,
                })
            })
            .collect()
    }

    /// The stability of every point of a branch (in parallel) and the
    /// markers between them; `points` in branch order.
    pub fn branch(&self, points: &[Point]) -> Result<BranchStability, StabilityError> {
        self.branch_until(points, &Interrupt::new())
    }

    /// [`Self::branch`], given up with [`StabilityError::Interrupted`] once
    /// `interrupt` is raised.
    pub fn branch_until(
        &self,
        points: &[Point],
        interrupt: &Interrupt,
    ) -> Result<BranchStability, StabilityError> {
        // Contiguous runs of points, one per thread, each followed from
        // point to point (the classes of a point are solved in parallel too).
        let run = points
            .len()
            .div_ceil(rayon::current_num_threads().max(1))
            .max(1);
        let runs: Vec<Vec<PointStability>> = points
            .par_chunks(run)
            .map(|chunk| {
                let mut following: Option<Following> = None;
                let mut out = Vec::with_capacity(chunk.len());
                for p in chunk {
                    if interrupt.raised() {
                        return Err(StabilityError::Interrupted);
                    }
                    let (point, next) =
                        self.point_following(&p.unknowns, p.omega, following.as_ref())?;
                    following = Some(next);
                    out.push(point);
                }
                Ok(out)
            })
            .collect::<Result<_, _>>()?;
        let stabilities: Vec<PointStability> = runs.into_iter().flatten().collect();
        let markers = markers(&stabilities, !self.classes().is_empty());
        Ok(BranchStability {
            harmonics: self.harmonics,
            solved_by_hill: stabilities
                .iter()
                .filter(|p| p.off_contact_bound.is_none())
                .count(),
            points: stabilities,
            markers,
        })
    }

    fn by_class(
        &self,
        classes: &[SymmetryClass],
        dynamics: &BTreeMap<i64, Arc<LocalDynamics>>,
        stiffness: &StiffnessSpectrum,
        omega: f64,
        solver: HillSolver,
        previous: Option<&Following>,
    ) -> Result<(Vec<ClassSpectrum>, Following), StabilityError> {
        let table = stiffness.space_time_table();
        let block = |class| self.class_block(class, dynamics, &table);
        if matches!(solver, HillSolver::Condensed | HillSolver::DenseRegion) {
            let dense = solver == HillSolver::DenseRegion;
            type Solved = (i64, Vec<Picked>, Option<ClassTrack>);
            let solved: Vec<Solved> = classes
                .par_iter()
                .filter(|c| c.nodal_diameter >= 0)
                .map(|class| {
                    let b = block(class);
                    let (groups, coupling, damping) = (&b.groups, &b.coupling, &b.damping);
                    let picked = if dense {
                        let step = b.step.max(1) as f64;
                        dense_in_region(groups, coupling, damping, omega, step, &REGION)
                            .map(|picked| (picked, None))
                    } else {
                        let track = previous.and_then(|p| p.class(class.nodal_diameter));
                        followed_exponents(groups, coupling, damping, omega, b.step, &REGION, track)
                    };
                    picked.map(|(picked, track)| (class.nodal_diameter, picked, track))
                })
                .collect::<Result<_, _>>()?;
            let mut following = Following::default();
            for (nodal_diameter, _, track) in &solved {
                if let Some(track) = track {
                    following.insert(*nodal_diameter, track.clone());
                }
            }
            let spectra = classes
                .iter()
                .map(|class| {
                    let step = class.harmonic_step.max(1) as f64 * omega;
                    if let Some((_, picked, _)) =
                        solved.iter().find(|(s, ..)| *s == class.nodal_diameter)
                    {
                        return Ok(spectrum(class.nodal_diameter, picked, false, false));
                    }
                    let (_, picked, _) = solved
                        .iter()
                        .find(|(s, ..)| *s == class.conjugate)
                        .ok_or_else(|| StabilityError::Eigen {
                            message: format!(
                                "neither class {} nor its conjugate {} was solved",
                                class.nodal_diameter, class.conjugate
                            ),
                        })?;
                    let mut mirrored = spectrum(class.nodal_diameter, picked, dense, true);
                    // The strip is (−gω/2, gω/2]: a conjugate exactly on its
                    // lower edge has its copy on the upper edge in another
                    // class, not in this one.
                    mirrored
                        .exponents
                        .retain(|e| e.im > -0.5 * step * (1.0 - 1e-12));
                    Ok(mirrored)
                })
                .collect::<Result<_, StabilityError>>()?;
            return Ok((spectra, following));
        }
        // Classes the targeted pass already solved densely, and its blocks:
        // the dense fallback below does not solve or build them again.
        let mut solved_densely: BTreeMap<i64, Vec<Picked>> = BTreeMap::new();
        let mut built: Vec<ClassBlock> = Vec::new();
        if solver == HillSolver::Targeted {
            let blocks: Vec<ClassBlock> = classes.iter().map(block).collect();
            let targeted = targeted_classes(&blocks, omega);
            let results: Vec<(ClassSpectrum, Option<Vec<Picked>>)> = classes
                .par_iter()
                .zip(&blocks)
                .zip(targeted)
                .map(|((class, b), picked)| match picked {
                    Some(picked) => {
                        Ok((spectrum(class.nodal_diameter, &picked, false, false), None))
                    }
                    None => physical_exponents(&b.groups, &b.coupling, &b.damping, omega, b.step)
                        .map(|picked| {
                            (
                                spectrum(class.nodal_diameter, &picked, true, false),
                                Some(picked),
                            )
                        }),
                })
                .collect::<Result<_, _>>()?;
            // Each targeted class is a subset of its dense pick: with the
            // wheel's count in all, every one is the whole pick.
            let families: usize = classes
                .iter()
                .map(|c| 2 * self.dofs * c.diameters_at_rest)
                .sum();
            // Where the truncation bites, a family may also be counted
            // twice by the dense pick: the count vouches only where every
            // eigenvector found stays off the highest harmonics.
            let count: usize = results.iter().map(|(c, _)| c.exponents.len()).sum();
            let resolved = results
                .iter()
                .all(|(c, _)| c.dense || c.truncation <= TARGETED_TRUNCATION);
            if count == families && resolved {
                let spectra = results.into_iter().map(|(c, _)| c).collect();
                return Ok((spectra, Following::default()));
            }
            for (class, (_, picked)) in classes.iter().zip(results) {
                if let Some(picked) = picked {
                    solved_densely.insert(class.nodal_diameter, picked);
                }
            }
            built = blocks;
        }
        // A class and its conjugate have conjugate spectra: solve one of each.
        let solved: Vec<(i64, Vec<Picked>, bool)> = classes
            .par_iter()
            .enumerate()
            .filter(|(_, c)| c.nodal_diameter >= 0)
            .map(|(i, class)| {
                if let Some(picked) = solved_densely.get(&class.nodal_diameter) {
                    return Ok((class.nodal_diameter, picked.clone(), true));
                }
                let fresh;
                let b = match built.get(i) {
                    Some(b) => b,
                    None => {
                        fresh = block(class);
                        &fresh
                    }
                };
                physical_exponents(&b.groups, &b.coupling, &b.damping, omega, b.step)
                    .map(|picked| (class.nodal_diameter, picked, true))
            })
            .collect::<Result<_, _>>()?;
        classes
            .iter()
            .map(|class| {
                let direct = solved.iter().find(|(s, ..)| *s == class.nodal_diameter);
                let conjugate = solved.iter().find(|(s, ..)| *s == class.conjugate);
                let (picked, dense, conjugate) = match (direct, conjugate) {
                    (Some((_, picked, dense)), _) => (picked, *dense, false),
                    (None, Some((_, picked, dense))) => (picked, *dense, true),
                    (None, None) => {
                        return Err(StabilityError::Eigen {
                            message: format!(
                                "neither class {} nor its conjugate {} was solved",
                                class.nodal_diameter, class.conjugate
                            ),
                        })
                    }
                };
                Ok(spectrum(class.nodal_diameter, picked, dense, conjugate))
            })
            .collect::<Result<_, _>>()
            .map(|spectra| (spectra, Following::default()))
    }

    /// One class's Hill block: a group per pair, the contact stiffness
    /// between them.
    fn class_block<'c>(
        &self,
        class: &'c SymmetryClass,
        dynamics: &BTreeMap<i64, Arc<LocalDynamics>>,
        table: &SpaceTimeTable,
    ) -> ClassBlock<'c> {
        let groups = self.class_groups(class, dynamics);
        let (mut coupling, mut damping) = (Vec::new(), Vec::new());
        for (row, p) in class.pairs.iter().enumerate() {
            for (col, q) in class.pairs.iter().enumerate() {
                for (t, term) in table.terms().iter().enumerate() {
                    let value = table.at(
                        t,
                        p.nodal_diameter - q.nodal_diameter,
                        p.harmonic - q.harmonic,
                    );
                    let (r, c) = self.term_dofs(term);
                    let entry = (row * self.dofs + r, col * self.dofs + c, value);
                    match term.kind {
                        TermKind::Stiffness => coupling.push(entry),
                        TermKind::Damping => damping.push(entry),
                    }
                }
            }
        }
        ClassBlock {
            pairs: &class.pairs,
            groups,
            coupling,
            damping,
            step: class.harmonic_step as i64,
        }
    }

    /// One group per pair of a class, on its diameter's dynamics.
    fn class_groups(
        &self,
        class: &SymmetryClass,
        dynamics: &BTreeMap<i64, Arc<LocalDynamics>>,
    ) -> Vec<Group> {
        class
            .pairs
            .iter()
            .map(|p| Group {
                harmonic: p.harmonic,
                dynamics: Arc::clone(&dynamics[&p.nodal_diameter]),
            })
            .collect()
    }

    /// The sector dofs of a term's row and column.
    fn term_dofs(&self, term: &ContactTerm) -> (usize, usize) {
        (self.contact_dofs[term.row], self.contact_dofs[term.column])
    }

    fn whole_wheel(
        &self,
        dynamics: &Arc<LocalDynamics>,
        stiffness: &StiffnessSpectrum,
        omega: f64,
        previous: Option<&Following>,
    ) -> Result<(ClassSpectrum, Option<ClassTrack>), StabilityError> {
        let (groups, coupling, damping) = self.wheel_block(dynamics, stiffness);
        if self.solver == HillSolver::Condensed {
            let track = previous.and_then(|p| p.class(0));
            let (picked, track) =
                followed_exponents(&groups, &coupling, &damping, omega, 1, &REGION, track)?;
            return Ok((spectrum(0, &picked, false, false), track));
        }
        if self.solver == HillSolver::DenseRegion {
            let picked = dense_in_region(&groups, &coupling, &damping, omega, 1.0, &REGION)?;
            return Ok((spectrum(0, &picked, true, false), None));
        }
        let picked = physical_exponents(&groups, &coupling, &damping, omega, 1)?;
        Ok((spectrum(0, &picked, true, false), None))
    }

    /// The whole wheel's Hill block: one group per harmonic `−H..=H`, the
    /// linearized contact of every sector between them (stiffness, then
    /// velocity terms).
    fn wheel_block(&self, dynamics: &Arc<LocalDynamics>, stiffness: &StiffnessSpectrum) -> Block {
        let h = self.harmonics as i64;
        let sectors = dynamics.dofs() / self.dofs;
        let groups: Vec<Group> = (-h..=h)
            .map(|k| Group {
                harmonic: k,
                dynamics: Arc::clone(dynamics),
            })
            .collect();
        let size = dynamics.dofs();
        let (mut coupling, mut damping) = (Vec::new(), Vec::new());
        for (row, p) in groups.iter().enumerate() {
            for (col, q) in groups.iter().enumerate() {
                for j in 0..sectors {
                    for (t, term) in stiffness.terms().iter().enumerate() {
                        let value = stiffness.sector_coefficient(j, t, p.harmonic - q.harmonic);
                        let (r, c) = self.term_dofs(term);
                        let (r, c) = (j * self.dofs + r, j * self.dofs + c);
                        let entry = (row * size + r, col * size + c, value);
                        match term.kind {
                            TermKind::Stiffness => coupling.push(entry),
                            TermKind::Damping => damping.push(entry),
                        }
                    }
                }
            }
        }
        (groups, coupling, damping)
    }
}

/// A Hill block: its groups, the contact stiffness and velocity terms
/// between their dofs.
type Block = (
    Vec<Group>,
    Vec<(usize, usize, c64)>,
    Vec<(usize, usize, c64)>,
);

/// Above this bound (in units of `ω`) on how far the contact moves the
/// linear exponents, the dense solver is used directly: on the default
/// case the targeted one vouches for most points below 100 and for none
/// of the contact plateau (about 1450).
const TARGETED_UP_TO: f64 = 100.0;

/// Where the condensed solver seeks each class's exponents.
const REGION: Region = Region {
    margin: 0.05,
    upper: 0.5,
};

/// The largest share of a targeted eigenvector on the highest harmonics
/// for the count to vouch for the targeted classes.
const TARGETED_TRUNCATION: f64 = 1e-3;

impl Common {
    /// The check of `problem` on `wheel`.
    fn with(
        self,
        problem: &HarmonicBalance,
        wheel: Wheel,
        off_contact: Option<OffContact>,
    ) -> Stability<'_> {
        Stability {
            problem,
            contact_dofs: self.contact_dofs,
            dofs: self.dofs,
            harmonics: self.harmonics,
            time_samples: self.time_samples,
            tolerance: self.tolerance,
            solver: self.solver,
            wheel,
            off_contact,
        }
    }
}

fn spectrum(nodal_diameter: i64, picked: &[Picked], dense: bool, conjugate: bool) -> ClassSpectrum {
    let exponents = picked
        .iter()
        .map(|p| {
            Exponent::new(if conjugate {
                p.exponent.conj()
            } else {
                p.exponent
            })
        })
        .collect();
    ClassSpectrum {
        nodal_diameter,
        exponents,
        truncation: picked.iter().map(|p| p.edge).fold(0.0, f64::max),
        dense,
    }
}
