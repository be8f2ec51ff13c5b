//! Step control: the step is shrunk when refused and grown after easy
//! steps, between the smallest step (below which the branch stops) and the
//! policy's largest; the last step that went through at the first attempt
//! is the measure of "far below" for the kink and leap heuristics.

use super::settings::StepSettings;

/// The smallest resume fraction, relative to `after_kink`: 1/64, about
/// the ~1e-3 step that locates a kink against the 0.03 cap.
const MIN_RESUME: f64 = 1.0 / 64.0;

/// The step length and its history.
pub(crate) struct StepControl {
    step: f64,
    /// The last step that went through at the first attempt.
    good_step: f64,
    /// Refusals since the last accepted step.
    failures: usize,
    largest: f64,
    smallest: f64,
    settings: StepSettings,
    /// The fraction of the last easy step at which the step resumes after
    /// a kink: doubled (up to `after_kink`) when a resumed step goes
    /// through, halved when it is refused, so that it follows how close
    /// together the kinks lie.
    resume: f64,
    /// Whether the step now set was resumed after a kink.
    resumed: bool,
}

impl StepControl {
    /// Starting at `initial`, within `[smallest, largest]` (`initial` above
    /// `largest` is lowered to it).
    pub(crate) fn new(initial: f64, smallest: f64, largest: f64, settings: StepSettings) -> Self {
        let step = initial.min(largest);
        Self {
            step,
            good_step: step,
            failures: 0,
            largest,
            smallest,
            settings,
            resume: settings.after_kink,
            resumed: false,
        }
    }

    /// The step to try.
    pub(crate) fn step(&self) -> f64 {
        self.step
    }

    /// The last step that went through at the first attempt.
    pub(crate) fn good_step(&self) -> f64 {
        self.good_step
    }

    /// Whether `step` is at the floor, where nothing shorter is left to
    /// try: it is not refused for turning.
    pub(crate) fn at_floor(&self, step: f64) -> bool {
        step <= self.settings.floor_factor * self.smallest
    }

    /// The step was refused and no other way was found: shrinks it.
    /// `false` when it fell below the smallest step.
    pub(crate) fn refused(&mut self) -> bool {
        self.step *= self.settings.shrink;
        self.step >= self.smallest
    }

    /// Counts a refusal (before the policy looks for another way).
    pub(crate) fn failed(&mut self) {
        self.failures += 1;
        if std::mem::take(&mut self.resumed) {
            self.resume = (0.5 * self.resume).max(MIN_RESUME * self.settings.after_kink);
        }
    }

    /// A kink was turned: the next step is the resume fraction of the last
    /// easy one (at most the largest step), if that is longer than the
    /// step now set (the short one that located the kink).
    pub(crate) fn resume_after_kink(&mut self) {
        let resumed = (self.resume * self.good_step).min(self.largest);
        if resumed > self.step {
            self.step = resumed;
            self.resumed = true;
        }
    }

    /// A step converged in `iterations` was accepted: returns its length
    /// and sets the next (grown if it went through at once, easily).
    pub(crate) fn accepted(&mut self, iterations: usize) -> f64 {
        let used = self.step;
        let grow = self.failures == 0 && iterations <= self.settings.easy_iterations;
        if std::mem::take(&mut self.resumed) {
            self.resume = (2.0 * self.resume).min(self.settings.after_kink);
        }
        if self.failures == 0 {
            self.good_step = used;
        }
        self.failures = 0;
        if grow {
            self.step = (used * self.settings.growth).min(self.largest);
        }
        used
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    #[allow(clippy::float_cmp)] // halving and growing by 1.5 are exact here
    fn the_step_grows_after_easy_steps_and_halves_down_to_the_floor() {
        let mut control = StepControl::new(0.2, 0.01, 0.1, StepSettings::default());
        assert_eq!(control.step(), 0.1);
        control.failed();
        assert!(control.refused());
        assert_eq!(control.step(), 0.05);
        // Accepted after a failure: not grown, not a good step.
        assert_eq!(control.accepted(1), 0.05);
        assert_eq!((control.step(), control.good_step()), (0.05, 0.1));
        // Easy: grown by 1.5, and a good step.
        assert_eq!(control.accepted(3), 0.05);
        assert_eq!((control.step(), control.good_step()), (0.05 * 1.5, 0.05));
        // Hard (more iterations): not grown.
        let grown = 0.05 * 1.5;
        assert_eq!(control.accepted(4), grown);
        assert_eq!(control.step(), grown);
        // Halved until below the smallest step.
        let refusals = std::iter::from_fn(|| control.refused().then_some(())).count();
        assert_eq!(refusals, 2);
        assert!(control.step() < 0.01);
        assert!(control.at_floor(0.02) && !control.at_floor(0.021));
    }

    #[test]
    #[allow(clippy::float_cmp)] // halving and doubling are exact here
    fn the_step_after_a_kink_resumes_at_a_fraction_that_adapts() {
        let mut control = StepControl::new(0.03, 1e-7, 0.03, StepSettings::default());
        let halve = |control: &mut StepControl, times: usize| {
            for _ in 0..times {
                control.failed();
                assert!(control.refused());
            }
        };
        // An easy step of 0.03, then halvings down to a kink, turned: the
        // step resumes at the last easy one.
        control.accepted(2);
        halve(&mut control, 5);
        control.accepted(2);
        control.resume_after_kink();
        assert_eq!(control.step(), 0.03);
        // The resumed step is refused: the next kink resumes at half.
        halve(&mut control, 1);
        assert_eq!(control.resume, 0.5);
        control.accepted(2);
        halve(&mut control, 4);
        control.accepted(2);
        control.resume_after_kink();
        assert_eq!(control.step(), 0.015);
        // This one goes through at once: the fraction doubles back.
        control.accepted(2);
        assert_eq!((control.resume, control.good_step()), (1.0, 0.015));
        halve(&mut control, 1);
        control.accepted(2);
        control.resume_after_kink();
        assert_eq!(control.step(), 0.015);
        // Refused again and again: the fraction stops at 1/64.
        for _ in 0..10 {
            control.failed();
            control.accepted(2);
            control.step = 1e-6;
            control.resume_after_kink();
        }
        assert_eq!(control.resume, 1.0 / 64.0);
        // Never above the largest step.
        control.good_step = 1.0;
        control.resume = 1.0;
        control.resume_after_kink();
        assert_eq!(control.step(), 0.03);
    }
}
