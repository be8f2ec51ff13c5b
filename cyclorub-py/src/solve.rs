//! A solve on a worker thread, the GIL released, Ctrl-C honoured.
//!
//! The calling thread waits for the worker in slices of [`TICK`] with the
//! GIL released (`Python::detach`); between two slices it takes the GIL
//! back to run `Python::check_signals` (where Ctrl-C becomes
//! `KeyboardInterrupt`) and to hand the latest progress to the Python
//! callback. On `KeyboardInterrupt` it raises the library's
//! [`Interrupt`]: the branch stops before its next point, keeping every
//! point, and the partial solution is returned, marked interrupted.

use crate::errors::Error;
use cyclorub::case::{BasisChoice, Case};
use cyclorub::continuation::{Interrupt, Observer, Point, Progress, ProgressFn};
use cyclorub::forced_response::{ForcedResponse, Solution};
use cyclorub::run::RunError;
use cyclorub::stability::StabilitySettings;
use pyo3::exceptions::PyKeyboardInterrupt;
use pyo3::prelude::*;
use std::path::PathBuf;
use std::sync::mpsc::{channel, Receiver, RecvTimeoutError};
use std::time::{Duration, Instant};

/// How often the calling thread looks for Ctrl-C and reports progress.
pub const TICK: Duration = Duration::from_millis(50);

/// What to solve.
pub struct Request {
    /// The case.
    pub case: Case,
    /// The folder its relative paths start from.
    pub case_dir: PathBuf,
    /// The basis.
    pub basis: BasisChoice,
    /// Fixed frequencies (Hz) instead of arc-length continuation.
    pub at_hz: Option<Vec<f64>>,
    /// The stability check, if asked for.
    pub stability: Option<StabilitySettings>,
}

/// What the worker sends back.
enum Message {
    /// A point was accepted.
    Progress(Progress),
    /// The solve is over.
    Done(Box<Result<Solution, RunError>>),
}

/// Solves `request` on the worker thread: the library's whole pipeline
/// (set-up, continuation, stability check), nothing of Python.
fn solve_on_worker(
    request: Request,
    interrupt: Interrupt,
    observer: &mut dyn Observer,
) -> Result<Solution, RunError> {
    let Request {
        case,
        case_dir,
        basis,
        at_hz,
        stability,
    } = request;
    let mut forced = ForcedResponse::from_case(&case)?
        .case_dir(case_dir)
        .basis(basis)
        .stability(stability)
        .interrupt(interrupt);
    if let Some(list) = at_hz {
        forced = forced.at_frequencies_hz(list);
    }
    forced.build()?.run(&mut [observer])
}

/// What one wait for the worker saw.
struct Waited {
    /// The latest progress, if a point came.
    progress: Option<Progress>,
    /// The result, if the solve is over.
    result: Option<Result<Solution, RunError>>,
    /// The worker is gone without a result (it panicked).
    gone: bool,
}

/// Waits up to `TICK` for the worker.
fn wait(rx: &Receiver<Message>) -> Waited {
    let deadline = Instant::now() + TICK;
    let mut waited = Waited {
        progress: None,
        result: None,
        gone: false,
    };
    loop {
        let left = deadline.saturating_duration_since(Instant::now());
        match rx.recv_timeout(left) {
            Ok(Message::Progress(p)) => waited.progress = Some(p),
            Ok(Message::Done(result)) => {
                waited.result = Some(*result);
                return waited;
            }
            Err(RecvTimeoutError::Timeout) => return waited,
            Err(RecvTimeoutError::Disconnected) => {
                waited.gone = true;
                return waited;
            }
        }
    }
}

/// Solves `request` with the GIL released; `progress`, if given, is called
/// as `progress(points, frequency_hz, step)` at most every [`TICK`] with
/// the latest point. Returns the solution and whether Ctrl-C cut it short.
pub fn solve(
    py: Python<'_>,
    request: Request,
    progress: Option<Py<PyAny>>,
) -> PyResult<(Solution, bool)> {
    let interrupt = Interrupt::new();
    let (tx, rx) = channel::<Message>();
    let worker = {
        let interrupt = interrupt.clone();
        std::thread::Builder::new()
            .name("cyclorub-solve".into())
            .spawn(move || {
                let points = tx.clone();
                let mut observer = ProgressFn(move |_: &Point, p: &Progress| {
                    let _ = points.send(Message::Progress(*p));
                });
                let result = solve_on_worker(request, interrupt, &mut observer);
                let _ = tx.send(Message::Done(Box::new(result)));
            })
            .map_err(|e| Error::internal(format!("cannot start the solver thread: {e}")))?
    };
    let mut rx = rx;
    let mut interrupted = false;
    let mut pending: Option<PyErr> = None;
    let outcome = loop {
        // The receiver is not Sync: it goes into the GIL-free closure and
        // comes back out.
        let (received, waited) = py.detach(move || {
            let waited = wait(&rx);
            (rx, waited)
        });
        rx = received;
        if let (Some(callback), Some(p)) = (&progress, waited.progress) {
            if let Err(error) = callback.call1(py, (p.points, p.frequency_hz, p.step)) {
                // Ctrl-C while the callback runs is raised inside it: the
                // same as Ctrl-C between two waits. A broken callback stops
                // the run like Ctrl-C, and is raised.
                interrupt.raise();
                if error.is_instance_of::<PyKeyboardInterrupt>(py) {
                    interrupted = true;
                } else {
                    pending.get_or_insert(error);
                }
            }
        }
        if let Some(result) = waited.result {
            break result;
        }
        if waited.gone {
            let _ = worker.join();
            return Err(Error::internal("the solver thread ended without a result (a panic in the library: please report it)").into());
        }
        if !interrupted {
            if let Err(error) = py.check_signals() {
                interrupt.raise();
                interrupted = true;
                if !error.is_instance_of::<PyKeyboardInterrupt>(py) {
                    pending.get_or_insert(error);
                }
            }
        }
    };
    let _ = worker.join();
    if let Some(error) = pending {
        return Err(error);
    }
    let solution = outcome.map_err(Error::from)?;
    Ok((solution, interrupted))
}
