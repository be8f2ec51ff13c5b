//! The datasets of `results.h5` that hold one entry per point (under
//! `/branch`). Each is a one-dimensional dataset over the points, chunked,
//! unlimited and compressed (shuffle + deflate, which h5py and MATLAB read
//! without plugins), so a run appends its points as they come
//! (`Appender`) and the final file is written by the same code. An entry
//! that is an array (a row of unknowns, a value per sector) is one element
//! of an HDF5 array datatype: h5py reads the dataset as a `[P, …]` array.

use super::put::{text, Container, DEFLATE_LEVEL};
use crate::results::data::{PointResults, ResultsData};
use hdf5_pure::{make_f64_type, MaxExtent};

/// Largest chunk, bytes before compression: a chunk rewritten by a partial
/// append (streaming) stays small, and a whole chunk still compresses well.
const CHUNK_BYTES: usize = 16 * 1024;

/// What `results.h5` keeps per point beyond what every run keeps (the
/// unknowns, the observed dof's coordinates and extremes, the contact
/// summary); the rest is recovered from the unknowns on demand
/// (`cyclorub recover`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Contents {
    /// The harmonic coordinates of every contact force
    /// (`branch/contact/force_coordinates`, `N · n_c · (2N_h + 1)` values
    /// per point).
    pub contact_harmonics: bool,
}

impl Contents {
    /// Everything.
    pub const ALL: Self = Self {
        contact_harmonics: true,
    };
}

/// The sizes that shape a point's entries.
#[derive(Clone, Copy, Debug)]
pub(super) struct Sizes {
    pub sectors: usize,
    pub harmonics: usize,
    pub contacts: usize,
    pub unknowns: usize,
}

impl Sizes {
    pub fn of(data: &ResultsData) -> Self {
        Self {
            sectors: data.sectors,
            harmonics: data.harmonics,
            contacts: data.contact_dofs.len(),
            unknowns: data.points.first().map_or(0, |q| q.unknowns.len()),
        }
    }
}

/// How a point gives its entry.
#[derive(Clone, Copy)]
enum Values {
    Real(fn(&PointResults, &mut Vec<f64>)),
    Integer(fn(&PointResults) -> i64),
}

/// One per-point dataset.
pub(super) struct Column {
    /// The group it is in (`branch`, `branch/observed`, `branch/contact`).
    pub group: &'static str,
    /// Its name in the group.
    pub name: &'static str,
    /// The shape of one point's entry (empty: a number).
    pub dims: Vec<usize>,
    unit: &'static str,
    description: &'static str,
    values: Values,
}

/// The per-point datasets, in the order they are appended: the point's
/// frequency last, so that a file cut between two appends has every
/// dataset at least as long as `frequency_hz`, whose length the reader
/// takes as the point count.
pub(super) fn columns(sizes: Sizes, contents: Contents) -> Vec<Column> {
    let Sizes {
        sectors: n,
        harmonics,
        contacts: nc,
        unknowns,
    } = sizes;
    let size = 2 * harmonics + 1;
    let real = |group, name, dims, unit, description, f| Column {
        group,
        name,
        dims,
        unit,
        description,
        values: Values::Real(f),
    };
    let integer = |group, name, description, f| Column {
        group,
        name,
        dims: Vec::new(),
        unit: "1",
        description,
        values: Values::Integer(f),
    };
    let mut list = vec![
        integer("branch", "iterations", "Newton iterations", |q| {
            q.iterations as i64
        }),
        real(
            "branch",
            "residual_norm",
            vec![],
            "1",
            "residual norm divided by the force scale",
            |q, out| out.push(q.residual_norm),
        ),
        integer(
            "branch",
            "converged",
            "1 if Newton converged, 0 otherwise",
            |q| i64::from(q.converged),
        ),
        real(
            "branch",
            "unknowns",
            vec![unknowns],
            "m",
            "the unknowns of the basis solved on (layout in run.json's basis)",
            |q, out| out.extend_from_slice(&q.unknowns),
        ),
        real(
            "branch/observed",
            "coordinates",
            vec![n, size],
            "m",
            "harmonic coordinates [a0, Re X1, Im X1, ...] per sector",
            |q, out| q.observed.iter().for_each(|c| out.extend_from_slice(c)),
        ),
        real(
            "branch/observed",
            "amplitude",
            vec![n],
            "m",
            "largest displacement over the period (toward the casing), as branch.csv",
            |q, out| out.extend_from_slice(&q.amplitude),
        ),
        real(
            "branch/observed",
            "max_abs",
            vec![n],
            "m",
            "largest |displacement| over the period",
            |q, out| out.extend_from_slice(&q.max_abs),
        ),
        real(
            "branch/observed",
            "velocity_max_abs",
            vec![n],
            "m/s",
            "largest |velocity| over the period",
            |q, out| out.extend_from_slice(&q.velocity_max_abs),
        ),
        real(
            "branch/contact",
            "peak_force",
            vec![n, nc],
            "N",
            "largest contact force over the period",
            |q, out| out.extend_from_slice(&q.peak_force),
        ),
        real(
            "branch/contact",
            "fraction",
            vec![n, nc],
            "1",
            "fraction of the period in contact (penetration > 0 for a law, force > 0 for DLFT)",
            |q, out| out.extend_from_slice(&q.contact_fraction),
        ),
        real(
            "branch/contact",
            "max_penetration",
            vec![n, nc],
            "m",
            "largest penetration x - g0 over the period",
            |q, out| out.extend_from_slice(&q.max_penetration),
        ),
        integer(
            "branch/contact",
            "sectors_in_contact",
            "number of sectors in contact at some instant of the period",
            |q| q.sectors_in_contact as i64,
        ),
    ];
    if contents.contact_harmonics {
        list.push(real(
            "branch/contact",
            "force_coordinates",
            vec![n, nc, size],
            "N",
            "harmonic coordinates of the contact force f >= 0 (acting as -f on the blade)",
            |q, out| {
                q.contact_force
                    .iter()
                    .for_each(|c| out.extend_from_slice(c))
            },
        ));
    }
    list.push(real(
        "branch",
        "frequency_hz",
        vec![],
        "Hz",
        "excitation frequency",
        |q, out| out.push(q.frequency_hz),
    ));
    list
}

impl Column {
    /// Values in one point's entry.
    fn width(&self) -> usize {
        self.dims.iter().product()
    }

    /// The entries of `points`, little-endian, each padded with NaN (or cut)
    /// to the entry's shape.
    pub(super) fn bytes(&self, points: &[PointResults]) -> Vec<u8> {
        let width = self.width();
        let mut out = Vec::with_capacity(points.len() * width.max(1) * 8);
        let mut row = Vec::with_capacity(width);
        for q in points {
            match self.values {
                Values::Real(f) => {
                    row.clear();
                    f(q, &mut row);
                    row.resize(width.max(1), f64::NAN);
                    row.iter()
                        .for_each(|x| out.extend_from_slice(&x.to_le_bytes()));
                }
                Values::Integer(f) => out.extend_from_slice(&f(q).to_le_bytes()),
            }
        }
        out
    }

    /// Points per chunk: as many as [`CHUNK_BYTES`] holds, at least one.
    fn chunk_points(&self) -> u64 {
        (CHUNK_BYTES / (8 * self.width().max(1))).max(1) as u64
    }

    /// Whether the column has a dataset: an entry of no values (no contact
    /// dofs, a file without points and so without unknowns) has none.
    pub fn stored(&self) -> bool {
        self.dims.is_empty() || self.width() > 0
    }

    /// Adds the dataset, holding `points`, to `group` (nothing when not
    /// [`stored`](Self::stored)).
    pub fn create(&self, group: &mut impl Container, points: &[PointResults]) {
        if !self.stored() {
            return;
        }
        let p = points.len() as u64;
        let builder = group.dataset(self.name);
        match self.values {
            Values::Integer(f) => {
                builder.with_i64_data(&points.iter().map(f).collect::<Vec<_>>());
            }
            Values::Real(_) if self.dims.is_empty() => {
                let values: Vec<f64> = self
                    .bytes(points)
                    .chunks_exact(8)
                    .map(|b| f64::from_le_bytes(b.try_into().unwrap_or([0; 8])))
                    .collect();
                builder.with_f64_data(&values);
            }
            Values::Real(_) => {
                let dims: Vec<u32> = self.dims.iter().map(|&d| d as u32).collect();
                builder.with_array_data(make_f64_type(), &dims, self.bytes(points), p);
            }
        }
        builder
            .with_shape(&[p])
            .with_maxshape(&[MaxExtent::Unlimited])
            .with_chunks(&[self.chunk_points()])
            .with_shuffle()
            .with_deflate(DEFLATE_LEVEL)
            .set_attr("unit", text(self.unit))
            .set_attr("description", text(self.description));
    }

    /// The dataset's path in the file.
    pub fn path(&self) -> String {
        format!("{}/{}", self.group, self.name)
    }
}
