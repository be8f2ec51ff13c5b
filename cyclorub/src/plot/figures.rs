//! The figures of a results folder, drawn from its [`ResultsData`]: what
//! `run` writes at the end and `cyclorub plot` redraws with other choices.

use super::components::{branch_components, cyclic_components};
use super::event_symbols::{classes_label, EventSymbol};
use super::forced_response::{forced_response, Captions, SectorCurves};
use super::modes::frequency_versus_nodal_diameter;
use super::PlotError;
use crate::results::data::ResultsData;
use crate::results::folder::{BranchTable, ResultsFolder};
use crate::results::sizes::ConvergedSizes;
use crate::results::ResultsError;
use crate::stability::{group_events, nodal_diameters};
use std::path::{Path, PathBuf};

/// The file names, in the figures folder.
pub const FORCED_RESPONSE: &str = "forced_response.svg";
/// Cyclic components at one point.
pub const CYCLIC_COMPONENTS: &str = "cyclic_components.svg";
/// First-harmonic components along the branch.
pub const BRANCH_COMPONENTS: &str = "first_harmonic_components.svg";
/// Natural frequencies per nodal diameter.
pub const MODES: &str = "frequency_vs_nodal_diameter.svg";
/// The leading Floquet exponent of each class along the branch.
pub const STABILITY: &str = "stability_exponents.svg";

/// The branch of a comparison run, drawn dashed.
#[derive(Clone, Debug, PartialEq)]
pub struct Reference {
    /// Legend name (e.g. `reference (physical)`).
    pub label: String,
    /// Its `branch.csv`.
    pub branch: BranchTable,
}

impl Reference {
    /// The branch of the results folder `dir`, labelled with the basis its
    /// `run.json` records (`reference (physical)`; `reference (reference)`
    /// when `run.json` cannot be read). Fails when `branch.csv` cannot.
    pub fn read(dir: &Path) -> Result<Self, ResultsError> {
        let branch = BranchTable::read(&dir.join("branch.csv"))?;
        let kind = ResultsFolder::read(dir)
            .map(|f| f.basis_kind())
            .unwrap_or_else(|_| "reference".into());
        Ok(Self {
            label: format!("reference ({kind})"),
            branch,
        })
    }
}

/// What to draw.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct FigureOptions {
    /// Sectors (1-based) of the forced response; `None`: sector 1 and the
    /// sectors of largest and smallest peak, without repeating alike curves.
    pub sectors: Option<Vec<usize>>,
    /// Point (index along the branch) of the component bar chart; `None`:
    /// the point of largest amplitude.
    pub point: Option<usize>,
    /// A comparison run.
    pub reference: Option<Reference>,
    /// Components below this fraction of the largest are not drawn
    /// (default when 0: 1e-12).
    pub relative_floor: f64,
    /// Whether each figure is also written as a PNG at 300 dpi beside its
    /// SVG (`[output] figures`).
    pub png: bool,
    /// The sizes converged at one point (`run.json` `stability.sizes`),
    /// drawn on the stability figure.
    pub sizes: Option<ConvergedSizes>,
}

/// Whether the case of `data` asks for PNG figures (`[output] figures`;
/// results of a case that does not say: the default case's choice).
pub fn png_asked(data: &ResultsData) -> bool {
    let figures = serde_json::from_str::<serde_json::Value>(&data.case_json)
        .ok()
        .and_then(|case| case.get("output")?.get("figures").cloned());
    match figures {
        Some(list) => serde_json::from_value::<Vec<crate::case::FigureFormat>>(list)
            .map(|formats| formats.contains(&crate::case::FigureFormat::Png))
            .unwrap_or(false),
        None => crate::case::OutputSpec::default().png_figures(),
    }
}

/// The relative distance between the amplitude curves of two sectors.
fn curve_distance(data: &ResultsData, a: usize, b: usize) -> f64 {
    let (mut difference, mut scale) = (0.0_f64, 0.0_f64);
    for p in &data.points {
        difference = difference.max((p.amplitude[a] - p.amplitude[b]).abs());
        scale = scale.max(p.amplitude[a].abs()).max(p.amplitude[b].abs());
    }
    if scale == 0.0 {
        0.0
    } else {
        difference / scale
    }
}

/// The default sectors (0-based): sector 1 and those of largest and
/// smallest peak, each kept only if its curve differs from those already
/// kept; with the number of other sectors alike.
fn default_sectors(data: &ResultsData) -> Vec<(usize, usize)> {
    let n = data.sectors;
    if data.points.is_empty() || n == 0 {
        return vec![(0, 0)];
    }
    let peak = |j: usize| {
        data.points
            .iter()
            .map(|p| p.amplitude[j])
            .fold(f64::NEG_INFINITY, f64::max)
    };
    let mut order: Vec<usize> = (0..n).collect();
    order.sort_by(|&a, &b| peak(b).total_cmp(&peak(a)));
    let candidates = [0, order[0], order[n - 1]];
    let mut kept: Vec<usize> = Vec::new();
    for j in candidates {
        if kept.iter().all(|&k| curve_distance(data, j, k) > 1e-6) {
            kept.push(j);
        }
    }
    kept.iter()
        .map(|&j| {
            let alike = (0..n)
                .filter(|&o| o != j && curve_distance(data, j, o) <= 1e-6)
                .count();
            (j, alike)
        })
        .collect()
}

/// The curves of the chosen sectors.
fn sector_curves(data: &ResultsData, options: &FigureOptions) -> Vec<SectorCurves> {
    let n = data.sectors;
    let chosen: Vec<(usize, usize)> = match &options.sectors {
        Some(list) => list.iter().map(|&s| (s - 1, 0)).collect(),
        None => default_sectors(data),
    };
    let chosen_columns: Vec<usize> = chosen.iter().map(|&(j, _)| j).collect();
    let mut curves: Vec<SectorCurves> = chosen
        .into_iter()
        .map(|(j, alike)| {
            let label = match alike {
                0 => format!("sector {}", j + 1),
                a if a + 1 == n => format!("sector {} (all {n} alike)", j + 1),
                a => format!("sector {} (and {a} alike)", j + 1),
            };
            let reference = options
                .reference
                .as_ref()
                .and_then(|r| {
                    r.branch.column(j + 1).map(|c| {
                        r.branch
                            .rows
                            .iter()
                            .filter(|row| row.converged)
                            .map(|row| (row.frequency_hz, row.amplitudes[c]))
                            .collect()
                    })
                })
                .unwrap_or_default();
            SectorCurves {
                label,
                nonlinear: data
                    .points
                    .iter()
                    .filter(|p| p.converged)
                    .map(|p| (p.frequency_hz, p.amplitude[j]))
                    .collect(),
                breaks: data.converged_breaks(),
                linear: data
                    .linear
                    .frequency_hz
                    .iter()
                    .zip(&data.linear.amplitude)
                    .map(|(&f, a)| (f, a[j]))
                    .collect(),
                reference,
                unstable: data.stability.as_ref().map_or_else(Vec::new, |s| {
                    data.points
                        .iter()
                        .zip(&s.stable)
                        .filter(|(p, _)| p.converged)
                        .map(|(_, stable)| !stable)
                        .collect()
                }),
                markers: Vec::new(),
            }
        })
        .collect();
    place_events(data, &chosen_columns, &mut curves);
    curves
}

/// One symbol per stability event ([`group_events`]), on the drawn curve
/// of largest amplitude there (as `run.json` records the amplitude of a
/// marker: the largest over the sectors), labelled with its classes.
/// `columns` are the drawn curves' sectors (0-based).
fn place_events(data: &ResultsData, columns: &[usize], curves: &mut [SectorCurves]) {
    let Some(stability) = &data.stability else {
        return;
    };
    for group in group_events(&stability.markers, |m| m) {
        let Some(&first) = group.first() else {
            continue;
        };
        let amplitude = |j: usize| -> Option<f64> {
            let a = data.points.get(first.index)?.amplitude.get(j).copied()?;
            let b = data
                .points
                .get(first.index + 1)
                .and_then(|p| p.amplitude.get(j).copied())
                .unwrap_or(a);
            Some(a + first.fraction * (b - a))
        };
        let best = columns
            .iter()
            .enumerate()
            .filter_map(|(curve, &j)| Some((curve, amplitude(j)?)))
            .filter(|(_, a)| a.is_finite())
            .max_by(|a, b| a.1.total_cmp(&b.1));
        if let Some((curve, amplitude_m)) = best {
            curves[curve].markers.push(EventSymbol {
                frequency_hz: first.frequency_hz,
                amplitude_m,
                kind: first.kind,
                label: classes_label(&nodal_diameters(group.iter().copied())),
            });
        }
    }
}

/// The stability figure of `data` at `path`.
fn stability_figure(
    path: &Path,
    data: &ResultsData,
    stability: &crate::results::stability::StabilityData,
    sizes: Option<&ConvergedSizes>,
) -> Result<(), PlotError> {
    super::stability::leading_exponents(
        path,
        data,
        stability,
        &format!(
            "Leading Floquet exponent per class along the branch (N = {}, Hill H = {})",
            data.sectors, stability.harmonics
        ),
        sizes,
    )
}

/// Draws the stability figure of `data` into `directory` again with the
/// sizes converged after the run (`cyclorub run` computes them once the
/// figures are written); returns the files written (none without
/// stability).
pub fn redraw_stability(
    directory: &Path,
    data: &ResultsData,
    sizes: &ConvergedSizes,
    png: bool,
) -> Result<Vec<PathBuf>, PlotError> {
    let Some(stability) = &data.stability else {
        return Ok(Vec::new());
    };
    let path = directory.join(STABILITY);
    stability_figure(&path, data, stability, Some(sizes))?;
    let mut written = vec![path.clone()];
    if png {
        written.extend(super::png::write_pngs_beside(&[path])?);
    }
    Ok(written)
}

/// Draws the figures of `data` into `directory` (created if needed) and
/// returns the files written. A figure with nothing to show is skipped; a
/// figure that fails is reported after the others are drawn. Sectors or a
/// point that do not exist are refused before anything is drawn.
pub fn write_figures(
    directory: &Path,
    data: &ResultsData,
    options: &FigureOptions,
) -> Result<Vec<PathBuf>, PlotError> {
    let n = data.sectors;
    if let Some(list) = &options.sectors {
        if let Some(&bad) = list.iter().find(|&&s| s == 0 || s > n) {
            return Err(PlotError::Choice(format!(
                "sector {bad} does not exist: the wheel has sectors 1..={n}"
            )));
        }
        if list.is_empty() {
            return Err(PlotError::Choice("give at least one sector".into()));
        }
    }
    if let Some(p) = options.point {
        if p >= data.points.len() {
            return Err(PlotError::Choice(format!(
                "point {p} does not exist: the branch has points 0..={}",
                data.points.len().saturating_sub(1)
            )));
        }
    }
    std::fs::create_dir_all(directory).map_err(|source| PlotError::Write {
        path: directory.to_path_buf(),
        source,
    })?;
    let floor = if options.relative_floor > 0.0 {
        options.relative_floor
    } else {
        1e-12
    };
    let mut written = Vec::new();
    let mut first_error = None;
    let mut keep = |outcome: Result<(), PlotError>, path: PathBuf| match outcome {
        Ok(()) => written.push(path),
        Err(PlotError::Empty { .. }) => {}
        Err(e) => {
            first_error.get_or_insert(e);
        }
    };
    let dof = &data.observed_name;
    let path = directory.join(FORCED_RESPONSE);
    let reference = options
        .reference
        .as_ref()
        .map_or("reference", |r| r.label.as_str());
    keep(
        forced_response(
            &path,
            &Captions {
                title: format!("Forced response of {dof} (N = {n})"),
                amplitude_axis: format!("amplitude of {dof} (m)"),
                reference: reference.into(),
            },
            &sector_curves(data, options),
        ),
        path,
    );
    if let Some(p) = options.point.or_else(|| data.peak_point()) {
        let q = &data.points[p];
        let path = directory.join(CYCLIC_COMPONENTS);
        keep(
            cyclic_components(
                &path,
                &q.components,
                &format!(
                    "Cyclic components of {dof} at point {p}, {:.4} Hz",
                    q.frequency_hz
                ),
                floor,
            ),
            path,
        );
    }
    if data.harmonics >= 1 && !data.points.is_empty() {
        let converged: Vec<&crate::results::data::PointResults> =
            data.points.iter().filter(|p| p.converged).collect();
        let frequencies: Vec<f64> = converged.iter().map(|p| p.frequency_hz).collect();
        let components: Vec<_> = converged.iter().map(|p| p.components.clone()).collect();
        let path = directory.join(BRANCH_COMPONENTS);
        keep(
            branch_components(
                &path,
                &frequencies,
                &components,
                1,
                &format!("First-harmonic cyclic components of {dof} along the branch"),
                floor,
                8,
            ),
            path,
        );
    }
    if let Some(stability) = &data.stability {
        let path = directory.join(STABILITY);
        keep(
            stability_figure(&path, data, stability, options.sizes.as_ref()),
            path,
        );
    }
    if !data.natural_frequencies.is_empty() {
        let path = directory.join(MODES);
        keep(
            frequency_versus_nodal_diameter(
                &path,
                data.sectors,
                &data.natural_frequencies,
                Some(6),
                &format!(
                    "Natural frequencies per nodal diameter (N = {})",
                    data.sectors
                ),
            ),
            path,
        );
    }
    if let Some(e) = first_error {
        return Err(e);
    }
    if options.png {
        let pngs = super::png::write_pngs_beside(&written)?;
        written.extend(pngs);
    }
    Ok(written)
}
