//! The continuation settings checked before any work: each bad setting is
//! named by its path in [`Settings`] with the rule it breaks.

use super::Settings;

/// A setting that cannot be used, named by its path in [`Settings`].
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("continuation setting {name} = {value}: {rule}")]
pub struct SettingsError {
    /// The setting, e.g. `arc_length.min_step` or `guards.tight.min_tangent_cosine`.
    pub name: &'static str,
    /// Its value, as written.
    pub value: String,
    /// The rule it breaks.
    pub rule: &'static str,
}

impl Settings {
    /// Checks every setting before any work: a bad one is named with the
    /// rule it breaks.
    pub fn validate(&self) -> Result<(), SettingsError> {
        let fail = |name, value: &dyn std::fmt::Debug, rule| {
            Err(SettingsError {
                name,
                value: format!("{value:?}"),
                rule,
            })
        };
        let a = &self.arc_length;
        for (name, value) in [("arc_length.start", a.start), ("arc_length.end", a.end)] {
            if !value.is_finite() {
                return fail(name, &value, "must be a finite frequency (rad/s)");
            }
        }
        let (g, k, s) = (&self.guards, &self.kinks, &self.step);
        let positive = [
            ("arc_length.initial_step", a.initial_step),
            ("arc_length.min_step", a.min_step),
            ("arc_length.max_step", a.max_step),
            ("arc_length.length_scale", a.length_scale),
            ("arc_length.newton.tolerance", a.newton.tolerance),
            (
                "arc_length.newton.sufficient_decrease",
                a.newton.sufficient_decrease,
            ),
            (
                "scaling.min_range_fraction",
                self.scaling.min_range_fraction,
            ),
            ("step.floor_factor", s.floor_factor),
            ("step.piecewise_max_step", s.piecewise_max_step),
            ("step.after_kink", s.after_kink),
            (
                "corrector.sufficient_decrease",
                self.corrector.sufficient_decrease,
            ),
            (
                "guards.tight.max_correction_ratio",
                g.tight.max_correction_ratio,
            ),
            (
                "guards.lax.max_correction_ratio",
                g.lax.max_correction_ratio,
            ),
            (
                "guards.retrace.segment_fraction",
                g.retrace.segment_fraction,
            ),
            ("guards.retrace.step_fraction", g.retrace.step_fraction),
            ("guards.closed_loop.same_point", g.closed_loop.same_point),
            (
                "guards.closed_loop.step_fraction",
                g.closed_loop.step_fraction,
            ),
            ("guards.old_sheet.arc_ratio", g.old_sheet.arc_ratio),
            ("guards.old_sheet.landing", g.old_sheet.landing),
            ("guards.old_sheet.drop", g.old_sheet.drop),
            ("guards.branch_point_step", g.branch_point_step),
            ("guards.branch_point_continuity", g.branch_point_continuity),
            ("kinks.corner_persistence", k.corner_persistence),
            ("kinks.cascade", k.cascade),
            ("kinks.piecewise_cascade", k.piecewise_cascade),
            ("kinks.piecewise_fine_step", k.piecewise_fine_step),
            ("kinks.resolution", k.resolution),
            ("kinks.near", k.near),
            ("kinks.test_distance", k.test_distance),
            ("kinks.side_ratio", k.side_ratio),
            ("kinks.leap_cascade", k.leap_cascade),
            ("join.distance", self.join.distance),
        ];
        for (name, value) in positive {
            if !(value.is_finite() && value > 0.0) {
                return fail(name, &value, "must be a finite number > 0");
            }
        }
        if a.min_step > a.max_step {
            return fail(
                "arc_length.min_step",
                &a.min_step,
                "must not exceed max_step",
            );
        }
        if !(s.growth.is_finite() && s.growth >= 1.0) {
            return fail("step.growth", &s.growth, "must be a finite number ≥ 1");
        }
        if !(s.shrink > 0.0 && s.shrink < 1.0) {
            return fail(
                "step.shrink",
                &s.shrink,
                "must lie strictly between 0 and 1",
            );
        }
        let cosines = [
            (
                "guards.tight.min_tangent_cosine",
                g.tight.min_tangent_cosine,
            ),
            ("guards.lax.min_tangent_cosine", g.lax.min_tangent_cosine),
            ("guards.retrace.cosine", g.retrace.cosine),
            ("kinks.max_reversal", k.max_reversal),
            ("join.cosine", self.join.cosine),
        ];
        for (name, value) in cosines {
            // A limit of 1 would refuse every turn (and divides by zero).
            if !(value > -1.0 && value < 1.0) {
                return fail(name, &value, "must be a cosine strictly between −1 and 1");
            }
        }
        let lists = [
            ("kinks.trial_divisors", &k.trial_divisors[..]),
            ("kinks.side_scales", &k.side_scales[..]),
            ("kinks.leap_multiples", &k.leap_multiples[..]),
        ];
        for (name, values) in lists {
            if !values.iter().all(|v| v.is_finite() && *v > 0.0) {
                return fail(name, &values, "every entry must be a finite number > 0");
            }
        }
        if g.trail < 2 {
            return fail("guards.trail", &g.trail, "must be at least 2 (one segment)");
        }
        if !(1..=52).contains(&g.branch_point_bisections) {
            return fail(
                "guards.branch_point_bisections",
                &g.branch_point_bisections,
                "must be 1 to 52 (beyond, the bracket is below round-off)",
            );
        }
        if g.branch_point_continuity < 1.0 {
            return fail(
                "guards.branch_point_continuity",
                &g.branch_point_continuity,
                "must be at least 1 (points on planes a step apart are at least a step apart)",
            );
        }
        if self.join.confirmations == 0 {
            return fail("join.confirmations", &0, "must be at least 1");
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::super::*;
    use crate::continuation::NewtonSettings;

    fn arc_length() -> ArcLengthSettings {
        ArcLengthSettings {
            start: 1.0,
            end: 2.0,
            initial_step: 0.01,
            min_step: 1e-9,
            max_step: 0.05,
            length_scale: 1.0,
            newton: NewtonSettings {
                tolerance: 1e-10,
                max_iterations: 20,
                ..Default::default()
            },
            max_points: 100,
        }
    }

    #[test]
    fn the_defaults_are_valid_and_a_bad_setting_is_named() {
        assert_eq!(Settings::from(arc_length()).validate(), Ok(()));
        let bad = Settings {
            arc_length: ArcLengthSettings {
                min_step: 0.0,
                ..arc_length()
            },
            ..Settings::from(arc_length())
        };
        let error = bad
            .validate()
            .expect_err("a zero min_step never underflows");
        assert_eq!(error.name, "arc_length.min_step");
        let bad = Settings {
            guards: GuardSettings {
                tight: TurnLimits {
                    min_tangent_cosine: 1.0,
                    max_correction_ratio: 0.1,
                },
                ..Default::default()
            },
            ..Settings::from(arc_length())
        };
        let error = bad
            .validate()
            .expect_err("a cosine of 1 refuses every turn");
        assert_eq!(error.name, "guards.tight.min_tangent_cosine");
        assert!(error.to_string().contains("strictly between"), "{error}");
        // The branch-point crossing: a continuity below 1 could never pass,
        // and beyond 52 bisections the bracket is below round-off.
        for (guards, name, told) in [
            (
                GuardSettings {
                    branch_point_continuity: 0.5,
                    ..Default::default()
                },
                "guards.branch_point_continuity",
                "at least 1",
            ),
            (
                GuardSettings {
                    branch_point_bisections: 0,
                    ..Default::default()
                },
                "guards.branch_point_bisections",
                "1 to 52",
            ),
            (
                GuardSettings {
                    branch_point_bisections: 60,
                    ..Default::default()
                },
                "guards.branch_point_bisections",
                "1 to 52",
            ),
        ] {
            let bad = Settings {
                guards,
                ..Settings::from(arc_length())
            };
            let error = bad.validate().expect_err(name);
            assert_eq!(error.name, name);
            assert!(error.to_string().contains(told), "{error}");
        }
    }
}
