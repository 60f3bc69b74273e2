//! `tumbler info FILE`: the run's identity (root attributes), its time span, the case and
//! every dataset with its shape, type, units and definition.

use super::number::short;
use super::reader::{attr_display, attr_string, format_shape};
use super::{InspectError, RunReader};
use hdf5::{Group, LocationType};
use std::fmt::Write;

/// What `tumbler info` prints beyond the summary.
#[derive(Debug, Clone, Copy, Default)]
pub struct InfoOptions {
    /// Print the whole case text (else its first [`CASE_LINES`] lines).
    pub full_case: bool,
    /// List every numbered group (`/snapshots/NNNNNN`), not only the first (the others are
    /// counted when there are more than three).
    pub all_groups: bool,
}

/// Lines of the case text shown without `--case`.
pub const CASE_LINES: usize = 12;

/// Root attributes shown in the summary, in this order (the case is shown apart).
const SUMMARY_ATTRS: [&str; 4] = ["version", "git_hash", "ranks", "steps"];

/// The text `tumbler info` prints for the file open in `reader`.
pub fn info(reader: &RunReader, opts: &InfoOptions) -> Result<String, InspectError> {
    let file = reader.file();
    let mut out = String::new();
    let _ = writeln!(out, "file:       {}", reader.path().display());
    for name in SUMMARY_ATTRS {
        let value = file
            .attr(name)
            .map(|a| attr_display(&a))
            .unwrap_or_else(|_| "(not written)".into());
        let _ = writeln!(out, "{:<11} {value}", format!("{name}:"));
    }
    let _ = writeln!(out, "time:       {}", time_span(reader));
    let names = file.attr_names().unwrap_or_default();
    let others: Vec<String> = names
        .iter()
        .filter(|n| *n != "case" && !SUMMARY_ATTRS.contains(&n.as_str()))
        .filter_map(|n| {
            file.attr(n)
                .ok()
                .map(|a| format!("{n} = {}", attr_display(&a)))
        })
        .collect();
    if !others.is_empty() {
        let _ = writeln!(out, "attributes: {}", others.join(", "));
    }
    case_section(&mut out, attr_string(file, "case"), opts.full_case);
    let _ = writeln!(out, "datasets:");
    walk(&mut out, file, "", opts)
        .map_err(|e| reader.layout("/", format!("cannot be listed ({e})")))?;
    Ok(out)
}

/// `first to last rotations (N axial samples)` from `/axial/rotations`.
fn time_span(reader: &RunReader) -> String {
    match reader.vector("axial/rotations") {
        Ok(r) if r.is_empty() => "no axial samples yet".into(),
        Ok(r) => format!(
            "{} to {} rotations ({} axial sample{})",
            short(r[0]),
            short(r[r.len() - 1]),
            r.len(),
            if r.len() == 1 { "" } else { "s" }
        ),
        Err(e) => format!("unknown ({e})"),
    }
}

fn case_section(out: &mut String, case: Option<String>, full: bool) {
    let Some(text) = case else {
        let _ = writeln!(out, "case:       (not written)");
        return;
    };
    let lines: Vec<&str> = text.lines().collect();
    let shown = if full {
        lines.len()
    } else {
        lines.len().min(CASE_LINES)
    };
    if shown < lines.len() {
        let _ = writeln!(
            out,
            "case (first {shown} of {} lines; --case prints it all):",
            lines.len()
        );
    } else {
        let _ = writeln!(out, "case:");
    }
    for line in &lines[..shown] {
        let _ = writeln!(out, "    {line}");
    }
}

/// List the members of `group` (path `prefix`) depth first, in name order.
fn walk(out: &mut String, group: &Group, prefix: &str, opts: &InfoOptions) -> hdf5::Result<()> {
    let names = group.member_names()?;
    // numbered groups (`/snapshots/000042`): the first is listed, the others counted
    let numbered: Vec<&String> = names
        .iter()
        .filter(|n| n.bytes().all(|b| b.is_ascii_digit()))
        .filter(|n| matches!(group.loc_type_by_name(n), Ok(LocationType::Group)))
        .collect();
    let collapse = !opts.all_groups && numbered.len() > 3;
    for name in &names {
        let path = format!("{prefix}/{name}");
        match group.loc_type_by_name(name)? {
            LocationType::Group => {
                if collapse && numbered.contains(&name) && *name != *numbered[0] {
                    if *name == *numbered[1] {
                        let _ = writeln!(
                            out,
                            "{prefix}/{name} ... {prefix}/{}  {} more groups like {prefix}/{}/ \
                             (--all lists them)",
                            numbered[numbered.len() - 1],
                            numbered.len() - 1,
                            numbered[0]
                        );
                    }
                    continue;
                }
                let sub = group.group(name)?;
                let _ = writeln!(out, "{path}/  (group)");
                describe(out, &sub, "    ");
                walk(out, &sub, &path, opts)?;
            }
            LocationType::Dataset => {
                let ds = group.dataset(name)?;
                let dtype = ds
                    .dtype()
                    .and_then(|t| t.to_descriptor())
                    .map(|d| d.to_string())
                    .unwrap_or_else(|_| "?".into());
                let _ = writeln!(out, "  {path}  [{}]  {dtype}", format_shape(&ds.shape()));
                describe(out, &ds, "      ");
            }
            LocationType::NamedDatatype => {
                let _ = writeln!(out, "  {path}  (named datatype)");
            }
            #[allow(unreachable_patterns)]
            _ => {}
        }
    }
    Ok(())
}

/// The `units` and `definition` of `loc`, then its other attributes, each line indented.
fn describe(out: &mut String, loc: &hdf5::Location, indent: &str) {
    for key in ["units", "definition"] {
        if let Some(v) = attr_string(loc, key) {
            let _ = writeln!(out, "{indent}{key}: {v}");
        }
    }
    let rest = attr_list(loc, &["units", "definition"]);
    if !rest.is_empty() {
        let _ = writeln!(out, "{indent}attributes:{rest}");
    }
}

/// ` a = 1, b = x` for the attributes of `loc` not in `skip` (empty if none).
fn attr_list(loc: &hdf5::Location, skip: &[&str]) -> String {
    let items: Vec<String> = loc
        .attr_names()
        .unwrap_or_default()
        .iter()
        .filter(|n| !skip.contains(&n.as_str()))
        .filter_map(|n| {
            loc.attr(n)
                .ok()
                .map(|a| format!("{n} = {}", attr_display(&a)))
        })
        .collect();
    if items.is_empty() {
        String::new()
    } else {
        format!(" {}", items.join(", "))
    }
}
