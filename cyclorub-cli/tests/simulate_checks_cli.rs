//! `cyclorub simulate`'s checks of its options (hostile run 3): a sweep too
//! fast for its end frequency, --periods and --rate beside what they do not
//! fit, a perturbation of 0 or less, a run's results folder, and one period.

use super::simulate_cli::{cyclorub, run_at, scratch, small_case, text};

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

/// Finding 4: a sweep of fewer than 10 periods of END is refused with the
/// fastest rate allowed; an allowed one ends at END, not past it.
#[test]
fn a_sweep_too_fast_is_refused_and_a_sweep_ends_at_its_end_frequency() {
    let dir = scratch("sweep-rate");
    let case = small_case(&dir);
    let out = dir.join("simulation");
    let sweep = |rate: &str| {
        cyclorub(&[
            "simulate",
            &case,
            "--sweep",
            "200..212",
            "--rate",
            rate,
            "--steps-per-period",
            "16",
            "--output",
            &out.display().to_string(),
        ])
    };
    // 12 Hz at 400 Hz/s: 0.03 s, 6.36 periods of 212 Hz; 12 × 212 / 10.
    let fast = sweep("400");
    assert_eq!(fast.status.code(), Some(2), "{}", text(&fast.stderr));
    let message = text(&fast.stderr);
    assert!(
        message.contains("--rate 400") && message.contains("--rate ≤ 254.4 Hz/s"),
        "{message}"
    );
    let allowed = sweep("250");
    assert!(allowed.status.success(), "{}", text(&allowed.stderr));
    let csv = std::fs::read_to_string(out.join("simulation.csv")).unwrap();
    let last: f64 = csv
        .lines()
        .last()
        .and_then(|l| l.split(',').nth(2))
        .and_then(|f| f.parse().ok())
        .unwrap_or_else(|| panic!("{csv}"));
    assert!((last - 212.0).abs() < 1e-9, "the sweep ends at {last} Hz");
}

/// Finding 5: --periods with --sweep, and --rate without it (beside
/// --at-hz, where clap's `requires` lets it through), are refused.
#[test]
fn periods_with_a_sweep_and_a_rate_without_one_are_refused() {
    let dir = scratch("sweep-flags");
    let case = small_case(&dir);
    let out = dir.join("simulation").display().to_string();
    let periods = cyclorub(&[
        "simulate",
        &case,
        "--sweep",
        "200..212",
        "--rate",
        "100",
        "--periods",
        "3",
        "--output",
        &out,
    ]);
    assert_eq!(periods.status.code(), Some(2));
    let message = text(&periods.stderr);
    assert!(
        message.contains("--periods 3 with --sweep 200..212")
            && message.contains("leave --periods out"),
        "{message}"
    );
    let rate = cyclorub(&[
        "simulate", &case, "--at-hz", "150", "--rate", "5", "--output", &out,
    ]);
    assert_eq!(rate.status.code(), Some(2));
    let message = text(&rate.stderr);
    assert!(
        message.contains("--rate 5: a sweep rate needs --sweep START..END"),
        "{message}"
    );
    assert!(!dir.join("simulation").exists(), "nothing written");
}

/// Finding 6: an amplitude of 0 or less is refused; one above 10 gaps
/// (the default case's gap is 1 mm) is warned about.
#[test]
fn a_perturbation_of_zero_or_less_is_refused_and_a_huge_one_warned() {
    let dir = scratch("perturb-sign");
    let case = small_case(&dir);
    let out = dir.join("simulation").display().to_string();
    let perturbed = |amplitude: &str| {
        cyclorub(&[
            "simulate",
            &case,
            "--at-hz",
            "150",
            "--periods",
            "1",
            "--steps-per-period",
            "16",
            &format!("--perturb={amplitude}"),
            "--output",
            &out,
        ])
    };
    for amplitude in ["0", "-1e-6:2"] {
        let refused = perturbed(amplitude);
        assert_eq!(refused.status.code(), Some(2), "{amplitude}");
        let message = text(&refused.stderr);
        assert!(
            message.contains(&format!("--perturb {amplitude}")) && message.contains("must be > 0"),
            "{message}"
        );
    }
    let huge = perturbed("2e-2");
    assert!(huge.status.success(), "{}", text(&huge.stderr));
    let message = text(&huge.stderr);
    assert!(
        message
            .contains("--perturb 2e-2: the amplitude 0.02 m is 20 times the casing's smallest gap"),
        "{message}"
    );
}

/// Finding 8: --output into a run's results folder is refused unless
/// --overwrite.
#[test]
fn an_output_folder_holding_a_run_is_refused_without_overwrite() {
    let dir = scratch("run-folder");
    let case = small_case(&dir);
    let results = dir.join("results").display().to_string();
    run_at(&case, "150", &results);
    let simulate = |extra: &[&str]| {
        let mut args = vec![
            "simulate",
            &case,
            "--at-hz",
            "150",
            "--periods",
            "1",
            "--steps-per-period",
            "16",
            "--output",
            &results,
        ];
        args.extend(extra);
        cyclorub(&args)
    };
    let refused = simulate(&[]);
    assert_eq!(refused.status.code(), Some(2));
    let message = text(&refused.stderr);
    assert!(
        message.contains("(--output)")
            && message.contains("holds the results of another run")
            && message.contains("--overwrite"),
        "{message}"
    );
    assert!(!dir.join("results/simulation.json").exists());
    let overwritten = simulate(&["--overwrite"]);
    assert!(
        overwritten.status.success(),
        "{}",
        text(&overwritten.stderr)
    );
    assert!(dir.join("results/simulation.json").is_file());
}
