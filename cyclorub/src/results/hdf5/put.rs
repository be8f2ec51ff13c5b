//! The building blocks of `results.h5`: datasets with their unit and
//! description, attributes, and the compression every writer shares.

use hdf5_pure::{make_f64_type, make_i64_type, AttrValue, FileBuilder};

/// Deflate level: level 4 is within a few per cent of level 9's size on
/// these files, several times faster.
pub(super) const DEFLATE_LEVEL: u32 = 4;

/// Where datasets can be created: the file's root or a group.
pub(super) trait Container {
    fn dataset(&mut self, name: &str) -> &mut hdf5_pure::DatasetBuilder;
}

impl Container for FileBuilder {
    fn dataset(&mut self, name: &str) -> &mut hdf5_pure::DatasetBuilder {
        self.create_dataset(name)
    }
}

impl Container for hdf5_pure::GroupBuilder {
    fn dataset(&mut self, name: &str) -> &mut hdf5_pure::DatasetBuilder {
        self.create_dataset(name)
    }
}

/// A string attribute.
pub(super) fn text(value: &str) -> AttrValue {
    AttrValue::VarLenString(value.to_string())
}

fn described<'a>(
    builder: &'a mut hdf5_pure::DatasetBuilder,
    unit: &str,
    description: &str,
) -> &'a mut hdf5_pure::DatasetBuilder {
    builder
        .set_attr("unit", text(unit))
        .set_attr("description", text(description))
}

fn shape_u64(shape: &[usize]) -> Vec<u64> {
    shape.iter().map(|&s| s as u64).collect()
}

/// A dataset of `f64` with its shape, unit and description (compressed
/// when large).
pub(super) fn put_f64(
    group: &mut impl Container,
    name: &str,
    data: &[f64],
    shape: &[usize],
    unit: &str,
    description: &str,
) {
    put_f64_with(group, name, data, shape, unit, description, true);
}

/// [`put_f64`]; `compress` large datasets or not (time histories compress
/// by a quarter only, at twice the write time).
pub(super) fn put_f64_with(
    group: &mut impl Container,
    name: &str,
    data: &[f64],
    shape: &[usize],
    unit: &str,
    description: &str,
    compress: bool,
) {
    let builder = group.dataset(name);
    if data.is_empty() {
        builder.with_dtype(make_f64_type());
    } else {
        builder.with_f64_data(data);
    }
    builder.with_shape(&shape_u64(shape));
    if compress && data.len() >= COMPRESS_FROM && !shape.is_empty() {
        // Chunks of whole rows along the first axis, about 64 KiB each.
        let row: usize = shape.iter().skip(1).product::<usize>().max(1);
        let mut chunks = shape_u64(shape);
        chunks[0] = (8192 / row).clamp(1, shape[0].max(1)) as u64;
        builder
            .with_chunks(&chunks)
            .with_shuffle()
            .with_deflate(DEFLATE_LEVEL);
    }
    described(builder, unit, description);
}

/// Datasets of at least this many values (the time histories) are
/// compressed; smaller ones are not worth a chunk index.
const COMPRESS_FROM: usize = 4096;

/// A dataset of `i64` with its shape and description (unit `1`).
pub(super) fn put_i64(
    group: &mut impl Container,
    name: &str,
    data: &[i64],
    shape: &[usize],
    description: &str,
) {
    let builder = group.dataset(name);
    if data.is_empty() {
        builder.with_dtype(make_i64_type());
    } else {
        builder.with_i64_data(data);
    }
    builder.with_shape(&shape_u64(shape));
    described(builder, "1", description);
}
