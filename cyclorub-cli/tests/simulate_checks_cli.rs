//! `cyclorub simulate`'s checks of its options (hostile run 3): a sweep too
//! fast for its end frequency, --periods and --rate beside what they do not
//! fit, a perturbation of 0 or less, a run's results folder, and one period.

use super::simulate_cli::{cyclorub, scratch, small_case, text};

/// Finding 11: over one period there is no modulation over periods: "n/a"
/// and null, not a number computed from one period.
#[test]
fn one_period_has_no_modulation_over_periods() {
    let dir = scratch("one-period");
    let case = small_case(&dir);
    let out = dir.join("simulation");
    let simulate = |periods: &str| {
        let run = cyclorub(&[
            "simulate",
            &case,
            "--at-hz",
            "150",
            "--periods",
            periods,
            "--steps-per-period",
            "16",
            "--output",
            &out.display().to_string(),
        ]);
        assert!(run.status.success(), "{}", text(&run.stderr));
        let record: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(out.join("simulation.json")).unwrap())
                .unwrap();
        (text(&run.stdout), record["modulation_over_periods"].clone())
    };
    let (said, over) = simulate("1");
    assert!(said.contains("n/a over periods"), "{said}");
    assert!(over.is_null(), "{over}");
    let (said, over) = simulate("2");
    assert!(said.contains("over the last 2 periods"), "{said}");
    assert!(over.is_f64(), "{over}");
}
