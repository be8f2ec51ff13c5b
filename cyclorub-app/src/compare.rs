//! Comparing two results folders of the same case (e.g. a reduced basis
//! against the physical full model) point by point at the same frequencies.
//!
//! Points are matched by frequency (relative tolerance), in branch order:
//! a point of A takes the next unmatched point of B at its frequency, so
//! the several points a branch with turning points has at one frequency
//! pair up in order. Only converged points are compared. Two differences
//! are reported, each the largest over matched points and common sectors:
//! - amplitudes (`branch.csv`): `|a − b| / max(|a|, |b|)`;
//! - recovered displacements (`observed_harmonics.csv`): the RMS over the
//!   period of `u_a − u_b` divided by the larger RMS of `u_a`, `u_b`
//!   (Parseval on the harmonic coordinates).

use cyclorub::results::folder::ResultsFolder;
use cyclorub::results::ResultsError;
use std::path::Path;

/// Settings of a comparison.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CompareOptions {
    /// Two points match when their frequencies differ by at most this
    /// fraction of the frequency.
    pub frequency_tolerance: f64,
}

impl Default for CompareOptions {
    fn default() -> Self {
        Self {
            frequency_tolerance: 1e-9,
        }
    }
}

/// Where a largest difference occurs.
#[derive(Clone, Debug, PartialEq)]
pub struct Difference {
    /// The relative difference.
    pub value: f64,
    /// The point of A.
    pub point_a: usize,
    /// The point of B.
    pub point_b: usize,
    /// The sector (1-based).
    pub sector: usize,
    /// The frequency (of A's point), Hz.
    pub frequency_hz: f64,
}

/// A point left out of the comparison.
#[derive(Clone, Debug, PartialEq)]
pub struct Unmatched {
    /// Point index in its folder.
    pub point: usize,
    /// Its frequency, Hz.
    pub frequency_hz: f64,
    /// Why: no point of the other folder at that frequency, or not converged.
    pub reason: &'static str,
}

/// The outcome of a comparison.
#[derive(Clone, Debug, PartialEq)]
pub struct Comparison {
    /// Basis kinds of A and B.
    pub bases: (String, String),
    /// Points of A and B.
    pub points: (usize, usize),
    /// Matched point pairs `(A, B)` (point numbers of `branch.csv`).
    pub matched: Vec<(usize, usize)>,
    /// Points of A left out.
    pub unmatched_a: Vec<Unmatched>,
    /// Points of B left out.
    pub unmatched_b: Vec<Unmatched>,
    /// The sectors compared (reported by both, 1-based).
    pub sectors: Vec<usize>,
    /// Largest relative difference of the observed amplitudes.
    pub amplitude: Option<Difference>,
    /// Largest relative difference of the recovered displacements.
    pub displacement: Option<Difference>,
}

impl Comparison {
    /// The larger of the two differences (0 when nothing was compared,
    /// NaN if a difference is NaN).
    pub fn worst(&self) -> f64 {
        [&self.amplitude, &self.displacement]
            .iter()
            .filter_map(|d| d.as_ref().map(|d| d.value))
            .fold(0.0, |worst: f64, v| {
                if v.is_nan() || worst.is_nan() {
                    f64::NAN
                } else {
                    worst.max(v)
                }
            })
    }
}

/// The keys (JSON paths) where two cases differ, ignoring what does not
/// change the physics: the basis, the continuation settings, the output
/// folder and which optional files it holds, and the centrifugal force a
/// run computes from the model and `preload.speed` (stored once computed).
pub fn case_differences(a: &serde_json::Value, b: &serde_json::Value) -> Vec<String> {
    fn walk(path: String, a: &serde_json::Value, b: &serde_json::Value, out: &mut Vec<String>) {
        use serde_json::Value;
        match (a, b) {
            (Value::Object(x), Value::Object(y)) => {
                let mut keys: Vec<&String> = x.keys().chain(y.keys()).collect();
                keys.sort();
                keys.dedup();
                for key in keys {
                    let child = if path.is_empty() {
                        key.clone()
                    } else {
                        format!("{path}.{key}")
                    };
                    if matches!(
                        child.as_str(),
                        "basis"
                            | "continuation"
                            | "output.directory"
                            | "output.harmonics_csv"
                            | "output.contact_harmonics"
                            | "preload.centrifugal_forces"
                    ) {
                        continue;
                    }
                    match (x.get(key), y.get(key)) {
                        (Some(p), Some(q)) => walk(child, p, q, out),
                        _ => out.push(child),
                    }
                }
            }
            (Value::Number(x), Value::Number(y)) => {
                let (p, q) = (
                    x.as_f64().unwrap_or(f64::NAN),
                    y.as_f64().unwrap_or(f64::NAN),
                );
                if (p - q).abs() > 1e-12 * p.abs().max(q.abs()) {
                    out.push(path);
                }
            }
            _ => {
                if a != b {
                    out.push(path);
                }
            }
        }
    }
    let mut out = Vec::new();
    walk(String::new(), a, b, &mut out);
    out
}

/// Refuses results of another case: `Err` says in which keys the case
/// stored with the results (`theirs`: run.json's or results.h5's `case`)
/// differs from `ours` ([`case_differences`]), for the caller to prefix
/// with what it was given (`compare`, `simulate --from`, `--reference`).
pub fn same_case(ours: &serde_json::Value, theirs: &serde_json::Value) -> Result<(), String> {
    let differences = case_differences(ours, theirs);
    if differences.is_empty() {
        Ok(())
    } else {
        Err(format!(
            "not results of the same case: they differ in {}",
            differences.join(", ")
        ))
    }
}

fn relative(a: f64, b: f64) -> f64 {
    let scale = a.abs().max(b.abs());
    if scale == 0.0 {
        0.0
    } else {
        (a - b).abs() / scale
    }
}

/// Mean square over the period of the signal of coordinates `c` (Parseval).
fn mean_square(c: impl Iterator<Item = f64> + Clone) -> f64 {
    c.enumerate()
        .map(|(i, v)| if i == 0 { v * v } else { 2.0 * v * v })
        .sum()
}

fn keep_worst(slot: &mut Option<Difference>, candidate: Difference) {
    if slot.as_ref().is_none_or(|d| candidate.value > d.value) || candidate.value.is_nan() {
        *slot = Some(candidate);
    }
}

/// Compares the results folders `a` and `b`. Fails (bad input) when a
/// folder cannot be read, or when the cases differ in anything but the
/// basis, the continuation settings and the output folder (and files).
pub fn compare_folders(
    a: &Path,
    b: &Path,
    options: &CompareOptions,
) -> Result<Comparison, ResultsError> {
    let folder_a = ResultsFolder::read(a)?;
    let folder_b = ResultsFolder::read(b)?;
    let null = serde_json::Value::Null;
    same_case(
        folder_a.run.get("case").unwrap_or(&null),
        folder_b.run.get("case").unwrap_or(&null),
    )
    .map_err(|why| ResultsError::Input(format!("{} and {} are {why}", a.display(), b.display())))?;
    Ok(compare(&folder_a, &folder_b, options))
}

/// Compares two folders already read (their cases are not checked).
pub fn compare(a: &ResultsFolder, b: &ResultsFolder, options: &CompareOptions) -> Comparison {
    let rows_a = &a.branch.rows;
    let rows_b = &b.branch.rows;
    let mut taken = vec![false; rows_b.len()];
    let mut matched_rows = Vec::new();
    let mut unmatched_a = Vec::new();
    let mut last: Option<usize> = None;
    let close =
        |f: f64, g: f64| (f - g).abs() <= options.frequency_tolerance * f.abs().max(g.abs());
    for (ia, row) in rows_a.iter().enumerate() {
        if !row.converged {
            unmatched_a.push(Unmatched {
                point: row.point,
                frequency_hz: row.frequency_hz,
                reason: "not converged",
            });
            continue;
        }
        let candidates: Vec<usize> = (0..rows_b.len())
            .filter(|&ib| {
                !taken[ib]
                    && rows_b[ib].converged
                    && close(row.frequency_hz, rows_b[ib].frequency_hz)
            })
            .collect();
        // The next one in branch order, else any.
        let choice = candidates
            .iter()
            .find(|&&ib| last.is_none_or(|l| ib > l))
            .or(candidates.first())
            .copied();
        match choice {
            Some(ib) => {
                taken[ib] = true;
                last = Some(ib);
                matched_rows.push((ia, ib));
            }
            None => unmatched_a.push(Unmatched {
                point: row.point,
                frequency_hz: row.frequency_hz,
                reason: "no point of the other folder at this frequency",
            }),
        }
    }
    let unmatched_b = rows_b
        .iter()
        .zip(&taken)
        .filter(|(_, &t)| !t)
        .map(|(row, _)| Unmatched {
            point: row.point,
            frequency_hz: row.frequency_hz,
            reason: if row.converged {
                "no point of the other folder at this frequency"
            } else {
                "not converged"
            },
        })
        .collect();
    let sectors: Vec<usize> = a
        .branch
        .sectors
        .iter()
        .copied()
        .filter(|s| b.branch.column(*s).is_some())
        .collect();
    let mut amplitude = None;
    let mut displacement = None;
    for &(ia, ib) in &matched_rows {
        let (ra, rb) = (&rows_a[ia], &rows_b[ib]);
        for &sector in &sectors {
            let (Some(ca), Some(cb)) = (a.branch.column(sector), b.branch.column(sector)) else {
                continue;
            };
            let at = |value| Difference {
                value,
                point_a: ra.point,
                point_b: rb.point,
                sector,
                frequency_hz: ra.frequency_hz,
            };
            keep_worst(
                &mut amplitude,
                at(relative(ra.amplitudes[ca], rb.amplitudes[cb])),
            );
            if let (Some(xa), Some(xb)) = (
                a.harmonics.get(&(ra.point, sector)),
                b.harmonics.get(&(rb.point, sector)),
            ) {
                let len = xa.len().max(xb.len());
                let get = |x: &Vec<f64>, i: usize| x.get(i).copied().unwrap_or(0.0);
                let difference = mean_square((0..len).map(|i| get(xa, i) - get(xb, i)));
                let scale = mean_square(xa.iter().copied()).max(mean_square(xb.iter().copied()));
                let value = if scale == 0.0 {
                    0.0
                } else {
                    (difference / scale).sqrt()
                };
                keep_worst(&mut displacement, at(value));
            }
        }
    }
    Comparison {
        bases: (a.basis_kind(), b.basis_kind()),
        points: (rows_a.len(), rows_b.len()),
        matched: matched_rows
            .iter()
            .map(|&(ia, ib)| (rows_a[ia].point, rows_b[ib].point))
            .collect(),
        unmatched_a,
        unmatched_b,
        sectors,
        amplitude,
        displacement,
    }
}
