//! Sliding friction on the casing (Eqs. 83–84): while a contact node presses
//! on the casing with the normal force `f_N ≥ 0`, the casing rubs it with
//! `μ f_N` against the node's sliding velocity relative to the casing,
//! `w = (v_θ + ρ Ω, v_z)` (circumferential, axial), `ρ` the node's radius
//! and `Ω` the rotation speed. Sliding is assumed at all times, as in the
//! paper: the tangential force is `−μ f_N w / |w|` on the structure.
//!
//! The friction is evaluated from the normal force the contact law gives
//! at the same instant (both laws: the DLFT's corrected multiplier is that
//! force), so a friction node adds two tangential dofs to its contact dof
//! and nothing to the law.
//!
//! The symmetry rule stays exact (docs/design.md §3): the force at a node
//! depends only on that node's own displacement and velocity at the same
//! instant, through one function shared by every sector, so a solution
//! whose sectors repeat with a shift keeps that shift in its forces.

use super::ContactError;

/// How fast the wheel turns, which sets the sliding speed `ρ Ω`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum RotationSpeed {
    /// A fixed speed `Ω`, rad/s.
    Fixed(f64),
    /// `Ω = ω` along the sweep: the excitation synchronous with the
    /// rotation (the paper's choice, Sec. 5.2).
    Synchronous,
}

impl RotationSpeed {
    /// `Ω` at the excitation frequency `omega` (rad/s).
    pub fn at(&self, omega: f64) -> f64 {
        match self {
            RotationSpeed::Fixed(speed) => *speed,
            RotationSpeed::Synchronous => omega,
        }
    }

    /// `∂Ω/∂ω`: 1 when synchronous, 0 otherwise.
    pub fn derivative(&self) -> f64 {
        match self {
            RotationSpeed::Fixed(_) => 0.0,
            RotationSpeed::Synchronous => 1.0,
        }
    }
}

/// The two tangential dofs and the radius of one friction node, beside its
/// contact (normal) dof.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FrictionNode {
    /// The circumferential dof of the sector (0-based), positive in the
    /// direction of rotation.
    pub circumferential: usize,
    /// The axial dof of the sector (0-based).
    pub axial: usize,
    /// The node's distance `ρ` to the rotation axis, m.
    pub radius: f64,
}

/// Sliding friction at every contact dof: the coefficient, the rotation
/// and, per contact dof (in the order of the contact dofs), its friction
/// node.
#[derive(Clone, Debug, PartialEq)]
pub struct SlidingFriction {
    coefficient: f64,
    speed: RotationSpeed,
    nodes: Vec<FrictionNode>,
}

impl SlidingFriction {
    /// Friction of coefficient `μ ≥ 0` at the rotation `speed`, one node per
    /// contact dof.
    pub fn new(
        coefficient: f64,
        speed: RotationSpeed,
        nodes: Vec<FrictionNode>,
    ) -> Result<Self, ContactError> {
        if !(coefficient.is_finite() && coefficient >= 0.0) {
            return Err(ContactError::InvalidParameter {
                key: "friction",
                value: coefficient,
                allowed: "the friction coefficient μ must be a finite number ≥ 0",
            });
        }
        if let RotationSpeed::Fixed(speed) = speed {
            if !speed.is_finite() {
                return Err(ContactError::InvalidParameter {
                    key: "speed",
                    value: speed,
                    allowed: "the rotation speed Ω must be a finite number (rad/s)",
                });
            }
        }
        if let Some(node) = nodes
            .iter()
            .find(|n| !(n.radius.is_finite() && n.radius >= 0.0))
        {
            return Err(ContactError::InvalidParameter {
                key: "radius",
                value: node.radius,
                allowed: "a contact node's radius ρ must be a finite number ≥ 0 (m)",
            });
        }
        Ok(Self {
            coefficient,
            speed,
            nodes,
        })
    }

    /// `μ`.
    pub fn coefficient(&self) -> f64 {
        self.coefficient
    }

    /// The rotation.
    pub fn speed(&self) -> RotationSpeed {
        self.speed
    }

    /// The friction node of each contact dof.
    pub fn nodes(&self) -> &[FrictionNode] {
        &self.nodes
    }
}

/// The sliding direction `t = w / |w|` of the relative velocity
/// `w = (w_θ, w_z)` and its derivative `∂t/∂w = (I − t tᵀ) / |w|`
/// (row-major `[[∂t_θ/∂w_θ, ∂t_θ/∂w_z], [∂t_z/∂w_θ, ∂t_z/∂w_z]]`).
/// At `w = 0` (no sliding: no rotation and a node at rest) the direction is
/// undefined; the force is taken as zero there, with a zero derivative.
pub fn sliding_direction(w_theta: f64, w_axial: f64) -> ([f64; 2], [[f64; 2]; 2]) {
    // The plain square root where the squares neither overflow nor
    // underflow (hypot costs 3 % of a reduced run with friction).
    let square = w_theta * w_theta + w_axial * w_axial;
    let norm = if square.is_normal() && square < 1e300 {
        square.sqrt()
    } else {
        w_theta.hypot(w_axial)
    };
    if norm == 0.0 {
        return ([0.0; 2], [[0.0; 2]; 2]);
    }
    let t = [w_theta / norm, w_axial / norm];
    let cross = -t[0] * t[1] / norm;
    (
        t,
        [
            [(1.0 - t[0] * t[0]) / norm, cross],
            [cross, (1.0 - t[1] * t[1]) / norm],
        ],
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_direction_is_a_unit_vector_and_its_derivative_matches_differences() {
        for &(a, b) in &[(3.0, 4.0), (120.0, -0.5), (-2.0, 1e-3), (1e-4, 7.0)] {
            let (t, d) = sliding_direction(a, b);
            assert!((t[0].hypot(t[1]) - 1.0).abs() < 1e-15);
            for (col, step) in [(0, [1.0, 0.0]), (1, [0.0, 1.0])] {
                let norm = f64::hypot(a, b);
                let h = 1e-6 * norm;
                let (plus, _) = sliding_direction(a + h * step[0], b + h * step[1]);
                let (minus, _) = sliding_direction(a - h * step[0], b - h * step[1]);
                for row in 0..2 {
                    let fd = (plus[row] - minus[row]) / (2.0 * h);
                    assert!(
                        (fd - d[row][col]).abs() < 1e-8 / norm,
                        "w = ({a}, {b}) ∂t{row}/∂w{col}: {} vs {fd}",
                        d[row][col]
                    );
                }
            }
        }
        assert_eq!(sliding_direction(0.0, 0.0), ([0.0; 2], [[0.0; 2]; 2]));
    }

    #[test]
    fn bad_friction_parameters_are_refused_by_name() {
        let node = FrictionNode {
            circumferential: 1,
            axial: 2,
            radius: 0.3,
        };
        let error = SlidingFriction::new(-0.1, RotationSpeed::Synchronous, vec![node]).unwrap_err();
        assert!(error.to_string().contains("friction = -0.1"), "{error}");
        let error =
            SlidingFriction::new(0.1, RotationSpeed::Fixed(f64::NAN), vec![node]).unwrap_err();
        assert!(error.to_string().contains("speed"), "{error}");
        let bad = FrictionNode {
            radius: -1.0,
            ..node
        };
        let error = SlidingFriction::new(0.1, RotationSpeed::Synchronous, vec![bad]).unwrap_err();
        assert!(error.to_string().contains("radius = -1"), "{error}");
    }
}
