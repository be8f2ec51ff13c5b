//! The Result's data behind its Python methods: the points' results
//! recovered on first use (solved) or read (loaded), the residual rebuilt,
//! the per-sector and per-point arrays.

use super::*;

impl RunResult {
    /// A result solved in this process.
    pub fn solved(solution: Solution, case_dir: PathBuf, interrupted: bool) -> Self {
        Self {
            case: solution.case.clone(),
            source: Source::Solved(Box::new(solution)),
            case_dir,
            interrupted,
            points: OnceLock::new(),
            data: OnceLock::new(),
            problem: OnceLock::new(),
            mistuning: OnceLock::new(),
        }
    }

    /// The points' results on every sector.
    pub(super) fn points(&self) -> Result<&[PointResults]> {
        if let Some(points) = self.points.get() {
            return Ok(points);
        }
        let computed = match &self.source {
            Source::Solved(solution) => solution
                .point_summaries()
                .into_iter()
                .zip(&solution.branch.points)
                .map(|(summary, point)| {
                    let summary = summary?;
                    PointResults::from_summary(point, summary.observed, summary.contact?)
                })
                .collect::<std::result::Result<Vec<_>, ResultsError>>()?,
            Source::Loaded(_) => {
                let mut points = self.data()?.points.clone();
                // results.h5 keeps the contact forces' harmonics only when
                // the case asks: otherwise they come from the unknowns.
                if !self.case.contact.dofs.is_empty()
                    && points.iter().any(|p| p.contact_force.is_empty())
                {
                    let (problem, _) = self.problem()?;
                    let recovery = BranchRecovery::new(
                        problem,
                        self.case.output.observed_index(),
                        self.case.harmonic_balance.time_samples,
                    );
                    for p in points.iter_mut().filter(|p| p.contact_force.is_empty()) {
                        let omega = 2.0 * std::f64::consts::PI * p.frequency_hz;
                        p.contact_force = recovery
                            .point(&p.unknowns, omega)?
                            .contact?
                            .force_coordinates;
                    }
                }
                points
            }
        };
        Ok(self.points.get_or_init(|| computed))
    }

    /// A mistuned wheel's record as JSON text (`None` for a tuned wheel):
    /// `run.json`'s for a loaded result; for a solved one, computed as
    /// `cyclorub run` writes it (the tuned reference branch solved here).
    pub(super) fn mistuning_text(&self) -> Result<Option<String>> {
        if let Some(text) = self.mistuning.get() {
            return Ok(text.clone());
        }
        let computed = match &self.source {
            Source::Solved(solution) => {
                let summaries = solution
                    .point_summaries()
                    .into_iter()
                    .collect::<std::result::Result<Vec<_>, ResultsError>>()?;
                cyclorub::run::mistuning::record(solution, &summaries)?.map(|r| json(&r))
            }
            Source::Loaded(folder) => folder.record.mistuning.as_ref().map(json),
        };
        Ok(self.mistuning.get_or_init(|| computed).clone())
    }

    /// Everything `results.h5` holds.
    pub(super) fn data(&self) -> Result<&ResultsData> {
        if let Some(data) = self.data.get() {
            return Ok(data);
        }
        let computed = match &self.source {
            Source::Solved(solution) => solution.results_data()?,
            Source::Loaded(folder) => Err(Error::usage(
                None,
                format!("{}: results.h5 was not read", folder.directory.display()),
            ))?,
        };
        Ok(self.data.get_or_init(|| computed))
    }

    /// The residual the branch was solved on (rebuilt for a loaded result)
    /// and the dofs of a sector.
    pub(super) fn problem(&self) -> Result<(&HarmonicBalance, usize)> {
        match &self.source {
            Source::Solved(solution) => Ok((&solution.problem, solution.model.dofs_per_sector())),
            Source::Loaded(folder) => {
                if let Some((problem, dofs)) = self.problem.get() {
                    return Ok((problem, *dofs));
                }
                // The basis the branch was solved on, as run.json records it.
                let prepared =
                    cyclorub::forced_response::prepare(&self.case, &self.case_dir, folder.basis)?;
                let dofs = prepared.model.dofs_per_sector();
                let (problem, dofs) = self.problem.get_or_init(|| (prepared.problem, dofs));
                Ok((problem, *dofs))
            }
        }
    }

    /// The stability arrays, when the check ran.
    pub(super) fn stability_data(&self) -> Result<Option<StabilityData>> {
        Ok(match &self.source {
            Source::Solved(solution) => solution
                .stability
                .computed()
                .map(StabilityData::from_branch),
            Source::Loaded(_) => self.data()?.stability.clone(),
        })
    }

    /// A per-point, per-sector array of the points' results.
    pub(super) fn per_sector<'py>(
        &self,
        py: Python<'py>,
        field: fn(&PointResults) -> &Vec<f64>,
    ) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let points = self.points()?;
        let rows: Vec<Vec<f64>> = points.iter().map(|p| field(p).clone()).collect();
        Ok(matrix(&rows).into_pyarray(py))
    }

    /// A per-point, per-sector, per-contact-dof array.
    pub(super) fn per_contact<'py>(
        &self,
        py: Python<'py>,
        field: fn(&PointResults) -> &Vec<f64>,
    ) -> PyResult<Bound<'py, PyArray3<f64>>> {
        let points = self.points()?;
        let (sectors, contact) = (self.sectors(), self.case.contact.dofs.len().max(1));
        let array = Array3::from_shape_fn((points.len(), sectors, contact), |(p, j, c)| {
            field(&points[p])
                .get(j * contact + c)
                .copied()
                .unwrap_or(f64::NAN)
        });
        Ok(array.into_pyarray(py))
    }

    /// A per-point array of one number.
    pub(super) fn per_point<T: Copy + numpy::Element>(
        &self,
        py: Python<'_>,
        field: fn(&PointResults) -> T,
    ) -> PyResult<Py<PyArray1<T>>> {
        let points = self.points()?;
        let values: Vec<T> = points.iter().map(field).collect();
        Ok(PyArray1::from_vec(py, values).unbind())
    }

    /// The cyclic components `[point, harmonic, nodal diameter]`.
    pub(super) fn components<'py>(
        &self,
        py: Python<'py>,
        forward: bool,
    ) -> PyResult<Bound<'py, PyArray3<f64>>> {
        let points = self.points()?;
        let pick = |p: &PointResults| {
            if forward {
                p.components.forward.clone()
            } else {
                p.components.backward.clone()
            }
        };
        let (harmonics, diameters) = points
            .first()
            .map(|p| {
                let c = pick(p);
                (c.len(), c.first().map_or(0, Vec::len))
            })
            .unwrap_or((
                self.case.harmonic_balance.harmonics + 1,
                self.sectors() / 2 + 1,
            ));
        let array = Array3::from_shape_fn((points.len(), harmonics, diameters), |(p, k, d)| {
            let c = if forward {
                &points[p].components.forward
            } else {
                &points[p].components.backward
            };
            c.get(k).and_then(|r| r.get(d)).copied().unwrap_or(f64::NAN)
        });
        Ok(array.into_pyarray(py))
    }

    /// The frequency of every point, Hz.
    pub(super) fn frequencies(&self) -> Result<Vec<f64>> {
        Ok(match &self.source {
            Source::Solved(solution) => solution
                .branch
                .points
                .iter()
                .map(|p| p.omega / (2.0 * std::f64::consts::PI))
                .collect(),
            Source::Loaded(_) => self.points()?.iter().map(|p| p.frequency_hz).collect(),
        })
    }

    pub(super) fn sectors(&self) -> usize {
        self.case.model.sectors()
    }

    pub(super) fn check_sector(&self, sector: usize) -> Result<usize> {
        if sector == 0 || sector > self.sectors() {
            return Err(Error::usage(
                Some("sector"),
                format!(
                    "sector {sector} does not exist: the wheel has sectors 1..={} (numbered from 1, like case files)",
                    self.sectors()
                ),
            ));
        }
        Ok(sector - 1)
    }
}
