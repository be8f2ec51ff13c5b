//! Every number that steers continuation, with its unit and why its
//! default: the public range and step settings ([`ArcLengthSettings`], as a
//! case file gives them) and the tuning that used to be hidden constants
//! (step control, guards against jumps, kink handling, the join of two
//! sweeps). Lengths are *scaled*: unknowns by the length scale, the
//! frequency by the range, so that the whole sweep is one unit of arc
//! length (see `Scaling`).

use super::NewtonSettings;
use serde::{Deserialize, Serialize};

mod validate;

pub use validate::SettingsError;

/// Arc-length settings (frequencies in rad/s): the ones a case file sets.
#[derive(Clone, Copy, Debug)]
pub struct ArcLengthSettings {
    /// Start frequency.
    pub start: f64,
    /// End frequency (below `start` to go down).
    pub end: f64,
    /// First step, scaled arc length.
    pub initial_step: f64,
    /// Smallest step before giving up.
    pub min_step: f64,
    /// Largest step.
    pub max_step: f64,
    /// Length by which displacements are scaled (e.g. the gap), m.
    pub length_scale: f64,
    /// Corrector settings.
    pub newton: NewtonSettings,
    /// Cap on points.
    pub max_points: usize,
}

/// All the settings of a continuation: the public ones and the tuning, each
/// part with defaults. `Settings::from(arc_length)` takes the defaults of
/// the tuning; change a part with struct update syntax:
///
/// ```
/// # use cyclorub::continuation::{ArcLengthSettings, NewtonSettings, Settings, StepSettings};
/// # let arc_length = ArcLengthSettings { start: 1.0, end: 2.0, initial_step: 0.01,
/// #     min_step: 1e-9, max_step: 0.05, length_scale: 1.0, max_points: 1000,
/// #     newton: NewtonSettings { tolerance: 1e-10, max_iterations: 20, ..Default::default() } };
/// let settings = Settings {
///     step: StepSettings { growth: 2.0, ..Default::default() },
///     ..Settings::from(arc_length)
/// };
/// assert!(settings.validate().is_ok());
/// ```
#[derive(Clone, Copy, Debug)]
pub struct Settings {
    /// Range, steps, length scale, corrector tolerance and cap on points.
    pub arc_length: ArcLengthSettings,
    /// How the step grows and shrinks.
    pub step: StepSettings,
    /// The corrector's line search.
    pub corrector: CorrectorSettings,
    /// Refusals of steps that jump between sheets, and the stops.
    pub guards: GuardSettings,
    /// Kinks of nonsmooth residuals: when they are looked for and how they
    /// are turned.
    pub kinks: KinkSettings,
    /// The join of a sweep back from the end with the sweep from the start
    /// (see [`continue_from_both_ends`](super::continue_from_both_ends)).
    pub join: JoinSettings,
    /// The scaling of the frequency in the continuation space.
    pub scaling: ScalingSettings,
}

impl From<ArcLengthSettings> for Settings {
    fn from(arc_length: ArcLengthSettings) -> Self {
        Self {
            arc_length,
            step: StepSettings::default(),
            corrector: CorrectorSettings::default(),
            guards: GuardSettings::default(),
            kinks: KinkSettings::default(),
            join: JoinSettings::default(),
            scaling: ScalingSettings::default(),
        }
    }
}

/// The scaling of the frequency: the whole range `[start, end]` is one unit
/// of arc length.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ScalingSettings {
    /// The narrowest range the frequency is scaled by, as a fraction of the
    /// larger end frequency: a narrower range (down to `start = end`, a
    /// branch at one frequency) counts as this wide, so that the scaling
    /// stays finite. 1e-6: far below any range a sweep asks for, far above
    /// round-off of the frequency.
    pub min_range_fraction: f64,
}

impl Default for ScalingSettings {
    fn default() -> Self {
        Self {
            min_range_fraction: 1e-6,
        }
    }
}

/// How a residual that tells its pieces (DLFT) is predicted.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum PiecewisePredictor {
    /// Along the tangent of the point's piece, with steps of at most
    /// [`StepSettings::piecewise_max_step`], every kink that refuses a
    /// step located and turned: resolves sharp nonsmooth folds and kinks
    /// far apart (the academic cases).
    #[default]
    Tangent,
    /// Along the last chord, the turn measured between chords, with the
    /// case's largest step; the tangent still serves for steps far shorter
    /// or longer than the last chord (halved after refusals, or resumed
    /// past a kink), where the chord points more than 60° off it, and
    /// where a kink is located and turned. For finely sampled contact
    /// (thousands of instants), whose pieces are so short that each
    /// point's tangent is off the branch's direction by the angle of its
    /// nearest kink (about 15° on the open fan at 2000 instants): along
    /// it, most long steps were refused for turning. The chord follows the
    /// branch's direction over the step.
    Secant,
}

/// Step control.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StepSettings {
    /// Factor of the next step after an easy one (≥ 1). 1.5: grows a step
    /// collapsed at a fold back to the largest in a few points, without
    /// overshooting the next turn.
    pub growth: f64,
    /// A step whose corrector converged within this many iterations, at
    /// the first attempt, is easy and grows the next. 3: Newton from a good
    /// tangent prediction converges quadratically in 2 or 3.
    pub easy_iterations: usize,
    /// Factor of a refused step (in (0, 1)). 0.5: halving.
    pub shrink: f64,
    /// A step no longer than this many times `min_step` is never refused
    /// for turning or for reversing the orientation: there is no shorter
    /// step left to try. 2.
    pub floor_factor: f64,
    /// The largest step on a residual that tells its pieces, predicted
    /// along the tangent (scaled arc length). 0.03: longer steps across
    /// many kinks landed on a nearby sheet near resonance peaks (DLFT).
    pub piecewise_max_step: f64,
    /// The prediction on a residual that tells its pieces.
    pub piecewise_predictor: PiecewisePredictor,
    /// After a kink turned, the next step is up to this fraction of the
    /// last easy one before the kink (at most the largest step; when longer
    /// than the short step that located the kink), instead of growing back
    /// from it. The fraction used adapts: doubled up to this one when a
    /// resumed step goes through, halved (down to 1/64 of it) when it is
    /// refused, since kinks close together refuse long steps. 1: on the
    /// open fan's DLFT branch (hundreds of isolated kinks) regrowing took
    /// about 8 points per kink and the branch met the point cap.
    pub after_kink: f64,
}

impl Default for StepSettings {
    fn default() -> Self {
        Self {
            growth: 1.5,
            easy_iterations: 3,
            shrink: 0.5,
            floor_factor: 2.0,
            piecewise_max_step: 0.03,
            piecewise_predictor: PiecewisePredictor::Tangent,
            after_kink: 1.0,
        }
    }
}

/// The corrector's backtracking line search on `‖(R / F, c)‖`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CorrectorSettings {
    /// Halvings of a Newton correction before the corrector gives up. 4:
    /// a correction that does not descend within 1/16 of its length points
    /// away from the branch (DLFT: into far contact states); a shorter
    /// step does better.
    pub max_backtracks: usize,
    /// Sufficient decrease (Armijo): a correction scaled by `f` must lower
    /// the merit by the fraction `sufficient_decrease · f`. 1e-4, the usual
    /// choice.
    pub sufficient_decrease: f64,
}

impl Default for CorrectorSettings {
    fn default() -> Self {
        Self {
            max_backtracks: 4,
            sufficient_decrease: 1e-4,
        }
    }
}

/// How far a step may turn the tangent and stray from its prediction.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TurnLimits {
    /// Smallest cosine between consecutive tangents.
    pub min_tangent_cosine: f64,
    /// Largest distance from the prediction to the corrected point, as a
    /// fraction of the step.
    pub max_correction_ratio: f64,
}

/// Guards against steps that jump onto another sheet of the branch, and
/// the stops of a branch that comes back on itself.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GuardSettings {
    /// Turn limits on a smooth residual or one that tells its pieces: 11°
    /// (cosine 0.98) and a tenth of the step. The regularized law's folds
    /// have radii ~ γ/κ with another sheet close by, and near a fold tip
    /// the other sheet is as close as the step: lax limits let the
    /// corrector land there.
    pub tight: TurnLimits,
    /// Turn limits on a nonsmooth residual without pieces, and on the
    /// steps that turn a kink: 60° (cosine 0.5) and half the step. A kink
    /// turns the tangent by a fixed angle however short the step; tighter
    /// limits would refuse every step across one.
    pub lax: TurnLimits,
    /// Going back along the recent trail (nonsmooth residuals without pieces).
    pub retrace: RetraceSettings,
    /// Recent points (and, on a piecewise residual, their pieces) kept to
    /// recognize going back. 64: a few folds' worth of points.
    pub trail: usize,
    /// Coming back to an earlier point: the branch stops (a closed loop).
    pub closed_loop: ClosedLoopSettings,
    /// Landing on a sheet travelled long before: the step is refused.
    pub old_sheet: OldSheetSettings,
    /// On a smooth residual, a step may reverse the branch's orientation
    /// (the sign of `det [J; tᵀ]`: cross a branch point) only when it is
    /// at most this fraction of the last easy step. 1/1024: longer ones
    /// that reversed it had gone back along the branch or onto a close
    /// sheet (a closed curve, on the N = 45 deformed-casing branch).
    pub branch_point_step: f64,
    /// A longer step that reverses it crosses a branch point when the
    /// corrected points on either side of the reversal, located by this
    /// many bisections of the step, are no farther apart than
    /// `branch_point_continuity` times their steps' difference: the branch
    /// goes on continuously there, while a jump onto a close sheet leaves a
    /// gap. 12 (a 4096th of the step).
    pub branch_point_bisections: usize,
    /// See `branch_point_bisections` (≥ 1: points corrected on planes a
    /// step apart are at least a step apart). 2: a chord up to 60° off the
    /// tangent.
    pub branch_point_continuity: f64,
}

impl Default for GuardSettings {
    fn default() -> Self {
        Self {
            tight: TurnLimits {
                min_tangent_cosine: 0.98,
                max_correction_ratio: 0.1,
            },
            lax: TurnLimits {
                min_tangent_cosine: 0.5,
                max_correction_ratio: 0.5,
            },
            retrace: RetraceSettings::default(),
            trail: 64,
            closed_loop: ClosedLoopSettings::default(),
            old_sheet: OldSheetSettings::default(),
            branch_point_step: 1.0 / 1024.0,
            branch_point_bisections: 12,
            branch_point_continuity: 2.0,
        }
    }
}

/// When a step goes back along the recent trail: it ends near a travelled
/// segment and runs against it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RetraceSettings {
    /// Near a segment: closer than this fraction of its length... 0.25: a
    /// chord misses its curved arc by its sagitta.
    pub segment_fraction: f64,
    /// ... plus this fraction of the step. 0.05.
    pub step_fraction: f64,
    /// Against it: a cosine with the segment below minus this. 0.8: near
    /// a fold the two sheets are close too, but the branch runs on through
    /// the fold, not back.
    pub cosine: f64,
}

impl Default for RetraceSettings {
    fn default() -> Self {
        Self {
            segment_fraction: 0.25,
            step_fraction: 0.05,
            cosine: 0.8,
        }
    }
}

/// When a new point repeats an earlier one (not one of the last two).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ClosedLoopSettings {
    /// Relative distance in frequency and in every unknown. 1e-7: far
    /// above the corrector's tolerance, far below a step.
    pub same_point: f64,
    /// ... and a scaled distance below this fraction of the step. 1e-2:
    /// steps at the sharpest folds of the regularized law are shorter than
    /// `same_point`, and the sheet beyond one passed that close to an
    /// earlier point without repeating it.
    pub step_fraction: f64,
}

impl Default for ClosedLoopSettings {
    fn default() -> Self {
        Self {
            same_point: 1e-7,
            step_fraction: 1e-2,
        }
    }
}

/// When a step lands on a sheet travelled long before.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OldSheetSettings {
    /// A segment of the trail is another sheet when the arc length from it
    /// to the current point exceeds this many times their distance. 8: a
    /// fold of radius r, about 2.4 r past its tip; a corner, when it turns
    /// by more than 166°.
    pub arc_ratio: f64,
    /// A step lands on another sheet when it ends closer to it than this
    /// fraction of its length... 0.1.
    pub landing: f64,
    /// ... and than this fraction of its start's distance from it. 0.25:
    /// a branch that runs beside an old sheet, however close, keeps its
    /// distance and goes on.
    pub drop: f64,
}

impl Default for OldSheetSettings {
    fn default() -> Self {
        Self {
            arc_ratio: 8.0,
            landing: 0.1,
            drop: 0.25,
        }
    }
}

/// Kinks: where a nonsmooth residual's branch turns by a finite angle.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct KinkSettings {
    /// (No pieces.) A step refused for turning, then refused again at half
    /// the step with at least this fraction of the turn, has crossed a
    /// corner. 0.6: a smooth turn halves with the step.
    pub corner_persistence: f64,
    /// (No pieces.) A step halved to this fraction of the last easy one
    /// is creeping toward a kink. 1/8.
    pub cascade: f64,
    /// (Pieces.) A step halved to this fraction of the last easy one has
    /// met a kink. 1/256.
    pub piecewise_cascade: f64,
    /// (Pieces.) A refused step up to this length (scaled) looks for a
    /// kink ahead; longer ones are only halved. 1e-3: turning kinks at
    /// long steps chose the wrong way at nearly coincident folds (N = 24
    /// deformed casing).
    pub piecewise_fine_step: f64,
    /// Steps tried past a kink: the first trial step divided by each. 1, 8
    /// and 64: the piece beyond may be short.
    pub trial_divisors: [f64; 3],
    /// (Pieces.) A kink is located by bisection to this fraction of the
    /// step. 1e-6.
    pub resolution: f64,
    /// (Pieces.) Kinks within this fraction of the longest trial step of
    /// each other are turned at once (several instants switching
    /// together). 1e-3.
    pub near: f64,
    /// (Pieces.) ... up to this many in a row. 16.
    pub max_pivots: usize,
    /// (Pieces, orientation unknown.) Distances, in units of the located
    /// kink's width, at which the pieces on either side are compared. 4
    /// to 16384: a factor 16 apart, out to where the next kink may lie.
    pub side_scales: [f64; 4],
    /// How far out (in units of the distance within which the kink lies)
    /// the residual is compared on either side. 16.
    pub test_distance: f64,
    /// The residual on one side must be below this fraction of the other's
    /// to tell the way on. 0.1: on the wrong side it grows at first order.
    pub side_ratio: f64,
    /// A way on may not go back along the way in more steeply than this
    /// (cosine with the reversed tangent) unless the pieces told it. 0.9.
    pub max_reversal: f64,
    /// (No pieces.) A step halved to this fraction of the last easy one
    /// leaps: longer steps along the tangent pass over a small nonsmooth
    /// structure (an instant grazing the casing). 1/64.
    pub leap_cascade: f64,
    /// (No pieces.) The leaps tried, in units of the last easy step. 1, 2
    /// and 4.
    pub leap_multiples: [f64; 3],
}

impl Default for KinkSettings {
    fn default() -> Self {
        Self {
            corner_persistence: 0.6,
            cascade: 1.0 / 8.0,
            piecewise_cascade: 1.0 / 256.0,
            piecewise_fine_step: 1e-3,
            trial_divisors: [1.0, 8.0, 64.0],
            resolution: 1e-6,
            near: 1e-3,
            max_pivots: 16,
            side_scales: [4.0, 64.0, 1024.0, 16384.0],
            test_distance: 16.0,
            side_ratio: 0.1,
            max_reversal: 0.9,
            leap_cascade: 1.0 / 64.0,
            leap_multiples: [1.0, 2.0, 4.0],
        }
    }
}

/// When a point of the sweep back lies on the sweep from the start, and
/// when the two are joined.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct JoinSettings {
    /// On a segment: within this fraction of its length. 0.05: under the
    /// tight turn limits a chord misses its arc by at most a fortieth of
    /// its length.
    pub distance: f64,
    /// ... and running against it at least this closely (cosine). 0.95: the
    /// two sweeps travel the same curve in opposite ways; a part of the
    /// first that went back along itself is never joined.
    pub cosine: f64,
    /// Consecutive points on the first sweep, each on the same segment or
    /// an earlier one, before the two are joined. 3: a sheet that passes
    /// close by does not run along it.
    pub confirmations: usize,
}

impl Default for JoinSettings {
    fn default() -> Self {
        Self {
            distance: 0.05,
            cosine: 0.95,
            confirmations: 3,
        }
    }
}
