//! Table specs: the TOML files of `tables/`.
//!
//! ```toml
//! model = "linear"            # or "hertz"
//! box = "paper_table_1"       # a preset (paper_table_1, paper_table_2), or a table:
//! # [box]                     # SI units; the model's parameters, each [min, max]
//! # stiffness = [1e3, 1e6]    # linear: stiffness radius density damping speed eccentricity
//! # ...                       # hertz:  young poisson radius density dissipation speed eccentricity
//! cells = [2, 2, 4]           # top cells along a, b, c (also the unit of shards)
//! degree = 7                  # total degree of the patch polynomials
//! tolerance = 2e-7            # error goal of each stored log in every patch
//! max_depth = 14              # optional: bisections below a top cell at most
//! b_knee = 0.05               # optional: store b as w = ln(1 + (b − b_min)/b_knee)
//! m_min = 0.6931              # optional: raise the lower end of m (b = 0) above the box's
//! ```
//!
//! `m_min` cuts off the impacts of the box with m = ln(lω/v) (linear) or
//! ln(l(κ/v²)^{2/5}) (Hertz) below it: lookups there are out of the box (an error, or a
//! counted exact solve). It may only raise m_min, never lower it below the box's value.

use emdstar_contact::{HertzBox, LinearBox, Model, ParameterBox, Range, RectBounds};
use serde::Deserialize;
use std::collections::BTreeMap;

/// A parsed, validated table spec.
#[derive(Debug, Clone, PartialEq)]
pub struct Spec {
    pub model: Model,
    pub parameter_box: ParameterBox,
    pub bounds: RectBounds,
    /// Top cells along a, b, c.
    pub cells: [usize; 3],
    /// Total degree of the patch polynomials.
    pub degree: usize,
    /// Error goal per patch (absolute, in each stored log).
    pub tolerance: f64,
    /// Bisections below a top cell at most.
    pub max_depth: usize,
    /// d of the b axis map (0: none), see [`emdstar_table::BMap`].
    pub b_knee: f64,
    /// The spec's text, stored in the table file.
    pub text: String,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawSpec {
    model: String,
    #[serde(rename = "box")]
    parameter_box: RawBox,
    cells: [usize; 3],
    degree: usize,
    tolerance: f64,
    max_depth: Option<usize>,
    b_knee: Option<f64>,
    m_min: Option<f64>,
}

#[derive(Deserialize)]
#[serde(untagged)]
enum RawBox {
    Preset(String),
    Ranges(BTreeMap<String, [f64; 2]>),
}

impl Spec {
    /// Parses and checks a spec's TOML text.
    pub fn parse(text: &str) -> Result<Self, String> {
        let raw: RawSpec = toml::from_str(text).map_err(|e| format!("invalid table spec: {e}"))?;
        let model: Model = raw
            .model
            .parse()
            .map_err(|_| format!("model must be \"linear\" or \"hertz\", got {:?}", raw.model))?;
        let parameter_box = match raw.parameter_box {
            RawBox::Preset(name) => match name.as_str() {
                "paper_table_1" => ParameterBox::paper_table_1(),
                "paper_table_2" => ParameterBox::paper_table_2(),
                _ => {
                    return Err(format!(
                        "unknown box preset {name:?}; use paper_table_1, paper_table_2 or a [box] table of ranges"
                    ));
                }
            },
            RawBox::Ranges(map) => box_from_ranges(model, &map)?,
        };
        if parameter_box.model() != model {
            return Err(format!(
                "the box belongs to the {} model, but the spec says model = \"{model}\"",
                parameter_box.model()
            ));
        }
        let mut bounds = parameter_box
            .bounds()
            .map_err(|e| format!("invalid box: {e}"))?;
        if let Some(m) = raw.m_min {
            if !(m.is_finite() && m >= bounds.m.min && m < bounds.m.max) {
                return Err(format!(
                    "m_min = {m} must lie in [{}, {}) (the box's range of m): it can only \
                     cut impacts off, not add them",
                    bounds.m.min, bounds.m.max
                ));
            }
            bounds.m.min = m;
        }
        if raw.cells.iter().any(|&c| !(1..=4096).contains(&c)) {
            return Err(format!(
                "cells = {:?}: each count of top cells must lie in 1..=4096",
                raw.cells
            ));
        }
        if !(2..=12).contains(&raw.degree) {
            return Err(format!(
                "degree = {} must lie in 2..=12 (7 is a good start)",
                raw.degree
            ));
        }
        if !(raw.tolerance.is_finite() && raw.tolerance > 0.0 && raw.tolerance < 0.1) {
            return Err(format!(
                "tolerance = {} must be a positive error goal below 0.1, e.g. 2e-7",
                raw.tolerance
            ));
        }
        let b_knee = raw.b_knee.unwrap_or(0.0);
        if !(b_knee.is_finite() && b_knee >= 0.0) {
            return Err(format!(
                "b_knee = {b_knee} must be a distance >= 0 (0: no map)"
            ));
        }
        let max_depth = raw.max_depth.unwrap_or(14);
        if max_depth > 30 {
            return Err(format!("max_depth = {max_depth} must be at most 30"));
        }
        Ok(Self {
            model,
            parameter_box,
            bounds,
            cells: raw.cells,
            degree: raw.degree,
            tolerance: raw.tolerance,
            max_depth,
            b_knee,
            text: text.to_string(),
        })
    }

    /// Reads a spec file.
    pub fn read(path: &std::path::Path) -> Result<Self, String> {
        let text = std::fs::read_to_string(path)
            .map_err(|e| format!("cannot read spec {}: {e}", path.display()))?;
        Self::parse(&text).map_err(|e| format!("{}: {e}", path.display()))
    }

    /// The ranges of a, b and c.
    pub fn rect(&self) -> [Range; 3] {
        self.bounds.axes()
    }

    /// How the pieces store the b axis.
    pub fn b_map(&self) -> emdstar_table::BMap {
        emdstar_table::BMap {
            b_min: self.rect()[1].min,
            knee: self.b_knee,
        }
    }
}

fn box_from_ranges(model: Model, map: &BTreeMap<String, [f64; 2]>) -> Result<ParameterBox, String> {
    let names: &[&str] = match model {
        Model::Linear => &[
            "stiffness",
            "radius",
            "density",
            "damping",
            "speed",
            "eccentricity",
        ],
        Model::Hertz => &[
            "young",
            "poisson",
            "radius",
            "density",
            "dissipation",
            "speed",
            "eccentricity",
        ],
    };
    if let Some(extra) = map.keys().find(|k| !names.contains(&k.as_str())) {
        return Err(format!(
            "unknown box parameter {extra:?} for the {model} model; expected {}",
            names.join(", ")
        ));
    }
    let get = |name: &str| -> Result<Range, String> {
        map.get(name)
            .map(|r| Range::new(r[0], r[1]))
            .ok_or_else(|| format!("the [box] table lacks {name} = [min, max]"))
    };
    Ok(match model {
        Model::Linear => ParameterBox::Linear(LinearBox {
            stiffness: get("stiffness")?,
            radius: get("radius")?,
            density: get("density")?,
            damping: get("damping")?,
            speed: get("speed")?,
            eccentricity: get("eccentricity")?,
        }),
        Model::Hertz => ParameterBox::Hertz(HertzBox {
            young: get("young")?,
            poisson: get("poisson")?,
            radius: get("radius")?,
            density: get("density")?,
            dissipation: get("dissipation")?,
            speed: get("speed")?,
            eccentricity: get("eccentricity")?,
        }),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn presets_and_explicit_ranges_agree() {
        let a = Spec::parse(
            "model='linear'\nbox='paper_table_1'\ncells=[1,1,1]\ndegree=4\ntolerance=1e-4",
        )
        .unwrap();
        let b = Spec::parse(
            "model='linear'\ncells=[1,1,1]\ndegree=4\ntolerance=1e-4\n[box]\nstiffness=[1e3,1e6]\n\
             radius=[0.001,0.1]\ndensity=[250.0,3250.0]\ndamping=[0.01,1.25]\n\
             speed=[0.001,25.0]\neccentricity=[0.01,0.99]",
        )
        .unwrap();
        assert_eq!(a.bounds, b.bounds);
    }

    #[test]
    fn bad_specs_say_what_is_wrong() {
        let cases = [
            (
                "model='foo'\nbox='paper_table_1'\ncells=[1,1,1]\ndegree=4\ntolerance=1e-4",
                "model must be",
            ),
            (
                "model='hertz'\nbox='paper_table_1'\ncells=[1,1,1]\ndegree=4\ntolerance=1e-4",
                "belongs to",
            ),
            (
                "model='linear'\nbox='nope'\ncells=[1,1,1]\ndegree=4\ntolerance=1e-4",
                "unknown box preset",
            ),
            (
                "model='linear'\nbox='paper_table_1'\ncells=[0,1,1]\ndegree=4\ntolerance=1e-4",
                "top cells",
            ),
            (
                "model='linear'\nbox='paper_table_1'\ncells=[1,1,1]\ndegree=40\ntolerance=1e-4",
                "degree = 40",
            ),
            (
                "model='linear'\nbox='paper_table_1'\ncells=[1,1,1]\ndegree=4\ntolerance=0",
                "tolerance = 0",
            ),
            (
                "model='linear'\ncells=[1,1,1]\ndegree=4\ntolerance=1e-4\n[box]\nk=[1.0,2.0]",
                "unknown box",
            ),
            (
                "model='linear'\nbox='paper_table_1'\ncells=[1,1,1]\ndegree=4\ntolerance=1e-4\nm_min=-9.0",
                "can only cut",
            ),
        ];
        for (text, want) in cases {
            let err = Spec::parse(text).unwrap_err();
            assert!(err.contains(want), "{text}: {err}");
        }
    }
}
