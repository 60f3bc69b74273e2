//! The XDMF file beside a run's HDF5 file (`NAME.xmf`), so that ParaView's default reader
//! for `.xmf` (Xdmf3ReaderS; not the older XDMF reader, which stops on the `xi:include`s)
//! opens the run directly. Each time step (every snapshot and every field window's end) is
//! a spatial collection of three grids, each written once and included where it repeats
//! (the reader shows at a time only the grids of that time; docs/interop.md):
//!
//! - `particles`: the latest snapshot, the particles as a `Polyvertex` topology (one
//!   vertex cell per particle, so that ParaView's Surface and Points views show them) with every particle array (diameter, species, id, velocity,
//!   angular velocity) as point attributes. Xdmf3 makes no cells without a connectivity
//!   array, so the first snapshot of each particle count carries `0 .. N-1` inline and the
//!   others include that topology (`xi:include`).
//! - `drum`: the drum's wall as a coarse triangle mesh in the lab frame (the frame of the
//!   particle positions): a cylinder along `z` with its end caps (no caps when the ends are
//!   periodic) or a sphere, from the case stored in the file.
//! - `fields`: the latest `/fields` window, the bins as hexahedral cells with the binned
//!   fields as cell data (one window and component of a dataset each). The bins are
//!   cuboids in the *surface frame* (docs/diagnostics.md, "Frames"), so the grid's
//!   coordinates are surface-frame coordinates: `x` down the free surface, `y` out of the
//!   bed, `z` the axis. The datasets store `z` fastest, while an XDMF rectilinear mesh
//!   takes `x` fastest; a rectilinear mesh would therefore mirror the fields, and the grid
//!   is written as a structured mesh (`3DSMesh`) with its point coordinates inline (once:
//!   later windows include them).
//!
//! Every HDF5 item's number type and precision is the dataset's own (read from the file).

use crate::case::{parse_case, Case};
use hdf5::types::{FloatSize, IntSize, TypeDescriptor};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

mod drum_mesh;
pub use drum_mesh::{drum_mesh, DrumMesh, DRUM_SEGMENTS, SPHERE_RINGS};

/// The XDMF file of an output (`NAME.h5` -> `NAME.xmf`).
pub fn xdmf_path(output: &Path) -> PathBuf {
    output.with_extension("xmf")
}

/// A dataset named in the XDMF file: its path, shape and XDMF number type.
#[derive(Debug, Clone, PartialEq)]
pub struct Item {
    /// Path in the HDF5 file, without the leading `/`.
    pub path: String,
    /// Shape.
    pub shape: Vec<usize>,
    /// XDMF `NumberType` (`Float`, `Int`, `UInt`, `Char`, `UChar`).
    pub number: &'static str,
    /// XDMF `Precision` in bytes.
    pub precision: usize,
}

/// One snapshot: its group, time and datasets (position first).
#[derive(Debug, Clone)]
pub struct Snapshot {
    /// `snapshots/NNNNNNNNNN`.
    pub group: String,
    /// Time in rotations.
    pub rotations: f64,
    /// Number of particles.
    pub count: usize,
    /// `position`, then the point attributes.
    pub items: Vec<Item>,
}

/// The `/fields` windows: bin edges (surface frame), window ends and the binned datasets.
#[derive(Debug, Clone)]
pub struct Fields {
    /// Bin edges along surface-frame `x`, `y` and the axis `z`.
    pub edges: [Vec<f64>; 3],
    /// End of each window, in rotations.
    pub ends: Vec<f64>,
    /// `(attribute name, dataset, index along the dataset's second axis or None)`.
    pub arrays: Vec<(String, Item, Option<usize>)>,
}

/// Everything the XDMF file describes.
#[derive(Debug, Clone)]
pub struct Layout {
    /// The drum's wall at time zero.
    pub drum: Option<DrumMesh>,
    /// The snapshots, in order of time.
    pub snapshots: Vec<Snapshot>,
    /// The field windows, if any.
    pub fields: Option<Fields>,
}

/// XDMF number type and precision of an HDF5 type.
fn number_type(t: &TypeDescriptor) -> Option<(&'static str, usize)> {
    let bytes = |s: &IntSize| match s {
        IntSize::U1 => 1,
        IntSize::U2 => 2,
        IntSize::U4 => 4,
        IntSize::U8 => 8,
    };
    match t {
        TypeDescriptor::Float(FloatSize::U4) => Some(("Float", 4)),
        TypeDescriptor::Float(FloatSize::U8) => Some(("Float", 8)),
        TypeDescriptor::Unsigned(IntSize::U1) => Some(("UChar", 1)),
        TypeDescriptor::Unsigned(s) => Some(("UInt", bytes(s))),
        TypeDescriptor::Integer(IntSize::U1) => Some(("Char", 1)),
        TypeDescriptor::Integer(s) => Some(("Int", bytes(s))),
        _ => None,
    }
}

/// The dataset `path` of `file`, if it is there with a numeric type.
fn item(file: &hdf5::File, path: &str) -> Option<Item> {
    let ds = file.dataset(path).ok()?;
    let (number, precision) = number_type(&ds.dtype().ok()?.to_descriptor().ok()?)?;
    Some(Item {
        path: path.to_string(),
        shape: ds.shape(),
        number,
        precision,
    })
}

/// The particle datasets of a snapshot group, `position` first, in the XDMF order.
const PARTICLE_ARRAYS: [&str; 6] = [
    "position",
    "diameter",
    "species",
    "id",
    "velocity",
    "angular_velocity",
];

/// Read what the XDMF file describes from the run's open HDF5 file.
pub fn describe(file: &hdf5::File) -> hdf5::Result<Layout> {
    let case: Option<Case> =
        crate::inspect::attr_string(file, "case").and_then(|text| parse_case(&text, "case").ok());
    let drum = case.as_ref().map(|c| drum_mesh(&c.drum));
    let mut snapshots = Vec::new();
    for (group, rotations, count) in super::diag_file::snapshots(file)? {
        let items: Vec<Item> = PARTICLE_ARRAYS
            .iter()
            .filter_map(|name| item(file, &format!("{group}/{name}")))
            .filter(|it| it.shape.first() == Some(&count))
            .collect();
        if items.first().is_some_and(|p| p.path.ends_with("/position")) {
            snapshots.push(Snapshot {
                group,
                rotations,
                count,
                items,
            });
        }
    }
    let fields = case.as_ref().and_then(|c| fields(file, c));
    Ok(Layout {
        drum,
        snapshots,
        fields,
    })
}

/// The field windows of `file`, read by name and shape.
fn fields(file: &hdf5::File, case: &Case) -> Option<Fields> {
    let read = |name: &str| -> Option<Vec<f64>> {
        file.dataset(&format!("fields/{name}"))
            .ok()?
            .read_raw::<f64>()
            .ok()
    };
    let (x, y, z) = (read("x")?, read("y")?, read("z")?);
    let ends = read("rotations_end")?;
    let dims = [x.len(), y.len(), z.len()];
    if ends.is_empty() || dims.contains(&0) {
        return None;
    }
    let r = 0.5 * case.drum.diameter;
    let half = 0.5 * case.drum.axial_length();
    let uniform = |lo: f64, hi: f64, n: usize| -> Vec<f64> {
        (0..=n)
            .map(|k| lo + k as f64 * ((hi - lo) / n as f64))
            .collect()
    };
    let edges = [
        uniform(-r, r, dims[0]),
        uniform(-r, r, dims[1]),
        uniform(-half, half, dims[2]),
    ];
    let species: Vec<String> = case.species.iter().map(|s| s.name.clone()).collect();
    let mut arrays = Vec::new();
    let mut windows = ends.len();
    for (name, parts) in [
        ("number_density", species.clone()),
        ("volume_fraction", species.clone()),
        ("axial_flux", species.clone()),
        ("velocity", names(&["u", "v", "w"])),
        ("velocity_drum", names(&["ud", "vd", "wd"])),
        ("rms", names(&["u_rms", "v_rms", "w_rms", "rms"])),
    ] {
        let Some(it) = item(file, &format!("fields/{name}")) else {
            continue;
        };
        if it.shape.len() != 5 || it.shape[2..] != dims || it.shape[1] != parts.len() {
            continue;
        }
        windows = windows.min(it.shape[0]);
        for (k, part) in parts.iter().enumerate() {
            let label = if parts == species {
                format!("{name}_{part}")
            } else {
                part.clone()
            };
            arrays.push((label, it.clone(), Some(k)));
        }
    }
    if arrays.is_empty() || windows == 0 {
        return None;
    }
    Some(Fields {
        edges,
        ends: ends[..windows].to_vec(),
        arrays,
    })
}

fn names(list: &[&str]) -> Vec<String> {
    list.iter().map(|s| s.to_string()).collect()
}

/// Dimensions as XDMF writes them (space-separated).
fn dims(shape: &[usize]) -> String {
    shape
        .iter()
        .map(|d| d.to_string())
        .collect::<Vec<_>>()
        .join(" ")
}

/// An HDF5 data item for the whole dataset.
fn hdf_item(h5_name: &str, it: &Item) -> String {
    format!(
        "<DataItem Dimensions=\"{}\" NumberType=\"{}\" Precision=\"{}\" Format=\"HDF\">{h5_name}:/{}</DataItem>",
        dims(&it.shape),
        it.number,
        it.precision,
        it.path
    )
}

/// Window `w`, component `c` of `it` (shape `F x C x X x Y x Z`), as an Xdmf3 HDF item
/// with a selection (`path|start:stride:count:dataspace`, which Xdmf3 reads directly).
fn slab_item(h5_name: &str, it: &Item, w: usize, c: usize) -> String {
    let s = &it.shape;
    let (x, y, z) = (s[2], s[3], s[4]);
    format!(
        "<DataItem Dimensions=\"{x} {y} {z}\" NumberType=\"{}\" Precision=\"{}\" Format=\"HDF\">{h5_name}:/{}|{w} {c} 0 0 0:1 1 1 1 1:1 1 {x} {y} {z}:{}</DataItem>",
        it.number,
        it.precision,
        it.path,
        dims(s)
    )
}
/// The grid of the drum's wall.
fn drum_grid(s: &mut String, mesh: &DrumMesh) {
    let (np, nt) = (mesh.points.len(), mesh.triangles.len());
    let _ = writeln!(s, "    <Grid Name=\"drum\" GridType=\"Uniform\">");
    let _ = write!(
        s,
        "     <Topology TopologyType=\"Triangle\" NumberOfElements=\"{nt}\">\n      <DataItem Dimensions=\"{nt} 3\" NumberType=\"UInt\" Precision=\"4\" Format=\"XML\">"
    );
    for t in &mesh.triangles {
        let _ = write!(s, "\n       {} {} {}", t[0], t[1], t[2]);
    }
    s.push_str("\n      </DataItem>\n     </Topology>\n");
    let _ = write!(
        s,
        "     <Geometry GeometryType=\"XYZ\">\n      <DataItem Dimensions=\"{np} 3\" NumberType=\"Float\" Precision=\"8\" Format=\"XML\">"
    );
    for p in &mesh.points {
        let _ = write!(s, "\n       {:?} {:?} {:?}", p[0], p[1], p[2]);
    }
    s.push_str("\n      </DataItem>\n     </Geometry>\n    </Grid>\n");
}

/// An `xi:include` of the grid (or the grid's `part`) named `name` in time step `step`.
fn include(s: &mut String, step: usize, name: &str, part: &str) {
    let _ = writeln!(
        s,
        "    <xi:include xpointer=\"xpointer(//Grid[@Name='time {step}']/Grid[@Name='{name}']{part})\"/>"
    );
}

/// The grid of one snapshot. `topology`: the time step whose snapshot grid holds the
/// connectivity for this particle count, if one before does.
fn particle_grid(s: &mut String, h5_name: &str, snap: &Snapshot, topology: Option<usize>) {
    let n = snap.count;
    let _ = writeln!(s, "    <Grid Name=\"particles\" GridType=\"Uniform\">");
    let _ = writeln!(
        s,
        "     <Information Name=\"group\" Value=\"{}\"/>",
        snap.group
    );
    match topology {
        Some(step) => include(s, step, "particles", "/Topology"),
        None => {
            let _ = write!(
                s,
                "     <Topology TopologyType=\"Polyvertex\" NumberOfElements=\"{n}\" NodesPerElement=\"1\">\n      <DataItem Dimensions=\"{n}\" NumberType=\"UInt\" Precision=\"8\" Format=\"XML\">"
            );
            for i in 0..n {
                s.push_str(if i % 16 == 0 { "\n       " } else { " " });
                let _ = write!(s, "{i}");
            }
            s.push_str("\n      </DataItem>\n     </Topology>\n");
        }
    }
    for it in &snap.items {
        let name = it.path.rsplit('/').next().unwrap_or_default();
        if name == "position" {
            let _ = writeln!(
                s,
                "     <Geometry GeometryType=\"XYZ\">\n      {}\n     </Geometry>",
                hdf_item(h5_name, it)
            );
        } else {
            let kind = if it.shape.len() == 2 {
                "Vector"
            } else {
                "Scalar"
            };
            let _ = writeln!(
                s,
                "     <Attribute Name=\"{name}\" AttributeType=\"{kind}\" Center=\"Node\">\n      {}\n     </Attribute>",
                hdf_item(h5_name, it)
            );
        }
    }
    s.push_str("    </Grid>\n");
}

/// The grid of field window `w`. `geometry`: the time step whose field grid holds the
/// point coordinates, if one before does.
fn field_grid(s: &mut String, h5_name: &str, f: &Fields, w: usize, geometry: Option<usize>) {
    let [ex, ey, ez] = &f.edges;
    let _ = writeln!(s, "    <Grid Name=\"fields\" GridType=\"Uniform\">");
    let _ = writeln!(
        s,
        "     <Information Name=\"window\" Value=\"{w}\"/>\n     <Topology TopologyType=\"3DSMesh\" Dimensions=\"{} {} {}\"/>",
        ex.len(),
        ey.len(),
        ez.len()
    );
    match geometry {
        Some(step) => include(s, step, "fields", "/Geometry"),
        None => {
            let points = ex.len() * ey.len() * ez.len();
            let _ = write!(
                s,
                "     <Geometry GeometryType=\"XYZ\">\n      <DataItem Dimensions=\"{points} 3\" NumberType=\"Float\" Precision=\"8\" Format=\"XML\">"
            );
            // point (i, j, k) of the mesh is at (x_i, y_j, z_k), k fastest like the data
            for x in ex {
                for y in ey {
                    for z in ez {
                        let _ = write!(s, "\n       {x:?} {y:?} {z:?}");
                    }
                }
            }
            s.push_str("\n      </DataItem>\n     </Geometry>\n");
        }
    }
    for (name, it, part) in &f.arrays {
        let _ = writeln!(
            s,
            "     <Attribute Name=\"{name}\" AttributeType=\"Scalar\" Center=\"Cell\">\n      {}\n     </Attribute>",
            slab_item(h5_name, it, w, part.unwrap_or(0))
        );
    }
    s.push_str("    </Grid>\n");
}

/// The times of the XDMF file: every snapshot's and every field window's end, in order,
/// each with the latest snapshot and field window at that time (indices).
pub fn time_steps(layout: &Layout) -> Vec<(f64, Option<usize>, Option<usize>)> {
    let ends: &[f64] = layout.fields.as_ref().map_or(&[], |f| &f.ends);
    let mut times: Vec<f64> = layout.snapshots.iter().map(|s| s.rotations).collect();
    times.extend_from_slice(ends);
    times.sort_by(f64::total_cmp);
    times.dedup();
    let latest = |t: f64, at: &mut dyn Iterator<Item = f64>| at.filter(|&x| x <= t).count();
    times
        .into_iter()
        .map(|t| {
            let s = latest(t, &mut layout.snapshots.iter().map(|s| s.rotations));
            let f = latest(t, &mut ends.iter().copied());
            (t, s.checked_sub(1), f.checked_sub(1))
        })
        .collect()
}

/// The XDMF text for `layout`, whose datasets are in the HDF5 file named `h5_name`
/// (relative to the XDMF file): one temporal collection whose time steps are spatial
/// collections of the particles, the drum and the fields at that time.
pub fn render(h5_name: &str, layout: &Layout) -> String {
    let mut s = String::new();
    s.push_str("<?xml version=\"1.0\" ?>\n<!DOCTYPE Xdmf SYSTEM \"Xdmf.dtd\" []>\n");
    s.push_str("<Xdmf Version=\"3.0\" xmlns:xi=\"http://www.w3.org/2001/XInclude\">\n <Domain>\n");
    s.push_str("  <Grid Name=\"run\" GridType=\"Collection\" CollectionType=\"Temporal\">\n");
    // where each snapshot, each particle count's connectivity and each window is written
    let mut snapshot_at: Vec<Option<usize>> = vec![None; layout.snapshots.len()];
    let mut count_at: Vec<(usize, usize)> = Vec::new();
    let mut window_at: Vec<Option<usize>> =
        vec![None; layout.fields.as_ref().map_or(0, |f| f.ends.len())];
    let mut geometry_at = None;
    for (step, (t, snap, window)) in time_steps(layout).into_iter().enumerate() {
        let _ = writeln!(
            s,
            "   <Grid Name=\"time {step}\" GridType=\"Collection\" CollectionType=\"Spatial\">\n    <Time Value=\"{t:?}\"/>"
        );
        if let Some(k) = snap {
            match snapshot_at[k] {
                Some(at) => include(&mut s, at, "particles", ""),
                None => {
                    let n = layout.snapshots[k].count;
                    let topology = count_at.iter().find(|(c, _)| *c == n).map(|(_, at)| *at);
                    if topology.is_none() {
                        count_at.push((n, step));
                    }
                    particle_grid(&mut s, h5_name, &layout.snapshots[k], topology);
                    snapshot_at[k] = Some(step);
                }
            }
        }
        match (step, &layout.drum) {
            (0, Some(drum)) => drum_grid(&mut s, drum),
            (_, Some(_)) => include(&mut s, 0, "drum", ""),
            _ => {}
        }
        if let (Some(w), Some(f)) = (window, &layout.fields) {
            match window_at[w] {
                Some(at) => include(&mut s, at, "fields", ""),
                None => {
                    field_grid(&mut s, h5_name, f, w, geometry_at);
                    geometry_at.get_or_insert(step);
                    window_at[w] = Some(step);
                }
            }
        }
        s.push_str("   </Grid>\n");
    }
    s.push_str("  </Grid>\n </Domain>\n</Xdmf>\n");
    s
}

/// Write the XDMF file for `output` from what its open HDF5 file `file` holds, atomically
/// (temporary file, then rename). Nothing is written while the file holds neither a
/// snapshot nor a field window; whether it was written.
pub fn write(output: &Path, file: &hdf5::File) -> Result<bool, String> {
    let layout = describe(file).map_err(|e| format!("reading {}: {e}", output.display()))?;
    if layout.snapshots.is_empty() && layout.fields.is_none() {
        return Ok(false);
    }
    let h5_name = output
        .file_name()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default();
    let path = xdmf_path(output);
    let mut tmp = path.as_os_str().to_owned();
    tmp.push(".tmp");
    std::fs::write(&tmp, render(&h5_name, &layout))
        .and_then(|()| std::fs::rename(&tmp, &path))
        .map_err(|e| format!("writing {}: {e}", path.display()))?;
    Ok(true)
}

#[cfg(test)]
mod tests {
    use super::*;
    use hdf5::types::VarLenUnicode;

    const CASE: &str = include_str!("../../tests/cases/sd_capped.toml");

    /// A file with one snapshot (`u64` ids, `u8` species, `f64` vectors) and one field
    /// window of `f32` datasets on 2 x 3 x 2 bins.
    fn write_file(path: &Path) {
        let f = hdf5::File::create(path).unwrap();
        let text: VarLenUnicode = CASE.parse().unwrap();
        f.new_attr::<VarLenUnicode>()
            .create("case")
            .unwrap()
            .write_scalar(&text)
            .unwrap();
        let g = f.create_group("snapshots/0000000100").unwrap();
        g.new_attr::<f64>()
            .create("rotations")
            .unwrap()
            .write_scalar(&0.5)
            .unwrap();
        g.new_dataset_builder()
            .with_data(&[3u64, 4])
            .create("id")
            .unwrap();
        g.new_dataset_builder()
            .with_data(&[0u8, 1])
            .create("species")
            .unwrap();
        g.new_dataset_builder()
            .with_data(&[0.002f64, 0.003])
            .create("diameter")
            .unwrap();
        for name in ["position", "velocity", "angular_velocity"] {
            g.new_dataset_builder()
                .with_data(&ndarray::Array2::<f64>::zeros((2, 3)))
                .create(name)
                .unwrap();
        }
        let fl = f.create_group("fields").unwrap();
        for (name, v) in [
            ("x", vec![-0.0075, 0.0075]),
            ("y", vec![-0.01, 0.0, 0.01]),
            ("z", vec![-0.01, 0.01]),
            ("rotations_end", vec![1.0]),
        ] {
            fl.new_dataset_builder().with_data(&v).create(name).unwrap();
        }
        for (name, parts) in [("number_density", 2), ("velocity", 3)] {
            fl.new_dataset_builder()
                .with_data(&ndarray::Array5::<f32>::zeros((1, parts, 2, 3, 2)))
                .create(name)
                .unwrap();
        }
    }

    #[test]
    fn number_types_come_from_the_datasets_and_times_merge() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("run.h5");
        write_file(&path);
        let layout = describe(&hdf5::File::open(&path).unwrap()).unwrap();
        assert_eq!(
            time_steps(&layout),
            [(0.5, Some(0), None), (1.0, Some(0), Some(0))]
        );
        let text = render("run.h5", &layout);
        for want in [
            "NumberType=\"UInt\" Precision=\"8\" Format=\"HDF\">run.h5:/snapshots/0000000100/id<",
            "NumberType=\"UChar\" Precision=\"1\" Format=\"HDF\">run.h5:/snapshots/0000000100/species<",
            "Dimensions=\"2 3\" NumberType=\"Float\" Precision=\"8\" Format=\"HDF\">run.h5:/snapshots/0000000100/position<",
            // window 0, species 1 of an f32 dataset
            "Dimensions=\"2 3 2\" NumberType=\"Float\" Precision=\"4\" Format=\"HDF\">run.h5:/fields/number_density|0 1 0 0 0:1 1 1 1 1:1 1 2 3 2:1 2 2 3 2<",
            "<Attribute Name=\"number_density_large\"",
            "<Attribute Name=\"w\"",
            "<Topology TopologyType=\"3DSMesh\" Dimensions=\"3 4 3\"/>",
        ] {
            assert!(text.contains(want), "{want} not in:\n{text}");
        }
        // the particles of the second time step, and the drum, are included, not repeated
        assert_eq!(text.matches("<Grid Name=\"particles\"").count(), 1);
        assert_eq!(text.matches("<Grid Name=\"drum\"").count(), 1);
        assert!(text.contains("xpointer(//Grid[@Name='time 0']/Grid[@Name='particles'])"));
        assert!(text.contains("xpointer(//Grid[@Name='time 0']/Grid[@Name='drum'])"));
        // bin corners: x and z from the drum (R = 0.015, L = 0.04), 3 x 4 x 3 points
        assert!(text.contains("\n       -0.015 -0.015 -0.02\n"));
        assert!(text.contains("\n       0.015 0.015 0.02\n"));
    }

    #[test]
    fn drum_meshes_lie_on_the_wall() {
        let drum = |text: &str| -> crate::case::Drum {
            toml::from_str(&format!("omega = 1.0\n{text}")).unwrap()
        };
        let m = drum_mesh(&drum("shape = \"sphere\"\ndiameter = 2.0"));
        assert_eq!(m.points.len(), 2 + (SPHERE_RINGS - 1) * DRUM_SEGMENTS);
        assert_eq!(m.triangles.len(), 2 * DRUM_SEGMENTS * (SPHERE_RINGS - 1));
        for p in &m.points {
            let r = (p[0] * p[0] + p[1] * p[1] + p[2] * p[2]).sqrt();
            assert!((r - 1.0).abs() < 1e-15, "{p:?}");
        }
        let open = drum_mesh(&drum("diameter = 2.0\nlength = 4.0\nends = \"periodic\""));
        assert_eq!(open.points.len(), 2 * DRUM_SEGMENTS);
        assert_eq!(open.triangles.len(), 2 * DRUM_SEGMENTS);
        assert!(open.points.iter().all(|p| p[2].abs() == 2.0));
        let capped = drum_mesh(&drum("diameter = 2.0\nlength = 4.0\nends = \"capped\""));
        assert_eq!(capped.triangles.len(), 4 * DRUM_SEGMENTS);
        // a cone: the rings at the radii of its two ends; lifters: 12 triangles each
        let cone = drum_mesh(&drum(
            "shape = \"cone\"\ndiameter = 2.0\ndiameter_high = 1.0\nlength = 4.0",
        ));
        assert_eq!(cone.triangles.len(), 4 * DRUM_SEGMENTS);
        for p in &cone.points[..2 * DRUM_SEGMENTS] {
            let r = (p[0] * p[0] + p[1] * p[1]).sqrt();
            let want = if p[2] < 0.0 { 1.0 } else { 0.5 };
            assert!((r - want).abs() < 1e-15, "{p:?}");
        }
        let lifted = drum_mesh(&drum(
            "diameter = 2.0\nlength = 4.0\nends = \"capped\"\n[lifters]\ncount = 4\nheight = 0.2\nthickness = 0.05",
        ));
        assert_eq!(lifted.triangles.len(), 4 * DRUM_SEGMENTS + 4 * 12);
        for p in &lifted.points[2 * DRUM_SEGMENTS + 2..] {
            let r = (p[0] * p[0] + p[1] * p[1]).sqrt();
            assert!(r > 0.79 && r < 1.001, "{p:?}");
        }
        // every triangle uses three different points
        for t in capped
            .triangles
            .iter()
            .chain(&m.triangles)
            .chain(&lifted.triangles)
        {
            assert!(t[0] != t[1] && t[1] != t[2] && t[0] != t[2], "{t:?}");
        }
    }
}
