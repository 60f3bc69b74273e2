//! The diagnostics' part of the run's HDF5 file: `/slices`, `/fields`, `/paths`,
//! `/snapshots` and the per-sample additions to `/axial` (layout in `docs/diagnostics.md`).

use super::series::{self, str_attr};
use crate::diag::fields::FieldWindow;
use crate::diag::{BandRule, SliceRecord};
use crate::engine::sim::BalanceCheck;
use hdf5::types::VarLenUnicode;
use hdf5::{File, Group};
use std::str::FromStr;

/// Shapes of the diagnostics' datasets.
#[derive(Debug, Clone)]
pub struct DiagLayout {
    /// Number of species.
    pub ns: usize,
    /// Axial slice centres.
    pub z: Vec<f64>,
    /// Cross-section bin centres along the surface frame's `x` and `y`.
    pub x: Vec<f64>,
    /// See `x`.
    pub y: Vec<f64>,
    /// Axial centres of the field bins.
    pub zf: Vec<f64>,
    /// Ids of the particles whose paths are recorded.
    pub path_ids: Vec<u64>,
    /// The band rule and the species counted.
    pub bands: BandRule,
    /// Index of the species whose bands are counted.
    pub band_species: usize,
    /// Samples in a whole per-slice window (a trailing partial window has fewer).
    pub samples_per_window: u64,
    /// Samples in a whole field window.
    pub samples_per_field_window: u64,
    /// The file's units of length and time.
    pub units: series::Units,
}

const LEN: &str = "length";
const VEL: &str = "length/time";

/// Write the names `values` as the 1-D string dataset `name` of `g` (`units` `-`).
pub fn names(
    g: &Group,
    name: &str,
    values: &[&str],
    definition: &str,
) -> hdf5::Result<hdf5::Dataset> {
    let v = values
        .iter()
        .map(|s| VarLenUnicode::from_str(s).map_err(|e| hdf5::Error::from(e.to_string().as_str())))
        .collect::<hdf5::Result<Vec<_>>>()?;
    let ds = g.new_dataset_builder().with_data(&v).create(name)?;
    series::describe(&ds, "-", definition)?;
    Ok(ds)
}

fn group(file: &File, name: &str) -> hdf5::Result<Group> {
    if file.link_exists(name) {
        file.group(name)
    } else {
        file.create_group(name)
    }
}

/// Create every diagnostics dataset, empty.
pub fn create(file: &File, l: &DiagLayout) -> hdf5::Result<()> {
    let (ns, nz, nx, ny, nzf) = (l.ns, l.z.len(), l.x.len(), l.y.len(), l.zf.len());
    let axial = group(file, "axial")?;
    series::create::<f64>(&axial, "mean_axial_velocity", &[ns, nz], VEL,
        "mean axial velocity w of the species' particles whose centre lies in the slice (axes: sample, species, slice); NaN where there are none")?;
    let bands = series::create::<u64>(&axial, "bands", &[], "-",
        "number of segregation bands in the big species' volume-fraction profile (docs/diagnostics.md: departure from the drum mean beyond `threshold`, runs of at least `min_slices` slices, wrapped when `periodic`)")?;
    bands
        .new_attr::<f64>()
        .create("threshold")?
        .write_scalar(&l.bands.threshold)?;
    bands
        .new_attr::<u64>()
        .create("min_slices")?
        .write_scalar(&(l.bands.min_slices as u64))?;
    bands
        .new_attr::<u64>()
        .create("periodic")?
        .write_scalar(&(l.bands.periodic as u64))?;
    bands
        .new_attr::<u64>()
        .create("species")?
        .write_scalar(&(l.band_species as u64))?;

    let s = group(file, "slices")?;
    str_attr(&s, "definition", "per-slice diagnostics averaged over windows of diagnostics.window rotations (thesis 4.5, appendix A)")?;
    series::fixed(&s, "z", &[nz], &l.z, LEN, "axial slice centres")?;
    series::fixed(
        &s,
        "x",
        &[nx],
        &l.x,
        LEN,
        "streamwise bin centres of the cross-section (surface frame)",
    )?;
    series::fixed(
        &s,
        "y",
        &[ny],
        &l.y,
        LEN,
        "surface-normal bin centres of the cross-section (surface frame)",
    )?;
    window_bounds(&s, l.samples_per_window)?;
    for (name, row, units, def) in [
        ("angle", vec![nz], "degrees", "dynamic angle of repose per slice, mean over the window's samples"),
        ("angle_drum", vec![], "degrees", "dynamic angle of repose of the whole drum, window mean"),
        ("concentration", vec![ns, nz], "-", "<C_s>: species' share of the particle volume in the slice over the window"),
        ("mean_axial_velocity", vec![ns, nz], VEL, "<w_s> = <C_s w_s>/<C_s>, volume-weighted mean axial velocity of the species"),
        ("mixture_axial_velocity", vec![nz], VEL, "<w>, volume-weighted mean axial velocity of all particles in the slice"),
        ("q_up", vec![ns, nz], "length^3/time", "upstream axial flow rate sum_i w_i n_i S_i V / 0.64 over the bins with x < split_x (thesis 4.5)"),
        ("q_down", vec![ns, nz], "length^3/time", "downstream axial flow rate: the same over the bins with x >= split_x"),
        ("q_up_mixture", vec![nz], "length^3/time", "q_up summed over species"),
        ("q_down_mixture", vec![nz], "length^3/time", "q_down summed over species"),
        ("relative_flux", vec![ns, nz], VEL, "<C_s>(<w_s> - <w>)"),
        ("gradient", vec![ns, nz], "1/length", "d<C_s>/dz by central differences (wrapped at periodic ends, one-sided at caps)"),
        ("diffusivity", vec![ns, nz], "length^2/time", "K from <C_s>(<w_s> - <w>) = -K d<C_s>/dz (thesis appendix A); NaN where the gradient is zero"),
        ("split_x", vec![nz, ny], LEN, "streamwise position separating upstream (x < split_x) from downstream bins, per slice and depth row; NaN for empty rows"),
    ] {
        series::create_mean(&s, name, &row, units, def)?;
    }
    series::create::<u8>(&s, "split_by_sign", &[nz, ny], "-",
        "1 where split_x is the sign change of the mixture's axial velocity along x nearest x = 0 (the thesis' rule), 0 where w keeps its sign and x = 0 is used")?;

    let f = group(file, "fields")?;
    str_attr(&f, "definition", "binned fields in the surface frame averaged over windows of diagnostics.fields.window rotations (thesis 2.2.3, ch. 3)")?;
    series::fixed(
        &f,
        "x",
        &[nx],
        &l.x,
        LEN,
        "streamwise bin centres (surface frame, down the free surface)",
    )?;
    series::fixed(
        &f,
        "y",
        &[ny],
        &l.y,
        LEN,
        "surface-normal bin centres (surface frame, out of the bed)",
    )?;
    series::fixed(&f, "z", &[nzf], &l.zf, LEN, "axial bin centres")?;
    names(
        &f,
        "component",
        &["u", "v", "w"],
        "components of velocity and velocity_drum: streamwise, surface-normal, axial",
    )?;
    names(
        &f,
        "rms_component",
        &["u_rms", "v_rms", "w_rms", "rms"],
        "components of rms",
    )?;
    window_bounds(&f, l.samples_per_field_window)?;
    let grid = |lead: usize| vec![lead, nx, ny, nzf];
    for (name, row, units, def) in [
        ("angle", vec![], "degrees", "mean angle of the surface frame over the window"),
        ("number_density", grid(ns), "1/length^3", "particles of each species per unit volume"),
        ("volume_fraction", grid(ns), "-", "particle volume of each species per bin volume (centre binning)"),
        ("velocity", grid(3), VEL, "mean (u, v, w) of all particles in the bin, lab frame, surface-frame components; NaN in empty bins"),
        ("velocity_drum", grid(3), VEL, "mean (u, v, w) in the drum frame (solid-body rotation removed)"),
        ("rms", grid(4), VEL, "u_rms, v_rms, w_rms of the drum-frame velocity about the bin mean, and sqrt(u_rms^2 + v_rms^2 + w_rms^2)"),
        ("axial_flux", grid(ns), "1/(length^2 time)", "n_s w_s: particles of each species crossing unit area along z per unit time"),
        ("u0", vec![], VEL, "drum-frame streamwise velocity at the free surface at the centre (x = 0, z = 0)"),
        ("surface", vec![nx, nzf], LEN, "y of the top of the highest bin with volume fraction >= 0.25"),
        ("boundary", vec![nx, nzf], LEN, "lower edge of the flowing layer: y where the drum-frame streamwise velocity falls to 0.05 u0 below the surface; NaN where the column does not flow"),
        ("depth", vec![nx, nzf], LEN, "flowing-layer depth: surface - boundary"),
    ] {
        if row.is_empty() {
            series::create::<f64>(&f, name, &row, units, def)?;
        } else {
            series::create_mean(&f, name, &row, units, def)?;
        }
    }

    if !l.path_ids.is_empty() {
        let p = group(file, "paths")?;
        series::fixed(
            &p,
            "id",
            &[l.path_ids.len()],
            &l.path_ids,
            "-",
            "ids of the particles followed",
        )?;
        series::create::<f64>(
            &p,
            "rotations",
            &[],
            "rotations",
            "time of each path sample",
        )?;
        let np = l.path_ids.len();
        series::create::<f64>(&p, "position", &[np, 3], LEN, "lab-frame position (axes: sample, particle, component); NaN if the particle does not exist")?;
        series::create::<f64>(
            &p,
            "velocity",
            &[np, 3],
            VEL,
            "lab-frame velocity (axes: sample, particle, component)",
        )?;
    }
    Ok(())
}

/// Make the coordinates dimension scales and attach them to the axes they label (layout in
/// `docs/diagnostics.md`): time (`/axial/rotations`, `/slices/rotations_end`,
/// `/fields/rotations_end`, `/paths/rotations`), `/species`, the slice and bin centres, and
/// the components of `/fields/velocity`, `velocity_drum` and `rms`.
pub fn label_axes(file: &File) -> hdf5::Result<()> {
    use super::dimscales::{label_group, make_scale};
    let species = file.dataset("species")?;
    make_scale(&species)?;
    let scale = |g: &Group, name: &str| -> hdf5::Result<hdf5::Dataset> {
        let ds = g.dataset(name)?;
        make_scale(&ds)?;
        Ok(ds)
    };
    let coords = [
        "z",
        "x",
        "y",
        "rotations",
        "rotations_end",
        "id",
        "component",
        "rms_component",
    ];
    let series = |name: &str| !coords.contains(&name);

    let axial = file.group("axial")?;
    let (t, z) = (scale(&axial, "rotations")?, scale(&axial, "z")?);
    label_group(&axial, &t, |n, _| if series(n) { vec![0] } else { vec![] })?;
    label_group(&axial, &z, |n, sh| {
        if series(n) && sh.len() == 3 {
            vec![2]
        } else {
            vec![]
        }
    })?;
    label_group(&axial, &species, |n, sh| {
        if series(n) && sh.len() == 3 {
            vec![1]
        } else {
            vec![]
        }
    })?;

    let s = file.group("slices")?;
    let (t, z, y) = (
        scale(&s, "rotations_end")?,
        scale(&s, "z")?,
        scale(&s, "y")?,
    );
    scale(&s, "x")?;
    let by_species = |n: &str| {
        [
            "concentration",
            "mean_axial_velocity",
            "q_up",
            "q_down",
            "relative_flux",
            "gradient",
            "diffusivity",
        ]
        .contains(&n)
    };
    label_group(&s, &t, |n, _| if series(n) { vec![0] } else { vec![] })?;
    label_group(&s, &z, |n, sh| match n {
        "split_x"
        | "split_by_sign"
        | "angle"
        | "mixture_axial_velocity"
        | "q_up_mixture"
        | "q_down_mixture" => vec![1],
        _ if by_species(n) && sh.len() == 3 => vec![2],
        _ => vec![],
    })?;
    label_group(&s, &y, |n, _| {
        if n == "split_x" || n == "split_by_sign" {
            vec![2]
        } else {
            vec![]
        }
    })?;
    label_group(
        &s,
        &species,
        |n, _| if by_species(n) { vec![1] } else { vec![] },
    )?;

    let f = file.group("fields")?;
    let (t, x, y, z) = (
        scale(&f, "rotations_end")?,
        scale(&f, "x")?,
        scale(&f, "y")?,
        scale(&f, "z")?,
    );
    let (comp, rms) = (scale(&f, "component")?, scale(&f, "rms_component")?);
    label_group(&f, &t, |n, _| if series(n) { vec![0] } else { vec![] })?;
    let grid = |sh: &[usize]| -> Vec<usize> {
        match sh.len() {
            5 => vec![2, 3, 4],
            3 => vec![1, 2],
            _ => vec![],
        }
    };
    label_group(&f, &x, |n, sh| match (series(n), sh.len()) {
        (true, 5) => vec![2],
        (true, 3) => vec![1],
        _ => vec![],
    })?;
    label_group(&f, &y, |n, sh| {
        if series(n) && sh.len() == 5 {
            vec![3]
        } else {
            vec![]
        }
    })?;
    label_group(&f, &z, |n, sh| match (series(n), grid(sh).as_slice()) {
        (true, [_, _, z]) => vec![*z],
        (true, [_, z]) => vec![*z],
        _ => vec![],
    })?;
    label_group(&f, &species, |n, _| {
        if ["number_density", "volume_fraction", "axial_flux"].contains(&n) {
            vec![1]
        } else {
            vec![]
        }
    })?;
    label_group(&f, &comp, |n, _| {
        if n == "velocity" || n == "velocity_drum" {
            vec![1]
        } else {
            vec![]
        }
    })?;
    label_group(&f, &rms, |n, _| if n == "rms" { vec![1] } else { vec![] })?;

    if file.link_exists("paths") {
        let p = file.group("paths")?;
        let (t, id) = (scale(&p, "rotations")?, scale(&p, "id")?);
        label_group(&p, &t, |n, _| if series(n) { vec![0] } else { vec![] })?;
        label_group(&p, &id, |n, _| {
            if series(n) && n != "rotations" {
                vec![1]
            } else {
                vec![]
            }
        })?;
    }
    Ok(())
}

/// Prepare the load-balance series for `ranks` slabs. A fresh run (`keep_until` is `None`)
/// creates `/balance`. A restart passes the rotations of its checkpoint: every record after
/// them is cut (in `/balance` and in the earlier segments); if the rank count changed, the
/// records so far (whose bounds have another width) move to `/balance_earlier/segment_K`
/// (K = 0, 1, ... in order) and a new `/balance` starts. Each segment has a `ranks`
/// attribute.
pub fn prepare_balance(file: &File, ranks: usize, keep_until: Option<f64>) -> hdf5::Result<()> {
    if let Some(until) = keep_until {
        if file.link_exists("balance_earlier") {
            let earlier = file.group("balance_earlier")?;
            let mut names = earlier.member_names()?;
            names.sort();
            for name in names {
                if cut_balance(&earlier.group(&name)?, until)? == 0 {
                    earlier.unlink(&name)?;
                }
            }
        }
        if file.link_exists("balance") {
            let kept = cut_balance(&file.group("balance")?, until)?;
            let same = file.dataset("balance/bounds")?.shape().get(1) == Some(&(ranks + 1));
            if same {
                // a file from before the bound was recorded: unknown for its checks so far
                if !file.link_exists("balance/imbalance_bound") {
                    create_bound(&file.group("balance")?)?;
                    for _ in 0..kept {
                        put(file, "balance/imbalance_bound", &[f64::NAN])?;
                    }
                }
                return Ok(());
            }
            if kept == 0 {
                file.unlink("balance")?;
            } else {
                let earlier = group(file, "balance_earlier")?;
                let k = earlier.member_names()?.len();
                file.relink("balance", &format!("balance_earlier/segment_{k}"))?;
            }
        }
    } else if file.link_exists("balance") {
        file.unlink("balance")?;
    }
    let g = group(file, "balance")?;
    str_attr(&g, "definition", "load-balance checks every run.balance_every rotations: work per rank = particles + listed pairs it evaluates")?;
    g.new_attr::<u64>()
        .create("ranks")?
        .write_scalar(&(ranks as u64))?;
    series::create::<f64>(&g, "rotations", &[], "rotations", "time of each check")?;
    series::create::<f64>(
        &g,
        "imbalance_before",
        &[],
        "-",
        "max / mean work per rank with the slabs as they were",
    )?;
    series::create::<f64>(
        &g,
        "imbalance_after",
        &[],
        "-",
        "max / mean work per rank with the slabs after the check (the same if they did not move)",
    )?;
    create_bound(&g)?;
    series::create::<f64>(
        &g,
        "bounds",
        &[ranks + 1],
        LEN,
        "slab boundaries after the check, from -L/2 to L/2",
    )?;
    let t = g.dataset("rotations")?;
    super::dimscales::make_scale(&t)?;
    super::dimscales::label_group(
        &g,
        &t,
        |n, _| if n == "rotations" { vec![] } else { vec![0] },
    )?;
    Ok(())
}

fn create_bound(g: &Group) -> hdf5::Result<()> {
    series::create::<f64>(
        g,
        "imbalance_bound",
        &[],
        "-",
        "the least imbalance any slabs longer than the halo width (interaction range + skin) can reach",
    )?;
    Ok(())
}

/// Cut a load-balance segment back to its checks at or before `until` rotations; the
/// records kept.
fn cut_balance(g: &Group, until: f64) -> hdf5::Result<usize> {
    let rotations: Vec<f64> = g.dataset("rotations")?.read_raw()?;
    let keep = rotations.iter().take_while(|&&r| r <= until).count();
    for name in g.member_names()? {
        let ds = g.dataset(&name)?;
        if ds.is_chunked() {
            series::truncate(&ds, keep.min(ds.shape()[0]))?;
        }
    }
    Ok(keep)
}

/// Append one load-balance check.
pub fn append_balance(
    file: &File,
    rotations: f64,
    check: &BalanceCheck,
    bounds: &[f64],
) -> hdf5::Result<()> {
    put(file, "balance/rotations", &[rotations])?;
    put(file, "balance/imbalance_before", &[check.before])?;
    put(file, "balance/imbalance_after", &[check.after])?;
    put(file, "balance/imbalance_bound", &[check.bound])?;
    put(file, "balance/bounds", bounds)?;
    file.flush()
}

/// The window times and sample counts of `g`, with the group attribute
/// `samples_per_window`: a window with fewer samples is the run's trailing partial one.
fn window_bounds(g: &Group, per_window: u64) -> hdf5::Result<()> {
    if g.attr_names()?.iter().any(|n| n == "samples_per_window") {
        g.delete_attr("samples_per_window")?;
    }
    g.new_attr::<u64>()
        .create("samples_per_window")?
        .write_scalar(&per_window)?;
    series::create::<f64>(
        g,
        "rotations_start",
        &[],
        "rotations",
        "start of each window",
    )?;
    series::create::<f64>(g, "rotations_end", &[], "rotations", "end of each window")?;
    series::create::<u64>(
        g,
        "samples",
        &[],
        "-",
        "samples averaged in each window (the group's samples_per_window for a whole one)",
    )?;
    Ok(())
}

fn put<T: hdf5::H5Type>(file: &File, name: &str, record: &[T]) -> hdf5::Result<()> {
    series::append(&file.dataset(name)?, record)
}

/// Append a record of means to a `float32` series.
fn put_mean(file: &File, name: &str, record: &[f64]) -> hdf5::Result<()> {
    series::append_mean(&file.dataset(name)?, record)
}

/// Append the per-sample additions to `/axial`.
pub fn append_axial(file: &File, mean_axial_velocity: &[f64], bands: u64) -> hdf5::Result<()> {
    put(file, "axial/mean_axial_velocity", mean_axial_velocity)?;
    put(file, "axial/bands", &[bands])
}

/// Append one window of per-slice diagnostics over `(start, end)` rotations.
pub fn append_slices(file: &File, start: f64, end: f64, r: &SliceRecord) -> hdf5::Result<()> {
    let s = &r.slices;
    put(file, "slices/rotations_start", &[start])?;
    put(file, "slices/rotations_end", &[end])?;
    put(file, "slices/samples", &[s.samples])?;
    put_mean(file, "slices/angle", &r.angle)?;
    put_mean(file, "slices/angle_drum", &[r.angle_drum])?;
    for (name, v) in [
        ("concentration", &s.concentration),
        ("mean_axial_velocity", &s.mean_axial_velocity),
        ("mixture_axial_velocity", &s.mixture_axial_velocity),
        ("q_up", &s.q_up),
        ("q_down", &s.q_down),
        ("q_up_mixture", &s.q_up_mixture),
        ("q_down_mixture", &s.q_down_mixture),
        ("relative_flux", &s.relative_flux),
        ("gradient", &s.gradient),
        ("diffusivity", &s.diffusivity),
        ("split_x", &s.split_x),
    ] {
        put_mean(file, &format!("slices/{name}"), v)?;
    }
    put(file, "slices/split_by_sign", &s.split_by_sign)?;
    file.flush()
}

/// Append one window of binned fields over `(start, end)` rotations.
pub fn append_fields(file: &File, start: f64, end: f64, w: &FieldWindow) -> hdf5::Result<()> {
    put(file, "fields/rotations_start", &[start])?;
    put(file, "fields/rotations_end", &[end])?;
    put(file, "fields/samples", &[w.samples])?;
    put(file, "fields/angle", &[w.angle])?;
    put(file, "fields/u0", &[w.u0])?;
    for (name, v) in [
        ("number_density", &w.number_density),
        ("volume_fraction", &w.volume_fraction),
        ("velocity", &w.velocity),
        ("velocity_drum", &w.velocity_drum),
        ("rms", &w.rms),
        ("axial_flux", &w.axial_flux),
        ("surface", &w.surface),
        ("boundary", &w.boundary),
        ("depth", &w.depth),
    ] {
        put_mean(file, &format!("fields/{name}"), v)?;
    }
    file.flush()
}

/// Append one path sample (`P x 6`: position, velocity per particle).
pub fn append_path(file: &File, rotations: f64, data: &[f64]) -> hdf5::Result<()> {
    let pos: Vec<f64> = data.chunks_exact(6).flat_map(|r| r[..3].to_vec()).collect();
    let vel: Vec<f64> = data.chunks_exact(6).flat_map(|r| r[3..].to_vec()).collect();
    put(file, "paths/rotations", &[rotations])?;
    put(file, "paths/position", &pos)?;
    put(file, "paths/velocity", &vel)?;
    file.flush()
}

/// Name of the snapshot group of `step`.
pub fn snapshot_name(step: u64) -> String {
    format!("snapshots/{step:010}")
}

/// Write a snapshot of every particle (sorted by id) taken at `step` into the open `f` (all
/// ranks together, each its share of `states`, as `h5::write_states`).
pub fn write_snapshot(
    comm: &dyn crate::comm::Comm,
    f: &super::pario::ParFile,
    step: u64,
    rotations: f64,
    states: &crate::particles::Records,
) -> Result<(), String> {
    use super::pario::together;
    let file = &f.file;
    together(comm, group(file, "snapshots"))?;
    let g = together(comm, file.create_group(&snapshot_name(step)))?;
    super::h5::write_states(comm, f, &g, states)?;
    together(
        comm,
        g.new_attr::<u64>()
            .create("step")
            .and_then(|a| a.write_scalar(&step))
            .and_then(|()| g.new_attr::<f64>().create("rotations"))
            .and_then(|a| a.write_scalar(&rotations)),
    )
}

/// The snapshots in the file: `(group name, rotations, particles)` in step order.
pub fn snapshots(file: &File) -> hdf5::Result<Vec<(String, f64, usize)>> {
    if !file.link_exists("snapshots") {
        return Ok(Vec::new());
    }
    let mut names = file.group("snapshots")?.member_names()?;
    names.sort();
    names
        .into_iter()
        .map(|n| {
            let g = file.group(&format!("snapshots/{n}"))?;
            let rot: f64 = g.attr("rotations")?.read_scalar()?;
            let count = g.dataset("id")?.size();
            Ok((format!("snapshots/{n}"), rot, count))
        })
        .collect()
}

/// Cut the diagnostics back to what a checkpoint at `step` had written: `slices` and
/// `fields` windows, `paths` samples, and snapshots up to `step`.
pub fn truncate(
    file: &File,
    slices: usize,
    fields: usize,
    paths: usize,
    step: u64,
) -> hdf5::Result<()> {
    for (grp, n) in [("slices", slices), ("fields", fields), ("paths", paths)] {
        if !file.link_exists(grp) {
            continue;
        }
        let g = file.group(grp)?;
        for name in g.member_names()? {
            let ds = g.dataset(&name)?;
            if ds.is_chunked() {
                series::truncate(&ds, n)?;
            }
        }
    }
    if file.link_exists("snapshots") {
        let g = file.group("snapshots")?;
        for name in g.member_names()? {
            if name.parse::<u64>().is_ok_and(|s| s > step) {
                g.unlink(&name)?;
            }
        }
    }
    Ok(())
}
