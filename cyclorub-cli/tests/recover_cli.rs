//! `cyclorub recover RESULTS`: any dof of any sector of a stored point is
//! the recovery the run did.

use crate::common::{cyclorub, text};
use crate::stability_cli::{run_tiny, scratch};
use cyclorub::case::Case;
use cyclorub::forced_response::prepare;
use cyclorub::results::hdf5;
use std::path::Path;

/// Reads the CSV of `cyclorub recover`: its header and its columns.
fn read_csv(path: &Path) -> (Vec<String>, Vec<Vec<f64>>) {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines();
    let header: Vec<String> = lines.next().unwrap().split(',').map(String::from).collect();
    let mut columns = vec![Vec::new(); header.len()];
    for line in lines {
        for (column, value) in columns.iter_mut().zip(line.split(',')) {
            column.push(value.parse::<f64>().unwrap());
        }
    }
    (header, columns)
}

#[test]
fn recover_gives_the_histories_the_run_stored_and_any_other_dof() {
    let dir = scratch("recover");
    let (case_path, out) = run_tiny(&dir);
    let data = hdf5::read(&out.join(hdf5::FILE_NAME)).unwrap();
    let stored = data.histories.as_ref().expect("the peak point's histories");
    let p = stored.point;

    // The observed dof (1) on every sector, at the peak point: the run's
    // own histories, to 1e-12.
    let csv = dir.join("observed.csv");
    let output = cyclorub(&[
        "recover",
        out.to_str().unwrap(),
        "--dof",
        "1",
        "--point",
        &p.to_string(),
        "--output",
        csv.to_str().unwrap(),
    ]);
    assert!(output.status.success(), "{}", text(&output));
    let (header, columns) = read_csv(&csv);
    assert_eq!(header.len(), 1 + 2 * 6, "{header:?}");
    let scale = stored
        .displacement
        .iter()
        .flatten()
        .fold(0.0_f64, |m, x| m.max(x.abs()));
    let velocity_scale = stored
        .velocity
        .iter()
        .flatten()
        .fold(0.0_f64, |m, x| m.max(x.abs()));
    for sector in 0..6 {
        assert_eq!(
            header[1 + 2 * sector],
            format!("displacement_sector{}_m", sector + 1)
        );
        for (n, (&got, &want)) in columns[1 + 2 * sector]
            .iter()
            .zip(&stored.displacement[sector])
            .enumerate()
        {
            assert!(
                (got - want).abs() <= 1e-12 * scale,
                "sector {sector}, sample {n}: {got} {want}"
            );
        }
        for (&got, &want) in columns[2 + 2 * sector].iter().zip(&stored.velocity[sector]) {
            assert!((got - want).abs() <= 1e-12 * velocity_scale, "{got} {want}");
        }
    }
    for (got, want) in columns[0].iter().zip(&stored.time_s) {
        assert!(
            (got - want).abs() <= 1e-12 * want.abs().max(1e-3),
            "{got} {want}"
        );
    }

    // Another dof on two sectors at another point, against the library's
    // recovery from the case file itself.
    let csv = dir.join("other.csv");
    let output = cyclorub(&[
        "recover",
        out.to_str().unwrap(),
        "--dof",
        "3",
        "--sector",
        "2",
        "--sector",
        "5",
        "--point",
        "1",
        "--time-samples",
        "32",
        "--output",
        csv.to_str().unwrap(),
    ]);
    assert!(output.status.success(), "{}", text(&output));
    let (header, columns) = read_csv(&csv);
    assert_eq!(header.len(), 5, "{header:?}");
    assert_eq!(columns[0].len(), 32);
    let case = Case::from_file_checked(&case_path).unwrap();
    let prepared = prepare(&case, &dir, case.basis.kind).unwrap();
    let point = &data.points[1];
    let omega = 2.0 * std::f64::consts::PI * point.frequency_hz;
    let expected = cyclorub::results::recovery::dof_histories(
        &prepared.problem,
        &point.unknowns,
        omega,
        2,
        &[1, 4],
        32,
    )
    .unwrap();
    for (k, history) in expected.iter().enumerate() {
        let scale = history
            .displacement
            .iter()
            .fold(0.0_f64, |m, x| m.max(x.abs()));
        assert!(scale > 0.0);
        for (&got, &want) in columns[1 + 2 * k].iter().zip(&history.displacement) {
            assert!((got - want).abs() <= 1e-12 * scale, "{got} {want}");
        }
    }

    // Bad dofs and sectors: exit 2, naming the flag and the range.
    for (flag, value, range) in [
        ("--dof", "0", "1..=5"),
        ("--dof", "6", "1..=5"),
        ("--sector", "7", "1..=6"),
    ] {
        let mut args = vec!["recover", out.to_str().unwrap(), "--dof", "1"];
        if flag == "--dof" {
            args[3] = value;
        } else {
            args.extend([flag, value]);
        }
        let output = cyclorub(&args);
        assert_eq!(output.status.code(), Some(2), "{}", text(&output));
        let message = String::from_utf8_lossy(&output.stderr);
        assert!(message.contains(&format!("{flag} {value}")), "{message}");
        assert!(message.contains(range), "{message}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}
