//! A numbered check: a measured value, the bar it must clear, and the verdict.

use serde::Serialize;

/// How the value is compared with the bar.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub enum Comparison {
    /// value ≤ bar.
    AtMost,
    /// value ≥ bar.
    AtLeast,
}

/// One check of the report.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Check {
    /// Its number, e.g. "1.2".
    pub id: String,
    /// What is measured, in words.
    pub name: String,
    pub value: f64,
    pub comparison: Comparison,
    pub bar: f64,
    pub passed: bool,
}

impl Check {
    /// A check whose value must not exceed `bar` (a NaN value fails).
    pub fn at_most(id: &str, name: impl Into<String>, value: f64, bar: f64) -> Self {
        Self {
            id: id.into(),
            name: name.into(),
            value,
            comparison: Comparison::AtMost,
            bar,
            passed: value <= bar,
        }
    }

    /// A check whose value must reach `bar` (a NaN value fails).
    pub fn at_least(id: &str, name: impl Into<String>, value: f64, bar: f64) -> Self {
        Self {
            id: id.into(),
            name: name.into(),
            value,
            comparison: Comparison::AtLeast,
            bar,
            passed: value >= bar,
        }
    }

    /// "≤ 1e-6" or "≥ 1.5".
    pub fn bar_text(&self) -> String {
        let op = match self.comparison {
            Comparison::AtMost => "≤",
            Comparison::AtLeast => "≥",
        };
        format!("{op} {}", short(self.bar))
    }

    /// The value, in 4 significant digits.
    pub fn value_text(&self) -> String {
        short(self.value)
    }
}

/// A number in a few significant digits, scientific when small or large.
pub fn short(x: f64) -> String {
    if x == 0.0 || !x.is_finite() {
        return format!("{x}");
    }
    let a = x.abs();
    if (1e-3..1e4).contains(&a) {
        format!("{}", (x * 1e4).round() / 1e4)
    } else {
        format!("{x:.3e}")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn nan_fails_either_way() {
        assert!(!Check::at_most("1", "x", f64::NAN, 1.0).passed);
        assert!(!Check::at_least("1", "x", f64::NAN, 1.0).passed);
        assert!(Check::at_most("1", "x", 1.0, 1.0).passed);
        assert!(!Check::at_least("1", "x", 0.5, 1.0).passed);
    }

    #[test]
    fn short_numbers() {
        assert_eq!(short(1.5), "1.5");
        assert_eq!(short(100.0), "100");
        assert_eq!(short(2.0e-7), "2.000e-7");
    }
}
