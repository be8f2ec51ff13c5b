//! `cyclorub study FOLDER`: every case file of a folder solved, one row
//! each in study.csv; a mistuned case's amplification factor is the one
//! `cyclorub run` records in run.json for the same case (issue 44 item 5).

use crate::common::{cyclorub, text};

fn scratch(name: &str) -> crate::common::Scratch {
    crate::common::scratch("study-cli", name)
}

/// The 6-sector academic wheel, linear (the casing 1 m away), one
/// harmonic, mistuned by 1 % with `seed`.
fn pattern(seed: u64) -> String {
    format!(
        "[model]\nsectors = 6\n[harmonic_balance]\nharmonics = 1\ntime_samples = 96\n\
         [casing]\ngap = 1.0\n[basis]\nkind = \"physical\"\n[stability]\nenabled = false\n\
         [output]\nfigures = [\"svg\"]\n\
         [mistuning]\nstandard_deviation = 0.01\nseed = {seed}\n"
    )
}

const FREQUENCIES: &str = "206.0,207.5,208.5,209.0,209.5,210.0,210.5,211.0,212.0";

#[test]
fn a_folder_of_patterns_gives_one_row_each_and_the_figure() {
    let dir = scratch("patterns");
    let cases = dir.join("cases");
    std::fs::create_dir_all(&cases).unwrap();
    for seed in [1, 2] {
        std::fs::write(cases.join(format!("seed{seed}.toml")), pattern(seed)).unwrap();
    }
    std::fs::write(cases.join("zbad.toml"), "[casing]\ngap = -1.0\n").unwrap();
    let out = dir.join("out");
    let output = cyclorub(&[
        "study",
        cases.to_str().unwrap(),
        "--output",
        out.to_str().unwrap(),
        "--at-hz",
        FREQUENCIES,
    ]);
    // The refused case leaves the study incomplete: exit code 3, counted on
    // the last line (study.csv and the figure are written all the same).
    assert_eq!(output.status.code(), Some(3), "{}", text(&output));
    let stdout = String::from_utf8_lossy(&output.stdout);
    assert_eq!(
        stdout.lines().last(),
        Some("1 of 3 cases unfinished (finished = false in study.csv): zbad (refused)"),
        "{stdout}"
    );
    let table = std::fs::read_to_string(out.join("study.csv")).unwrap();
    let lines: Vec<&str> = table.lines().collect();
    let header: Vec<&str> = lines[0].split(',').collect();
    let column = |name: &str| header.iter().position(|h| *h == name).unwrap();
    assert_eq!(lines.len(), 4, "{table}");
    assert!(lines[3].starts_with("\"zbad\"") && lines[3].contains("casing.gap"));
    assert_eq!(lines[3].split(',').nth(column("finished")), Some("false"));
    for (line, seed) in lines[1..3].iter().zip([1, 2]) {
        let cells: Vec<&str> = line.split(',').collect();
        assert_eq!(cells[column("seed")], seed.to_string());
        let factor: f64 = cells[column("amplification_factor")].parse().unwrap();
        // The same case through `cyclorub run`: run.json's record.
        let case = dir.join(format!("run{seed}.toml"));
        std::fs::write(&case, pattern(seed)).unwrap();
        let folder = dir.join(format!("run{seed}"));
        let ran = cyclorub(&[
            "run",
            case.to_str().unwrap(),
            "--output",
            folder.to_str().unwrap(),
            "--at-hz",
            FREQUENCIES,
        ]);
        assert!(ran.status.success(), "{}", text(&ran));
        let run: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(folder.join("run.json")).unwrap())
                .unwrap();
        let recorded = run["mistuning"]["amplification_factor"].as_f64().unwrap();
        // study.csv prints 17 significant digits (`{:e}`): equal to round-off.
        assert!(
            (factor - recorded).abs() <= 1e-12 * recorded,
            "{factor} against {recorded}"
        );
        assert_eq!(
            cells[column("most_responding_sector")],
            run["mistuning"]["most_responding_sector"].to_string()
        );
    }
    let svg = std::fs::read_to_string(out.join("amplification_factors.svg")).unwrap();
    assert!(
        svg.contains("of 2 patterns (N = 6)"),
        "the refused case is left out"
    );
    // A folder without case files is refused by name.
    let empty = cyclorub(&["study", out.join("nothing").to_str().unwrap()]);
    assert_eq!(empty.status.code(), Some(2), "{}", text(&empty));
    let _ = std::fs::remove_dir_all(&dir);
}

/// A study whose every case finishes exits with 0 and says so last.
#[test]
fn a_study_whose_cases_all_finish_exits_with_0() {
    let dir = scratch("finished");
    std::fs::write(dir.join("seed1.toml"), pattern(1)).unwrap();
    let output = cyclorub(&["study", dir.to_str().unwrap(), "--at-hz", "208.0,209.0"]);
    assert!(output.status.success(), "{}", text(&output));
    let stdout = String::from_utf8_lossy(&output.stdout);
    assert_eq!(
        stdout.lines().last(),
        Some("1 of 1 cases finished"),
        "{stdout}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}
