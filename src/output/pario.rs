//! Files every rank writes together: HDF5 with the MPI-IO driver when the run has MPI
//! (HDF5's default driver without it, as in the unit tests), and datasets of which every
//! rank writes its own rows, so that nothing of size N passes through one rank.
//!
//! HDF5's metadata operations (creating the file, a group, a dataset, an attribute) are
//! collective: every rank calls them with the same arguments. The rows are written with
//! the collective transfer mode, which chunked datasets with filters (the byte shuffle and
//! gzip, the checkpoints' Fletcher32 checksums) require in parallel HDF5 (1.10.2 and later);
//! a rank with no rows takes part with an empty selection. After each write the ranks agree
//! on the outcome ([`together`]), so that one rank's failure stops every rank before the
//! next collective call instead of leaving the others waiting in it.
//!
//! Storage ([`Storage::of`]): a dataset of [`FILTER_MIN_BYTES`] or more is chunked, about
//! [`CHUNK_BYTES`] per chunk, and stored with the byte shuffle and gzip level
//! [`GZIP_LEVEL`], as the series are; a smaller one is contiguous (or, checksummed, one
//! chunk). The chunk shape depends only on the dataset's global row count and row size, so
//! every rank creates the same dataset. The values are stored as they are (`f64` particle
//! states, integer ids): gzip keeps every bit, and a restart stays bit-identical.

use super::series::{CHUNK_BYTES, FILTER_MIN_BYTES, GZIP_LEVEL};
use crate::comm::Comm;
use hdf5::H5Type;
use hdf5_sys::h5d::{H5Dread, H5Dwrite};
use hdf5_sys::h5i::hid_t;
use hdf5_sys::h5p::{H5FD_mpio_xfer_t, H5Pclose, H5Pcreate, H5Pset_dxpl_mpio};
use hdf5_sys::h5s::{
    H5S_seloper_t, H5Sclose, H5Screate_simple, H5Sselect_hyperslab, H5Sselect_none,
};
use std::path::Path;

/// A file open on every rank.
pub struct ParFile<'c> {
    /// The file.
    pub file: hdf5::File,
    /// The ranks that hold it open.
    pub comm: &'c dyn Comm,
}

impl ParFile<'_> {
    /// Whether it is open with the MPI-IO driver (rows are then written collectively).
    pub fn mpio(&self) -> bool {
        self.comm.raw().is_some()
    }
}

fn access(comm: &dyn Comm, p: &mut hdf5::plist::FileAccessBuilder, v110: bool) {
    if let Some(raw) = comm.raw() {
        p.mpio(raw.0, None);
    }
    if v110 {
        p.libver_v110();
    }
}

/// Create `path` on every rank (replacing a file there); `v110`: metadata in the 1.10
/// format, whose object headers are checksummed.
pub fn create<'c>(comm: &'c dyn Comm, path: &Path, v110: bool) -> hdf5::Result<ParFile<'c>> {
    let file = hdf5::File::with_options()
        .with_fapl(|p| {
            access(comm, p, v110);
            p
        })
        .create(path)?;
    Ok(ParFile { file, comm })
}

/// Open the existing `path` for writing on every rank.
pub fn open_rw<'c>(comm: &'c dyn Comm, path: &Path) -> hdf5::Result<ParFile<'c>> {
    let file = hdf5::File::with_options()
        .with_fapl(|p| {
            access(comm, p, false);
            p
        })
        .open_rw(path)?;
    Ok(ParFile { file, comm })
}

/// Close the file on every rank (a collective flush of its metadata), reporting failures.
pub fn close(f: ParFile) -> Result<(), String> {
    together(f.comm, f.file.close())
}

/// `r` if every rank's outcome is a success; otherwise an error on every rank (this rank's
/// own message, or one saying another rank failed, whose message that rank logs).
pub fn together<T>(comm: &dyn Comm, r: hdf5::Result<T>) -> Result<T, String> {
    let ok = comm.all_ok(r.is_ok());
    // rank 0 reports the run's error; another rank's own reason is logged where it happened
    if let (Err(e), false) = (&r, comm.rank() == 0) {
        log::error!("rank {}: {e}", comm.rank());
    }
    match r {
        Ok(v) if ok => Ok(v),
        Ok(_) => Err("another rank could not write its part of the file (see its message)".into()),
        Err(e) => Err(e.to_string()),
    }
}

/// Where this rank's rows go in a dataset every rank writes a part of: 64-bit offsets.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Rows {
    /// First row of this rank's part.
    pub offset: u64,
    /// This rank's rows.
    pub count: u64,
    /// Rows over all ranks.
    pub total: u64,
}

impl Rows {
    /// The place of this rank's `count` rows when the ranks' parts follow in rank order.
    pub fn of(comm: &dyn Comm, count: u64) -> Rows {
        Rows {
            offset: comm.exscan_u64(count),
            count,
            total: comm.sum_u64(count),
        }
    }

    /// Rows `[r * total / size, (r + 1) * total / size)`: rank `r`'s even share of a dataset
    /// of `total` rows that every rank reads a part of.
    pub fn share(total: u64, rank: usize, size: usize) -> Rows {
        let at = |r: usize| (total as u128 * r as u128 / size.max(1) as u128) as u64;
        let (lo, hi) = (at(rank), at(rank + 1));
        Rows {
            offset: lo,
            count: hi - lo,
            total,
        }
    }

    /// The range of rows, as indices.
    pub fn range(&self) -> std::ops::Range<usize> {
        self.offset as usize..(self.offset + self.count) as usize
    }
}

/// Most rows per chunk (a checksum covers one chunk).
pub const CHUNK_ROWS: u64 = 1 << 16;

/// How a dataset that every rank writes rows of is stored: a function of the global row
/// count and the row's size only, so every rank creates the same dataset.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Storage {
    /// Rows per chunk; 0 for a contiguous dataset.
    pub chunk_rows: u64,
    /// Byte shuffle and gzip ([`GZIP_LEVEL`]).
    pub compressed: bool,
    /// A Fletcher32 checksum per chunk.
    pub checksum: bool,
}

impl Storage {
    /// The storage of a dataset of `total` rows of `row_bytes` bytes; `checksum`: one
    /// Fletcher32 checksum per chunk (a dataset with rows is then always chunked). Datasets
    /// of [`FILTER_MIN_BYTES`] or more are compressed, in chunks of about [`CHUNK_BYTES`]
    /// (at most [`CHUNK_ROWS`] rows); an empty one is contiguous.
    pub fn of(total: u64, row_bytes: usize, checksum: bool) -> Storage {
        let row_bytes = row_bytes.max(1) as u64;
        let compressed = total.saturating_mul(row_bytes) >= FILTER_MIN_BYTES as u64;
        let chunk_rows = if total == 0 || !(compressed || checksum) {
            0
        } else if compressed {
            (CHUNK_BYTES as u64 / row_bytes)
                .clamp(1, CHUNK_ROWS)
                .min(total)
        } else {
            total.min(CHUNK_ROWS)
        };
        Storage {
            chunk_rows,
            compressed: compressed && chunk_rows > 0,
            checksum: checksum && chunk_rows > 0,
        }
    }
}

/// Create dataset `name` of `rows.total` rows of `cols` values (1-D when `cols` is 1) in `g`
/// on every rank, stored as [`Storage::of`] says, and write this rank's `data` (`rows.count`
/// rows) at `rows.offset`. `checksum`: a Fletcher32 checksum per chunk. The ranks agree on
/// the outcome before returning.
pub fn write_rows<T: H5Type>(
    f: &ParFile,
    g: &hdf5::Group,
    name: &str,
    data: &[T],
    cols: usize,
    rows: Rows,
    checksum: bool,
) -> Result<hdf5::Dataset, String> {
    let r = write_rows_here(f, g, name, data, cols, rows, checksum);
    together(f.comm, r).map_err(|e| format!("{name}: {e}"))
}

fn write_rows_here<T: H5Type>(
    f: &ParFile,
    g: &hdf5::Group,
    name: &str,
    data: &[T],
    cols: usize,
    rows: Rows,
    checksum: bool,
) -> hdf5::Result<hdf5::Dataset> {
    let cols = cols.max(1);
    if data.len() as u64 != rows.count * cols as u64 {
        return Err(hdf5::Error::from(
            format!(
                "{} values are not {} rows of {cols}",
                data.len(),
                rows.count
            )
            .as_str(),
        ));
    }
    let total = rows.total as usize;
    let storage = Storage::of(rows.total, cols * std::mem::size_of::<T>(), checksum);
    let mut b = g.new_dataset::<T>();
    if storage.chunk_rows > 0 {
        let chunk = storage.chunk_rows as usize;
        if cols == 1 {
            b = b.chunk(chunk);
        } else {
            b = b.chunk((chunk, cols));
        }
        if storage.compressed {
            b = b.shuffle().deflate(GZIP_LEVEL);
        }
        if storage.checksum {
            // last: the checksum covers the bytes stored, and is verified before inflating
            b = b.fletcher32();
        }
    }
    let ds = if cols == 1 {
        b.shape(total).create(name)?
    } else {
        b.shape((total, cols)).create(name)?
    };
    let rank = if cols == 1 { 1 } else { 2 };
    let start = [rows.offset, 0];
    let count = [rows.count, cols as u64];
    let mem_dims = [rows.count.max(1), cols as u64];
    put_selected(f, &ds, data, &mem_dims[..rank], rows.count > 0, |fs| {
        // SAFETY: `fs` is the open file space of `ds`; `start` and `count` have its rank
        hdf5::h5check(unsafe {
            H5Sselect_hyperslab(
                fs,
                H5S_seloper_t::H5S_SELECT_SET,
                start.as_ptr(),
                std::ptr::null(),
                count.as_ptr(),
                std::ptr::null(),
            )
        })
        .map(drop)
    })?;
    Ok(ds)
}

/// Write `data` (shaped `mem_dims`, at least one element per dimension) into the part of
/// `ds` that `select` selects of its file space, collectively when the file is open with
/// MPI-IO; a rank with nothing to write (`!any`) takes part with empty selections.
fn put_selected<T: H5Type>(
    f: &ParFile,
    ds: &hdf5::Dataset,
    data: &[T],
    mem_dims: &[u64],
    any: bool,
    select: impl FnOnce(hid_t) -> hdf5::Result<()>,
) -> hdf5::Result<()> {
    let mem_type = hdf5::Datatype::from_type::<T>()?;
    let ds_id = ds.id();
    let fspace = ds.space()?;
    let (fs, tp) = (fspace.id(), mem_type.id());
    let collective = f.mpio();
    hdf5::sync::sync(|| -> hdf5::Result<()> {
        // SAFETY: the ids are open objects of this function; the caller's selection indexes
        // `data` within `mem_dims`.
        unsafe {
            let check = |code: i32| hdf5::h5check(code).map(|_| ());
            let ms = hdf5::h5check(H5Screate_simple(
                mem_dims.len() as i32,
                mem_dims.as_ptr(),
                std::ptr::null(),
            ))?;
            let dxpl: hid_t = match hdf5::h5check(H5Pcreate(*hdf5_sys::h5p::H5P_CLS_DATASET_XFER)) {
                Ok(id) => id,
                Err(e) => {
                    H5Sclose(ms);
                    return Err(e);
                }
            };
            let result = (|| {
                if collective {
                    check(H5Pset_dxpl_mpio(
                        dxpl,
                        H5FD_mpio_xfer_t::H5FD_MPIO_COLLECTIVE,
                    ))?;
                }
                if any {
                    select(fs)?;
                } else {
                    check(H5Sselect_none(fs))?;
                    check(H5Sselect_none(ms))?;
                }
                check(H5Dwrite(ds_id, tp, ms, fs, dxpl, data.as_ptr().cast()))
            })();
            H5Pclose(dxpl);
            H5Sclose(ms);
            result
        }
    })
}

/// This rank's part of a 1-D dataset of `total` values that the ranks hold in blocks:
/// `count` blocks of `block` values, `stride` apart, the first at `offset` (a hyperslab).
/// The per-slice window sums (`diag::grid::BinnedSums`) are laid out `x, y, z, ...` with
/// `z` fastest, so a rank's own run of axial slices is one block per `x, y` bin.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Blocks {
    /// First value of the first block.
    pub offset: u64,
    /// Values per block.
    pub block: u64,
    /// Distance between the starts of consecutive blocks.
    pub stride: u64,
    /// Number of blocks.
    pub count: u64,
    /// Values in the whole dataset.
    pub total: u64,
}

impl Blocks {
    /// The whole dataset of `total` values as one block.
    pub fn whole(total: u64) -> Blocks {
        Blocks {
            offset: 0,
            block: total,
            stride: total,
            count: u64::from(total > 0),
            total,
        }
    }

    /// Values in this rank's part.
    pub fn len(&self) -> u64 {
        self.block * self.count
    }

    /// Whether this rank's part is empty.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The same values with adjacent blocks merged (`stride == block`: one block).
    fn simplest(self) -> Blocks {
        if self.count > 1 && self.stride == self.block {
            Blocks {
                block: self.block * self.count,
                stride: self.block * self.count,
                count: 1,
                ..self
            }
        } else {
            self
        }
    }

    /// Whether the blocks lie within the dataset without overlapping.
    fn fits(&self, total: u64) -> bool {
        self.total == total
            && (self.is_empty()
                || (self.stride >= self.block
                    && (self.count - 1)
                        .checked_mul(self.stride)
                        .and_then(|x| x.checked_add(self.offset + self.block))
                        .is_some_and(|end| end <= total)))
    }

    /// Select the blocks in the 1-D file space `fs`.
    fn select(&self, fs: hid_t) -> hdf5::Result<()> {
        let b = self.simplest();
        let (start, stride, count, block) = ([b.offset], [b.stride], [b.count], [b.block]);
        // SAFETY: `fs` is an open 1-D dataspace; the arrays have its rank
        hdf5::h5check(unsafe {
            H5Sselect_hyperslab(
                fs,
                H5S_seloper_t::H5S_SELECT_SET,
                start.as_ptr(),
                stride.as_ptr(),
                count.as_ptr(),
                block.as_ptr(),
            )
        })
        .map(drop)
    }
}

/// Write this rank's `blocks` of the 1-D dataset `ds` (created beforehand on every rank with
/// the same arguments), `data` being the blocks' values in the file's order; every rank
/// calls this together (collective transfer), and the ranks agree on the outcome before
/// returning. The ranks' blocks together make the whole dataset, each value written once.
pub fn write_blocks<T: H5Type>(
    f: &ParFile,
    ds: &hdf5::Dataset,
    data: &[T],
    blocks: Blocks,
) -> Result<(), String> {
    let r = (|| {
        let total = ds.size() as u64;
        if !blocks.fits(total) || data.len() as u64 != blocks.len() {
            return Err(hdf5::Error::from(
                format!(
                    "{} values do not make the blocks {blocks:?} of a dataset of {total}",
                    data.len()
                )
                .as_str(),
            ));
        }
        let mem_dims = [blocks.len().max(1)];
        put_selected(f, ds, data, &mem_dims, !blocks.is_empty(), |fs| {
            blocks.select(fs)
        })
    })();
    together(f.comm, r).map_err(|e| format!("{}: {e}", ds.name()))
}

/// Read `blocks` of the 1-D dataset `ds`, in the file's order (the checksums of the chunks
/// read are verified, as for any read).
pub fn read_blocks<T: H5Type + Copy + Default>(
    ds: &hdf5::Dataset,
    blocks: Blocks,
) -> hdf5::Result<Vec<T>> {
    let total = ds.size() as u64;
    if !blocks.fits(total) {
        return Err(hdf5::Error::from(
            format!("the blocks {blocks:?} do not fit a dataset of {total} values").as_str(),
        ));
    }
    let mut out = vec![T::default(); blocks.len() as usize];
    if out.is_empty() {
        return Ok(out);
    }
    let mem_type = hdf5::Datatype::from_type::<T>()?;
    let fspace = ds.space()?;
    let (ds_id, fs, tp) = (ds.id(), fspace.id(), mem_type.id());
    let mem_dims = [blocks.len()];
    hdf5::sync::sync(|| -> hdf5::Result<()> {
        // SAFETY: the ids are open objects of this function; the memory space is `out`,
        // which holds exactly the values the file selection selects
        unsafe {
            let ms = hdf5::h5check(H5Screate_simple(1, mem_dims.as_ptr(), std::ptr::null()))?;
            let result = blocks.select(fs).and_then(|()| {
                hdf5::h5check(H5Dread(
                    ds_id,
                    tp,
                    ms,
                    fs,
                    hdf5_sys::h5p::H5P_DEFAULT,
                    out.as_mut_ptr().cast(),
                ))
                .map(drop)
            });
            H5Sclose(ms);
            result
        }
    })?;
    Ok(out)
}

/// Read this rank's `rows` of dataset `ds` (`cols` values per row, 1-D when `cols` is 1),
/// flattened.
pub fn read_rows<T: H5Type>(ds: &hdf5::Dataset, cols: usize, rows: Rows) -> hdf5::Result<Vec<T>> {
    let r = rows.range();
    if cols <= 1 {
        Ok(ds.read_slice_1d::<T, _>(r)?.into_raw_vec_and_offset().0)
    } else {
        Ok(ds
            .read_slice_2d::<T, _>(ndarray::s![r, ..])?
            .into_raw_vec_and_offset()
            .0)
    }
}

/// Start the HDF5 library before MPI, and keep it from closing, at MPI's end or the
/// program's exit, what the program left open. Only a file whose close failed (a full disk)
/// is left open, and HDF5 1.10's MPI-IO driver crashes closing it there (in `H5D_close`);
/// the program itself closes every file it writes, and removes such a failed one. Started
/// before MPI, the library does not hook its end to `MPI_Finalize`. Call it first, before
/// MPI and any other HDF5 call.
pub fn start_library() {
    // SAFETY: sets a flag read when the library starts, then starts it; nothing else of
    // HDF5 runs yet
    unsafe {
        hdf5_sys::h5::H5dont_atexit();
        hdf5_sys::h5::H5open();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn storage_depends_on_the_global_rows_only_and_spares_tiny_datasets() {
        // tiny: contiguous, or one checksummed chunk
        let tiny = Storage::of(100, 24, false);
        assert_eq!((tiny.chunk_rows, tiny.compressed), (0, false));
        let tiny = Storage::of(100, 24, true);
        assert_eq!(
            (tiny.chunk_rows, tiny.compressed, tiny.checksum),
            (100, false, true)
        );
        // empty: contiguous, whatever is asked
        assert_eq!(Storage::of(0, 24, true).chunk_rows, 0);
        // not tiny: compressed, in chunks of about CHUNK_BYTES, never more rows than exist
        let s = Storage::of(1_000_000, 24, true);
        assert!(s.compressed && s.checksum);
        assert_eq!(s.chunk_rows, (CHUNK_BYTES / 24) as u64);
        assert_eq!(Storage::of(2_000, 24, false).chunk_rows, 2_000);
        assert_eq!(Storage::of(10_000_000, 1, false).chunk_rows, CHUNK_ROWS);
        assert_eq!(
            Storage::of(FILTER_MIN_BYTES as u64 / 8, 8, false),
            Storage {
                chunk_rows: FILTER_MIN_BYTES as u64 / 8,
                compressed: true,
                checksum: false
            }
        );
    }
}
