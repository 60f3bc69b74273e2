//! The XDMF file beside a run's HDF5 file, so ParaView and VisIt open the snapshots
//! directly: a temporal collection with one grid of points per snapshot and the particles'
//! diameter, species, id, velocity and angular velocity as point attributes.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// The XDMF file of an output (`NAME.h5` -> `NAME.xmf`).
pub fn xdmf_path(output: &Path) -> PathBuf {
    output.with_extension("xmf")
}

/// The XDMF text for `snapshots` (`(group, rotations, particles)`) stored in the HDF5 file
/// named `h5_name` (relative to the XDMF file).
pub fn render(h5_name: &str, snapshots: &[(String, f64, usize)]) -> String {
    let mut s = String::new();
    s.push_str("<?xml version=\"1.0\" ?>\n<!DOCTYPE Xdmf SYSTEM \"Xdmf.dtd\" []>\n");
    s.push_str("<Xdmf Version=\"3.0\">\n <Domain>\n");
    s.push_str("  <Grid Name=\"particles\" GridType=\"Collection\" CollectionType=\"Temporal\">\n");
    for (group, rot, n) in snapshots {
        let item = |name: &str, dims: &str, ty: &str, prec: usize| {
            format!(
                "<DataItem Dimensions=\"{dims}\" NumberType=\"{ty}\" Precision=\"{prec}\" Format=\"HDF\">{h5_name}:/{group}/{name}</DataItem>"
            )
        };
        let (n1, n3) = (format!("{n}"), format!("{n} 3"));
        let _ = writeln!(s, "   <Grid Name=\"{group}\" GridType=\"Uniform\">");
        let _ = writeln!(s, "    <Time Value=\"{rot}\"/>");
        let _ = writeln!(
            s,
            "    <Topology TopologyType=\"Polyvertex\" NumberOfElements=\"{n}\" NodesPerElement=\"1\"/>"
        );
        let _ = writeln!(
            s,
            "    <Geometry GeometryType=\"XYZ\">\n     {}\n    </Geometry>",
            item("position", &n3, "Float", 8)
        );
        for (name, kind, dims, ty, prec) in [
            ("diameter", "Scalar", &n1, "Float", 8),
            ("species", "Scalar", &n1, "UChar", 1),
            ("id", "Scalar", &n1, "UInt", 8),
            ("velocity", "Vector", &n3, "Float", 8),
            ("angular_velocity", "Vector", &n3, "Float", 8),
        ] {
            let _ = writeln!(
                s,
                "    <Attribute Name=\"{name}\" AttributeType=\"{kind}\" Center=\"Node\">\n     {}\n    </Attribute>",
                item(name, dims, ty, prec)
            );
        }
        s.push_str("   </Grid>\n");
    }
    s.push_str("  </Grid>\n </Domain>\n</Xdmf>\n");
    s
}

/// Write the XDMF file for `output` atomically (temporary file, then rename).
pub fn write(output: &Path, snapshots: &[(String, f64, usize)]) -> std::io::Result<()> {
    let h5_name = output
        .file_name()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default();
    let path = xdmf_path(output);
    let mut tmp = path.as_os_str().to_owned();
    tmp.push(".tmp");
    std::fs::write(&tmp, render(&h5_name, snapshots))?;
    std::fs::rename(&tmp, &path)
}
