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
    let text = apply_overrides(&text, overrides, &name).map_err(|e| vec![e])?;
    let case = parse_case(&text, &name)?;
    Ok(LoadedCase {
        case,
        text,
        path: name,
    })
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
    match table.get_mut(head).expect("present") {
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
