//! The sliding friction of a case: each contact dof's circumferential and
//! axial dofs, checked against the model's nodes where it knows them.

use super::{contact_error, invalid, Case, CaseError};
use crate::contact::{FrictionNode, RotationSpeed, SlidingFriction};
use crate::model::SectorModel;

impl Case {
    /// The sliding friction on `model` (`None` without `contact.friction`,
    /// or with `friction = 0`: frictionless, so a study over μ may start at
    /// 0 without the tangential dofs): the tangential dofs, the rotation,
    /// and the radii given or taken from the model's node coordinates.
    pub fn friction(&self, model: &SectorModel) -> Result<Option<SlidingFriction>, CaseError> {
        let c = &self.contact;
        let Some(coefficient) = c.friction.filter(|&mu| mu != 0.0) else {
            return Ok(None);
        };
        let count = c.dofs.len();
        let listed = |key: &str, list: &[usize]| -> Result<Vec<usize>, CaseError> {
            if list.len() != count {
                return Err(invalid(
                    key,
                    format!("{list:?}"),
                    format!(
                        "with contact.friction, give one dof per contact dof ({count}), 1-based"
                    ),
                ));
            }
            list.iter()
                .map(|&d| {
                    d.checked_sub(1).ok_or_else(|| {
                        invalid(key, format!("{list:?}"), "dofs are numbered from 1")
                    })
                })
                .collect()
        };
        let circumferential = listed("contact.circumferential_dofs", &c.circumferential_dofs)?;
        let axial = listed("contact.axial_dofs", &c.axial_dofs)?;
        let radii = match &c.radius {
            Some(radius) => radius.expand("contact.radius", count)?,
            None => circumferential
                .iter()
                .map(|&d| {
                    model.dof_radius(d).ok_or_else(|| {
                        invalid(
                            "contact.radius",
                            "absent",
                            format!(
                                "the model has no node coordinates for dof {}: give the radius \
                                 of each contact node (m)",
                                d + 1
                            ),
                        )
                    })
                })
                .collect::<Result<_, _>>()?,
        };
        let speed = match (self.rotation.speed, self.rotation.synchronous) {
            (Some(speed), false) => RotationSpeed::Fixed(speed),
            (None, true) => RotationSpeed::Synchronous,
            (Some(speed), true) => {
                return Err(invalid(
                    "rotation.speed",
                    speed.to_string(),
                    "give either rotation.speed or rotation.synchronous = true, not both",
                ))
            }
            (None, false) => {
                return Err(invalid(
                    "rotation.speed",
                    "absent",
                    "with contact.friction, give the rotation speed Ω (rad/s) or \
                     rotation.synchronous = true (Ω = ω)",
                ))
            }
        };
        same_nodes(model, &self.contact_dofs(), &circumferential, &axial)?;
        let nodes = circumferential
            .iter()
            .zip(&axial)
            .zip(&radii)
            .map(|((&circumferential, &axial), &radius)| FrictionNode {
                circumferential,
                axial,
                radius,
            })
            .collect();
        SlidingFriction::new(coefficient, speed, nodes)
            .map(Some)
            .map_err(contact_error)
    }
}

/// On a model that knows its dofs' nodes (a finite-element sector), each
/// contact dof's circumferential and axial dofs (0-based, one per contact
/// dof) are on its own node: the friction force acts where the contact
/// does.
fn same_nodes(
    model: &SectorModel,
    contact: &[usize],
    circumferential: &[usize],
    axial: &[usize],
) -> Result<(), CaseError> {
    for (i, &c) in contact.iter().enumerate() {
        let Some(node) = model.dof_node(c) else {
            continue;
        };
        for (key, list) in [
            ("contact.circumferential_dofs", circumferential),
            ("contact.axial_dofs", axial),
        ] {
            let Some(&d) = list.get(i) else { continue };
            if model.dof_node(d) == Some(node) {
                continue;
            }
            let own: Vec<String> = (0..model.dofs_per_sector())
                .filter(|&e| model.dof_node(e) == Some(node) && e != c)
                .map(|e| format!("{} ({})", e + 1, model.dof_label(e)))
                .collect();
            let numbers: Vec<String> = list.iter().map(|d| (d + 1).to_string()).collect();
            return Err(invalid(
                key,
                format!("[{}]", numbers.join(", ")),
                format!(
                    "entry {} is dof {} ({}), but contact dof {} (contact.dofs entry {}) is on \
                     node {node}: a contact dof's circumferential and axial dofs must be its own \
                     node's, here {}",
                    i + 1,
                    d + 1,
                    model.dof_label(d),
                    c + 1,
                    i + 1,
                    own.join(" or ")
                ),
            ));
        }
    }
    Ok(())
}
