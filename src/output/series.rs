//! Growing series in the run's HDF5 file: datasets whose first axis is time (a sample or a
//! window) and that gain one record at a time, each with `units` and `definition`
//! attributes.
//!
//! Storage: a series is chunked along time, about [`CHUNK_BYTES`] per chunk (a whole number
//! of records, one at least), and a chunk of [`FILTER_MIN_BYTES`] or more is stored with
//! the byte shuffle and gzip level [`GZIP_LEVEL`] (every HDF5 reader decodes both). Means
//! meant for plotting are stored as `float32` ([`create_mean`]; computed in `f64`, rounded
//! once when written); sums, counts, times and particle states stay `f64`/integers.

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

/// The units of a file: what `length` and `time` in a unit formula stand for.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Units {
    /// Unit of length (`m`, or `d`, the small-particle diameter of reduced cases).
    pub length: &'static str,
    /// Unit of time (`s`, or `tau`, the reduced time unit).
    pub time: &'static str,
}

impl Units {
    /// SI units (the spring-dashpot family).
    pub const SI: Units = Units {
        length: "m",
        time: "s",
    };
    /// Rapaport's reduced units: lengths in small-particle diameters.
    pub const REDUCED: Units = Units {
        length: "d",
        time: "tau",
    };

    /// The units of `case`, from its model family.
    pub fn of(case: &crate::case::Case) -> Units {
        match case.model.family {
            crate::case::Family::SpringDashpot => Units::SI,
            crate::case::Family::Rapaport => Units::REDUCED,
        }
    }

    /// `formula` (`length/time`, `1/(length^2 time)`, `degrees`...) with the words `length`
    /// and `time` replaced by this file's units.
    pub fn resolve(&self, formula: &str) -> String {
        let mut out = String::with_capacity(formula.len());
        let mut word = String::new();
        let flush = |word: &mut String, out: &mut String| {
            out.push_str(match word.as_str() {
                "length" => self.length,
                "time" => self.time,
                w => w,
            });
            word.clear();
        };
        for c in formula.chars() {
            if c.is_ascii_alphabetic() || c == '_' {
                word.push(c);
            } else {
                flush(&mut word, &mut out);
                out.push(c);
            }
        }
        flush(&mut word, &mut out);
        out
    }

    /// Record them as the attributes `length_unit` and `time_unit` of `loc`.
    pub fn write(&self, loc: &hdf5::Location) -> hdf5::Result<()> {
        str_attr(loc, "length_unit", self.length)?;
        str_attr(loc, "time_unit", self.time)
    }

    /// The units recorded in `loc` by [`Units::write`]; `length`/`time` left as words when
    /// absent (a file from before they were recorded).
    pub fn read(loc: &hdf5::Location) -> Units {
        let get = |name: &str| -> Option<String> {
            let a = loc.attr(name).ok()?;
            let v: VarLenUnicode = a.read_scalar().ok()?;
            Some(v.as_str().to_string())
        };
        match (get("length_unit").as_deref(), get("time_unit").as_deref()) {
            (Some("m"), Some("s")) => Units::SI,
            (Some("d"), Some("tau")) => Units::REDUCED,
            _ => Units {
                length: "length",
                time: "time",
            },
        }
    }
}

/// Describe a dataset: `units` is a formula in `length` and `time` (or a unit such as
/// `rotations`, `degrees`, `-` for none), written in the units the file records
/// ([`Units::read`] of its root).
pub fn describe(ds: &Dataset, units: &str, definition: &str) -> hdf5::Result<()> {
    let file = ds.file()?;
    let resolved = Units::read(&file).resolve(units);
    str_attr(ds, "units", &resolved)?;
    str_attr(ds, "definition", definition)
}

/// Bytes aimed at per chunk of a series: big enough for gzip to find the repeats, small
/// enough that a reader of one record does not decode much more.
pub const CHUNK_BYTES: usize = 256 << 10;

/// Most records per chunk (series of scalars).
pub const CHUNK_RECORDS_MAX: usize = 1024;

/// Chunks smaller than this are stored unfiltered (the filters would gain nothing).
pub const FILTER_MIN_BYTES: usize = 4 << 10;

/// gzip level of every filtered dataset (level 4: nearly the size of 9 at a third of the
/// time).
pub const GZIP_LEVEL: u8 = 4;

/// Records per chunk of a series of records of `row_bytes` bytes.
pub fn chunk_records(row_bytes: usize) -> usize {
    (CHUNK_BYTES / row_bytes.max(1)).clamp(1, CHUNK_RECORDS_MAX)
}

/// Create an empty series `name` in `group` whose records have shape `row`, stored as `T`.
pub fn create<T: H5Type>(
    group: &Group,
    name: &str,
    row: &[usize],
    units: &str,
    definition: &str,
) -> hdf5::Result<Dataset> {
    let row_len: usize = row.iter().product();
    let row_bytes = row_len * std::mem::size_of::<T>();
    let per_chunk = chunk_records(row_bytes);
    let mut chunk = vec![per_chunk];
    chunk.extend_from_slice(row);
    let mut shape: Vec<hdf5::Extent> = vec![hdf5::Extent::resizable(0)];
    shape.extend(row.iter().map(|&n| hdf5::Extent::fixed(n)));
    let b = group.new_dataset::<T>().chunk(chunk).shape(shape);
    let ds = if per_chunk * row_bytes >= FILTER_MIN_BYTES {
        b.shuffle().deflate(GZIP_LEVEL).create(name)?
    } else {
        b.create(name)?
    };
    describe(&ds, units, definition)?;
    Ok(ds)
}

/// Create an empty series of means meant for plotting, stored as `float32` (appended with
/// [`append_mean`]).
pub fn create_mean(
    group: &Group,
    name: &str,
    row: &[usize],
    units: &str,
    definition: &str,
) -> hdf5::Result<Dataset> {
    create::<f32>(group, name, row, units, definition)
}

/// Append one record of means (computed in `f64`) to a series made by [`create_mean`].
pub fn append_mean(ds: &Dataset, record: &[f64]) -> hdf5::Result<()> {
    let narrow: Vec<f32> = record.iter().map(|&x| x as f32).collect();
    append(ds, &narrow)
}

/// Write a fixed array (coordinates) `name` with shape `shape`, contiguous.
pub fn fixed<T: H5Type>(
    group: &Group,
    name: &str,
    shape: &[usize],
    data: &[T],
    units: &str,
    definition: &str,
) -> hdf5::Result<Dataset> {
    let view = ArrayView::from_shape(IxDyn(shape), data).map_err(to_err)?;
    // contiguous, uncompressed: coordinates are small, and a restart tells the series it
    // cuts from them by their being chunked
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn unit_formulas_are_written_in_the_files_units() {
        assert_eq!(Units::SI.resolve("length/time"), "m/s");
        assert_eq!(Units::SI.resolve("1/(length^2 time)"), "1/(m^2 s)");
        assert_eq!(Units::REDUCED.resolve("length^3/time"), "d^3/tau");
        assert_eq!(Units::REDUCED.resolve("1/length^3"), "1/d^3");
        for kept in ["rotations", "degrees", "-", "lengths", "timely"] {
            assert_eq!(Units::SI.resolve(kept), kept);
        }
    }

    #[test]
    fn chunks_hold_whole_records_near_the_target_size() {
        assert_eq!(chunk_records(8), CHUNK_RECORDS_MAX);
        assert_eq!(chunk_records(CHUNK_BYTES), 1);
        assert_eq!(chunk_records(10 * CHUNK_BYTES), 1);
        assert_eq!(chunk_records(1000), CHUNK_BYTES / 1000);
    }
}
