//! Growing series in the run's HDF5 file: datasets whose first axis is time (a sample or a
//! window) and that gain one record at a time, each with `units` and `definition`
//! attributes.

use hdf5::types::VarLenUnicode;
use hdf5::{Dataset, Group, H5Type};
use ndarray::{ArrayView, IxDyn};
use std::str::FromStr;

fn to_err(e: impl std::fmt::Display) -> hdf5::Error {
    hdf5::Error::from(e.to_string().as_str())
}

/// Set a string attribute.
pub fn str_attr(loc: &hdf5::Location, name: &str, value: &str) -> hdf5::Result<()> {
    let v = VarLenUnicode::from_str(value).map_err(to_err)?;
    if loc.attr_names()?.iter().any(|n| n == name) {
        loc.delete_attr(name)?;
    }
    loc.new_attr::<VarLenUnicode>()
        .create(name)?
        .write_scalar(&v)
}

/// Describe a dataset.
pub fn describe(ds: &Dataset, units: &str, definition: &str) -> hdf5::Result<()> {
    str_attr(ds, "units", units)?;
    str_attr(ds, "definition", definition)
}

/// Create an empty series `name` in `group` whose records have shape `row`.
pub fn create<T: H5Type>(
    group: &Group,
    name: &str,
    row: &[usize],
    units: &str,
    definition: &str,
) -> hdf5::Result<Dataset> {
    let mut chunk = vec![1usize];
    chunk.extend_from_slice(row);
    let mut shape: Vec<hdf5::Extent> = vec![hdf5::Extent::resizable(0)];
    shape.extend(row.iter().map(|&n| hdf5::Extent::fixed(n)));
    let ds = group
        .new_dataset::<T>()
        .chunk(if row.is_empty() { vec![64] } else { chunk })
        .shape(shape)
        .create(name)?;
    describe(&ds, units, definition)?;
    Ok(ds)
}

/// Write a fixed array (coordinates) `name` with shape `shape`.
pub fn fixed<T: H5Type>(
    group: &Group,
    name: &str,
    shape: &[usize],
    data: &[T],
    units: &str,
    definition: &str,
) -> hdf5::Result<Dataset> {
    let view = ArrayView::from_shape(IxDyn(shape), data).map_err(to_err)?;
    let ds = group.new_dataset_builder().with_data(view).create(name)?;
    describe(&ds, units, definition)?;
    Ok(ds)
}

/// Append one record (flat, in C order over the record shape) to series `ds`.
pub fn append<T: H5Type>(ds: &Dataset, record: &[T]) -> hdf5::Result<()> {
    let mut shape = ds.shape();
    let t = shape[0];
    shape[0] = t + 1;
    let row: Vec<usize> = shape[1..].to_vec();
    if row.iter().product::<usize>() != record.len() {
        return Err(to_err(format!(
            "record of {} values for {} of record shape {row:?}",
            record.len(),
            ds.name()
        )));
    }
    ds.resize(shape.clone())?;
    let mut full = vec![1usize];
    full.extend_from_slice(&row);
    let view = ArrayView::from_shape(IxDyn(&full), record).map_err(to_err)?;
    match row.len() {
        0 => ds.write_slice(
            view.into_dimensionality::<ndarray::Ix1>().map_err(to_err)?,
            t..t + 1,
        ),
        1 => ds.write_slice(
            view.into_dimensionality::<ndarray::Ix2>().map_err(to_err)?,
            (t..t + 1, ..),
        ),
        2 => ds.write_slice(
            view.into_dimensionality::<ndarray::Ix3>().map_err(to_err)?,
            (t..t + 1, .., ..),
        ),
        3 => ds.write_slice(
            view.into_dimensionality::<ndarray::Ix4>().map_err(to_err)?,
            (t..t + 1, .., .., ..),
        ),
        4 => ds.write_slice(
            view.into_dimensionality::<ndarray::Ix5>().map_err(to_err)?,
            (t..t + 1, .., .., .., ..),
        ),
        n => Err(to_err(format!("records of rank {n} are not supported"))),
    }
}

/// Cut series `ds` back to its first `records` records (a restart).
pub fn truncate(ds: &Dataset, records: usize) -> hdf5::Result<()> {
    let mut shape = ds.shape();
    if shape[0] < records {
        return Err(to_err(format!(
            "{} holds {} records, fewer than the checkpoint's {records}",
            ds.name(),
            shape[0]
        )));
    }
    shape[0] = records;
    ds.resize(shape)
}
