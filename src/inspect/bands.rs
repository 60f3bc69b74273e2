//! `tumbler bands FILE`: the band count of the big species over time, as the run wrote it
//! (`/axial/bands`) or recomputed from `/axial/volume_fraction` with a given rule.

use super::number::short;
use super::reader::attr_number;
use super::{InspectError, RunReader};
use crate::diag::bands::{count_bands, BandRule};
use std::fmt;

/// Threshold used when neither the command line nor the file gives one.
pub const DEFAULT_THRESHOLD: f64 = 0.2;
/// Fewest slices of a band when neither the command line nor the file gives it.
pub const DEFAULT_MIN_SLICES: usize = 2;

/// The rule asked for on the command line; an option left out takes the file's value.
#[derive(Debug, Clone, Copy, Default)]
pub struct BandsOptions {
    /// `--threshold C`.
    pub threshold: Option<f64>,
    /// `--min-slices N`.
    pub min_slices: Option<usize>,
}

/// The band count at each axial sample, and where it came from.
#[derive(Debug, Clone)]
pub struct BandTable {
    /// One line saying which species, which rule and which dataset.
    pub source: String,
    /// Sample times, in rotations.
    pub rotations: Vec<f64>,
    /// Band count at each sample.
    pub bands: Vec<u64>,
}

impl fmt::Display for BandTable {
    /// `# source`, then `rotations  bands` and one line per sample.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(f, "# {}", self.source)?;
        writeln!(f, "rotations  bands")?;
        for (r, b) in self.rotations.iter().zip(&self.bands) {
            writeln!(f, "{r:>9.3}  {b:>5}")?;
        }
        Ok(())
    }
}

/// The band table of the file open in `reader`: `/axial/bands` when no rule is given and
/// the run wrote it, else recomputed from `/axial/volume_fraction`.
pub fn band_table(reader: &RunReader, opts: &BandsOptions) -> Result<BandTable, InspectError> {
    let rotations = reader.vector("axial/rotations")?;
    let stored = reader.bands_attrs();
    let names = reader.species_names();
    let rule_given = opts.threshold.is_some() || opts.min_slices.is_some();
    if let (Some(ds), false) = (&stored, rule_given) {
        let bands: Vec<u64> = ds
            .read_raw::<u64>()
            .map_err(|e| reader.layout("axial/bands", format!("cannot be read ({e})")))?;
        let n = rotations.len().min(bands.len());
        let rule = stored_rule(ds)
            .map(|r| format!(", {}", describe(&r)))
            .unwrap_or_default();
        let species = attr_number(ds, "species")
            .map(|s| format!(" of {}", species_label(s as usize, &names)))
            .unwrap_or_default();
        return Ok(BandTable {
            source: format!("band count{species} as the run wrote it in /axial/bands{rule}"),
            rotations: rotations[..n].to_vec(),
            bands: bands[..n].to_vec(),
        });
    }
    let rule = effective_rule(reader, opts)?;
    let species = reader.big_species()?;
    let vf = reader.array("axial/volume_fraction", &["T", "S", "Z"])?;
    let (nt, ns) = (vf.shape()[0], vf.shape()[1]);
    if species >= ns {
        return Err(reader.layout(
            "axial/volume_fraction",
            format!("has {ns} species, so the big species {species} is not in it"),
        ));
    }
    let n = rotations.len().min(nt);
    let bands = (0..n)
        .map(|t| {
            let profile: Vec<f64> = vf
                .slice(ndarray::s![t, species, ..])
                .iter()
                .copied()
                .collect();
            count_bands(&profile, &rule) as u64
        })
        .collect();
    Ok(BandTable {
        source: format!(
            "band count of {} recomputed from /axial/volume_fraction, {}",
            species_label(species, &names),
            describe(&rule)
        ),
        rotations: rotations[..n].to_vec(),
        bands,
    })
}

/// The rule: each option from the command line, else the `/axial/bands` attributes, else
/// the defaults (and the ends from the case).
pub fn effective_rule(reader: &RunReader, opts: &BandsOptions) -> Result<BandRule, InspectError> {
    if let Some(c) = opts.threshold {
        if !(c.is_finite() && c >= 0.0) {
            return Err(InspectError::Invalid(format!(
                "--threshold {c}: the threshold must be a number of at least 0"
            )));
        }
    }
    if opts.min_slices == Some(0) {
        return Err(InspectError::Invalid(
            "--min-slices 0: a band needs at least 1 slice".into(),
        ));
    }
    let stored = reader.bands_attrs();
    let attr = |name: &str| stored.as_ref().and_then(|ds| attr_number(ds, name));
    let periodic = match attr("periodic") {
        Some(p) => p != 0.0,
        None => reader
            .case()
            .map_err(|e| {
                InspectError::Invalid(format!(
                    "cannot tell whether the ends are periodic (no /axial/bands attributes): {e}"
                ))
            })?
            .drum
            .periodic(),
    };
    Ok(BandRule {
        threshold: opts
            .threshold
            .or_else(|| attr("threshold"))
            .unwrap_or(DEFAULT_THRESHOLD),
        min_slices: opts
            .min_slices
            .or_else(|| attr("min_slices").map(|n| n as usize))
            .unwrap_or(DEFAULT_MIN_SLICES),
        periodic,
    })
}

/// The rule recorded on `/axial/bands`, if all three attributes are there.
fn stored_rule(ds: &hdf5::Dataset) -> Option<BandRule> {
    Some(BandRule {
        threshold: attr_number(ds, "threshold")?,
        min_slices: attr_number(ds, "min_slices")? as usize,
        periodic: attr_number(ds, "periodic")? != 0.0,
    })
}

fn describe(rule: &BandRule) -> String {
    format!(
        "threshold {}, min_slices {}, {} ends",
        short(rule.threshold),
        rule.min_slices,
        if rule.periodic {
            "periodic"
        } else {
            "non-periodic"
        }
    )
}

/// `species 1 (big)`, or `species 1` when the names are unknown.
pub(crate) fn species_label(index: usize, names: &[String]) -> String {
    match names.get(index) {
        Some(name) => format!("species {index} ({name})"),
        None => format!("species {index}"),
    }
}
