//! Reading a case file, applying `--set key=value` overrides, and refusing bad input.

use super::schema::Case;
use super::validate::validate;
use std::fmt;
use std::path::Path;
use toml_edit::{Item, TableLike, Value};

/// Why a case was refused: the key (or file and line) at fault and the reason.
#[derive(Debug, Clone, PartialEq)]
pub struct CaseError {
    /// Dotted key (`drum.diameter`), or the file and line for syntax errors.
    pub key: String,
    /// What is wrong with it.
    pub why: String,
}

impl CaseError {
    /// A refusal of `key` because `why`.
    pub fn new(key: impl Into<String>, why: impl Into<String>) -> Self {
        CaseError {
            key: key.into(),
            why: why.into(),
        }
    }
}

impl fmt::Display for CaseError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}: {}", self.key, self.why)
    }
}

impl std::error::Error for CaseError {}

/// A case as the run uses it: the parsed structure and the effective TOML text
/// (the file with every override applied), which is recorded in the outputs.
#[derive(Debug, Clone)]
pub struct LoadedCase {
    /// The parsed, validated case.
    pub case: Case,
    /// The effective case text.
    pub text: String,
    /// The file it came from.
    pub path: String,
}

/// Read, override, parse and validate the case file at `path`.
pub fn load_case(path: &Path, overrides: &[String]) -> Result<LoadedCase, Vec<CaseError>> {
    let name = path.display().to_string();
    let text = std::fs::read_to_string(path).map_err(|e| {
        vec![CaseError::new(
            &name,
            format!("cannot read the case file: {e}"),
        )]
    })?;
    load_text(&text, overrides, &name)
}

/// Override, parse and validate case text read from `name`: what [`load_case`] does once the
/// file is read. A refusal caused by a `--set` names the `--set` (`--set drum.omega: ...`),
/// not the key or a line of the file.
pub fn load_text(
    text: &str,
    overrides: &[String],
    name: &str,
) -> Result<LoadedCase, Vec<CaseError>> {
    let effective = apply_overrides(text, overrides, name).map_err(|e| vec![e])?;
    let case: Case = match toml::from_str(&effective) {
        Ok(case) => case,
        Err(e) => {
            return Err(vec![attribute_toml_error(
                &e, text, &effective, overrides, name,
            )])
        }
    };
    if let Err(errs) = validate(&case) {
        let keys: Vec<&str> = overrides
            .iter()
            .filter_map(|o| o.split_once('=').map(|(k, _)| k.trim()))
            .collect();
        return Err(errs
            .into_iter()
            .map(|e| {
                if keys.contains(&e.key.as_str()) {
                    CaseError::new(format!("--set {}", e.key), e.why)
                } else {
                    e
                }
            })
            .collect());
    }
    Ok(LoadedCase {
        case,
        text: effective,
        path: name.to_string(),
    })
}

/// A TOML/serde error of the overridden text: the file's own (with its line in the file) when
/// the file alone gives it, else the first `--set` that brings it.
fn attribute_toml_error(
    e: &toml::de::Error,
    text: &str,
    effective: &str,
    overrides: &[String],
    name: &str,
) -> CaseError {
    if overrides.is_empty() {
        return describe_toml_error(e, text, name);
    }
    let same = |t: &str| match toml::from_str::<Case>(t) {
        Err(f) => f.message() == e.message(),
        Ok(_) => false,
    };
    if same(text) {
        let e0 = toml::from_str::<Case>(text).err();
        return describe_toml_error(e0.as_ref().unwrap_or(e), text, name);
    }
    for k in 1..=overrides.len() {
        let Ok(t) = apply_overrides(text, &overrides[..k], name) else {
            break;
        };
        if same(&t) {
            let key = overrides[k - 1]
                .split_once('=')
                .map_or(overrides[k - 1].as_str(), |(k, _)| k.trim());
            return CaseError::new(format!("--set {key}"), e.message().trim().to_string());
        }
    }
    let mut err = describe_toml_error(e, effective, name);
    err.key.push_str(" (with the --set values applied)");
    err
}

/// Parse and validate case text; `name` labels syntax errors.
pub fn parse_case(text: &str, name: &str) -> Result<Case, Vec<CaseError>> {
    let case: Case = toml::from_str(text).map_err(|e| vec![describe_toml_error(&e, text, name)])?;
    validate(&case)?;
    Ok(case)
}

/// Turn a TOML/serde error into a refusal naming the file, line and (via serde) the key.
fn describe_toml_error(e: &toml::de::Error, text: &str, name: &str) -> CaseError {
    let line = e
        .span()
        .map(|s| {
            let n = 1 + text.as_bytes()[..s.start.min(text.len())]
                .iter()
                .filter(|&&b| b == b'\n')
                .count();
            format!(" line {n}")
        })
        .unwrap_or_default();
    CaseError::new(format!("{name}{line}"), e.message().trim().to_string())
}

/// Apply `key=value` overrides to the case text. `key` is a dotted path (`run.rotations`,
/// `species.1.gamma_s`: arrays of tables are indexed from 0); `value` is a TOML value, and a
/// bare word is taken as a string.
pub fn apply_overrides(text: &str, overrides: &[String], name: &str) -> Result<String, CaseError> {
    if overrides.is_empty() {
        return Ok(text.to_string());
    }
    let mut doc: toml_edit::DocumentMut = text.parse().map_err(|e: toml_edit::TomlError| {
        CaseError::new(name, format!("not valid TOML: {}", e.message()))
    })?;
    for ov in overrides {
        let (key, raw) = ov
            .split_once('=')
            .ok_or_else(|| CaseError::new(format!("--set {ov}"), "expected section.key=value"))?;
        let key = key.trim();
        let parts: Vec<&str> = key.split('.').map(str::trim).collect();
        if parts.iter().any(|p| p.is_empty()) {
            return Err(CaseError::new(
                format!("--set {key}"),
                "empty part in the key",
            ));
        }
        set_in_table(doc.as_table_mut(), &parts, parse_value(raw.trim()))
            .map_err(|why| CaseError::new(format!("--set {key}"), why))?;
    }
    Ok(doc.to_string())
}

fn parse_value(raw: &str) -> Value {
    format!("v = {raw}")
        .parse::<toml_edit::DocumentMut>()
        .ok()
        .and_then(|doc| doc.get("v").and_then(|i| i.as_value()).cloned())
        .unwrap_or_else(|| Value::from(raw))
}

fn set_in_table(table: &mut dyn TableLike, parts: &[&str], value: Value) -> Result<(), String> {
    let (head, rest) = (parts[0], &parts[1..]);
    if rest.is_empty() {
        table.insert(head, Item::Value(value));
        return Ok(());
    }
    if table.get(head).is_none() {
        table.insert(head, Item::Table(toml_edit::Table::new()));
    }
    let Some(item) = table.get_mut(head) else {
        return Err(format!("`{head}` cannot be made a table"));
    };
    match item {
        Item::Table(t) => set_in_table(t, rest, value),
        Item::Value(Value::InlineTable(t)) => set_in_table(t, rest, value),
        Item::ArrayOfTables(arr) => {
            let len = arr.len();
            let idx: usize = rest[0].parse().map_err(|_| {
                format!("`{}` must be an index (0..{len}) into [[{head}]]", rest[0])
            })?;
            let t = arr.get_mut(idx).ok_or_else(|| {
                format!("index {idx} is out of range: there are {len} [[{head}]]")
            })?;
            if rest.len() == 1 {
                return Err("cannot replace a whole table".into());
            }
            set_in_table(t, &rest[1..], value)
        }
        _ => Err(format!("`{head}` is a value, not a table")),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_run_is_the_same_whatever_the_title_and_comments() {
        let text = crate::validate::case_text("rapaport2002-A").unwrap();
        let case = parse_case(text, "A").unwrap();
        let retitled = format!("# another header\n{}", text).replacen(
            &format!("title = {:?}", case.title),
            "title = \"renamed\"",
            1,
        );
        let other = parse_case(&retitled, "retitled").unwrap();
        assert_eq!(other.title, "renamed");
        assert!(case.same_run_as(&other));
        let reseeded = apply_overrides(text, &["seed=7".into()], "reseeded").unwrap();
        let reseeded = parse_case(&reseeded, "reseeded").unwrap();
        assert!(!case.same_run_as(&reseeded), "the seed changes the run");
    }
}
