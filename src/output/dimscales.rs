//! HDF5 dimension scales (the high-level `H5DS` API of `libhdf5_hl`, which hdf5-metno does
//! not wrap): a coordinate dataset (`/axial/z`, `/slices/rotations_end`, `/species`...) is
//! made a scale and attached to the axes of the series it labels, so that h5py's `dims`,
//! netCDF readers and `xarray.open_dataset(..., engine="h5netcdf")` see named, labelled
//! axes. Attaching records references both ways (`DIMENSION_LIST` on the series,
//! `REFERENCE_LIST` on the scale); nothing of the data changes.

use hdf5::Dataset;
use hdf5_sys::h5::herr_t;
use hdf5_sys::h5i::hid_t;
use std::ffi::CString;
use std::os::raw::{c_char, c_uint};

extern "C" {
    fn H5DSset_scale(dsid: hid_t, dimname: *const c_char) -> herr_t;
    fn H5DSattach_scale(did: hid_t, dsid: hid_t, idx: c_uint) -> herr_t;
    fn H5DSis_attached(did: hid_t, dsid: hid_t, idx: c_uint) -> i32;
}

fn to_err(e: impl std::fmt::Display) -> hdf5::Error {
    hdf5::Error::from(e.to_string().as_str())
}

/// Make `ds` a dimension scale named after its own name (`/fields/x` -> `x`), as netCDF
/// expects of a coordinate variable.
pub fn make_scale(ds: &Dataset) -> hdf5::Result<()> {
    let full = ds.name();
    let name = full.rsplit('/').next().unwrap_or(&full).to_string();
    let c = CString::new(name).map_err(to_err)?;
    let id = ds.id();
    // SAFETY: `id` is an open dataset, `c` a NUL-terminated string alive for the call
    hdf5::sync::sync(|| hdf5::h5check(unsafe { H5DSset_scale(id, c.as_ptr()) })).map(drop)
}

/// Attach the scale `scale` to axis `axis` of `ds` (once; attaching again is a no-op).
pub fn attach(ds: &Dataset, scale: &Dataset, axis: usize) -> hdf5::Result<()> {
    let rank = ds.ndim();
    if axis >= rank {
        return Err(to_err(format!(
            "{} has {rank} axes, no axis {axis} to label with {}",
            ds.name(),
            scale.name()
        )));
    }
    let (did, sid) = (ds.id(), scale.id());
    let axis = axis as c_uint;
    hdf5::sync::sync(|| {
        // SAFETY: both ids are open datasets of the same file; `axis` is below the rank
        unsafe {
            if hdf5::h5check(H5DSis_attached(did, sid, axis))? > 0 {
                return Ok(());
            }
            hdf5::h5check(H5DSattach_scale(did, sid, axis)).map(drop)
        }
    })
}

/// Label axes of the datasets of `group` with `scale`: `pick(name, shape)` gives the axes
/// of dataset `name` it labels (none for the scale itself and the other coordinates).
pub fn label_group(
    group: &hdf5::Group,
    scale: &Dataset,
    pick: impl Fn(&str, &[usize]) -> Vec<usize>,
) -> hdf5::Result<()> {
    let own = scale.name();
    for ds in group.datasets()? {
        let name = ds.name();
        if name == own {
            continue;
        }
        let short = name.rsplit('/').next().unwrap_or(&name).to_string();
        for axis in pick(&short, &ds.shape()) {
            attach(&ds, scale, axis)?;
        }
    }
    Ok(())
}
