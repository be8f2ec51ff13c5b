//! Recovery of any sector dof from the condensed unknowns, on any sector
//! (reduced bases included: a pair's value on sector `j` is its wave there).
//!
//! With a flexible wall (DLFT-HBM), the unknowns are the wall nodes'
//! displacements; the recovery gives the structure's own dofs, contact dofs
//! included (the blade tip, on the blade side of the wall's spring).

use super::layout::{is_real_diameter, BlockKind};
use super::residual::HarmonicBalance;
use super::HbmError;
use faer::c64;
use std::f64::consts::PI;

/// Real harmonic coordinates (see [`super::aft`]) of sector dof `dof`
/// (0-based) on each sector of `sectors` (0-based), at the point `(x, omega)`.
/// Always the structure's displacement: with a wall, a contact dof's value
/// is the blade tip's, not the wall node's (for the latter, see
/// [`wall_coordinates`]).
pub fn dof_coordinates(
    problem: &HarmonicBalance,
    x: &[f64],
    omega: f64,
    dof: usize,
    sectors: &[usize],
) -> Result<Vec<Vec<f64>>, HbmError> {
    let layout = problem.layout();
    let linear = problem.linear();
    let n = layout.sectors;
    let size = layout.coordinates();
    let alpha = 2.0 * PI / n as f64;
    let mut out = vec![vec![0.0; size]; sectors.len()];
    for (index, block) in layout.blocks.iter().enumerate() {
        let unknown_values: Vec<c64> = block
            .slots
            .iter()
            .map(|slot| c64::new(x[slot.re], slot.im.map_or(0.0, |im| x[im])))
            .collect();
        let local = &linear.blocks()[index];
        // Neither moved nor loaded, the block's dofs are all at rest (e.g.
        // the unforced harmonics of a point far from the casing): no
        // condensation needed.
        let zero = |v: &c64| v.re == 0.0 && v.im == 0.0;
        if unknown_values.iter().all(zero) && local.load.iter().all(zero) {
            continue;
        }
        let contact_values = linear.blade_contact_values(layout, index, omega, &unknown_values)?;
        let dofs_per_sector = match block.kind {
            BlockKind::Pair { .. } => local.load.len(),
            BlockKind::Wheel => local.load.len() / n,
        };
        // A contact dof is read directly; any other dof is recovered.
        let values = if let Some(c) = local
            .contact
            .iter()
            .position(|&d| d % dofs_per_sector == dof)
        {
            match block.kind {
                BlockKind::Pair { .. } => vec![contact_values[c]],
                BlockKind::Wheel => {
                    let per_sector = local.contact.len() / n;
                    (0..n).map(|j| contact_values[j * per_sector + c]).collect()
                }
            }
        } else {
            let full = linear.recover(layout, index, omega, &contact_values)?;
            match block.kind {
                BlockKind::Pair { .. } => vec![full[dof]],
                BlockKind::Wheel => (0..n).map(|j| full[j * dofs_per_sector + dof]).collect(),
            }
        };
        add_block_values(&mut out, sectors, block, &values, n, alpha);
    }
    Ok(out)
}

/// Adds one block's values of a dof (one for a pair, one per sector for
/// the whole wheel) to each sector's real harmonic coordinates.
fn add_block_values(
    out: &mut [Vec<f64>],
    sectors: &[usize],
    block: &super::layout::Block,
    values: &[c64],
    n: usize,
    alpha: f64,
) {
    let k = block.harmonic;
    for (coordinates, &j) in out.iter_mut().zip(sectors) {
        let value = match block.kind {
            BlockKind::Pair { nodal_diameter: s } => {
                let wave = values[0] * c64::cis(-(s as f64) * alpha * j as f64);
                if k == 0 && !is_real_diameter(s, n) {
                    wave * 2.0
                } else {
                    wave
                }
            }
            BlockKind::Wheel => values[j],
        };
        if k == 0 {
            coordinates[0] += value.re;
        } else {
            coordinates[2 * k - 1] += value.re;
            coordinates[2 * k] += value.im;
        }
    }
}

/// Real harmonic coordinates of sector dof `dof` on each sector of
/// `sectors` in the linear response at `omega` (no contact force), over
/// the harmonics `keep` chooses: each loaded block's dynamic stiffness
/// solved on all its dofs (`u = Z(kω)⁻¹ f`), without condensing it on the
/// contact dofs, recovering the interior and the wall (the same response:
/// with no contact force the wall node follows the blade). Harmonic 0 does
/// not depend on `omega`: a linear curve computes it once.
pub fn linear_dof_coordinates(
    problem: &HarmonicBalance,
    omega: f64,
    dof: usize,
    sectors: &[usize],
    keep: impl Fn(usize) -> bool,
) -> Result<Vec<Vec<f64>>, HbmError> {
    let layout = problem.layout();
    let linear = problem.linear();
    let n = layout.sectors;
    let alpha = 2.0 * PI / n as f64;
    let mut out = vec![vec![0.0; layout.coordinates()]; sectors.len()];
    for (index, block) in layout.blocks.iter().enumerate() {
        if !keep(block.harmonic) {
            continue;
        }
        let Some(full) = linear.free_response(layout, index, omega)? else {
            continue;
        };
        let values: Vec<c64> = match block.kind {
            BlockKind::Pair { .. } => vec![full[dof]],
            BlockKind::Wheel => {
                let per_sector = full.len() / n;
                (0..n).map(|j| full[j * per_sector + dof]).collect()
            }
        };
        add_block_values(&mut out, sectors, block, &values, n, alpha);
    }
    Ok(out)
}

/// Real harmonic coordinates of the contact unknowns of contact dof number
/// `contact` (0-based position in the contact dof list) on each sector of
/// `sectors` (0-based): the wall node's displacement when there is a wall,
/// the contact dof's own otherwise (then equal to [`dof_coordinates`]).
pub fn wall_coordinates(
    problem: &HarmonicBalance,
    x: &[f64],
    contact: usize,
    sectors: &[usize],
) -> Vec<Vec<f64>> {
    let layout = problem.layout();
    let n = layout.sectors;
    let size = layout.coordinates();
    let alpha = 2.0 * PI / n as f64;
    let mut out = vec![vec![0.0; size]; sectors.len()];
    let value_of =
        |slot: &super::layout::Slot| c64::new(x[slot.re], slot.im.map_or(0.0, |im| x[im]));
    for block in &layout.blocks {
        let k = block.harmonic;
        for (coordinates, &j) in out.iter_mut().zip(sectors) {
            let value = match block.kind {
                BlockKind::Pair { nodal_diameter: s } => {
                    let Some(slot) = block.slots.get(contact) else {
                        continue;
                    };
                    let wave = value_of(slot) * c64::cis(-(s as f64) * alpha * j as f64);
                    if k == 0 && !is_real_diameter(s, n) {
                        wave * 2.0
                    } else {
                        wave
                    }
                }
                BlockKind::Wheel => {
                    let Some(slot) = block.slots.get(j * layout.contact_dofs + contact) else {
                        continue;
                    };
                    value_of(slot)
                }
            };
            if k == 0 {
                coordinates[0] += value.re;
            } else {
                coordinates[2 * k - 1] += value.re;
                coordinates[2 * k] += value.im;
            }
        }
    }
    out
}

/// The unknowns of the full wheel in physical coordinates
/// ([`super::layout::Layout::physical`]) that hold the same response as
/// `x` on `problem`'s basis: the contact unknowns of every sector, sector
/// by sector. A reduced solution carried over this way is a solution of
/// the full problem exactly when the reduction is exact.
pub fn physical_unknowns(problem: &HarmonicBalance, x: &[f64]) -> Vec<f64> {
    let layout = problem.layout();
    let size = layout.coordinates();
    let sectors: Vec<usize> = (0..layout.sectors).collect();
    let mut out = vec![0.0; layout.sectors * layout.contact_dofs * size];
    for contact in 0..layout.contact_dofs {
        for (j, coordinates) in wall_coordinates(problem, x, contact, &sectors)
            .into_iter()
            .enumerate()
        {
            let offset = (j * layout.contact_dofs + contact) * size;
            out[offset..offset + size].copy_from_slice(&coordinates);
        }
    }
    out
}
