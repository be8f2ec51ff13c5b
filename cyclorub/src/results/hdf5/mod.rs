//! `results.h5`: the whole content of a run in one self-describing HDF5
//! file, written and read in pure Rust (the `hdf5-pure` crate: no HDF5
//! system library), readable by h5py and MATLAB's `h5read`.
//!
//! The file is in the HDF5 1.10 format (it needs an HDF5 1.10 or later
//! reader: h5py, MATLAB releases built on HDF5 1.10): its per-point datasets are chunked,
//! unlimited along the points and compressed with shuffle + deflate (gzip),
//! filters every HDF5 build has, so a run appends its points as they come
//! and a run that is killed leaves a readable file (root attribute
//! `status` = `running`). Every dataset carries `unit` and `description`
//! attributes.
//!
//! A per-point dataset has one entry per point: a number, or an array
//! (HDF5 array datatype) whose shape is given below after the point axis
//! `[P]`; h5py reads it as one `[P, …]` array, MATLAB with the dimensions
//! reversed. Other datasets are plain arrays, row-major (C order).
//!
//! ```text
//! /                      attrs: format, format_version, cyclorub_version,
//!                        status (complete, or running while a run
//!                        streams its points), sectors, harmonics,
//!                        time_samples, observed_dof, observed_name
//!                        (`node 420, radial`, `m1, the blade tip`), contact_dofs
//!                        (1-based), mode, case_json, basis_json, stop_json,
//!                        conventions, gap_after (the last point before a
//!                        gap in the branch, −1 when it has none)
//! /branch/frequency_hz   [P]             Hz
//! /branch/iterations     [P]
//! /branch/residual_norm  [P]
//! /branch/converged      [P]             1 or 0
//! /branch/unknowns       [P] × [U]       the basis' unknowns
//! /branch/observed/coordinates       [P] × [N, 2N_h+1]  m
//! /branch/observed/amplitude         [P] × [N]          m (branch.csv's)
//! /branch/observed/max_abs           [P] × [N]          m
//! /branch/observed/velocity_max_abs  [P] × [N]          m/s
//! /branch/contact/force_coordinates  [P] × [N, n_c, 2N_h+1]  N
//!                        (only with `[output] contact_harmonics = true`)
//! /branch/contact/peak_force         [P] × [N, n_c]     N
//! /branch/contact/fraction           [P] × [N, n_c]
//! /branch/contact/max_penetration    [P] × [N, n_c]     m
//! /branch/contact/sectors_in_contact [P]
//! /linear/frequency_hz   [L]             Hz
//! /linear/amplitude      [L, N]          m
//! /modes/nodal_diameter  [D]
//! /modes/frequency_hz    [D, R]          Hz (NaN where a diameter has fewer modes)
//! /stability            (when checked) attrs harmonics, markers_json
//!   nodal_diameter [C]; stable [P] 1 or 0; unstable_exponents [P];
//!   leading_re [P, C, 4] 1/s, leading_im [P, C, 4] rad/s (the four
//!   exponents of largest real part of each class); off_contact_bound [P]
//!   rad/s (NaN: solved by Hill's method)
//! /mistuning            (a mistuned run) attrs most_responding_sector,
//!   tuned_peak_m m and amplification_factor (NaN: not computed),
//!   tuned_reference; deviations [N] 1, sector_peak [N] m (each sector's
//!   largest amplitude of the observed dof along the curve),
//!   sector_peak_frequency_hz [N] Hz
//! /branches             (after `cyclorub branches`) one group per branch
//!   point of branches/branches.json (named like its CSV, class1_212.7022Hz;
//!   class3_marker12 when not switched at), attrs order, marker and
//!   basis_unknowns and full_unknowns (−1: none), marker_hz Hz, class,
//!   parent_point (the /branch point after which the crossing lies),
//!   branch_point_hz Hz (NaN: not switched), file, not_switched (empty:
//!   switched); per side side_0 (+v), side_1 (−v): attrs direction,
//!   stop_reason, stop_json; frequency_hz [S] Hz, stable [S] (1, 0, −1:
//!   not checked), sector_amplitude [S, N] m
//! /peak/…                time histories of the peak point (with
//!   `[output] peak_histories = true`; not compressed):
//!   attrs point, frequency_hz; time_s [N_t], displacement [N, N_t],
//!   velocity [N, N_t], contact_force [N, n_c, N_t], penetration [N, n_c, N_t]
//! ```
//!
//! What follows from the stored values is not stored: the cyclic
//! components (a DFT over the sectors of the observed coordinates) and the
//! amplitude of each harmonic are computed when the file is read
//! ([`read`]); any other dof, on any sector, comes from the unknowns
//! (`cyclorub recover`). Format version 1 files (HDF5 1.8, N-dimensional
//! per-point datasets) are read too.

mod append;
mod branches;
mod mistuning;
mod per_point;
mod put;
mod read;
mod stability;
mod write;

pub use append::Appender;
pub use per_point::Contents;
pub use read::read;
pub use write::{write, write_with};

use super::ResultsError;
use std::path::Path;

/// The name of the file in a results folder.
pub const FILE_NAME: &str = "results.h5";

/// The value of the root attribute `format`.
pub const FORMAT: &str = "cyclorub results";

/// The version of this layout.
pub const FORMAT_VERSION: i64 = 2;

/// Whether a file is whole or a run is still appending to it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Stage {
    /// Written at the end of a run: every point, in branch order.
    Complete,
    /// Created at the start of a run, which appends its points.
    Running,
}

impl Stage {
    fn name(self) -> &'static str {
        match self {
            Self::Complete => "complete",
            Self::Running => "running",
        }
    }
}

const CONVENTIONS: &str = "Sectors are numbered 1..N in the text and stored 0-based along array \
axes (index j is sector j+1). Harmonic coordinates of a signal u(t) are [a0, Re X1, Im X1, ..., \
Re X_Nh, Im X_Nh] with u(t) = a0 + sum_k 2 Re(X_k exp(i k w t)); time samples are at \
w t_n = 2 pi n / N_t. Amplitude = largest displacement over the period toward the casing. The \
contact force f >= 0 acts as -f on the blade; penetration = x - g0 (> 0 in contact). Cyclic \
components: forward[k][d] and backward[k][d] are the amplitudes of the waves of nodal diameter d \
on harmonic k traveling forward (s = +d) and backward (s = -d) in blade numbering, the wave \
(s, k) being exp(i(k w t - s alpha (j - 1))); diameters 0 and N/2 are shown half forward, half \
backward. SI units.";

/// Rewrites the results file `path` with `branches` as its `/branches`
/// group (the one it had replaced), everything else kept as read: the
/// per-point datasets it stored (contact harmonics or not), its stability,
/// mistuning and time histories, and its status: a file of a run that
/// was killed (or is still going) stays `running`, its points in the
/// order the run accepted them, so that no reader takes it for a whole
/// branch.
pub fn replace_branches(
    path: &Path,
    branches: &[super::bifurcated::BifurcatedBranchData],
) -> Result<(), ResultsError> {
    let stage = stage(path)?;
    let mut data = read(path)?;
    data.branches = branches.to_vec();
    let contents = Contents {
        contact_harmonics: data
            .points
            .first()
            .is_some_and(|p| !p.contact_force.is_empty()),
    };
    write::write_stage(path, &data, contents, stage, None)
}

/// The root attribute `status` of the results file `path`: `complete`
/// (written whole at the end of a run), or `running` (a run is appending
/// its points, or was killed while it did); `None` in a format 1 file,
/// which was always written whole.
pub fn status(path: &Path) -> Result<Option<String>, ResultsError> {
    let file = hdf5_pure::File::open(path).map_err(h5_error(path))?;
    let attrs = file.root().attrs().map_err(h5_error(path))?;
    Ok(attrs
        .get("status")
        .and_then(|v| v.as_str().map(str::to_string)))
}

/// The root attribute `sectors` of the results file `path`: the number of
/// sectors its run solved (what `run.json`'s `case.model.sectors` must
/// say); `None` when the file does not record it.
pub fn sectors(path: &Path) -> Result<Option<usize>, ResultsError> {
    let file = hdf5_pure::File::open(path).map_err(h5_error(path))?;
    let attrs = file.root().attrs().map_err(h5_error(path))?;
    Ok(attrs
        .get("sectors")
        .and_then(hdf5_pure::AttrValue::as_i64)
        .and_then(|n| usize::try_from(n).ok()))
}

/// The stage the results file `path` is in, as its `status` says.
fn stage(path: &Path) -> Result<Stage, ResultsError> {
    let Some(status) = status(path)? else {
        return Ok(Stage::Complete);
    };
    [Stage::Complete, Stage::Running]
        .into_iter()
        .find(|s| s.name() == status)
        .ok_or_else(|| ResultsError::Read {
            path: path.to_path_buf(),
            message: format!("status {status:?}: expected complete or running"),
        })
}

fn h5_error(path: &Path) -> impl Fn(hdf5_pure::Error) -> ResultsError + '_ {
    move |e| ResultsError::Hdf5 {
        path: path.to_path_buf(),
        message: e.to_string(),
    }
}
