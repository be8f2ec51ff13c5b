//! The streaming writer: an [`Observer`] of the continuation that puts
//! every point on disk as it is accepted, so that a run stopped half-way
//! (Ctrl-C, a killed job, a failure) leaves `branch.csv` and
//! `observed_harmonics.csv` with every point computed.
//!
//! Points are recovered (the observed dof and the contact state on every
//! sector, [`BranchRecovery`]) on a thread of their own, on a copy of the
//! problem, while the solver goes on; each point's rows are written when
//! it is recovered and the files are flushed at least every
//! [`FLUSH_EVERY`]. The rows come in the order the points were accepted
//! (with both ends, the sweep back's points follow the first sweep's, from
//! the end frequency down); [`BranchStream::finish`] gives the summaries
//! back in that order, and the run then rewrites both files in the
//! branch's order with the stability columns.

use super::recovery::{BranchRecovery, PointSummary};
use super::{BranchFiles, BranchRow, ResultsError};
use crate::continuation::{Branch, Observer, Point, State};
use crate::hbm::HarmonicBalance;
use std::f64::consts::PI;
use std::path::Path;
use std::sync::mpsc::{channel, Sender};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

/// The longest time a recovered point waits in a buffer before the files
/// are flushed.
pub const FLUSH_EVERY: Duration = Duration::from_millis(500);

/// What the writer thread gives back: every point's frequency (rad/s) and
/// summary in the order of acceptance, or the first error (the points
/// before it are on disk).
pub type Written = Result<Vec<(f64, PointSummary)>, ResultsError>;

/// Streams the points of a branch to `branch.csv` and
/// `observed_harmonics.csv` in a results folder (see the module's header).
pub struct BranchStream {
    sender: Option<Sender<Point>>,
    worker: Option<JoinHandle<Written>>,
}

impl BranchStream {
    /// Creates both files in `directory` (which must exist) with their
    /// headers and starts the writer thread on `problem` (a copy of the
    /// problem being solved); `sectors` are the reported sectors
    /// (1-based), `observed_dof` 0-based, `time_samples` those of the
    /// recovery; `stability` adds the (empty, while streaming) stability
    /// columns.
    pub fn start(
        directory: &Path,
        problem: HarmonicBalance,
        sectors: Vec<usize>,
        observed_dof: usize,
        time_samples: usize,
        stability: bool,
    ) -> Result<Self, ResultsError> {
        let harmonics = problem.layout().harmonics;
        let mut files = BranchFiles::create(directory, &sectors, harmonics, stability)?;
        let (sender, receiver) = channel::<Point>();
        let worker = std::thread::Builder::new()
            .name("cyclorub-results".into())
            .spawn(move || -> Written {
                let recovery = BranchRecovery::new(&problem, observed_dof, time_samples);
                let mut summaries = Vec::new();
                let mut flushed = Instant::now();
                for point in receiver {
                    let summary = recovery.point(&point.unknowns, point.omega)?;
                    let row = BranchRow {
                        point: summaries.len(),
                        frequency_hz: point.omega / (2.0 * PI),
                        amplitudes: sectors
                            .iter()
                            .map(|s| summary.observed.peak[s - 1])
                            .collect(),
                        iterations: point.iterations,
                        residual_norm: point.residual_norm,
                        converged: point.converged,
                        stability: None,
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
                    summaries.push((point.omega, summary));
                }
                files.flush()?;
                Ok(summaries)
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

/// The summaries of `branch`'s points, in its order, from those of the
/// points in the order they were accepted (see [`Observer`]): the same
/// list for one sweep; with both ends, the first sweep's up to the meeting
/// and the sweep back's reversed. `None` when they do not match the branch
/// (then recover again).
pub fn in_branch_order(
    accepted: Vec<(f64, PointSummary)>,
    branch: &Branch,
) -> Option<Vec<PointSummary>> {
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
    let mut slots: Vec<Option<PointSummary>> = accepted.into_iter().map(|(_, s)| Some(s)).collect();
    order.iter().map(|&i| slots[i].take()).collect()
}
