//! `tumbler export FILE --vtu DIR [--group G]`: a run's snapshots as VTK XML unstructured
//! grids, one `STEM_NNNNNNNNNN.vtu` per snapshot (the step, as in the HDF5 group name), with
//! the particles as points and vertex cells and their diameter, species, id, velocity and
//! angular velocity as point data; `STEM_drum.vtu`, the drum's wall (the mesh of the
//! `.xmf` file, lab frame); and `STEM.pvd`, the time series (time in rotations) that
//! ParaView opens with both parts. `--group` exports one group instead (`particles` or
//! `snapshots/NNNNNNNNNN`).
//!
//! The numbers are written as text in their shortest exact form, so a `.vtu` holds the
//! same bits as the HDF5 file. Every file is written under a temporary name and renamed
//! when complete; the `.pvd` is written last.

use super::export::{group_name, read_group, write_atomically, Particles};
use super::reader::attr_number;
use super::{InspectError, RunReader};
use crate::output::xdmf::{drum_mesh, DrumMesh};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// What `tumbler export --vtu` wrote.
#[derive(Debug, Clone)]
pub struct VtuExported {
    /// The `.pvd` file.
    pub pvd: PathBuf,
    /// The `.vtu` files of the particles, in order of time.
    pub files: Vec<PathBuf>,
    /// Particles in the last of them.
    pub particles: usize,
}

impl std::fmt::Display for VtuExported {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        writeln!(
            f,
            "wrote {} ({} time steps, {} particles in the last; open it in ParaView) and {} .vtu files beside it",
            self.pvd.display(),
            self.files.len(),
            self.particles,
            self.files.len() + 1
        )
    }
}

/// A `<DataArray>` of `values` (written with `{:?}`: the shortest text that reads back to
/// the same number).
fn data_array<T: std::fmt::Debug>(
    s: &mut String,
    ty: &str,
    name: &str,
    components: usize,
    values: impl Iterator<Item = T>,
) {
    let _ = write!(
        s,
        "    <DataArray type=\"{ty}\" Name=\"{name}\" NumberOfComponents=\"{components}\" format=\"ascii\">"
    );
    for (k, v) in values.enumerate() {
        s.push_str(if k % (3 * components) == 0 {
            "\n     "
        } else {
            " "
        });
        let _ = write!(s, "{v:?}");
    }
    s.push_str("\n    </DataArray>\n");
}

/// The start of a `.vtu` file with one piece of `points` points and `cells` cells.
fn header(s: &mut String, points: usize, cells: usize) {
    s.push_str("<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\">\n <UnstructuredGrid>\n");
    let _ = writeln!(
        s,
        "  <Piece NumberOfPoints=\"{points}\" NumberOfCells=\"{cells}\">"
    );
}

const FOOTER: &str = "  </Piece>\n </UnstructuredGrid>\n</VTKFile>\n";

/// The `.vtu` text of a group of particles.
pub fn particles_vtu(p: &Particles) -> String {
    let n = p.id.len();
    let mut s = String::with_capacity(200 * n + 1000);
    header(&mut s, n, n);
    s.push_str("   <PointData Scalars=\"diameter\" Vectors=\"velocity\">\n");
    data_array(&mut s, "Float64", "diameter", 1, p.diameter.iter());
    data_array(&mut s, "UInt8", "species", 1, p.species.iter());
    data_array(&mut s, "UInt64", "id", 1, p.id.iter());
    data_array(&mut s, "Float64", "velocity", 3, p.velocity.iter());
    data_array(
        &mut s,
        "Float64",
        "angular_velocity",
        3,
        p.angular_velocity.iter(),
    );
    s.push_str("   </PointData>\n   <Points>\n");
    data_array(&mut s, "Float64", "position", 3, p.position.iter());
    s.push_str("   </Points>\n   <Cells>\n");
    // one vertex cell (VTK type 1) per particle
    data_array(&mut s, "Int64", "connectivity", 1, 0..n as u64);
    data_array(&mut s, "Int64", "offsets", 1, 1..=n as u64);
    data_array(&mut s, "UInt8", "types", 1, std::iter::repeat_n(1u8, n));
    s.push_str("   </Cells>\n");
    s.push_str(FOOTER);
    s
}

/// The `.vtu` text of the drum's wall (triangles, VTK type 5).
pub fn drum_vtu(m: &DrumMesh) -> String {
    let (np, nt) = (m.points.len(), m.triangles.len());
    let mut s = String::new();
    header(&mut s, np, nt);
    s.push_str("   <Points>\n");
    data_array(&mut s, "Float64", "position", 3, m.points.iter().flatten());
    s.push_str("   </Points>\n   <Cells>\n");
    data_array(
        &mut s,
        "Int64",
        "connectivity",
        1,
        m.triangles.iter().flatten().map(|&k| k as u64),
    );
    data_array(
        &mut s,
        "Int64",
        "offsets",
        1,
        (1..=nt as u64).map(|k| 3 * k),
    );
    data_array(&mut s, "UInt8", "types", 1, std::iter::repeat_n(5u8, nt));
    s.push_str("   </Cells>\n");
    s.push_str(FOOTER);
    s
}

/// Write the snapshots of the run open in `reader` (or only `group`) as `.vtu` files and
/// a `.pvd` series in `dir` (module documentation).
pub fn export_vtu(
    reader: &RunReader,
    dir: &Path,
    group: Option<&str>,
) -> Result<VtuExported, InspectError> {
    let case = reader.case()?;
    let groups: Vec<String> = match group {
        Some(g) => vec![group_name(Some(g))],
        None => {
            let mut names: Vec<String> = reader
                .file()
                .group("snapshots")
                .and_then(|g| g.member_names())
                .unwrap_or_default();
            names.sort();
            if names.is_empty() {
                return Err(reader.missing(
                    "/snapshots",
                    "; set diagnostics.snapshots.every to take snapshots, or export the final state with --group particles",
                ));
            }
            names
                .into_iter()
                .map(|n| format!("snapshots/{n}"))
                .collect()
        }
    };
    let write_err = |path: &Path| {
        let path = path.display().to_string();
        move |e: std::io::Error| InspectError::Write {
            path: path.clone(),
            reason: e.to_string(),
        }
    };
    std::fs::create_dir_all(dir).map_err(write_err(dir))?;
    let stem = reader
        .path()
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| "run".into());
    let drum = dir.join(format!("{stem}_drum.vtu"));
    let mesh = drum_mesh(&case.drum);
    let mut files = Vec::new();
    let mut series = Vec::new();
    let mut particles = 0;
    for g in &groups {
        let p = read_group(reader, g)?;
        let rotations = reader
            .file()
            .group(g)
            .ok()
            .and_then(|h| attr_number(&h, "rotations"))
            .unwrap_or(0.0);
        let name = g.rsplit('/').next().unwrap_or(g);
        let path = dir.join(format!("{stem}_{name}.vtu"));
        write_atomically(&path, particles_vtu(&p).as_bytes()).map_err(write_err(&path))?;
        particles = p.id.len();
        series.push((rotations, path.clone()));
        files.push(path);
    }
    write_atomically(&drum, drum_vtu(&mesh).as_bytes()).map_err(write_err(&drum))?;
    let pvd = dir.join(format!("{stem}.pvd"));
    let mut s = String::from("<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"1.0\" byte_order=\"LittleEndian\">\n <Collection>\n");
    let file_name = |p: &Path| {
        p.file_name()
            .map(|n| n.to_string_lossy().into_owned())
            .unwrap_or_default()
    };
    for (t, path) in &series {
        let _ = writeln!(
            s,
            "  <DataSet timestep=\"{t:?}\" part=\"0\" name=\"particles\" file=\"{}\"/>\n  <DataSet timestep=\"{t:?}\" part=\"1\" name=\"drum\" file=\"{}\"/>",
            file_name(path),
            file_name(&drum)
        );
    }
    s.push_str(" </Collection>\n</VTKFile>\n");
    write_atomically(&pvd, s.as_bytes()).map_err(write_err(&pvd))?;
    Ok(VtuExported {
        pvd,
        files,
        particles,
    })
}
