//! Checkpoints: the complete state of a run, from which `tumbler run --restart` continues
//! bit-identically to a run never interrupted, on the same or another number of ranks.
//!
//! One HDF5 file, written by every rank: every mobile particle (id, species, diameter, position,
//! velocity, spin, the force and torque of the last evaluation, which the next half kick
//! uses, its wall histories, and its order key of the last spatial sort, `engine::order`), every contact history keyed by the pair's ids, the step,
//! the number of axial samples written, the case text, and the diagnostics' windows in
//! progress (exact sums, so a restart averages the same bits). The particles and contacts
//! are written by all ranks together, each its own rows (`output::pario`: MPI-IO, a share of
//! about N/P rows of the id order per rank, [`crate::engine::Sim::particles_by_id`] and
//! [`crate::engine::Sim::histories_by_ids`], gathered one after the other as they are written);
//! so are the window sums in progress, each rank its own block of them ([`SavedSums`],
//! `pario::write_blocks`); rank 0 then adds the attributes and the rest of the diagnostics
//! (small). It is written as `NAME.tmp`, flushed to disk and renamed over `NAME` by rank 0
//! once every rank has closed it, so the previous checkpoint stays whole until the new one
//! is; a failed write (a full disk) removes the temporary file. A restart reads only its
//! share of the rows ([`read_share`]) and its own block of the window sums ([`read_sums`]),
//! whatever number of ranks wrote them. (The run
//! draws no random numbers after the initial state, so there is no generator state to keep.)
//!
//! The window sums (fixed-point `i128`, stored as their high and low 64-bit halves) are
//! mostly zeros, for bins no particle reached: they are stored shuffled and gzipped, which
//! keeps every bit. So are the particle and contact rows that are not tiny
//! (`pario::Storage`: chunks of about 256 KiB, the same on any rank count); their values are
//! the `f64`/integer words themselves, so a restart stays bit-identical.
//!
//! Every dataset carries HDF5's Fletcher32 checksum (HDF5 verifies it on every read) and the
//! file's metadata is written in the 1.10 format, whose object headers are checksummed too,
//! so a damaged checkpoint is refused on restart instead of loading wrong numbers.

use super::pario::{self, Rows};
use crate::comm::Comm;
use crate::diag::windows::AngleSums;
use crate::engine::neighbor::{SavedContact, SavedHistory};
use crate::particles::{Field, Records};
use crate::physics::contact::{History, HISTORY_MAX};
use crate::physics::materials::WALLS;
use hdf5::types::VarLenUnicode;
use hdf5::H5Type;
use ndarray::ArrayView2;
use std::path::{Path, PathBuf};
use std::str::FromStr;

/// The fewest history words per contact a checkpoint stores (zeros beyond the law's), so
/// that a law without histories writes the same layout as a tangential spring.
pub const FILE_WORDS_MIN: usize = 3;

/// The particles' `f64` columns besides the wall histories, as they are named in the file.
const COLUMNS_F64: [(&str, Field); 6] = [
    ("diameter", Field::Diameter),
    ("position", Field::Position),
    ("velocity", Field::Velocity),
    ("angular_velocity", Field::AngularVelocity),
    ("force", Field::Force),
    ("torque", Field::Torque),
];

/// Where a checkpoint's rows come from when it is written: each rank's share of the id
/// order, gathered when the writer reaches them (every rank calls each method together),
/// one part at a time, so that the write holds either the particles or the contacts.
pub trait Gather {
    /// This rank's particles and contacts, at most (for the check of the disk's room).
    fn counts(&self) -> [u64; 2];
    /// This rank's share of the particles, sorted by id.
    fn particles(&mut self) -> Records;
    /// This rank's share of the contacts, sorted by ids.
    fn histories(&mut self) -> SavedHistory;
}

/// The state a run continues from.
#[derive(Debug, Clone)]
pub struct Checkpoint {
    /// The effective case text of the run that wrote it.
    pub case_text: String,
    /// Steps taken since time zero.
    pub step: u64,
    /// Axial samples written to the output so far.
    pub samples: u64,
    /// Mobile particles, sorted by id: this rank's share as read by [`read_share`], the
    /// ranks' shares in increasing order of id (empty in a checkpoint being written: [`write`]
    /// takes its rows from a [`Gather`]).
    pub particles: Records,
    /// Contact histories, sorted by ids: this rank's share, as the particles.
    pub histories: SavedHistory,
    /// History words per contact, wall contacts included (the law's `history_words`; when
    /// read, the file's width: at least [`FILE_WORDS_MIN`]).
    pub history_words: usize,
    /// Mobile particles in the whole checkpoint (set when read).
    pub n_particles: u64,
    /// The windows in progress and the particles followed.
    pub diag: DiagState,
}

/// The diagnostics' state a restart needs: the sums of the windows in progress (each rank
/// its own block) and the ids of the particles whose paths are recorded.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct DiagState {
    /// Per-slice sums.
    pub slices: SavedSums,
    /// Field sums.
    pub fields: SavedSums,
    /// Angle sums of the per-slice window.
    pub angles: AngleSums,
    /// Ids of the particles followed.
    pub path_ids: Vec<u64>,
    /// Whether the windows follow the whole-rotation schedule ([`WINDOW_SCHEDULE`]); a
    /// checkpoint written before it (`false`) is refused by a restart.
    pub whole_windows: bool,
}

/// Version of the window schedule, the `diagnostics` attribute `window_schedule`: 2 for
/// windows of whole samples ending on whole multiples of their length
/// (`run::diagnostics`); absent before.
pub const WINDOW_SCHEDULE: u64 = 2;

/// The sums of one window in progress.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct SavedSums {
    /// Samples accumulated.
    pub samples: u64,
    /// Sum of their frame angles, degrees.
    pub angle_sum: f64,
    /// Fixed-point sums (see `diag::grid::BinnedSums`): this rank's `blocks` of them when
    /// written; when read, empty ([`read_share`]: each rank then reads its own block with
    /// [`read_sums`]) or whole ([`read`]).
    pub sums: Vec<i128>,
    /// How many sums the whole window holds.
    pub len: usize,
    /// Where `sums` lie in the whole window's sums, in the file's order.
    pub blocks: pario::Blocks,
}

/// Rank 0's part of the diagnostics group (the sums are in it already, written by every
/// rank in [`write_rows_of_all`]).
fn write_diag(f: &hdf5::File, d: &DiagState) -> hdf5::Result<()> {
    let g = f.group("diagnostics")?;
    for (name, s) in [("slices", &d.slices), ("fields", &d.fields)] {
        let (samples, angle_sum) = (&s.samples, &s.angle_sum);
        g.new_attr::<u64>()
            .create(format!("{name}_samples").as_str())?
            .write_scalar(samples)?;
        g.new_attr::<f64>()
            .create(format!("{name}_angle_sum").as_str())?
            .write_scalar(angle_sum)?;
    }
    let a = &d.angles;
    put(&g, "angle_slice_sum", &a.slice_sum, 1)?;
    put(&g, "angle_slice_n", &a.slice_n, 1)?;
    g.new_attr::<f64>()
        .create("angle_drum_sum")?
        .write_scalar(&a.drum_sum)?;
    g.new_attr::<u64>()
        .create("angle_drum_n")?
        .write_scalar(&a.drum_n)?;
    put(&g, "path_ids", &d.path_ids, 1)?;
    g.new_attr::<u64>()
        .create("window_schedule")?
        .write_scalar(&WINDOW_SCHEDULE)?;
    Ok(())
}

/// Rows per chunk of a checkpoint dataset written by rank 0 (a checksum covers one chunk).
const CHUNK_ROWS: usize = 1 << 16;

/// Write `data` (rows of `cols` values) as dataset `name` of `g`: 1-D when `cols` is 1,
/// else `rows x cols`; chunked with a Fletcher32 checksum unless empty.
fn put<T: H5Type>(g: &hdf5::Group, name: &str, data: &[T], cols: usize) -> hdf5::Result<()> {
    let rows = data.len() / cols.max(1);
    if rows * cols != data.len() {
        return Err(hdf5::Error::from(
            format!("{name}: {} values are not rows of {cols}", data.len()).as_str(),
        ));
    }
    let chunk = rows.clamp(1, CHUNK_ROWS);
    if cols == 1 {
        let b = g.new_dataset_builder().with_data(data);
        if rows > 0 {
            b.chunk(chunk).fletcher32().create(name)?;
        } else {
            b.create(name)?;
        }
    } else {
        let view = ArrayView2::from_shape((rows, cols), data)
            .map_err(|e| hdf5::Error::from(e.to_string().as_str()))?;
        let b = g.new_dataset_builder().with_data(view);
        if rows > 0 {
            b.chunk((chunk, cols)).fletcher32().create(name)?;
        } else {
            b.create(name)?;
        }
    }
    Ok(())
}

/// Create the 1-D dataset `name` of `len` values in `g` (every rank, with the same
/// arguments), chunked with a Fletcher32 checksum, the byte shuffle and gzip per chunk: the
/// window sums, whose bins are mostly empty (zeros), shrink to a few per cent and read back
/// bit for bit.
fn create_compressed<T: H5Type>(
    g: &hdf5::Group,
    name: &str,
    len: usize,
) -> hdf5::Result<hdf5::Dataset> {
    let b = g.new_dataset::<T>();
    if len == 0 {
        b.shape(0).create(name)
    } else {
        b.chunk(len.clamp(1, CHUNK_ROWS))
            .fletcher32()
            .shuffle()
            .deflate(super::series::GZIP_LEVEL)
            .shape(len)
            .create(name)
    }
}

/// Write every rank's block of the window sums of `d` into the diagnostics group `g` of the
/// file every rank has open (collective): the high and low 64-bit halves as two datasets.
fn write_sums_of_all(f: &pario::ParFile, g: &hdf5::Group, d: &DiagState) -> Result<(), String> {
    let comm = f.comm;
    for (name, s) in [("slices", &d.slices), ("fields", &d.fields)] {
        // one half at a time, to keep the checkpoint's memory peak low
        let hi_name = format!("{name}_hi");
        let ds = pario::together(comm, create_compressed::<i64>(g, &hi_name, s.len))?;
        let hi: Vec<i64> = s.sums.iter().map(|&x| (x >> 64) as i64).collect();
        pario::write_blocks(f, &ds, &hi, s.blocks)?;
        drop((hi, ds));
        let lo_name = format!("{name}_lo");
        let ds = pario::together(comm, create_compressed::<u64>(g, &lo_name, s.len))?;
        let lo: Vec<u64> = s.sums.iter().map(|&x| x as u64).collect();
        pario::write_blocks(f, &ds, &lo, s.blocks)?;
    }
    Ok(())
}

/// Read `blocks` of the window sums `name` (`slices` or `fields`) of the checkpoint at
/// `path`: each rank of a restart reads its own block, whatever number of ranks wrote them.
pub fn read_sums(path: &Path, name: &str, blocks: pario::Blocks) -> Result<Vec<i128>, String> {
    let f = hdf5::File::open(path).map_err(err(path))?;
    read_sums_of(&f, path, name, blocks)
}

fn read_sums_of(
    f: &hdf5::File,
    path: &Path,
    name: &str,
    blocks: pario::Blocks,
) -> Result<Vec<i128>, String> {
    let half = |which: &str| format!("diagnostics/{name}_{which}");
    let (hi_name, lo_name) = (half("hi"), half("lo"));
    let hi: Vec<i64> = f
        .dataset(&hi_name)
        .and_then(|d| pario::read_blocks(&d, blocks))
        .map_err(|e| read_error(path, &hi_name, &e))?;
    let lo: Vec<u64> = f
        .dataset(&lo_name)
        .and_then(|d| pario::read_blocks(&d, blocks))
        .map_err(|e| read_error(path, &lo_name, &e))?;
    Ok(hi
        .iter()
        .zip(&lo)
        .map(|(&h, &l)| ((h as i128) << 64) | l as i128)
        .collect())
}

/// Read dataset `name` whole; a checksum failure says the checkpoint is damaged.
fn get<T: H5Type>(f: &hdf5::File, path: &Path, name: &str) -> Result<Vec<T>, String> {
    f.dataset(name)
        .and_then(|d| d.read_raw())
        .map_err(|e| read_error(path, name, &e))
}

fn read_error(path: &Path, name: &str, e: &hdf5::Error) -> String {
    let text = e.to_string();
    let lower = text.to_lowercase();
    if lower.contains("checksum") || lower.contains("filter") || lower.contains("fletcher") {
        format!(
            "checkpoint {}: {name} fails its checksum: the file is damaged (a flipped byte, a bad disk or copy) and cannot be restarted from; use another copy of it ({text})",
            path.display()
        )
    } else {
        format!("checkpoint {}: cannot read {name}: {text}", path.display())
    }
}

/// The diagnostics state; the window sums themselves only if `sums_too` (whole: a restart's
/// ranks read their own blocks with [`read_sums`]).
fn read_diag(f: &hdf5::File, path: &Path, sums_too: bool) -> Result<DiagState, String> {
    let e = err(path);
    let g = f.group("diagnostics").map_err(&e)?;
    let attr_u64 = |name: &str| -> Result<u64, String> {
        g.attr(name).and_then(|a| a.read_scalar()).map_err(&e)
    };
    let attr_f64 = |name: &str| -> Result<f64, String> {
        g.attr(name).and_then(|a| a.read_scalar()).map_err(&e)
    };
    let sums = |name: &str| -> Result<SavedSums, String> {
        let len = f
            .dataset(&format!("diagnostics/{name}_hi"))
            .map_err(&e)?
            .size();
        let lo_len = f
            .dataset(&format!("diagnostics/{name}_lo"))
            .map_err(&e)?
            .size();
        if len != lo_len {
            return Err(format!(
                "checkpoint {}: diagnostics/{name}_hi and _lo differ in length",
                path.display()
            ));
        }
        let blocks = pario::Blocks::whole(len as u64);
        let sums = if sums_too {
            read_sums_of(f, path, name, blocks)?
        } else {
            Vec::new()
        };
        Ok(SavedSums {
            samples: attr_u64(&format!("{name}_samples"))?,
            angle_sum: attr_f64(&format!("{name}_angle_sum"))?,
            len,
            sums,
            blocks: if sums_too {
                blocks
            } else {
                pario::Blocks::default()
            },
        })
    };
    Ok(DiagState {
        slices: sums("slices")?,
        fields: sums("fields")?,
        angles: AngleSums {
            slice_sum: get(f, path, "diagnostics/angle_slice_sum")?,
            slice_n: get(f, path, "diagnostics/angle_slice_n")?,
            drum_sum: attr_f64("angle_drum_sum")?,
            drum_n: attr_u64("angle_drum_n")?,
        },
        path_ids: get(f, path, "diagnostics/path_ids")?,
        whole_windows: g
            .attr("window_schedule")
            .and_then(|a| a.read_scalar::<u64>())
            .is_ok_and(|v| v == WINDOW_SCHEDULE),
    })
}

/// The checkpoint written next to an output file (`NAME.h5` -> `NAME.ckpt.h5`).
pub fn checkpoint_path(output: &Path) -> PathBuf {
    output.with_extension("ckpt.h5")
}

fn err(path: &Path) -> impl Fn(hdf5::Error) -> String + '_ {
    move |e| format!("checkpoint {}: {e}", path.display())
}

/// The temporary name a checkpoint is written under (`NAME` -> `NAME.tmp`).
pub fn tmp_path(path: &Path) -> PathBuf {
    let mut tmp = path.as_os_str().to_owned();
    tmp.push(".tmp");
    PathBuf::from(tmp)
}

/// Write a checkpoint to `path` atomically (all ranks call this together, each with, in
/// `ck.diag`, its block of the window sums, and in `rows_of` its rows): written
/// whole under [`tmp_path`], synced, then renamed over `path`. On any error, on any rank,
/// every rank returns it, the temporary file is removed and `path` is left as it was. The
/// particles and contacts come from `rows_of`, not `ck` (whose rows are not read): each
/// is gathered when it is written and freed after, before the window sums are written
/// (their largest transient), so the checkpoint's peak holds one of the three only.
pub fn write(
    comm: &dyn Comm,
    path: &Path,
    ck: &Checkpoint,
    rows_of: &mut dyn Gather,
) -> Result<(), String> {
    let tmp = tmp_path(path);
    let root = comm.rank() == 0;
    // A disk that fills up while parallel HDF5 closes the file can leave the ranks waiting
    // for each other inside the library: refuse before writing when there is clearly no room.
    let mut rows = rows_of.counts();
    comm.sum_u64_all(&mut rows);
    let short = if root {
        short_of_room(path, rows, ck.history_words.max(FILE_WORDS_MIN))
    } else {
        None
    };
    if !comm.all_ok(short.is_none()) {
        return Err(format!(
            "checkpoint {}: {}; the previous checkpoint, if any, is kept",
            path.display(),
            short.unwrap_or_else(|| "rank 0 found no room for it".into())
        ));
    }
    let rows_written = write_rows_of_all(comm, &tmp, ck, rows_of);
    let written = rows_written.and_then(|()| {
        let r = if root {
            finish_file(&tmp, ck).and_then(|()| {
                std::fs::File::open(&tmp)
                    .and_then(|f| f.sync_all())
                    .and_then(|()| std::fs::rename(&tmp, path))
                    .map_err(|x| format!("checkpoint {}: {x}", path.display()))
            })
        } else {
            Ok(())
        };
        let ok = comm.all_ok(r.is_ok());
        match r {
            Ok(()) if !ok => Err(format!(
                "checkpoint {}: rank 0 could not finish it",
                path.display()
            )),
            r => r,
        }
    });
    if let Err(e) = written {
        let mut e = e;
        if root {
            // a write through MPI-IO loses the system's reason: say it if the disk is full
            if let Some(full) = no_room(&tmp) {
                e = format!("{e} ({full})");
            }
            let _ = std::fs::remove_file(&tmp);
        }
        return Err(format!("{e}; the previous checkpoint, if any, is kept"));
    }
    if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty() && root) {
        let _ = std::fs::File::open(dir).and_then(|d| d.sync_all());
    }
    Ok(())
}

/// Why a checkpoint at `path` of `rows` (particles, histories) cannot fit on its disk, if it
/// clearly cannot: it needs the size of the checkpoint it replaces (or, for the first one,
/// of its particle and history rows) with a tenth and 64 KiB to spare, and the disk has less
/// free space than that (`statvfs`).
///
/// The rows are stored compressed (`pario::Storage`), so their uncompressed size is an
/// upper bound of what they take (gzip's worst case, incompressible data in stored blocks,
/// adds about 5 bytes per 64 KiB, well within the tenth); the previous checkpoint, written
/// the same way, remains the closer estimate once there is one.
fn short_of_room(path: &Path, rows: [u64; 2], words: usize) -> Option<String> {
    let previous = std::fs::metadata(path).map(|m| m.len()).unwrap_or(0);
    // a particle's row is its full state, a history's its two ids and its `words` (the
    // file keeps no order keys of a contact's particles), uncompressed
    let words =
        rows[0] * crate::particles::packed_words(words) as u64 + rows[1] * (2 + words as u64);
    let estimate = previous.max(8 * words);
    let needed = estimate + estimate / 10 + (64 << 10);
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    let free = free_bytes(dir)?;
    (free < needed).then(|| {
        format!(
            "No space left on device: about {} kB needed, {} kB free on the disk of {}",
            needed >> 10,
            free >> 10,
            dir.display()
        )
    })
}

/// Bytes free for an unprivileged user on the file system holding `dir`.
fn free_bytes(dir: &Path) -> Option<u64> {
    use std::os::unix::ffi::OsStrExt;
    let c = std::ffi::CString::new(dir.as_os_str().as_bytes()).ok()?;
    let mut st: libc::statvfs = unsafe { std::mem::zeroed() };
    // SAFETY: `c` is a NUL-terminated path and `st` a writable statvfs.
    let r = unsafe { libc::statvfs(c.as_ptr(), &mut st) };
    (r == 0).then(|| st.f_bavail as u64 * st.f_frsize as u64)
}

/// Bytes a failed checkpoint's directory is probed for ([`no_room`]).
const PROBE_BYTES: usize = 1 << 20;

/// Whether the disk holding `tmp` is full, tested (before `tmp` is removed) by writing
/// [`PROBE_BYTES`] beside it: the system's refusal (`No space left on device`), or `None`
/// if there is room.
fn no_room(tmp: &Path) -> Option<String> {
    use std::io::Write;
    let probe = tmp.with_extension("space-probe");
    let r = std::fs::File::create(&probe).and_then(|mut f| {
        f.write_all(&vec![0u8; PROBE_BYTES])?;
        f.sync_all()
    });
    let _ = std::fs::remove_file(&probe);
    r.err()
        .map(|e| format!("the disk has less than {} MB free: {e}", PROBE_BYTES >> 20))
}

/// Every rank's rows of the particles and contacts (gathered from `rows_of` one part at a
/// time, each freed once written) and its block of the window sums of `ck`, into a new
/// `tmp` (collective): the write's peak holds one of the three only.
fn write_rows_of_all(
    comm: &dyn Comm,
    tmp: &Path,
    ck: &Checkpoint,
    rows_of: &mut dyn Gather,
) -> Result<(), String> {
    let on = |e: String| format!("checkpoint {}: {e}", tmp.display());
    let f = pario::together(comm, pario::create(comm, tmp, true)).map_err(on)?;
    {
        let group = |name: &str| pario::together(comm, f.file.create_group(name)).map_err(on);
        let p = rows_of.particles();
        let rows = Rows::of(comm, p.len() as u64);
        let g = group("particles")?;
        let put = |name: &str, data: &[f64], cols: usize| {
            pario::write_rows(&f, &g, name, data, cols, rows, true)
                .map(drop)
                .map_err(on)
        };
        let ids: Vec<u64> = p.column_as(Field::Id, |x| x as u64);
        pario::write_rows(&f, &g, "id", &ids, 1, rows, true).map_err(on)?;
        drop(ids);
        let keys: Vec<u64> = p.column_as(Field::Key, |x| x as u64);
        pario::write_rows(&f, &g, "order_key", &keys, 1, rows, true).map_err(on)?;
        drop(keys);
        let species: Vec<u8> = p.column_as(Field::Species, |x| x as u8);
        pario::write_rows(&f, &g, "species", &species, 1, rows, true).map_err(on)?;
        drop(species);
        for (name, field) in COLUMNS_F64 {
            put(name, &p.column(field), p.width(field))?;
        }
        let fw = ck.history_words.max(FILE_WORDS_MIN);
        let wall = p.wall_history(fw);
        put("wall_history", &wall, WALLS * fw)?;
        drop(wall);
        drop(g);
        drop(p);
        let h = rows_of.histories();
        let rows = Rows::of(comm, h.len() as u64);
        let c = group("contacts")?;
        let a: Vec<u64> = h.iter().map(|x| x.a).collect();
        pario::write_rows(&f, &c, "id_a", &a, 1, rows, true).map_err(on)?;
        let b: Vec<u64> = h.iter().map(|x| x.b).collect();
        pario::write_rows(&f, &c, "id_b", &b, 1, rows, true).map_err(on)?;
        let hist: Vec<f64> = h.iter().flat_map(|x| x.h[..fw].iter().copied()).collect();
        pario::write_rows(&f, &c, "history", &hist, fw, rows, true).map_err(on)?;
        drop(hist);
        drop(c);
        drop(h);
        let d = group("diagnostics")?;
        write_sums_of_all(&f, &d, &ck.diag).map_err(on)?;
    }
    pario::close(f).map_err(on)
}

/// Rank 0's part, once every rank has closed `tmp`: the attributes and the diagnostics.
fn finish_file(tmp: &Path, ck: &Checkpoint) -> Result<(), String> {
    let e = err(tmp);
    let f = hdf5::File::with_options()
        .with_fapl(|p| p.libver_v110())
        .open_rw(tmp)
        .map_err(&e)?;
    let text = VarLenUnicode::from_str(&ck.case_text).map_err(|x| format!("checkpoint: {x}"))?;
    f.new_attr::<VarLenUnicode>()
        .create("case")
        .and_then(|a| a.write_scalar(&text))
        .map_err(&e)?;
    let version = VarLenUnicode::from_str(env!("CARGO_PKG_VERSION")).map_err(|x| x.to_string())?;
    f.new_attr::<VarLenUnicode>()
        .create("version")
        .and_then(|a| a.write_scalar(&version))
        .map_err(&e)?;
    for (name, v) in [("step", ck.step), ("samples", ck.samples)] {
        f.new_attr::<u64>()
            .create(name)
            .and_then(|a| a.write_scalar(&v))
            .map_err(&e)?;
    }
    write_diag(&f, &ck.diag).map_err(&e)?;
    f.flush().map_err(&e)?;
    f.close().map_err(&e)
}

/// Read a whole checkpoint, the window sums included (every dataset's checksum is verified).
pub fn read(path: &Path) -> Result<Checkpoint, String> {
    read_part(path, 0, 1, true)
}

/// Read rank `rank`'s share (of `size` ranks) of a checkpoint: rows `[r N/P, (r+1) N/P)`
/// of the particles and of the contacts (the checksums of the chunks read are verified),
/// and the small rest whole; not the window sums, of which each rank reads its own block
/// with [`read_sums`] (their length is in [`SavedSums::len`]).
pub fn read_share(path: &Path, rank: usize, size: usize) -> Result<Checkpoint, String> {
    read_part(path, rank, size, false)
}

fn read_part(path: &Path, rank: usize, size: usize, sums: bool) -> Result<Checkpoint, String> {
    let e = err(path);
    let f = hdf5::File::open(path).map_err(&e)?;
    let case_text: VarLenUnicode = f.attr("case").and_then(|a| a.read_scalar()).map_err(&e)?;
    let step: u64 = f.attr("step").and_then(|a| a.read_scalar()).map_err(&e)?;
    let samples: u64 = f
        .attr("samples")
        .and_then(|a| a.read_scalar())
        .map_err(&e)?;
    let rows_of = |names: &[(&str, usize)]| -> Result<u64, String> {
        let mut n = None;
        for &(name, cols) in names {
            let shape = f.dataset(name).map_err(&e)?.shape();
            let rows = shape.first().copied().unwrap_or(0) as u64;
            let width = shape.get(1).copied().unwrap_or(1);
            if width != cols || n.is_some_and(|n| n != rows) {
                return Err(format!(
                    "checkpoint {}: the datasets of {} differ in length",
                    path.display(),
                    name.split('/').next().unwrap_or(name)
                ));
            }
            n = Some(rows);
        }
        Ok(n.unwrap_or(0))
    };
    // history words per contact: the width of the wall histories (at most what a law keeps)
    let wall_width = f
        .dataset("particles/wall_history")
        .map_err(&e)?
        .shape()
        .get(1)
        .copied()
        .unwrap_or(0);
    let fw = wall_width / WALLS;
    if wall_width == 3 * (WALLS - 1) {
        return Err(format!(
            "checkpoint {}: it was written by a tumbler with three wall slots (before lifters); finish that run with the version that started it",
            path.display()
        ));
    }
    if wall_width % WALLS != 0 || !(FILE_WORDS_MIN..=HISTORY_MAX).contains(&fw) {
        return Err(format!(
            "checkpoint {}: its wall histories have {wall_width} columns, not {WALLS} slots of {FILE_WORDS_MIN} to {HISTORY_MAX} words",
            path.display()
        ));
    }
    let n = rows_of(&[
        ("particles/id", 1),
        ("particles/species", 1),
        ("particles/diameter", 1),
        ("particles/position", 3),
        ("particles/velocity", 3),
        ("particles/angular_velocity", 3),
        ("particles/force", 3),
        ("particles/torque", 3),
        ("particles/wall_history", WALLS * fw),
    ])?;
    let rows = Rows::share(n, rank, size);
    let get = |name: &str, cols: usize, rows: Rows| -> Result<Vec<f64>, String> {
        get_rows(&f, path, name, cols, rows)
    };
    // the rows of this share as records, filled one column at a time
    let id: Vec<u64> = get_rows(&f, path, "particles/id", 1, rows)?;
    if let Some(bad) = id
        .iter()
        .find(|&&i| i >= crate::physics::rough_wall::FIRST_ID)
    {
        return Err(format!(
            "checkpoint {}: particles/id: id {bad} is out of range (a run's ids are below 2^40); the file is not a tumbler checkpoint or is damaged",
            path.display()
        ));
    }
    let mut particles = Records::zeros(id.len(), fw);
    let filled = |r: Result<(), String>, name: &str| {
        r.map_err(|x| format!("checkpoint {}: particles/{name}: {x}", path.display()))
    };
    filled(particles.set_column(Field::Id, &id, |x| x as f64), "id")?;
    drop(id);
    // the order keys (`engine::order`); a checkpoint from before the spatial sort has none:
    // the particles keep the order of their ids until the next sort
    if f.link_exists("particles/order_key") {
        rows_of(&[("particles/id", 1), ("particles/order_key", 1)])?;
        let key: Vec<u64> = get_rows(&f, path, "particles/order_key", 1, rows)?;
        // keys travel as f64 words too (`engine::order` keeps them below 2^53)
        if let Some(bad) = key.iter().find(|&&k| k >= 1 << 53) {
            return Err(format!(
                "checkpoint {}: particles/order_key: key {bad} is out of range (keys are below 2^53); the file is not a tumbler checkpoint or is damaged",
                path.display()
            ));
        }
        filled(
            particles.set_column(Field::Key, &key, |x| x as f64),
            "order_key",
        )?;
    }
    let species: Vec<u8> = get_rows(&f, path, "particles/species", 1, rows)?;
    filled(
        particles.set_column(Field::Species, &species, f64::from),
        "species",
    )?;
    drop(species);
    for (name, field) in COLUMNS_F64 {
        let v = get(&format!("particles/{name}"), particles.width(field), rows)?;
        filled(particles.set_column(field, &v, |x| x), name)?;
    }
    let wall = get("particles/wall_history", WALLS * fw, rows)?;
    filled(
        particles.set_column(Field::WallHistory, &wall, |x| x),
        "wall_history",
    )?;
    drop(wall);
    let nh = rows_of(&[
        ("contacts/id_a", 1),
        ("contacts/id_b", 1),
        ("contacts/history", fw),
    ])?;
    let hrows = Rows::share(nh, rank, size);
    let a: Vec<u64> = get_rows(&f, path, "contacts/id_a", 1, hrows)?;
    let b: Vec<u64> = get_rows(&f, path, "contacts/id_b", 1, hrows)?;
    let h = get("contacts/history", fw, hrows)?;
    let histories = (0..a.len())
        .map(|i| {
            let mut w = History::default();
            w[..fw].copy_from_slice(&h[fw * i..fw * (i + 1)]);
            SavedContact::new(a[i], b[i], w)
        })
        .collect();
    if !f.link_exists("diagnostics") {
        return Err(format!(
            "checkpoint {}: it was written by a tumbler without windowed diagnostics (before 0.2); finish that run with the version that started it",
            path.display()
        ));
    }
    let diag = read_diag(&f, path, sums)?;
    Ok(Checkpoint {
        case_text: case_text.as_str().to_string(),
        step,
        samples,
        particles,
        histories,
        history_words: fw,
        n_particles: n,
        diag,
    })
}

/// Read `rows` of dataset `name` (`cols` values each); a checksum failure says the checkpoint
/// is damaged.
fn get_rows<T: H5Type>(
    f: &hdf5::File,
    path: &Path,
    name: &str,
    cols: usize,
    rows: Rows,
) -> Result<Vec<T>, String> {
    f.dataset(name)
        .and_then(|d| pario::read_rows(&d, cols, rows))
        .map_err(|e| read_error(path, name, &e))
}
