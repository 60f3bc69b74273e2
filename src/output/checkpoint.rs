//! Checkpoints: the complete state of a run, from which `tumbler run --restart` continues
//! bit-identically to a run never interrupted, on the same or another number of ranks.
//!
//! One HDF5 file, written by rank 0: every mobile particle (id, species, diameter, position,
//! velocity, spin, the force and torque of the last evaluation, which the next half kick
//! uses, and its wall histories), every contact history keyed by the pair's ids, the step,
//! the number of axial samples written, the case text, and the diagnostics' windows in
//! progress (exact sums, so a restart averages the same bits). It is written as `NAME.tmp`,
//! flushed to disk and renamed over `NAME`, so the previous checkpoint stays whole until the
//! new one is. (The run draws no random numbers after the initial state, so there is no
//! generator state to keep.)

use crate::diag::windows::AngleSums;
use crate::engine::neighbor::SavedHistory;
use crate::particles::ParticleState;
use crate::physics::materials::WALLS;
use hdf5::types::VarLenUnicode;
use ndarray::{Array1, Array2};
use std::path::{Path, PathBuf};
use std::str::FromStr;

/// The state a run continues from.
#[derive(Debug, Clone)]
pub struct Checkpoint {
    /// The effective case text of the run that wrote it.
    pub case_text: String,
    /// Steps taken since time zero.
    pub step: u64,
    /// Axial samples written to the output so far.
    pub samples: u64,
    /// Mobile particles, sorted by id.
    pub particles: Vec<ParticleState>,
    /// Contact histories, sorted by ids.
    pub histories: SavedHistory,
    /// The windows in progress and the particles followed.
    pub diag: DiagState,
}

/// The diagnostics' state a restart needs: the sums of the windows in progress (gathered on
/// rank 0) and the ids of the particles whose paths are recorded.
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
}

/// The sums of one window in progress.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct SavedSums {
    /// Samples accumulated.
    pub samples: u64,
    /// Sum of their frame angles, degrees.
    pub angle_sum: f64,
    /// Fixed-point sums (see `diag::grid::BinnedSums`).
    pub sums: Vec<i128>,
}

fn write_diag(f: &hdf5::File, d: &DiagState) -> hdf5::Result<()> {
    let g = f.create_group("diagnostics")?;
    for (name, s) in [("slices", &d.slices), ("fields", &d.fields)] {
        let (samples, angle_sum, sums) = (&s.samples, &s.angle_sum, &s.sums);
        // one half at a time, to keep the checkpoint's memory peak low
        let hi: Vec<i64> = sums.iter().map(|&x| (x >> 64) as i64).collect();
        g.new_dataset_builder()
            .with_data(&hi)
            .create(format!("{name}_hi").as_str())?;
        drop(hi);
        let lo: Vec<u64> = sums.iter().map(|&x| x as u64).collect();
        g.new_dataset_builder()
            .with_data(&lo)
            .create(format!("{name}_lo").as_str())?;
        g.new_attr::<u64>()
            .create(format!("{name}_samples").as_str())?
            .write_scalar(samples)?;
        g.new_attr::<f64>()
            .create(format!("{name}_angle_sum").as_str())?
            .write_scalar(angle_sum)?;
    }
    let a = &d.angles;
    g.new_dataset_builder()
        .with_data(&a.slice_sum)
        .create("angle_slice_sum")?;
    g.new_dataset_builder()
        .with_data(&a.slice_n)
        .create("angle_slice_n")?;
    g.new_attr::<f64>()
        .create("angle_drum_sum")?
        .write_scalar(&a.drum_sum)?;
    g.new_attr::<u64>()
        .create("angle_drum_n")?
        .write_scalar(&a.drum_n)?;
    g.new_dataset_builder()
        .with_data(&d.path_ids)
        .create("path_ids")?;
    Ok(())
}

fn read_diag(f: &hdf5::File) -> hdf5::Result<DiagState> {
    let g = f.group("diagnostics")?;
    let sums = |name: &str| -> hdf5::Result<SavedSums> {
        let hi: Vec<i64> = g.dataset(&format!("{name}_hi"))?.read_raw()?;
        let lo: Vec<u64> = g.dataset(&format!("{name}_lo"))?.read_raw()?;
        let v = hi
            .iter()
            .zip(&lo)
            .map(|(&h, &l)| ((h as i128) << 64) | l as i128)
            .collect();
        Ok(SavedSums {
            samples: g.attr(&format!("{name}_samples"))?.read_scalar()?,
            angle_sum: g.attr(&format!("{name}_angle_sum"))?.read_scalar()?,
            sums: v,
        })
    };
    Ok(DiagState {
        slices: sums("slices")?,
        fields: sums("fields")?,
        angles: AngleSums {
            slice_sum: g.dataset("angle_slice_sum")?.read_raw()?,
            slice_n: g.dataset("angle_slice_n")?.read_raw()?,
            drum_sum: g.attr("angle_drum_sum")?.read_scalar()?,
            drum_n: g.attr("angle_drum_n")?.read_scalar()?,
        },
        path_ids: g.dataset("path_ids")?.read_raw()?,
    })
}

/// The checkpoint written next to an output file (`NAME.h5` -> `NAME.ckpt.h5`).
pub fn checkpoint_path(output: &Path) -> PathBuf {
    output.with_extension("ckpt.h5")
}

fn err(path: &Path) -> impl Fn(hdf5::Error) -> String + '_ {
    move |e| format!("checkpoint {}: {e}", path.display())
}

/// Write `ck` to `path` atomically.
pub fn write(path: &Path, ck: &Checkpoint) -> Result<(), String> {
    let mut tmp = path.as_os_str().to_owned();
    tmp.push(".tmp");
    let tmp = PathBuf::from(tmp);
    {
        let e = err(&tmp);
        let f = hdf5::File::create(&tmp).map_err(&e)?;
        let text =
            VarLenUnicode::from_str(&ck.case_text).map_err(|x| format!("checkpoint: {x}"))?;
        f.new_attr::<VarLenUnicode>()
            .create("case")
            .and_then(|a| a.write_scalar(&text))
            .map_err(&e)?;
        let version =
            VarLenUnicode::from_str(env!("CARGO_PKG_VERSION")).map_err(|x| x.to_string())?;
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
        let p = &ck.particles;
        let n = p.len();
        let g = f.create_group("particles").map_err(&e)?;
        let rows = |k: usize, get: &dyn Fn(&ParticleState) -> Vec<f64>| {
            Array2::from_shape_vec((n, k), p.iter().flat_map(get).collect()).expect("rows")
        };
        g.new_dataset_builder()
            .with_data(&Array1::from_iter(p.iter().map(|s| s.id)))
            .create("id")
            .map_err(&e)?;
        g.new_dataset_builder()
            .with_data(&Array1::from_iter(p.iter().map(|s| s.species)))
            .create("species")
            .map_err(&e)?;
        g.new_dataset_builder()
            .with_data(&Array1::from_iter(p.iter().map(|s| s.diameter)))
            .create("diameter")
            .map_err(&e)?;
        for (name, get) in [
            (
                "position",
                &(|s: &ParticleState| s.x.to_vec()) as &dyn Fn(&ParticleState) -> Vec<f64>,
            ),
            ("velocity", &|s: &ParticleState| s.v.to_vec()),
            ("angular_velocity", &|s: &ParticleState| s.w.to_vec()),
            ("force", &|s: &ParticleState| s.f.to_vec()),
            ("torque", &|s: &ParticleState| s.t.to_vec()),
        ] {
            g.new_dataset_builder()
                .with_data(&rows(3, get))
                .create(name)
                .map_err(&e)?;
        }
        let wall = rows(3 * WALLS, &|s: &ParticleState| {
            s.wall_hist.iter().flatten().copied().collect()
        });
        g.new_dataset_builder()
            .with_data(&wall)
            .create("wall_history")
            .map_err(&e)?;
        let h = &ck.histories;
        let c = f.create_group("contacts").map_err(&e)?;
        c.new_dataset_builder()
            .with_data(&Array1::from_iter(h.iter().map(|x| x.0)))
            .create("id_a")
            .map_err(&e)?;
        c.new_dataset_builder()
            .with_data(&Array1::from_iter(h.iter().map(|x| x.1)))
            .create("id_b")
            .map_err(&e)?;
        let hist = Array2::from_shape_vec((h.len(), 3), h.iter().flat_map(|x| x.2).collect())
            .expect("rows");
        c.new_dataset_builder()
            .with_data(&hist)
            .create("history")
            .map_err(&e)?;
        write_diag(&f, &ck.diag).map_err(&e)?;
        f.flush().map_err(&e)?;
    }
    let io = |x: std::io::Error| format!("checkpoint {}: {x}", path.display());
    std::fs::File::open(&tmp)
        .and_then(|f| f.sync_all())
        .map_err(io)?;
    std::fs::rename(&tmp, path).map_err(io)?;
    if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
        let _ = std::fs::File::open(dir).and_then(|d| d.sync_all());
    }
    Ok(())
}

/// Read a checkpoint.
pub fn read(path: &Path) -> Result<Checkpoint, String> {
    let e = err(path);
    let f = hdf5::File::open(path).map_err(&e)?;
    let case_text: VarLenUnicode = f.attr("case").and_then(|a| a.read_scalar()).map_err(&e)?;
    let step: u64 = f.attr("step").and_then(|a| a.read_scalar()).map_err(&e)?;
    let samples: u64 = f
        .attr("samples")
        .and_then(|a| a.read_scalar())
        .map_err(&e)?;
    let ds = |name: &str| f.dataset(name).map_err(&e);
    let id: Vec<u64> = ds("particles/id")?.read_raw().map_err(&e)?;
    let species: Vec<u8> = ds("particles/species")?.read_raw().map_err(&e)?;
    let diameter: Vec<f64> = ds("particles/diameter")?.read_raw().map_err(&e)?;
    let v3 = |name: &str| -> Result<Vec<f64>, String> {
        ds(&format!("particles/{name}"))?.read_raw().map_err(&e)
    };
    let (x, v, w, force, torque) = (
        v3("position")?,
        v3("velocity")?,
        v3("angular_velocity")?,
        v3("force")?,
        v3("torque")?,
    );
    let wall = v3("wall_history")?;
    let n = id.len();
    if [species.len(), diameter.len()].iter().any(|&k| k != n)
        || [x.len(), v.len(), w.len(), force.len(), torque.len()]
            .iter()
            .any(|&k| k != 3 * n)
        || wall.len() != 3 * WALLS * n
    {
        return Err(format!(
            "checkpoint {}: the particle datasets differ in length",
            path.display()
        ));
    }
    let t3 = |a: &[f64], i: usize| [a[3 * i], a[3 * i + 1], a[3 * i + 2]];
    let particles = (0..n)
        .map(|i| {
            let mut s = ParticleState::new(
                id[i],
                species[i],
                diameter[i],
                t3(&x, i),
                t3(&v, i),
                t3(&w, i),
            );
            s.f = t3(&force, i);
            s.t = t3(&torque, i);
            for k in 0..WALLS {
                s.wall_hist[k] = t3(&wall[3 * WALLS * i..], k);
            }
            s
        })
        .collect();
    let a: Vec<u64> = ds("contacts/id_a")?.read_raw().map_err(&e)?;
    let b: Vec<u64> = ds("contacts/id_b")?.read_raw().map_err(&e)?;
    let h: Vec<f64> = ds("contacts/history")?.read_raw().map_err(&e)?;
    if b.len() != a.len() || h.len() != 3 * a.len() {
        return Err(format!(
            "checkpoint {}: the contact datasets differ in length",
            path.display()
        ));
    }
    let histories = (0..a.len()).map(|i| (a[i], b[i], t3(&h, i))).collect();
    if !f.link_exists("diagnostics") {
        return Err(format!(
            "checkpoint {}: it was written by a tumbler without windowed diagnostics (before 0.2); finish that run with the version that started it",
            path.display()
        ));
    }
    let diag = read_diag(&f).map_err(&e)?;
    Ok(Checkpoint {
        case_text: case_text.as_str().to_string(),
        step,
        samples,
        particles,
        histories,
        diag,
    })
}
