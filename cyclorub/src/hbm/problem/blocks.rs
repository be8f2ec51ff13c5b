//! The linear part of a problem, block by block: each signed pair's sector
//! matrices (cyclic) or the assembled wheel, mistuned or not (physical),
//! with the load each block carries.

use super::super::layout::{BlockKind, Layout};
use super::super::linear::{
    BlockMatrices, LocalBlock, PerturbedWheel, WheelDiameters, WheelStructure,
};
use super::super::HbmError;
use super::ProblemSpec;
use crate::cyclic::SignedPair;
use faer::{c64, Mat};
use std::collections::BTreeMap;
use std::f64::consts::PI;
use std::sync::Arc;

impl ProblemSpec<'_> {
    pub(super) fn excitation_coefficients(&self) -> Vec<(SignedPair, c64)> {
        self.forcing.map_or_else(Vec::new, |f| {
            f.pattern
                .pair_coefficients(self.model.sectors())
                .into_iter()
                .map(|(p, (re, im))| (p, c64::new(re, im) * f.amplitude))
                .collect()
        })
    }

    pub(super) fn interior(&self, size: usize, contact: &[usize]) -> Vec<usize> {
        (0..size).filter(|d| !contact.contains(d)).collect()
    }

    pub(super) fn cyclic_blocks(&self, layout: &Layout) -> Result<Vec<LocalBlock>, HbmError> {
        let dofs = self.model.dofs_per_sector();
        let mut cache: BTreeMap<i64, BlockMatrices> = BTreeMap::new();
        let coefficients = self.excitation_coefficients();
        let condensed = self.condensed_dofs();
        let interior = self.interior(dofs, &condensed);
        let mut blocks = Vec::with_capacity(layout.blocks.len());
        for block in &layout.blocks {
            let BlockKind::Pair { nodal_diameter: s } = block.kind else {
                continue;
            };
            let matrices = match cache.get(&s) {
                Some(m) => m.clone(),
                None => {
                    let m = self
                        .model
                        .nodal_diameter_matrices(s)
                        .map_err(HbmError::Model)?;
                    let m = BlockMatrices {
                        mass: Arc::new(m.mass),
                        stiffness: Arc::new(m.stiffness),
                        damping: Arc::new(m.damping),
                    };
                    cache.insert(s, m.clone());
                    m
                }
            };
            let mut load = vec![c64::new(0.0, 0.0); dofs];
            if let Some(forcing) = self.forcing {
                let value = match block.harmonic {
                    1 => coefficients
                        .iter()
                        .find(|(p, _)| p.nodal_diameter == s)
                        .map(|(_, c)| *c),
                    0 if s == 0 => Some(c64::new(forcing.static_force, 0.0)),
                    _ => None,
                };
                if let Some(value) = value {
                    for &d in &forcing.dofs {
                        load[d] += value;
                    }
                }
            }
            if let (Some(preload), 0, 0) = (self.preload, block.harmonic, s) {
                for (l, f) in load.iter_mut().zip(preload) {
                    *l += f;
                }
            }
            blocks.push(LocalBlock {
                matrices,
                contact: condensed.clone(),
                interior: interior.clone(),
                load,
                structure: WheelStructure::Dense,
            });
        }
        Ok(blocks)
    }

    pub(super) fn physical_blocks(&self, layout: &Layout) -> Result<Vec<LocalBlock>, HbmError> {
        let n = self.model.sectors();
        let dofs = self.model.dofs_per_sector();
        let wheel = self.model.full_wheel().map_err(HbmError::Model)?;
        let complex = |m: &Mat<f64>| {
            Arc::new(Mat::from_fn(m.nrows(), m.ncols(), |r, c| {
                c64::new(m[(r, c)], 0.0)
            }))
        };
        let matrices = BlockMatrices {
            mass: complex(&wheel.mass),
            stiffness: complex(&wheel.stiffness),
            damping: complex(&wheel.damping),
        };
        let condensed = self.condensed_dofs();
        let contact: Vec<usize> = (0..n)
            .flat_map(|j| condensed.iter().map(move |&d| j * dofs + d))
            .collect();
        let interior = self.interior(n * dofs, &contact);
        let diameters = WheelDiameters::new(&matrices, n, &contact, &interior);
        // A mistuned wheel: the tuned one by diameters plus the blades'
        // change, condensed in two stages (exact; the dense LU on the
        // changed dofs only).
        let perturbed = if diameters.is_none() && self.model.is_mistuned() {
            let tuned = self.model.tuned().full_wheel().map_err(HbmError::Model)?;
            let tuned = BlockMatrices {
                mass: complex(&tuned.mass),
                stiffness: complex(&tuned.stiffness),
                damping: complex(&tuned.damping),
            };
            PerturbedWheel::new(&matrices, &tuned, n, &condensed)
        } else {
            None
        };
        let structure = match (diameters, perturbed) {
            (Some(diameters), _) => WheelStructure::Diameters(diameters),
            (None, Some(perturbed)) => WheelStructure::Perturbed(perturbed),
            (None, None) => WheelStructure::Dense,
        };
        let coefficients = self.excitation_coefficients();
        let alpha = 2.0 * PI / n as f64;
        Ok(layout
            .blocks
            .iter()
            .map(|block| {
                let mut load = vec![c64::new(0.0, 0.0); n * dofs];
                if let Some(forcing) = self.forcing {
                    for j in 0..n {
                        let value = match block.harmonic {
                            // X_j = Σ_s c_s e^{−i s α j}.
                            1 => coefficients
                                .iter()
                                .map(|(p, c)| {
                                    c * c64::cis(-(p.nodal_diameter as f64) * alpha * j as f64)
                                })
                                .sum(),
                            0 => c64::new(forcing.static_force, 0.0),
                            _ => c64::new(0.0, 0.0),
                        };
                        for &d in &forcing.dofs {
                            load[j * dofs + d] += value;
                        }
                    }
                }
                if let (Some(preload), 0) = (self.preload, block.harmonic) {
                    for j in 0..n {
                        for (d, f) in preload.iter().enumerate() {
                            load[j * dofs + d] += f;
                        }
                    }
                }
                LocalBlock {
                    matrices: matrices.clone(),
                    contact: contact.clone(),
                    interior: interior.clone(),
                    load,
                    structure: structure.clone(),
                }
            })
            .collect())
    }
}
