//! Opening a run's HDF5 file and reading its datasets and attributes, with errors that name
//! the file and what is missing or malformed.

use super::number::short;
use super::InspectError;
use crate::case::{parse_case, Case, Family};
use hdf5::types::{TypeDescriptor, VarLenAscii, VarLenUnicode};
use hdf5::{Attribute, Location};
use ndarray::ArrayD;
use std::cell::OnceCell;
use std::path::{Path, PathBuf};

/// An HDF5 file written by `tumbler run`, open for reading.
pub struct RunReader {
    file: hdf5::File,
    path: PathBuf,
    /// The case's model family, parsed once (`None` inside: no readable case).
    family: OnceCell<Option<Family>>,
}

/// One averaging window of `/slices` or `/fields`.
#[derive(Debug, Clone, PartialEq)]
pub struct Window {
    /// Index of the window (0 = first).
    pub index: usize,
    /// Number of windows in the file.
    pub count: usize,
    /// Start of the window, in rotations.
    pub start: f64,
    /// End of the window, in rotations.
    pub end: f64,
}

impl Window {
    /// `window K (start-end rotations)`, for titles and legends.
    pub fn label(&self) -> String {
        format!(
            "window {} ({}-{} rotations)",
            self.index,
            short(self.start),
            short(self.end)
        )
    }
}

impl RunReader {
    /// Open `path` for reading.
    pub fn open(path: &Path) -> Result<Self, InspectError> {
        let shown = path.display().to_string();
        if !path.exists() {
            return Err(InspectError::File {
                path: shown,
                reason: "no such file".into(),
            });
        }
        let file = hdf5::File::open(path).map_err(|e| InspectError::File {
            path: shown,
            reason: format!("not a readable HDF5 file ({e})"),
        })?;
        Ok(RunReader {
            file,
            path: path.to_path_buf(),
            family: OnceCell::new(),
        })
    }

    /// The file's path.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// The open HDF5 file.
    pub fn file(&self) -> &hdf5::File {
        &self.file
    }

    fn shown(&self) -> String {
        self.path.display().to_string()
    }

    /// Whether the file holds the object `name` (`/axial/bands` or `axial/bands`); every
    /// group on the way is checked, so a missing group is simply `false`.
    pub fn has(&self, name: &str) -> bool {
        let mut prefix = String::new();
        for part in name.trim_matches('/').split('/') {
            if !prefix.is_empty() {
                prefix.push('/');
            }
            prefix.push_str(part);
            if !self.file.link_exists(&prefix) {
                return false;
            }
        }
        true
    }

    /// The refusal for a dataset or attribute `name` that the file lacks.
    pub fn missing(&self, name: &str, hint: &str) -> InspectError {
        InspectError::Missing {
            path: self.shown(),
            name: display_name(name),
            hint: hint.to_string(),
        }
    }

    /// The refusal for a dataset `name` that is not as documented.
    pub fn layout(&self, name: &str, reason: impl Into<String>) -> InspectError {
        InspectError::Layout {
            path: self.shown(),
            name: display_name(name),
            reason: reason.into(),
        }
    }

    /// The dataset `name`, or a refusal saying the run did not write it.
    pub fn dataset(&self, name: &str) -> Result<hdf5::Dataset, InspectError> {
        if !self.has(name) {
            return Err(self.missing(name, ""));
        }
        self.file
            .dataset(name.trim_matches('/'))
            .map_err(|e| self.layout(name, format!("is not a readable dataset ({e})")))
    }

    /// Dataset `name` read as `f64` (integers converted), checked to have one axis per
    /// entry of `axes` (the documented axis names, for the message).
    pub fn array(&self, name: &str, axes: &[&str]) -> Result<ArrayD<f64>, InspectError> {
        let ds = self.dataset(name)?;
        let shape = ds.shape();
        if shape.len() != axes.len() {
            return Err(self.layout(
                name,
                format!(
                    "has shape {} where {} was expected",
                    format_shape(&shape),
                    axes.join(" x ")
                ),
            ));
        }
        ds.read_dyn::<f64>()
            .map_err(|e| self.layout(name, format!("cannot be read as numbers ({e})")))
    }

    /// One-axis dataset `name` read as `f64`.
    pub fn vector(&self, name: &str) -> Result<Vec<f64>, InspectError> {
        Ok(self.array(name, &["N"])?.iter().copied().collect())
    }

    /// Bin centres (`/axial/z`, `/fields/x`...): a one-axis dataset that is not empty.
    pub fn centres(&self, name: &str) -> Result<Vec<f64>, InspectError> {
        let v = self.vector(name)?;
        if v.is_empty() {
            return Err(self.layout(name, "is empty"));
        }
        Ok(v)
    }

    /// Refuse unless axis `axis` of dataset `name` has `expected` entries (`what` names them).
    pub fn check_len(
        &self,
        name: &str,
        got: usize,
        expected: usize,
        what: &str,
    ) -> Result<(), InspectError> {
        if got == expected {
            Ok(())
        } else {
            Err(self.layout(
                name,
                format!("has {got} {what} where the file's other datasets have {expected}"),
            ))
        }
    }

    /// The effective case text (root attribute `case`).
    pub fn case_text(&self) -> Result<String, InspectError> {
        attr_string(&self.file, "case").ok_or_else(|| self.missing("attribute case", ""))
    }

    /// The run's case, parsed from the root attribute `case`.
    pub fn case(&self) -> Result<Case, InspectError> {
        let text = self.case_text()?;
        parse_case(&text, "case").map_err(|errs| {
            let why: Vec<String> = errs.iter().map(|e| e.to_string()).collect();
            self.layout(
                "attribute case",
                format!("does not parse as a case: {}", why.join("; ")),
            )
        })
    }

    /// Species names in index order: the `/axial` attribute `species`, else the case's
    /// species; empty when neither is readable.
    pub fn species_names(&self) -> Vec<String> {
        if let Some(names) = self
            .file
            .group("axial")
            .ok()
            .and_then(|g| attr_string(&g, "species"))
        {
            return names.split(',').map(|s| s.trim().to_string()).collect();
        }
        self.case()
            .map(|c| c.species.iter().map(|s| s.name.clone()).collect())
            .unwrap_or_default()
    }

    /// Index of the big species: the `species` attribute of `/axial/bands` if written,
    /// else the species of largest `diameter` in the case.
    pub fn big_species(&self) -> Result<usize, InspectError> {
        if let Some(s) = self
            .bands_attrs()
            .and_then(|ds| attr_number(&ds, "species"))
        {
            return Ok(s as usize);
        }
        let case = self.case()?;
        let mut big = 0;
        for (i, s) in case.species.iter().enumerate() {
            // the last of equal diameters, as the run chooses
            if s.diameter >= case.species[big].diameter {
                big = i;
            }
        }
        Ok(big)
    }

    /// The `/axial/bands` dataset, whose attributes hold the run's band rule, if written.
    pub fn bands_attrs(&self) -> Option<hdf5::Dataset> {
        if self.has("axial/bands") {
            self.file.dataset("axial/bands").ok()
        } else {
            None
        }
    }

    /// Window `requested` of `group` (`slices` or `fields`), from its `rotations_start` and
    /// `rotations_end`; by default the last whole window ([`RunReader::last_whole`]).
    pub fn window(&self, group: &str, requested: Option<usize>) -> Result<Window, InspectError> {
        let starts = self.vector(&format!("{group}/rotations_start"))?;
        let ends = self.vector(&format!("{group}/rotations_end"))?;
        let count = starts.len().min(ends.len());
        if count == 0 {
            return Err(InspectError::Invalid(format!(
                "{}: /{group} holds no windows yet",
                self.shown()
            )));
        }
        let index = requested.unwrap_or_else(|| self.last_whole(group, count));
        if index >= count {
            return Err(InspectError::Invalid(format!(
                "window {index} is out of range: /{group} of {} holds {count} window{} (0 to {})",
                self.shown(),
                if count == 1 { "" } else { "s" },
                count - 1
            )));
        }
        Ok(Window {
            index,
            count,
            start: starts[index],
            end: ends[index],
        })
    }

    /// The last of the `count` windows of `group` that holds the group's
    /// `samples_per_window` samples: a run that stops inside a window writes that window
    /// partial, with fewer. The last window if none is whole or the file does not say.
    pub fn last_whole(&self, group: &str, count: usize) -> usize {
        let per = self
            .file
            .group(group)
            .ok()
            .and_then(|g| g.attr("samples_per_window").ok())
            .and_then(|a| a.read_scalar::<u64>().ok());
        let samples: Option<Vec<u64>> = self
            .file
            .dataset(&format!("{group}/samples"))
            .ok()
            .and_then(|d| d.read_raw().ok());
        match (per, samples) {
            (Some(per), Some(samples)) => samples
                .iter()
                .take(count)
                .rposition(|&n| n == per)
                .unwrap_or(count - 1),
            _ => count - 1,
        }
    }

    /// The units of dataset `name` for an axis or colour-bar label, from its `units`
    /// attribute: an explanation in parentheses is dropped, `-` (dimensionless) gives
    /// `None`, and a formula in `length` and `time` is written in the run's units (`m`, `s`
    /// for SI cases; `d`, small-particle diameters, for reduced ones).
    pub fn units(&self, name: &str) -> Option<String> {
        if !self.has(name) {
            return None;
        }
        let ds = self.file.dataset(name.trim_matches('/')).ok()?;
        let raw = attr_string(&ds, "units")?;
        let base = raw.split(" (").next().unwrap_or(&raw).trim().to_string();
        if base.is_empty() || base == "-" {
            return None;
        }
        let words: Vec<&str> = base
            .split(|c: char| !c.is_ascii_alphabetic())
            .filter(|w| !w.is_empty())
            .collect();
        let formula = !words.is_empty() && words.iter().all(|w| *w == "length" || *w == "time");
        match (formula, self.unit_words()) {
            (true, Some((length, time))) => {
                Some(base.replace("length", length).replace("time", time))
            }
            _ => Some(base),
        }
    }

    /// Names of the length and time units, from the case's model family (SI for the
    /// spring-dashpot laws, reduced for Rapaport's); `None` if the case does not parse.
    fn unit_words(&self) -> Option<(&'static str, &'static str)> {
        let family = *self
            .family
            .get_or_init(|| self.case().ok().map(|c| c.model.family));
        match family? {
            Family::SpringDashpot => Some(("m", "s")),
            Family::Rapaport => Some(("d", "time")),
        }
    }
}

/// `/axial/bands` for a dataset path, `attribute case` unchanged.
fn display_name(name: &str) -> String {
    if name.starts_with("attribute ") {
        name.to_string()
    } else {
        format!("/{}", name.trim_matches('/'))
    }
}

/// `2 x 3 x 4`; a scalar is `scalar`.
pub fn format_shape(shape: &[usize]) -> String {
    if shape.is_empty() {
        return "scalar".into();
    }
    let dims: Vec<String> = shape.iter().map(|n| n.to_string()).collect();
    dims.join(" x ")
}

/// A string attribute (variable-length UTF-8 or ASCII), if present.
pub fn attr_string(loc: &Location, name: &str) -> Option<String> {
    read_string(&loc.attr(name).ok()?)
}

/// The value of a scalar string attribute.
fn read_string(attr: &Attribute) -> Option<String> {
    match attr.dtype().ok()?.to_descriptor().ok()? {
        TypeDescriptor::VarLenUnicode => attr
            .read_scalar::<VarLenUnicode>()
            .ok()
            .map(|s| s.as_str().to_string()),
        TypeDescriptor::VarLenAscii => attr
            .read_scalar::<VarLenAscii>()
            .ok()
            .map(|s| s.as_str().to_string()),
        _ => None,
    }
}

/// A numeric scalar attribute as `f64`, if present.
pub fn attr_number(loc: &Location, name: &str) -> Option<f64> {
    let attr = loc.attr(name).ok()?;
    match attr.dtype().ok()?.to_descriptor().ok()? {
        TypeDescriptor::Integer(_) | TypeDescriptor::Unsigned(_) | TypeDescriptor::Float(_) => {
            attr.read_raw::<f64>().ok()?.first().copied()
        }
        _ => None,
    }
}

/// Any attribute as short text: numbers and strings shown (a string of several lines by
/// its first), up to eight values of an array, other types by their type name.
pub fn attr_display(attr: &Attribute) -> String {
    let Some(desc) = attr.dtype().ok().and_then(|t| t.to_descriptor().ok()) else {
        return "<unreadable>".into();
    };
    let list = |v: Vec<String>| -> String {
        match v.len() {
            1 => v[0].clone(),
            n if n <= 8 => format!("[{}]", v.join(", ")),
            n => format!("[{}, ...] ({n} values)", v[..8].join(", ")),
        }
    };
    let shown = match desc {
        TypeDescriptor::Integer(_) => attr
            .read_raw::<i64>()
            .ok()
            .map(|v| list(v.iter().map(|x| x.to_string()).collect())),
        TypeDescriptor::Unsigned(_) => attr
            .read_raw::<u64>()
            .ok()
            .map(|v| list(v.iter().map(|x| x.to_string()).collect())),
        TypeDescriptor::Float(_) => attr
            .read_raw::<f64>()
            .ok()
            .map(|v| list(v.iter().map(|x| short(*x)).collect())),
        TypeDescriptor::Boolean => attr
            .read_raw::<bool>()
            .ok()
            .map(|v| list(v.iter().map(|x| x.to_string()).collect())),
        TypeDescriptor::VarLenUnicode | TypeDescriptor::VarLenAscii => {
            read_string(attr).map(|s| match s.split_once('\n') {
                Some((first, _)) => format!("{first} ..."),
                None => s,
            })
        }
        _ => None,
    };
    shown.unwrap_or_else(|| format!("<{desc}>"))
}
