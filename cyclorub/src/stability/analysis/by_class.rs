//! Each class's exponents at one point, by the solver asked for (the
//! condensed one followed from the previous point, the dense region, the
//! targeted pick, the dense eigenproblem), and the Hill blocks they solve.

use super::{Stability, Wheel};
use crate::stability::classes::SymmetryClass;
use crate::stability::condensed::{
    dense_in_region, exponent_near, followed_exponents, ClassTrack, Following, Region,
};
use crate::stability::contact_stiffness::{
    ContactTerm, SpaceTimeTable, StiffnessSpectrum, TermKind,
};
use crate::stability::hill::{physical_exponents, Group, LocalDynamics, Picked};
use crate::stability::settings::HillSolver;
use crate::stability::spectrum::{ClassSpectrum, Exponent};
use crate::stability::targeted::{targeted_classes, ClassBlock};
use crate::stability::StabilityError;
use faer::c64;
use rayon::prelude::*;
use std::collections::BTreeMap;
use std::sync::Arc;

impl Stability<'_> {
    /// The exponent of class `class` (its nodal diameter `σ`, as in
    /// [`Self::classes`]; 0 on the whole wheel) nearest to `guess` at the
    /// converged point `(x, omega)`, followed from it alone (and from
    /// `start`, its vector at a nearby point) without solving the whole
    /// class ([`exponent_near`]); with its vector. `None` when the class's
    /// block does not condense or the refinement does not converge: ask
    /// [`Self::class_exponents`] then. A class `σ < 0` is its conjugate's
    /// mirrored.
    pub fn exponent_near(
        &self,
        x: &[f64],
        omega: f64,
        class: i64,
        guess: Exponent,
        start: Option<&[c64]>,
    ) -> Result<Option<(Exponent, Vec<c64>)>, StabilityError> {
        let stiffness = self.contact_stiffness(x, omega)?;
        let spectrum = stiffness.spectrum(2 * self.harmonics);
        let mu = guess.value() / omega;
        let found = match &self.wheel {
            Wheel::Classes { classes, dynamics } => {
                let Some(chosen) = classes.iter().find(|c| c.nodal_diameter == class) else {
                    return Ok(None);
                };
                let (solved, mirrored) = if class >= 0 {
                    (chosen, false)
                } else {
                    match classes
                        .iter()
                        .find(|c| c.nodal_diameter == chosen.conjugate)
                    {
                        Some(c) => (c, true),
                        None => return Ok(None),
                    }
                };
                let table = spectrum.space_time_table();
                let b = self.class_block(solved, dynamics, &table);
                let guess = if mirrored { mu.conj() } else { mu };
                exponent_near(&b.groups, &b.coupling, &b.damping, omega, guess, start)
                    .map(|(mu, q)| (if mirrored { mu.conj() } else { mu }, q))
            }
            Wheel::Physical { dynamics } => {
                let (groups, coupling, damping) = self.wheel_block(dynamics, &spectrum);
                exponent_near(&groups, &coupling, &damping, omega, mu, start)
            }
        };
        Ok(found.map(|(mu, q)| (Exponent::new(mu * omega), q)))
    }

    pub(super) fn by_class(
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
    pub(super) fn class_block<'c>(
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
    pub(super) fn class_groups(
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
    pub(super) fn term_dofs(&self, term: &ContactTerm) -> (usize, usize) {
        (self.contact_dofs[term.row], self.contact_dofs[term.column])
    }

    pub(super) fn whole_wheel(
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
    pub(super) fn wheel_block(
        &self,
        dynamics: &Arc<LocalDynamics>,
        stiffness: &StiffnessSpectrum,
    ) -> Block {
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
pub(super) const TARGETED_UP_TO: f64 = 100.0;

/// Where the condensed solver seeks each class's exponents.
pub(super) const REGION: Region = Region {
    margin: 0.05,
    upper: 0.5,
};

/// The largest share of a targeted eigenvector on the highest harmonics
/// for the count to vouch for the targeted classes.
const TARGETED_TRUNCATION: f64 = 1e-3;

pub(super) fn spectrum(
    nodal_diameter: i64,
    picked: &[Picked],
    dense: bool,
    conjugate: bool,
) -> ClassSpectrum {
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
