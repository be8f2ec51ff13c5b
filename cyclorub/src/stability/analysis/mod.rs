//! The stability check of a problem's points: classes and local matrices
//! prepared once, then every point's exponents, class by class in parallel.

mod by_class;
mod floquet_modes;

use super::classes::{symmetry_classes, SymmetryClass};
use super::condensed::{linear_in_region, Following};
use super::contact_stiffness::{ContactStiffness, SectorSampling};
use super::hill::LocalDynamics;
use super::markers::{markers, BranchStability};
use super::off_contact::OffContact;
use super::settings::{HillSolver, StabilitySettings};
use super::spectrum::{Exponent, PointStability};
use super::validated::{with_friction_nodes, Common};
use super::StabilityError;
use crate::basis::PairLattice;
use crate::continuation::{Interrupt, Point};
use crate::cyclic::SignedPair;
use crate::hbm::layout::BlockKind;
use crate::hbm::HarmonicBalance;
use crate::model::SectorModel;
use by_class::{spectrum, REGION, TARGETED_UP_TO};
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
    /// The gaps and repeating sectors, the same at every point.
    sampling: SectorSampling,
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
        // The weak-contact bound holds the normal stiffness alone: with
        // friction every point in contact is solved by Hill's method.
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

    /// The growth tolerance, in units of `ω`: a real part above
    /// `tolerance · ω` counts as growth.
    pub fn tolerance(&self) -> f64 {
        self.tolerance
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

    /// Whether the classes tell a real crossing's kind: one of class 0 is
    /// then a fold (the solution's own symmetry), of another a branch
    /// point. Not on the whole wheel (no classes), nor on a basis that
    /// holds every nodal diameter at rest (the full basis: its one class
    /// holds the symmetry-breaking perturbations too, and its real
    /// crossings are real crossings of unknown kind).
    pub fn classes_tell_kinds(&self) -> bool {
        match self.classes() {
            [] => false,
            [only] => only.diameters_at_rest == 1,
            _ => true,
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
        let stiffness = self.contact_stiffness(x, omega)?;
        let peak = stiffness.peak();
        // The shortcut gives the dense pick's linear exponents; for the
        // condensed solver, the linear wheel's in its region.
        // Without contact (every term zero, friction's included) the
        // exponents are the linear wheel's exactly: bound 0.
        let weak = self.off_contact.as_ref().and_then(|o| o.spectra(peak));
        let shortcut = match weak {
            _ if stiffness.vanishes() => Some(0.0),
            Some((_, bound)) => Some(bound),
            None => None,
        };
        if let (Some(bound), HillSolver::Condensed, Wheel::Classes { classes, dynamics }) =
            (shortcut, self.solver, &self.wheel)
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
        let markers = markers(&stabilities, self.classes_tell_kinds());
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

    /// The exponents of class `class` alone (its nodal diameter `σ`, as in
    /// [`Self::classes`]; 0 on the whole wheel) at the converged point
    /// `(x, omega)`, with the check's solver and never the weak-contact
    /// shortcut, largest real part first: what locating a marker asks at
    /// each trial point of the branch (docs/design.md §10, "Located"). A
    /// class `σ < 0` is its conjugate's spectrum mirrored.
    pub fn class_exponents(
        &self,
        x: &[f64],
        omega: f64,
        class: i64,
    ) -> Result<Vec<Exponent>, StabilityError> {
        self.class_exponents_following(x, omega, class, None)
            .map(|(exponents, _)| exponents)
    }

    /// [`Self::class_exponents`], the condensed solver's exponents followed
    /// from `previous` (what this method returned at a nearby point of the
    /// branch for the same class) where the following vouches for them, as
    /// [`Self::point_following`] does; with what the next call can follow
    /// from.
    pub fn class_exponents_following(
        &self,
        x: &[f64],
        omega: f64,
        class: i64,
        previous: Option<&Following>,
    ) -> Result<(Vec<Exponent>, Following), StabilityError> {
        if !(omega.is_finite() && omega > 0.0) {
            return Err(StabilityError::Setting {
                key: "omega",
                value: omega.to_string(),
                allowed: "a finite angular frequency > 0",
            });
        }
        let stiffness = self.contact_stiffness(x, omega)?;
        let spectrum = stiffness.spectrum(2 * self.harmonics);
        match &self.wheel {
            Wheel::Classes { classes, dynamics } => {
                let no_class = || StabilityError::NoClass {
                    class,
                    available: classes
                        .iter()
                        .map(|c| c.nodal_diameter.to_string())
                        .collect::<Vec<_>>()
                        .join(", "),
                };
                let chosen = classes
                    .iter()
                    .find(|c| c.nodal_diameter == class)
                    .ok_or_else(no_class)?;
                // The solvers solve the classes σ ≥ 0 and mirror the others.
                let (solved, mirrored) = if class >= 0 {
                    (chosen, false)
                } else {
                    let conjugate = classes
                        .iter()
                        .find(|c| c.nodal_diameter == chosen.conjugate)
                        .ok_or_else(no_class)?;
                    (conjugate, true)
                };
                let (spectra, following) = self.by_class(
                    std::slice::from_ref(solved),
                    dynamics,
                    &spectrum,
                    omega,
                    self.solver,
                    previous,
                )?;
                let exponents = spectra
                    .into_iter()
                    .next()
                    .map(|c| c.exponents)
                    .unwrap_or_default();
                let exponents = if mirrored {
                    exponents
                        .into_iter()
                        .map(|e| Exponent {
                            re: e.re,
                            im: -e.im,
                        })
                        .collect()
                } else {
                    exponents
                };
                Ok((exponents, following))
            }
            Wheel::Physical { dynamics } => {
                if class != 0 {
                    return Err(StabilityError::NoClass {
                        class,
                        available: "0 (the whole wheel)".into(),
                    });
                }
                let (spectrum, track) = self.whole_wheel(dynamics, &spectrum, omega, previous)?;
                let mut following = Following::default();
                if let Some(track) = track {
                    following.insert(0, track);
                }
                Ok((spectrum.exponents, following))
            }
        }
    }
}

impl Stability<'_> {
    /// The linearized contact at the converged point `(x, omega)`.
    fn contact_stiffness(&self, x: &[f64], omega: f64) -> Result<ContactStiffness, StabilityError> {
        ContactStiffness::sample_with(self.problem, &self.sampling, x, omega)
    }
}

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
            sampling: SectorSampling::new(problem, self.time_samples, true),
            tolerance: self.tolerance,
            solver: self.solver,
            wheel,
            off_contact,
        }
    }
}
