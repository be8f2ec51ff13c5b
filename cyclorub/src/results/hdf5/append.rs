//! Streaming: a run creates `results.h5` with empty per-point datasets
//! and appends its points as they come.

use super::per_point::{columns, Column, Contents, Sizes};
use super::write::write_stage;
use super::{h5_error, Stage};
use crate::results::data::{PointResults, ResultsData};
use crate::results::ResultsError;
use hdf5_pure::{FileAccessProperties, SyncPolicy};
use std::path::{Path, PathBuf};

/// Appends points to a `results.h5` as a run accepts them: the file holds
/// every point of the last [`flush`](Self::flush), whatever happens to the
/// process after it (each append is atomic; the file's lock is released
/// when the process ends).
pub struct Appender {
    file: hdf5_pure::File,
    path: PathBuf,
    columns: Vec<Column>,
    pending: Vec<PointResults>,
    written: usize,
}

impl Appender {
    /// Writes `header` (a run's data without points, linear response or
    /// histories; `unknowns` per point) to `path` with empty per-point
    /// datasets, and opens it for appending.
    pub fn create(
        path: &Path,
        header: &ResultsData,
        unknowns: usize,
        contents: Contents,
    ) -> Result<Self, ResultsError> {
        write_stage(path, header, contents, Stage::Running, Some(unknowns))?;
        let properties = FileAccessProperties::new().with_sync_policy(SyncPolicy::OnClose);
        let file =
            hdf5_pure::File::open_rw_with_options(path, properties).map_err(h5_error(path))?;
        let sizes = Sizes {
            unknowns,
            ..Sizes::of(header)
        };
        Ok(Self {
            file,
            path: path.to_path_buf(),
            columns: columns(sizes, contents),
            pending: Vec::new(),
            written: 0,
        })
    }

    /// Keeps `point` for the next flush.
    pub fn push(&mut self, point: PointResults) {
        self.pending.push(point);
    }

    /// Points on disk.
    pub fn written(&self) -> usize {
        self.written
    }

    /// Appends the points kept since the last flush to every dataset.
    pub fn flush(&mut self) -> Result<(), ResultsError> {
        if self.pending.is_empty() {
            return Ok(());
        }
        let path = &self.path;
        for column in self.columns.iter().filter(|c| c.stored()) {
            let mut dataset = self.file.dataset(&column.path()).map_err(h5_error(path))?;
            dataset
                .append_raw(&column.bytes(&self.pending))
                .map_err(h5_error(path))?;
        }
        self.written += self.pending.len();
        self.pending.clear();
        Ok(())
    }

    /// Flushes and closes the file.
    pub fn close(mut self) -> Result<(), ResultsError> {
        self.flush()?;
        let Self { file, path, .. } = self;
        file.close().map_err(h5_error(&path))
    }
}
