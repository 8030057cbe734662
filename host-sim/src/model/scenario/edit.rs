//! Key edits of a scenario's text, `TABLE.KEY=VALUE` (`host-sim score --set gains.local.kp=36`):
//! the what-if a researcher or an engineer tuning a design tries most, without copying and
//! editing the file by hand.
//!
//! The value is read as a TOML value (`36`, `[0.2, 0.2, 0.05]`, `"hover"`, `true`); a bare word
//! that is not one (`hover`) is taken as a string. Missing tables on the path are created, so an
//! optional table can be added (`controller.airmode=false`). What the edit makes of the file is
//! then checked as any scenario is ([`Scenario::parse`]): an unknown key (a typo) or a value out
//! of range is refused there, by name.

use std::str::FromStr;

use anyhow::{anyhow, bail, Result};

use super::Scenario;

/// One edit: the dotted path of a key and its new value.
#[derive(Clone, Debug, PartialEq)]
pub struct KeyEdit {
    /// The key's path, table by table (`["gains", "local", "kp"]`).
    pub path: Vec<String>,
    /// The new value.
    pub value: toml::Value,
}

impl FromStr for KeyEdit {
    type Err = anyhow::Error;

    /// Parses `TABLE.KEY=VALUE`. Errors: no `=`, an empty key or path segment, a value that is
    /// neither a TOML value nor a bare word.
    fn from_str(s: &str) -> Result<Self> {
        let (key, value) = s
            .split_once('=')
            .ok_or_else(|| anyhow!("{s:?}: expected TABLE.KEY=VALUE"))?;
        let path: Vec<String> = key.trim().split('.').map(|p| p.trim().to_owned()).collect();
        if path.iter().any(String::is_empty) {
            bail!("{s:?}: empty key in {key:?}");
        }
        let value = value.trim();
        let parsed = toml::from_str::<toml::Table>(&format!("v = {value}"))
            .ok()
            .and_then(|mut t| t.remove("v"));
        let value = match parsed {
            Some(v) => v,
            None if !value.is_empty()
                && value
                    .chars()
                    .all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-') =>
            {
                toml::Value::String(value.to_owned())
            }
            None => bail!("{s:?}: {value:?} is not a TOML value (quote strings with spaces)"),
        };
        Ok(Self { path, value })
    }
}

/// `text` (a scenario file's TOML) with `edits` applied in order. Errors: `text` is not TOML;
/// a path runs through a key that is not a table (named, with what it is).
pub fn apply_edits(text: &str, edits: &[KeyEdit]) -> Result<String> {
    let mut root: toml::Table = toml::from_str(text).map_err(|e| anyhow!("{e}"))?;
    for edit in edits {
        let (leaf, tables) = edit
            .path
            .split_last()
            .ok_or_else(|| anyhow!("an edit without a key"))?;
        let mut table = &mut root;
        for (depth, name) in tables.iter().enumerate() {
            let entry = table
                .entry(name.clone())
                .or_insert_with(|| toml::Value::Table(toml::Table::new()));
            table = match entry {
                toml::Value::Table(t) => t,
                other => bail!(
                    "{} is a {}, not a table: cannot set {}",
                    edit.path[..=depth].join("."),
                    other.type_str(),
                    edit.path.join(".")
                ),
            };
        }
        table.insert(leaf.clone(), edit.value.clone());
    }
    toml::to_string(&root).map_err(|e| anyhow!("{e}"))
}

impl Scenario {
    /// The scenario file at `path` with `edits` applied ([`apply_edits`]), validated as
    /// [`Scenario::load`] validates a file. Errors: the file cannot be read; an edit's path runs
    /// through a value; the edited scenario is refused (an unknown key, a value out of range),
    /// named with the file and the edits.
    pub fn load_with_edits(path: &std::path::Path, edits: &[KeyEdit]) -> Result<Self> {
        if edits.is_empty() {
            return Self::load(path);
        }
        let text = std::fs::read_to_string(path)
            .map_err(|e| anyhow!("cannot read scenario file {}: {e}", path.display()))?;
        Self::parse_with_edits(&text, &path.display().to_string(), edits)
    }

    /// Scenario text `text` (named `origin` in errors) with `edits` applied, validated as
    /// [`Scenario::parse`] validates it; without edits, exactly [`Scenario::parse`]. Errors: an
    /// edit's path runs through a value; the edited scenario is refused, named with `origin` and
    /// the edits.
    pub fn parse_with_edits(text: &str, origin: &str, edits: &[KeyEdit]) -> Result<Self> {
        if edits.is_empty() {
            return Self::parse(text, origin);
        }
        let edited = apply_edits(text, edits).map_err(|e| anyhow!("scenario {origin}: {e}"))?;
        Self::parse(&edited, &format!("{origin} with {}", describe_edits(edits)))
    }
}

/// `edits` as the command line gave them, `a.b=1, c.d="x"`.
pub fn describe_edits(edits: &[KeyEdit]) -> String {
    edits
        .iter()
        .map(|e| format!("{}={}", e.path.join("."), e.value))
        .collect::<Vec<_>>()
        .join(", ")
}

#[cfg(test)]
mod tests;
