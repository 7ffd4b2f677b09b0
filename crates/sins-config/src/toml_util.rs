//! TOML deserialization with errors that name the file, line, column and dotted key path.

use crate::error::{ConfigError, line_col};
use serde::de::DeserializeOwned;
use toml::Spanned;
use toml::de::{DeTable, DeValue};

/// Deserializes `text` into `T`; on failure the error carries `origin`, the line and column the
/// toml crate reports and, when the position can be mapped back, the key path such as
/// `motion.segment[3]` (unknown keys inside an internally tagged table are reported at the table).
pub(crate) fn from_str<T: DeserializeOwned>(text: &str, origin: &str) -> Result<T, ConfigError> {
    toml::from_str::<T>(text).map_err(|e| {
        let span = e.span();
        let (line, column) = span.clone().map(|s| line_col(text, s.start)).unzip();
        ConfigError::Parse {
            origin: origin.to_owned(),
            line,
            column,
            key: span.and_then(|s| locate(text, s.start)),
            message: e.message().trim().to_owned(),
        }
    })
}

/// The dotted path of the deepest key or value whose span contains byte `pos`.
fn locate(text: &str, pos: usize) -> Option<String> {
    let table = DeTable::parse(text).ok()?;
    let mut best = None;
    walk_table(table.get_ref(), "", pos, &mut best);
    best
}

fn walk_table(table: &DeTable<'_>, prefix: &str, pos: usize, best: &mut Option<String>) {
    for (key, value) in table.iter() {
        let path = if prefix.is_empty() {
            key.get_ref().to_string()
        } else {
            format!("{prefix}.{}", key.get_ref())
        };
        if key.span().contains(&pos) || value.span().contains(&pos) {
            *best = Some(path.clone());
        }
        walk_value(value, &path, pos, best);
    }
}

fn walk_value(value: &Spanned<DeValue<'_>>, path: &str, pos: usize, best: &mut Option<String>) {
    match value.get_ref() {
        DeValue::Table(t) => walk_table(t, path, pos, best),
        DeValue::Array(a) => {
            for (i, item) in a.iter().enumerate() {
                let p = format!("{path}[{i}]");
                if item.span().contains(&pos) {
                    *best = Some(p.clone());
                }
                walk_value(item, &p, pos, best);
            }
        }
        _ => {}
    }
}

/// Quotes `s` as a TOML basic string.
pub(crate) fn quote(s: &str) -> String {
    let mut out = String::with_capacity(s.len() + 2);
    out.push('"');
    for c in s.chars() {
        match c {
            '"' => out.push_str("\\\""),
            '\\' => out.push_str("\\\\"),
            '\n' => out.push_str("\\n"),
            '\t' => out.push_str("\\t"),
            '\r' => out.push_str("\\r"),
            c if c.is_control() => out.push_str(&format!("\\u{:04X}", c as u32)),
            c => out.push(c),
        }
    }
    out.push('"');
    out
}
