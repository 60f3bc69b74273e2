//! The run's HDF5 file, written by rank 0, except the O(N) datasets (`/particles`, the
//! snapshots), which every rank writes its rows of ([`write_together`]).
//!
//! Public layout (read by users' scripts; keep the names):
//! - `/axial/rotations` (T), `/axial/z` (Z), `/axial/volume_fraction` (T x S x Z),
//!   `/axial/count` (T x S x Z);
//! - root attributes `steps`, `rebuilds`, `migrations` (particles moved between ranks),
//!   `histories_migrated` (contact histories moved with them), and for a pour fill
//!   `pour_poured`, `pour_cut_height`, `pour_measured_fill`;
//! - `/particles/{id, species, diameter, position, velocity, angular_velocity}`, the final
//!   state sorted by id;
//! - root attributes `case` (effective case text), `version`, `git_hash`, `ranks`,
//!   `length_unit` and `time_unit` (what every `units` attribute is written in);
//! - `/species`, the species names (a string array, the dimension scale of every species
//!   axis; coordinates are attached to the axes they label, `output::dimscales`).
//!
//! The file is written under `NAME.partial` and renamed to `NAME` once complete, so a file
//! with the final name is always whole. It is flushed after every record and, before every
//! checkpoint, synced to disk ([`RunFile::sync`]), so that what a checkpoint counts is on
//! disk before the checkpoint is; a restart reads the whole file back before cutting it
//! ([`verify`]) and refuses one that a failed write (a full disk) left unreadable.

use super::diag_file::DiagLayout;
use super::pario::{self, ParFile, Rows};
use super::series::{self, describe};
use crate::comm::Comm;
use crate::diag::AxialSample;
use crate::particles::{Field, Records};
use hdf5::types::VarLenUnicode;
use ndarray::Array1;
use std::path::{Path, PathBuf};
use std::str::FromStr;

/// What identifies a run in its output.
#[derive(Debug, Clone)]
pub struct RunMeta {
    /// The effective case text.
    pub case_text: String,
    /// Number of MPI ranks.
    pub ranks: usize,
    /// Species names, in index order.
    pub species: Vec<String>,
}

/// An open output file being written.
pub struct RunFile {
    // the datasets first: fields are dropped in order, and the file is closed after them
    rotations: hdf5::Dataset,
    volume_fraction: hdf5::Dataset,
    count: hdf5::Dataset,
    file: hdf5::File,
    final_path: PathBuf,
    partial_path: PathBuf,
}

/// The name a file is written under until it is complete.
pub fn partial_path(path: &Path) -> PathBuf {
    let mut s = path.as_os_str().to_owned();
    s.push(".partial");
    PathBuf::from(s)
}

fn str_attr(loc: &hdf5::Location, name: &str, value: &str) -> hdf5::Result<()> {
    let v =
        VarLenUnicode::from_str(value).map_err(|e| hdf5::Error::from(e.to_string().as_str()))?;
    loc.new_attr::<VarLenUnicode>()
        .create(name)?
        .write_scalar(&v)
}

impl RunFile {
    /// Create the file (as `path.partial`) with its metadata and empty axial series over the
    /// slice centres `z`.
    pub fn create(
        path: &Path,
        meta: &RunMeta,
        z: &[f64],
        layout: &DiagLayout,
    ) -> hdf5::Result<Self> {
        let partial_path = partial_path(path);
        let file = hdf5::File::create(&partial_path)?;
        str_attr(&file, "case", &meta.case_text)?;
        str_attr(&file, "version", env!("CARGO_PKG_VERSION"))?;
        str_attr(&file, "git_hash", crate::GIT_HASH)?;
        file.new_attr::<u64>()
            .create("ranks")?
            .write_scalar(&(meta.ranks as u64))?;
        // every dataset's `units` is written in these (series::describe)
        layout.units.write(&file)?;
        let names = meta.species.join(",");
        let axial = file.create_group("axial")?;
        str_attr(&axial, "species", &names)?;
        let (ns, nz) = (meta.species.len(), z.len());
        let zs = axial
            .new_dataset_builder()
            .with_data(&Array1::from(z.to_vec()))
            .create("z")?;
        describe(&zs, LENGTH, "axial slice centres")?;
        let rotations = series::create::<f64>(
            &axial,
            "rotations",
            &[],
            "rotations",
            "time of each axial sample, in drum rotations since time zero",
        )?;
        let volume_fraction = series::create::<f64>(&axial, "volume_fraction", &[ns, nz], "-", "share of the particle volume in the slice held by each species, <C_s>(z) (axes: sample, species, slice); NaN where the slice is empty")?;
        let count = series::create::<u64>(&axial, "count", &[ns, nz], "-", "particles of each species whose centre lies in the slice (axes: sample, species, slice)")?;
        let species: Vec<&str> = meta.species.iter().map(String::as_str).collect();
        super::diag_file::names(
            &file,
            "species",
            &species,
            "species names, in case order (index = species index)",
        )?;
        super::diag_file::create(&file, layout)?;
        super::diag_file::label_axes(&file)?;
        Ok(RunFile {
            file,
            final_path: path.to_path_buf(),
            partial_path,
            rotations,
            volume_fraction,
            count,
        })
    }

    /// Reopen the output of an interrupted (or finished) run to continue it from a
    /// checkpoint: the file is first read back whole ([`verify`]), then the axial series are
    /// cut back to its first `samples` samples and what a finished run added (`/particles`,
    /// end-of-run statistics) is removed; the root attribute `ranks` becomes `ranks`. Also
    /// returns the volume fractions of species `big` kept, for the space-time plot.
    pub fn reopen(
        path: &Path,
        samples: usize,
        big: usize,
        ranks: usize,
    ) -> Result<(Self, Vec<Vec<f64>>), String> {
        let partial_path = partial_path(path);
        let existing = if partial_path.exists() {
            partial_path.clone()
        } else {
            path.to_path_buf()
        };
        verify(&existing).map_err(|e| {
            format!(
                "the output {} cannot be read back ({e}); a write to it failed (a full disk?) after its last checkpoint and left it damaged, so it cannot be continued. The checkpoint itself is intact: continue into a new file with -o OTHER.h5 --new-output (it will hold only the continuation)",
                existing.display()
            )
        })?;
        let on = |e: hdf5::Error| format!("{}: {e}", existing.display());
        if existing != partial_path {
            std::fs::rename(path, &partial_path).map_err(|e| {
                format!(
                    "cannot rename {} to {}: {e}",
                    path.display(),
                    partial_path.display()
                )
            })?;
        }
        let file = hdf5::File::open_rw(&partial_path).map_err(on)?;
        if !file.link_exists("slices") || !file.link_exists("axial/mean_axial_velocity") {
            return Err(format!(
                "{}: it was written by a tumbler without windowed diagnostics (before 0.2); finish that run with the version that started it",
                partial_path.display()
            ));
        }
        let on = |e: hdf5::Error| format!("{}: {e}", partial_path.display());
        if file.link_exists("particles") {
            file.unlink("particles").map_err(on)?;
        }
        let names = file.attr_names().map_err(on)?;
        for a in [
            "steps",
            "rebuilds",
            "migrations",
            "histories_migrated",
            "peak_rss_bytes_per_rank",
            "ranks",
        ] {
            if names.iter().any(|n| n == a) {
                file.delete_attr(a).map_err(on)?;
            }
        }
        file.new_attr::<u64>()
            .create("ranks")
            .and_then(|a| a.write_scalar(&(ranks as u64)))
            .map_err(on)?;
        let rotations = file.dataset("axial/rotations").map_err(on)?;
        let volume_fraction = file.dataset("axial/volume_fraction").map_err(on)?;
        let count = file.dataset("axial/count").map_err(on)?;
        let shape = volume_fraction.shape();
        let (ns, nz) = (shape[1], shape[2]);
        if shape[0] < samples {
            return Err(format!(
                "{}: it holds {} axial samples, fewer than the checkpoint's {samples}: it is not the output of the run that wrote the checkpoint",
                partial_path.display(),
                shape[0]
            ));
        }
        let axial = file.group("axial").map_err(on)?;
        for name in axial.member_names().map_err(on)? {
            let ds = axial.dataset(&name).map_err(on)?;
            if ds.is_chunked() {
                super::series::truncate(&ds, samples).map_err(on)?;
            }
        }
        let vf: Vec<f64> = volume_fraction.read_raw().map_err(on)?;
        let columns = (0..samples)
            .map(|t| vf[(t * ns + big) * nz..(t * ns + big + 1) * nz].to_vec())
            .collect();
        Ok((
            RunFile {
                file,
                final_path: path.to_path_buf(),
                partial_path,
                rotations,
                volume_fraction,
                count,
            },
            columns,
        ))
    }

    /// Put everything written so far on disk (HDF5's buffers, then the file's), so that a
    /// checkpoint written next counts only records that are there.
    pub fn sync(&self) -> Result<(), String> {
        let path = &self.partial_path;
        self.file
            .flush()
            .map_err(|e| e.to_string())
            .and_then(|()| {
                std::fs::File::open(path)
                    .and_then(|f| f.sync_all())
                    .map_err(|e| e.to_string())
            })
            .map_err(|e| format!("output {}: cannot be written to disk: {e}", path.display()))
    }

    /// Append one axial sample taken at `rotations`, with its band count.
    pub fn append(&mut self, rotations: f64, s: &AxialSample, bands: u64) -> hdf5::Result<()> {
        series::append(&self.rotations, &[rotations])?;
        series::append(&self.volume_fraction, &s.volume_fraction)?;
        series::append(&self.count, &s.count)?;
        super::diag_file::append_axial(&self.file, &s.mean_axial_velocity, bands)?;
        // on disk after every sample, so that a job killed later leaves a readable file
        self.file.flush()
    }

    /// The open file, for the diagnostics' writers.
    pub fn file(&self) -> &hdf5::File {
        &self.file
    }

    /// Close the file (keeping its name) so that every rank can open it together.
    fn suspend(self) -> Result<(PathBuf, PathBuf), String> {
        let on = |e: hdf5::Error| format!("output {}: {e}", self.partial_path.display());
        self.file.flush().map_err(on)?;
        let RunFile {
            file,
            final_path,
            partial_path,
            rotations,
            volume_fraction,
            count,
        } = self;
        drop((rotations, volume_fraction, count));
        file.close()
            .map_err(|e| format!("output {}: {e}", partial_path.display()))?;
        Ok((final_path, partial_path))
    }

    /// Open again a file closed by [`RunFile::suspend`].
    fn resume(final_path: PathBuf, partial_path: PathBuf) -> Result<Self, String> {
        let on = |e: hdf5::Error| format!("output {}: {e}", partial_path.display());
        let file = hdf5::File::open_rw(&partial_path).map_err(on)?;
        let rotations = file.dataset("axial/rotations").map_err(on)?;
        let volume_fraction = file.dataset("axial/volume_fraction").map_err(on)?;
        let count = file.dataset("axial/count").map_err(on)?;
        Ok(RunFile {
            file,
            final_path,
            partial_path,
            rotations,
            volume_fraction,
            count,
        })
    }
}

/// Write into the run's output `output` with every rank (all ranks call this together;
/// rank 0 holds the open `file`): rank 0 closes it, every rank opens it (MPI-IO), `write`
/// writes each rank's part, every rank closes it and rank 0 opens it again. Any failure, on
/// any rank, is returned on every rank.
pub fn write_together(
    comm: &dyn Comm,
    output: &Path,
    file: &mut Option<RunFile>,
    write: impl FnOnce(&ParFile) -> Result<(), String>,
) -> Result<(), String> {
    let suspended = file.take().map(RunFile::suspend).transpose();
    let names = match suspended {
        Ok(names) if comm.all_ok(true) => names,
        Ok(_) => return Err("rank 0 could not close the output for the ranks to write".into()),
        Err(e) => {
            comm.all_ok(false);
            return Err(e);
        }
    };
    let partial = partial_path(output);
    let on = |e: String| format!("output {}: {e}", partial.display());
    let written = pario::together(comm, pario::open_rw(comm, &partial))
        .map_err(on)
        .and_then(|f| {
            let w = write(&f).map_err(on);
            let c = pario::close(f).map_err(on);
            w.and(c)
        });
    let reopened = names
        .map(|(fin, part)| RunFile::resume(fin, part).map(|f| *file = Some(f)))
        .transpose();
    let ok = comm.all_ok(reopened.is_ok());
    written?;
    reopened?;
    if ok {
        Ok(())
    } else {
        Err("rank 0 could not open the output again".into())
    }
}

/// Write particle states as `id, species, diameter, position, velocity, angular_velocity`
/// datasets in `g` (all ranks together): each rank's `states` (its share, sorted by id, the
/// ranks' shares in increasing order of id) are its rows.
pub fn write_states(
    comm: &dyn Comm,
    f: &ParFile,
    g: &hdf5::Group,
    states: &Records,
) -> Result<(), String> {
    let rows = Rows::of(comm, states.len() as u64);
    let described = |ds: hdf5::Dataset, name: &str, units: &str, def: &str| {
        pario::together(comm, describe(&ds, units, def)).map_err(|e| format!("{name}: {e}"))
    };
    let id: Vec<u64> = states.column_as(Field::Id, |x| x as u64);
    let ds = pario::write_rows(f, g, "id", &id, 1, rows, false)?;
    drop(id);
    described(
        ds,
        "id",
        "-",
        "particle id, stable for the whole run (rows sorted by it)",
    )?;
    let species: Vec<u8> = states.column_as(Field::Species, |x| x as u8);
    let ds = pario::write_rows(f, g, "species", &species, 1, rows, false)?;
    drop(species);
    described(ds, "species", "-", "species index, in case order")?;
    let diameter = states.column(Field::Diameter);
    let ds = pario::write_rows(f, g, "diameter", &diameter, 1, rows, false)?;
    drop(diameter);
    described(ds, "diameter", LENGTH, "particle diameter")?;
    for (name, field, units, def) in [
        (
            "position",
            Field::Position,
            LENGTH,
            "centre, lab frame (z wrapped into the drum at periodic ends)",
        ),
        (
            "velocity",
            Field::Velocity,
            "length/time",
            "velocity, lab frame",
        ),
        (
            "angular_velocity",
            Field::AngularVelocity,
            "1/time",
            "angular velocity, lab frame",
        ),
    ] {
        let v = states.column(field);
        let ds = pario::write_rows(f, g, name, &v, 3, rows, false)?;
        drop(v);
        described(ds, name, units, def)?;
    }
    Ok(())
}

/// Write the final particle state under `/particles` (all ranks together, each its share
/// as [`write_states`]) into the run's open `output`.
pub fn write_particles(
    comm: &dyn Comm,
    output: &Path,
    file: &mut Option<RunFile>,
    states: &Records,
) -> Result<(), String> {
    write_together(comm, output, file, |f| {
        let g = pario::together(comm, f.file.create_group("particles"))?;
        write_states(comm, f, &g, states)
    })
}

/// Open the run file at `path` read-only and read every dataset of its series back whole
/// (`/axial`, `/slices`, `/fields`, `/paths`, `/balance`, earlier load-balance segments) and
/// the attributes of its snapshots: what a restart relies on before it cuts the file.
pub fn verify(path: &Path) -> hdf5::Result<()> {
    let file = hdf5::File::open(path)?;
    let mut groups = Vec::new();
    for name in [
        "axial",
        "slices",
        "fields",
        "paths",
        "balance",
        "balance_earlier",
    ] {
        if file.link_exists(name) {
            groups.push(file.group(name)?);
        }
    }
    while let Some(g) = groups.pop() {
        for ds in g.datasets()? {
            let dt = ds.dtype()?;
            if dt.is::<f64>() {
                ds.read_raw::<f64>()?;
            } else if dt.is::<f32>() {
                ds.read_raw::<f32>()?;
            } else if dt.is::<u64>() {
                ds.read_raw::<u64>()?;
            } else if dt.is::<u8>() {
                ds.read_raw::<u8>()?;
            }
        }
        groups.extend(g.groups()?);
    }
    super::diag_file::snapshots(&file)?;
    Ok(())
}

/// Units of lengths (written as the file's unit of length, its root attribute
/// `length_unit`).
const LENGTH: &str = "length";

impl RunFile {
    /// Record a number as a root attribute (run statistics: `steps`, `rebuilds`,
    /// `migrations`, `histories_migrated`; pour: `pour_poured`, `pour_cut_height`,
    /// `pour_measured_fill`).
    pub fn write_number<T: hdf5::H5Type>(&self, name: &str, value: T) -> hdf5::Result<()> {
        self.file.new_attr::<T>().create(name)?.write_scalar(&value)
    }

    /// Close the file and give it its final name.
    pub fn finish(self) -> std::io::Result<PathBuf> {
        self.file.flush().map_err(std::io::Error::other)?;
        drop(self.rotations);
        drop(self.volume_fraction);
        drop(self.count);
        drop(self.file);
        std::fs::rename(&self.partial_path, &self.final_path)?;
        Ok(self.final_path)
    }
}
