//! The files of `RESULTS/branches/` that `cyclorub branches` reads and
//! writes: a bifurcated branch's CSV, and the records of earlier calls on
//! the same run.

use cyclorub::plot::branches::CurvePoint;
use cyclorub::results::bifurcated::{most_responding, BifurcatedSide, BranchSummary};
use cyclorub::results::folder::RunFile;
use std::fmt::Write as _;
use std::path::Path;

/// The bifurcated branches run.json records (those of this run: run.json
/// is rewritten by every run, so it never holds another's), and the
/// leftovers of another run in `folder` (`branches.json` entries it does
/// not list, from a folder overwritten before `--overwrite` cleared
/// `branches/`): their CSVs are removed.
pub(super) fn this_runs_records(results: &Path, folder: &Path) -> Vec<BranchSummary> {
    let path = results.join("run.json");
    let recorded: Vec<BranchSummary> = std::fs::read_to_string(&path)
        .ok()
        .and_then(|text| RunFile::parse(&path, &text).ok())
        .map(|run| run.branches)
        .unwrap_or_default();
    let listed: Vec<BranchSummary> = std::fs::read_to_string(folder.join("branches.json"))
        .ok()
        .and_then(|text| serde_json::from_str(&text).ok())
        .unwrap_or_default();
    for stale in &listed {
        let Some(file) = stale.file.as_deref() else {
            continue;
        };
        let kept = recorded.iter().any(|r| r.file.as_deref() == Some(file));
        if !kept && file.starts_with("branches/") && !file.contains("..") {
            let _ = std::fs::remove_file(results.join(file));
        }
    }
    recorded
}

/// The sides of a branch CSV written by [`branch_table`]: each side's
/// direction and points (rows that do not parse are skipped).
pub(super) fn read_sides(text: &str) -> Vec<(f64, Vec<CurvePoint>)> {
    let mut sides: Vec<(f64, Vec<CurvePoint>)> = Vec::new();
    for line in text.lines().skip(1) {
        let cells: Vec<&str> = line.split(',').collect();
        let number = |i: usize| cells.get(i).and_then(|c| c.parse::<f64>().ok());
        let (Some(direction), Some(frequency_hz), Some(largest_m), Some(smallest_m)) =
            (number(0), number(2), number(4), number(5))
        else {
            continue;
        };
        let stable = match cells.get(3) {
            Some(&"stable") => Some(true),
            Some(&"unstable") => Some(false),
            _ => None,
        };
        let point = CurvePoint {
            frequency_hz,
            largest_m,
            smallest_m,
            stable,
        };
        match sides.last_mut() {
            Some((d, points)) if *d == direction => points.push(point),
            _ => sides.push((direction, vec![point])),
        }
    }
    sides
}

/// The CSV of a bifurcated branch's `sides` on `sectors` sectors: one row
/// per point of each side, the observed dof's amplitude on every sector.
pub(super) fn branch_table(sides: &[BifurcatedSide], sectors: usize) -> String {
    let mut text = String::from("side,point,frequency_hz,stable,largest_sector_amplitude_m,smallest_sector_amplitude_m,most_responding_sector");
    for j in 1..=sectors {
        let _ = write!(text, ",sector_{j}_m");
    }
    text.push('\n');
    for side in sides {
        for (i, (amplitudes, hz)) in side
            .sector_amplitudes_m
            .iter()
            .zip(&side.frequency_hz)
            .enumerate()
        {
            let (most, largest) = most_responding(amplitudes);
            let smallest = amplitudes.iter().cloned().fold(f64::MAX, f64::min);
            let word = match side.stable.get(i).copied().flatten() {
                Some(true) => "stable",
                Some(false) => "unstable",
                None => "",
            };
            let _ = write!(
                text,
                "{},{i},{hz:.10},{word},{largest:.10e},{smallest:.10e},{}",
                side.direction,
                most + 1
            );
            for a in amplitudes {
                let _ = write!(text, ",{a:.10e}");
            }
            text.push('\n');
        }
    }
    text
}
