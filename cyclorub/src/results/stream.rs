//! The streaming writer: an [`Observer`] of the continuation that puts
//! every point on disk as it is accepted, so that a run stopped half-way
//! (Ctrl-C, a killed job, a failure) leaves `branch.csv` (and
//! `observed_harmonics.csv` when asked) with every point computed and
//! `results.h5` with every point up to its last append (at most
//! `RESULTS_FILE_EVERY` earlier).
//!
//! Points are recovered (the observed dof and the contact state on every
//! sector, [`BranchRecovery`]) on a thread of their own, on a copy of the
//! problem, while the solver goes on; each point's rows are written when
//! it is recovered and the CSV files are flushed at least every
//! [`FLUSH_EVERY`]. The rows come in the order the points were accepted
//! (with both ends, the sweep back's points follow the first sweep's, from
//! the end frequency down); [`BranchStream::finish`] gives the summaries
//! back in that order, and the run then rewrites both files in the
//! branch's order.
//!
//! With a [`StreamedCheck`], the same thread checks every point's
//! stability as it comes ([`Stability::point`]) and writes its verdict in
//! `branch.csv`'s row: a run stopped half-way keeps the verdicts of its
//! points. Once the run's interrupt is raised, the points still queued are
//! written without a verdict.

#[cfg(feature = "hdf5")]
use super::data::PointResults;
use super::recovery::{BranchRecovery, PointSummary};
use super::{BranchFiles, BranchRow, ResultsError};
use crate::continuation::{Branch, Interrupt, Observer, Point, State};
use crate::hbm::HarmonicBalance;
use crate::model::SectorModel;
use crate::stability::{
    markers, BranchStability, Following, PointStability, Stability, StabilitySettings,
};
use std::f64::consts::PI;
use std::path::Path;
use std::sync::mpsc::{channel, Sender};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

/// The longest time a recovered point waits in a buffer before the files
/// are flushed.
pub const FLUSH_EVERY: Duration = Duration::from_millis(500);

/// What the writer thread gives back, or the first error (the points
/// before it are on disk).
pub type Written = Result<Streamed, ResultsError>;

/// Every point the writer was sent, in the order of acceptance.
pub struct Streamed {
    /// Per point: its frequency (rad/s), its summary and, with a
    /// [`StreamedCheck`], its stability (`None` where it was not checked:
    /// the run was interrupted first, or the check failed there).
    pub points: Vec<(f64, PointSummary, Option<PointStability>)>,
    /// With a [`StreamedCheck`]: how the check went, or why it could not
    /// be set up.
    pub stability: Option<Result<Checked, String>>,
}

/// How the streamed stability check went.
pub struct Checked {
    /// Harmonics of Hill's truncation.
    pub harmonics: usize,
    /// Whether the exponents are sorted in symmetry classes (not the whole
    /// wheel as one block).
    pub classes_known: bool,
    /// Why the points after some point were not checked (the run was
    /// interrupted, or the check failed there); `None`: every point was.
    pub unchecked: Option<String>,
    /// Time spent checking on the writer's thread, s.
    pub seconds: f64,
}

impl Checked {
    /// The branch's stability from every point's, in branch order (see
    /// [`markers`]).
    pub fn branch(&self, points: Vec<PointStability>) -> BranchStability {
        BranchStability {
            harmonics: self.harmonics,
            solved_by_hill: points
                .iter()
                .filter(|p| p.off_contact_bound.is_none())
                .count(),
            markers: markers(&points, self.classes_known),
            points,
        }
    }
}

/// The stability check the writer thread runs on every point.
pub struct StreamedCheck {
    /// The model (a copy of the one being solved).
    pub model: SectorModel,
    /// The contact dofs (0-based, with the friction nodes'; see
    /// [`Stability::new`]).
    pub contact_dofs: Vec<usize>,
    /// Hill's settings.
    pub settings: StabilitySettings,
    /// The run's interrupt: once raised, the points left are not checked.
    pub interrupt: Interrupt,
}

/// Streams the points of a branch to `branch.csv` (and
/// `observed_harmonics.csv`, `results.h5` when asked) in a results folder
/// (see the module's header).
pub struct BranchStream {
    sender: Option<Sender<Point>>,
    worker: Option<JoinHandle<Written>>,
}

/// What a [`BranchStream`] writes.
pub struct StreamSettings {
    /// The reported sectors (1-based).
    pub sectors: Vec<usize>,
    /// The observed dof (0-based).
    pub observed_dof: usize,
    /// Time samples of the recovery.
    pub time_samples: usize,
    /// The stability check of every point (`branch.csv` then has the
    /// stability columns).
    pub stability: Option<StreamedCheck>,
    /// Whether `observed_harmonics.csv` is written.
    pub harmonics_csv: bool,
    /// `results.h5`: the header of the file (a run's data without points)
    /// and what it keeps per point.
    #[cfg(feature = "hdf5")]
    pub results_file: Option<(super::data::ResultsData, super::hdf5::Contents)>,
}

/// The longest time a point waits before it is appended to `results.h5`:
/// longer than the CSV files', since each append rewrites the last,
/// partial chunk of every dataset (the final file is written whole).
#[cfg(feature = "hdf5")]
const RESULTS_FILE_EVERY: Duration = Duration::from_secs(2);

impl BranchStream {
    /// Creates the files in `directory` (which must exist) with their
    /// headers and starts the writer thread on `problem` (a copy of the
    /// problem being solved).
    pub fn start(
        directory: &Path,
        problem: HarmonicBalance,
        settings: StreamSettings,
    ) -> Result<Self, ResultsError> {
        let harmonics = problem.layout().harmonics();
        let sectors = settings.sectors;
        let mut files = BranchFiles::create(
            directory,
            &sectors,
            harmonics,
            settings.stability.is_some(),
            settings.harmonics_csv,
        )?;
        let check = settings.stability;
        #[cfg(feature = "hdf5")]
        let mut results_file = match &settings.results_file {
            Some((header, contents)) => Some(super::hdf5::Appender::create(
                &directory.join(super::hdf5::FILE_NAME),
                header,
                problem.layout().unknowns,
                *contents,
            )?),
            None => None,
        };
        let (observed_dof, time_samples) = (settings.observed_dof, settings.time_samples);
        let (sender, receiver) = channel::<Point>();
        let worker = std::thread::Builder::new()
            .name("cyclorub-results".into())
            .spawn(move || -> Written {
                let recovery = BranchRecovery::new(&problem, observed_dof, time_samples);
                let mut checker = check.as_ref().map(|c| Checker::new(c, &problem));
                let mut points = Vec::new();
                let mut flushed = Instant::now();
                #[cfg(feature = "hdf5")]
                let mut appended = Instant::now();
                for point in receiver {
                    // The recovery beside the check, in the pool: the
                    // check's serial parts (the contact's sampling) and its
                    // classes' uneven costs leave a core idle otherwise.
                    let (summary, stability) = rayon::join(
                        || recovery.point(&point.unknowns, point.omega),
                        || checker.as_mut().and_then(|c| c.point(&point)),
                    );
                    let summary = summary?;
                    let row = BranchRow {
                        point: points.len(),
                        frequency_hz: point.omega / (2.0 * PI),
                        amplitudes: sectors
                            .iter()
                            .map(|s| summary.observed.peak[s - 1])
                            .collect(),
                        iterations: point.iterations,
                        residual_norm: point.residual_norm,
                        converged: point.converged,
                        // An unconverged point is no solution: no verdict.
                        stability: stability
                            .as_ref()
                            .filter(|_| point.converged)
                            .map(|p| (p.stable(), p.unstable_exponents())),
                    };
                    let coordinates: Vec<&[f64]> = sectors
                        .iter()
                        .map(|s| summary.observed.coordinates[s - 1].as_slice())
                        .collect();
                    files.write(&row, &sectors, &coordinates)?;
                    if flushed.elapsed() >= FLUSH_EVERY {
                        files.flush()?;
                        flushed = Instant::now();
                    }
                    #[cfg(feature = "hdf5")]
                    if let Some(appender) = &mut results_file {
                        let contact = summary.contact.as_ref().map_err(ToString::to_string);
                        let streamed = contact.and_then(|contact| {
                            let results = PointResults::from_summary(
                                &point,
                                summary.observed.clone(),
                                contact.clone(),
                            )
                            .map_err(|e| e.to_string())?;
                            appender.push(results);
                            if appended.elapsed() >= RESULTS_FILE_EVERY {
                                appended = Instant::now();
                                appender.flush().map_err(|e| e.to_string())?;
                            }
                            Ok(())
                        });
                        if let Err(error) = streamed {
                            // The CSV files go on; results.h5 is written
                            // whole at the end.
                            tracing::warn!("results.h5 is no longer streamed: {error}");
                            results_file = None;
                        }
                    }
                    points.push((point.omega, summary, stability));
                }
                files.flush()?;
                #[cfg(feature = "hdf5")]
                if let Some(appender) = results_file {
                    appender.close()?;
                }
                Ok(Streamed {
                    points,
                    stability: checker.map(Checker::outcome),
                })
            })
            .map_err(|source| ResultsError::Io {
                path: directory.to_path_buf(),
                source,
            })?;
        Ok(Self {
            sender: Some(sender),
            worker: Some(worker),
        })
    }

    /// Waits for every point sent to be written; gives their summaries in
    /// the order of acceptance.
    pub fn finish(mut self) -> Written {
        self.sender.take();
        match self.worker.take().map(JoinHandle::join) {
            Some(Ok(written)) => written,
            Some(Err(_)) | None => Err(ResultsError::Input(
                "the results writer thread stopped unexpectedly".into(),
            )),
        }
    }
}

/// The stability check on the writer's thread: set up once, then point by
/// point until it fails or the run is interrupted.
struct Checker<'a> {
    check: Result<Stability<'a>, String>,
    interrupt: &'a Interrupt,
    /// Why a point was left unchecked (the first reason).
    skipped: Option<String>,
    /// Time spent checking, s.
    seconds: f64,
    /// The exponents the next point follows from.
    following: Option<Following>,
    /// Classes solved by the condensed method, and how many of them were
    /// followed from the previous point (the others by the contour).
    class_solves: (usize, usize),
    /// Points checked, and when the last progress line was logged.
    checked: usize,
    logged: Instant,
}

/// The least time between two progress lines of the streamed check (it
/// can run on behind the solve, which has its own).
const PROGRESS_EVERY: Duration = Duration::from_secs(5);

impl<'a> Checker<'a> {
    fn new(check: &'a StreamedCheck, problem: &'a HarmonicBalance) -> Self {
        let built = Stability::new(&check.model, problem, &check.contact_dofs, &check.settings)
            .map_err(|error| error.to_string());
        if let Err(error) = &built {
            tracing::warn!("stability not computed: {error}");
        }
        Self {
            check: built,
            interrupt: &check.interrupt,
            skipped: None,
            seconds: 0.0,
            following: None,
            class_solves: (0, 0),
            checked: 0,
            logged: Instant::now(),
        }
    }

    /// The point's stability; `None` once the check failed or the run was
    /// interrupted.
    fn point(&mut self, point: &Point) -> Option<PointStability> {
        let check = self.check.as_ref().ok()?;
        if self.skipped.is_some() {
            return None;
        }
        if self.interrupt.raised() {
            self.skipped = Some("the run was interrupted".into());
            return None;
        }
        let clock = Instant::now();
        let checked = check.point_following(&point.unknowns, point.omega, self.following.as_ref());
        self.seconds += clock.elapsed().as_secs_f64();
        self.checked += 1;
        if self.logged.elapsed() >= PROGRESS_EVERY {
            self.logged = Instant::now();
            tracing::info!(
                "stability: {} points checked, the last at {:.4} Hz ({:.1} s of checking)",
                self.checked,
                point.omega / (2.0 * PI),
                self.seconds
            );
        }
        match checked {
            Ok((stability, following)) => {
                self.class_solves.0 += following.len();
                self.class_solves.1 += following.followed();
                self.following = Some(following);
                Some(stability)
            }
            Err(error) => {
                let reason = format!(
                    "the stability check failed at {:.6} Hz: {error}",
                    point.omega / (2.0 * PI)
                );
                tracing::warn!("{reason}; the points after it are not checked");
                self.skipped = Some(reason);
                None
            }
        }
    }

    /// How the check went, or why it could not be set up.
    fn outcome(self) -> Result<Checked, String> {
        let check = self.check?;
        tracing::debug!(
            "stability: {} class solves by the condensed method, {} followed from the previous point",
            self.class_solves.0,
            self.class_solves.1
        );
        Ok(Checked {
            harmonics: check.harmonics(),
            classes_known: check.classes_tell_kinds(),
            unchecked: self.skipped,
            seconds: self.seconds,
        })
    }
}

impl Drop for BranchStream {
    /// Lets the writer finish what it was sent, so the files hold it.
    fn drop(&mut self) {
        self.sender.take();
        if let Some(worker) = self.worker.take() {
            let _ = worker.join();
        }
    }
}

impl Observer for BranchStream {
    fn point(&mut self, _index: usize, point: &Point, _state: &State<'_>) {
        // A writer that stopped (a full disk) keeps its error for finish.
        if let Some(sender) = &self.sender {
            if sender.send(point.clone()).is_err() {
                self.sender = None;
            }
        }
    }
}

/// What was streamed for `branch`'s points (a summary, a verdict), in its
/// order, from the points in the order they were accepted (see
/// [`Observer`]): the same list for one sweep; with both ends, the first
/// sweep's up to the meeting and the sweep back's reversed. `None` when
/// they do not match the branch (then recover again).
pub fn in_branch_order<T>(accepted: Vec<(f64, T)>, branch: &Branch) -> Option<Vec<T>> {
    let order: Vec<usize> = match &branch.sweeps {
        None => (0..accepted.len()).collect(),
        Some(sweeps) => {
            let back = sweeps.from_start_points..sweeps.from_start_points + sweeps.from_end_points;
            (0..sweeps.from_start_kept).chain(back.rev()).collect()
        }
    };
    let fits = order.len() == branch.points.len()
        && order.iter().zip(&branch.points).all(|(&i, p)| {
            accepted
                .get(i)
                .is_some_and(|(w, _)| w.to_bits() == p.omega.to_bits())
        });
    if !fits {
        return None;
    }
    let mut slots: Vec<Option<T>> = accepted.into_iter().map(|(_, s)| Some(s)).collect();
    order.iter().map(|&i| slots[i].take()).collect()
}
