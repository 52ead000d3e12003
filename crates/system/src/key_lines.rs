//! Where each key of a config text is, so that a message about a value can give its
//! line: `line 5: material.young must be greater than zero`.

use std::collections::BTreeMap;
use toml::Spanned;
use toml::de::{DeTable, DeValue};

/// The line of every value of a config text, by its path: `t_end`, `material.young`,
/// `particles[1].velocity`, `particles[1].velocity[2]`, `walls[0].normal`. Tables are
/// not values: `material` and `particles[1]` have no entry.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct KeyLines {
    lines: BTreeMap<String, usize>,
}

impl KeyLines {
    /// The values of `text`; empty where it is not valid TOML.
    pub fn of(text: &str) -> Self {
        let mut keys = Self::default();
        if let Ok(root) = DeTable::parse(text) {
            let starts = line_starts(text);
            keys.table(root.get_ref(), "", &starts);
        }
        keys
    }

    fn table(&mut self, table: &DeTable<'_>, prefix: &str, starts: &[usize]) {
        for (key, value) in table {
            let path = match prefix {
                "" => key.get_ref().to_string(),
                p => format!("{p}.{}", key.get_ref()),
            };
            self.value(value, path, line_of(starts, key.span().start), starts);
        }
    }

    fn value(&mut self, value: &Spanned<DeValue<'_>>, path: String, line: usize, starts: &[usize]) {
        match value.get_ref() {
            DeValue::Table(t) => self.table(t, &path, starts),
            DeValue::Array(items) => {
                let of_tables = items
                    .iter()
                    .all(|v| matches!(v.get_ref(), DeValue::Table(_)));
                for (i, item) in items.iter().enumerate() {
                    let at = line_of(starts, item.span().start);
                    self.value(item, format!("{path}[{i}]"), at, starts);
                }
                if !of_tables || items.is_empty() {
                    self.lines.insert(path, line);
                }
            }
            _ => {
                self.lines.insert(path, line);
            }
        }
    }

    /// The line of the value at `path`, if the text sets it.
    pub fn line(&self, path: &str) -> Option<usize> {
        self.lines.get(path).copied()
    }

    /// Whether the text sets the value at `path`.
    pub fn contains(&self, path: &str) -> bool {
        self.lines.contains_key(path)
    }

    /// The paths of the values the text sets, in order.
    pub fn paths(&self) -> impl Iterator<Item = &str> {
        self.lines.keys().map(String::as_str)
    }

    /// `message` after "line N: ", N the line of the first key it names that the text
    /// sets (a path such as `material.young` or `particles[0].radius`, or a top-level
    /// value such as `gravity`); unchanged if it names none.
    pub fn locate(&self, message: &str) -> String {
        let bytes = message.as_bytes();
        let in_path = |b: u8| b.is_ascii_alphanumeric() || matches!(b, b'_' | b'.' | b'[' | b']');
        let mut i = 0;
        while i < bytes.len() {
            let starts_here = (bytes[i].is_ascii_alphabetic() || bytes[i] == b'_')
                && (i == 0 || !in_path(bytes[i - 1]));
            if !starts_here {
                i += 1;
                continue;
            }
            let mut end = i;
            while end < bytes.len() && in_path(bytes[end]) {
                end += 1;
            }
            let token = message[i..end].trim_end_matches('.');
            if let Some(line) = self.line(token) {
                return format!("line {line}: {message}");
            }
            i = end;
        }
        message.to_string()
    }
}

/// The byte offset at which each line of `text` starts.
fn line_starts(text: &str) -> Vec<usize> {
    std::iter::once(0)
        .chain(text.match_indices('\n').map(|(i, _)| i + 1))
        .collect()
}

/// The line (from 1) of byte `offset`.
fn line_of(starts: &[usize], offset: usize) -> usize {
    starts.partition_point(|&s| s <= offset)
}

#[cfg(test)]
mod tests {
    use super::*;

    const TEXT: &str = "t_end = 1.0\ngravity = [0.0, 0.0,\n  -9.81]\n[material]\nmodel = \
                        \"hertz\"\nyoung = -1.0\n[[particles]]\nradius = 0.1\n[[particles]]\n\
                        radius = 0.2\nvelocity = [1.0, 2.0, 3.0]\n";

    #[test]
    fn every_value_has_its_line_and_tables_none() {
        let keys = KeyLines::of(TEXT);
        assert_eq!(keys.line("t_end"), Some(1));
        assert_eq!(keys.line("gravity"), Some(2));
        assert_eq!(keys.line("gravity[2]"), Some(3));
        assert_eq!(keys.line("material.young"), Some(6));
        assert_eq!(keys.line("particles[0].radius"), Some(8));
        assert_eq!(keys.line("particles[1].radius"), Some(10));
        assert_eq!(keys.line("particles[1].velocity"), Some(11));
        assert_eq!(keys.line("material"), None);
        assert_eq!(keys.line("particles"), None);
        assert_eq!(keys.line("particles[1]"), None);
        assert!(KeyLines::of("t_end = [").paths().next().is_none());
    }

    #[test]
    fn a_message_gets_the_line_of_the_first_key_the_text_sets() {
        let keys = KeyLines::of(TEXT);
        assert_eq!(
            keys.locate("material.young must be greater than zero, got -1.0"),
            "line 6: material.young must be greater than zero, got -1.0"
        );
        // Not set: material.density; set: particles[1].radius.
        assert_eq!(
            keys.locate("set material.density or particles[1].radius."),
            "line 10: set material.density or particles[1].radius."
        );
        // A word that is a table is no value; `gravity` is.
        assert_eq!(
            keys.locate("the material: gravity = [0, 1e308, 0]"),
            "line 2: the material: gravity = [0, 1e308, 0]"
        );
        assert_eq!(keys.locate("nothing here"), "nothing here");
    }
}
