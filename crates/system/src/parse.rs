//! TOML text into the config types, with errors that name the key (`particles[0].position:
//! expected 3 numbers, got 2`), say where it is in the file and what to do.

use crate::error::{Result, SystemError};
use serde::Serialize;
use serde::de::DeserializeOwned;
use toml::Value;

/// Parses `text` as a `T`; a shape error (a wrong type, length, a missing or unknown
/// key) names the path of the key.
pub(crate) fn from_toml<T: DeserializeOwned + Serialize>(text: &str) -> Result<T> {
    let deserializer = toml::Deserializer::parse(text).map_err(|e| syntax(text, &e))?;
    let parsed: T = serde_path_to_error::deserialize(deserializer).map_err(|e| {
        let path = e.path().to_string();
        let inner = e.into_inner();
        SystemError::Parse(shape(text, &path, &inner))
    })?;
    // toml fills a fixed-size array from the first elements of a longer one and drops
    // the rest; compare every array of the text with what was read.
    let written: Value = toml::from_str(text).map_err(|e| syntax(text, &e))?;
    let read = Value::try_from(&parsed)
        .map_err(|e| SystemError::Parse(format!("the parsed config does not serialise: {e}")))?;
    let keys = crate::key_lines::KeyLines::of(text);
    same_lengths(&written, &read, &keys, &mut String::new())?;
    Ok(parsed)
}

/// Errs at the first array of `written` that `read` holds with another length.
fn same_lengths(
    written: &Value,
    read: &Value,
    keys: &crate::key_lines::KeyLines,
    path: &mut String,
) -> Result<()> {
    let start = path.len();
    match (written, read) {
        (Value::Table(w), Value::Table(r)) => {
            for (key, w) in w {
                if let Some(r) = r.get(key) {
                    if !path.is_empty() {
                        path.push('.');
                    }
                    path.push_str(key);
                    same_lengths(w, r, keys, path)?;
                    path.truncate(start);
                }
            }
        }
        (Value::Array(w), Value::Array(r)) => {
            if w.len() != r.len() {
                let message = format!(
                    "invalid length {}, expected an array of length {}",
                    w.len(),
                    r.len()
                );
                let (what, hint) = explain(path, &message);
                let at = keys
                    .line(path)
                    .map_or(String::new(), |line| format!(" (line {line})"));
                return Err(SystemError::Parse(format!("{path}: {what}{at}; {hint}")));
            }
            for (i, (w, r)) in w.iter().zip(r).enumerate() {
                path.push_str(&format!("[{i}]"));
                same_lengths(w, r, keys, path)?;
                path.truncate(start);
            }
        }
        _ => {}
    }
    Ok(())
}

/// A TOML syntax error: toml's own message, which shows the line.
fn syntax(text: &str, e: &toml::de::Error) -> SystemError {
    SystemError::Parse(format!(
        "{}{}; fix the TOML syntax there",
        e.message().trim_end(),
        location(text, e)
    ))
}

/// " (line L, column C)" of the error's span, if it has one.
fn location(text: &str, e: &toml::de::Error) -> String {
    let Some(span) = e.span() else {
        return String::new();
    };
    let before = &text[..span.start.min(text.len())];
    let line = before.matches('\n').count() + 1;
    let column = before.len() - before.rfind('\n').map_or(0, |i| i + 1) + 1;
    format!(" (line {line}, column {column})")
}

/// The message of a shape error at `path` ("." is the top level).
fn shape(text: &str, path: &str, e: &toml::de::Error) -> String {
    let message = e.message().trim_end();
    // The path of an unknown key ends with the key itself: name its table.
    let path = match message.strip_prefix("unknown field `") {
        Some(rest) => {
            let key = rest.split('`').next().unwrap_or("");
            match path.strip_suffix(key) {
                Some(parent) => parent.strip_suffix('.').unwrap_or(parent),
                None => path,
            }
        }
        None => path,
    };
    let (what, hint) = explain(path, message);
    let at = location(text, e);
    match path {
        "." | "" => format!("{what}{at}; {hint}"),
        _ => format!("{path}: {what}{at}; {hint}"),
    }
}

/// serde's message in the config's words, and what to do about it.
fn explain(path: &str, message: &str) -> (String, String) {
    const KEYS: &str = "the keys, their types and units are listed in docs/config.md";
    if let Some(rest) = message.strip_prefix("invalid length ") {
        // "invalid length 2, expected an array of length 3"
        let (got, expected) = rest.split_once(", expected ").unwrap_or((rest, ""));
        if let Some(n) = expected.strip_prefix("an array of length ") {
            let kind = if path.ends_with("periodic") {
                "booleans"
            } else {
                "numbers"
            };
            let example = if kind == "booleans" {
                "[true, true, false]"
            } else {
                "[x, y, z]"
            };
            return (
                format!("expected {n} {kind}, got {got}"),
                format!("write it as {example}"),
            );
        }
        return (
            format!("expected {expected}, got {got} values"),
            KEYS.into(),
        );
    }
    if let Some(rest) = message.strip_prefix("invalid type: ") {
        // "invalid type: string \"a\", expected f64"
        let (got, expected) = rest.split_once(", expected ").unwrap_or((rest, "?"));
        return (
            format!("expected {}, got {got}", plain_type(expected)),
            KEYS.into(),
        );
    }
    if let Some(rest) = message.strip_prefix("missing field ") {
        let where_ = match path {
            "." | "" => " at the top level (before the first [section])".to_string(),
            _ => String::new(),
        };
        return (
            format!("the required key {rest} is missing{where_}"),
            format!("add it; {KEYS}"),
        );
    }
    if let Some(rest) = message.strip_prefix("unknown field ") {
        // "unknown field `x`, expected one of `a`, `b`"
        let (key, expected) = rest.split_once(", expected ").unwrap_or((rest, ""));
        let hint = match expected {
            "" => format!("remove it; {KEYS}"),
            e => format!("check its spelling (expected {e}) or remove it"),
        };
        return (format!("unknown key {key}"), hint);
    }
    (message.to_string(), KEYS.into())
}

/// serde's names of the types a config uses, in plain words.
fn plain_type(expected: &str) -> String {
    match expected {
        "f64" | "f32" => "a number".into(),
        "u64" | "u32" | "usize" | "u16" | "u8" => "a whole number ≥ 0".into(),
        "i64" | "i32" => "a whole number".into(),
        "a boolean" => "true or false".into(),
        "a string" => "a string in quotes".into(),
        "a sequence" => "an array".into(),
        other if other.starts_with("an array of length ") => format!(
            "an array of {} values",
            other.trim_start_matches("an array of length ")
        ),
        other if other.starts_with("struct ") => {
            "a table (a [section] or { key = value, … })".into()
        }
        other => other.into(),
    }
}

#[cfg(test)]
mod tests {
    use crate::Config;

    const BASE: &str = "t_end = 1.0\n[material]\nmodel = \"linear\"\nstiffness = 1e4\n\
                        density = 1000.0\n";

    fn error(extra: &str) -> String {
        Config::from_toml(&format!("{BASE}{extra}"))
            .unwrap_err()
            .to_string()
    }

    #[test]
    fn a_short_position_names_its_key_and_line() {
        let err = error("[[particles]]\nradius = 0.1\nposition = [0.0, 0.0]\n");
        assert!(
            err.contains("particles[0].position: expected 3 numbers, got 2 (line 8, column 12)")
                && err.contains("write it as [x, y, z]"),
            "{err}"
        );
        let err = error(
            "[[particles]]\nradius = 0.1\nposition = [0.0, 0.0, 0.0]\n[[particles]]\n\
             radius = 0.1\nposition = [1.0, 0.0, 0.0]\nvelocity = [1.0, 2.0, 3.0, 4.0]\n",
        );
        assert!(
            err.contains("particles[1].velocity: expected 3 numbers, got 4 (line 12)"),
            "{err}"
        );
    }

    #[test]
    fn wrong_types_missing_and_unknown_keys_are_named() {
        let err = error("[gas]\ncount = \"many\"\n");
        assert!(
            err.contains("gas.count: expected a whole number ≥ 0, got string \"many\""),
            "{err}"
        );
        let err = error("[[particles]]\nposition = [0.0, 0.0, 0.0]\n");
        assert!(
            err.contains("particles[0]: the required key `radius` is missing")
                && err.contains("add it"),
            "{err}"
        );
        let err = error("[box]\nsize = [1.0, 1.0, 1.0]\nperiodic = [true, false]\n");
        assert!(
            err.contains("box.periodic: expected 3 booleans, got 2"),
            "{err}"
        );
        let err = Config::from_toml("[material]\nmodel = \"linear\"\n")
            .unwrap_err()
            .to_string();
        assert!(
            err.contains("the required key `t_end` is missing at the top level"),
            "{err}"
        );
        let err = error("[output]\ntrajectori = \"a.xyz\"\n");
        assert!(
            err.contains("config: output: unknown key `trajectori`")
                && err.contains("`trajectory`"),
            "{err}"
        );
    }

    #[test]
    fn a_syntax_error_says_where() {
        let err = error("[[particles]\n");
        assert!(
            err.contains("line 6") && err.contains("TOML syntax"),
            "{err}"
        );
    }
}
