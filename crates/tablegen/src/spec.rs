//! Table specs: the TOML files of `tables/`.
//!
//! ```toml
//! model = "linear"            # or "hertz"
//! box = "paper_table_1"       # a preset (paper_table_1, paper_table_2), or a table:
//! # [box]                     # SI units; the model's parameters, each [min, max]
//! # stiffness = [1e3, 1e6]    # linear: stiffness radius density damping speed eccentricity
//! # ...                       # hertz:  young poisson radius density dissipation speed eccentricity
//! nodes = [40, 80, 80]        # grid nodes along a, b, c
//! order = [6, 6, 6]           # interpolation points per axis (4 cubic, 6 quintic, 8 septic)
//! m_min = 0.6931              # optional: raise the lower end of m (b = 0) above the box's
//! [stretch]                   # optional: crowd the nodes of an axis towards its low end,
//! b = [1.3, 0.66]             # uniform in w = y + λ·ln(1 + y/d), y = b − b_min: [λ, d]
//! ```
//!
//! `m_min` cuts off the impacts of the box with m = ln(lω/v) (linear) or
//! ln(l(κ/v²)^{2/5}) (Hertz) below it: lookups there are out of the box (an error, or a
//! counted exact solve). It may only raise m_min, never lower it below the box's value.

use emdstar_contact::{HertzBox, LinearBox, Model, ParameterBox, Range, RectBounds};
use emdstar_table::{Axis, Stretch};
use serde::Deserialize;
use std::collections::BTreeMap;

/// A parsed, validated table spec.
#[derive(Debug, Clone, PartialEq)]
pub struct Spec {
    pub model: Model,
    pub parameter_box: ParameterBox,
    pub bounds: RectBounds,
    pub nodes: [usize; 3],
    pub order: [usize; 3],
    pub stretch: [Stretch; 3],
    /// The spec's text, stored in the table file.
    pub text: String,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawSpec {
    model: String,
    #[serde(rename = "box")]
    parameter_box: RawBox,
    nodes: [usize; 3],
    order: [usize; 3],
    m_min: Option<f64>,
    #[serde(default)]
    stretch: BTreeMap<String, [f64; 2]>,
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
        let mut stretch = [Stretch::NONE; 3];
        for (name, [amount, knee]) in &raw.stretch {
            let k = ["a", "b", "c"]
                .iter()
                .position(|a| a == name)
                .ok_or_else(|| format!("[stretch] names axes a, b or c, not {name:?}"))?;
            stretch[k] = Stretch {
                amount: *amount,
                knee: *knee,
            };
        }
        let axes = emdstar_table::grid_axes(&bounds, raw.nodes, raw.order, stretch);
        for (ax, name) in axes.iter().zip(["a", "b", "c"]) {
            ax.check().map_err(|why| format!("axis {name}: {why}"))?;
        }
        Ok(Self {
            model,
            parameter_box,
            bounds,
            nodes: raw.nodes,
            order: raw.order,
            stretch,
            text: text.to_string(),
        })
    }

    /// Reads a spec file.
    pub fn read(path: &std::path::Path) -> Result<Self, String> {
        let text = std::fs::read_to_string(path)
            .map_err(|e| format!("cannot read spec {}: {e}", path.display()))?;
        Self::parse(&text).map_err(|e| format!("{}: {e}", path.display()))
    }

    /// The grid axes.
    pub fn axes(&self) -> [Axis; 3] {
        emdstar_table::grid_axes(&self.bounds, self.nodes, self.order, self.stretch)
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
        let a = Spec::parse("model='linear'\nbox='paper_table_1'\nnodes=[6,6,6]\norder=[4,4,4]")
            .unwrap();
        let b = Spec::parse(
            "model='linear'\nnodes=[6,6,6]\norder=[4,4,4]\n[box]\nstiffness=[1e3,1e6]\n\
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
                "model='foo'\nbox='paper_table_1'\nnodes=[6,6,6]\norder=[4,4,4]",
                "model must be",
            ),
            (
                "model='hertz'\nbox='paper_table_1'\nnodes=[6,6,6]\norder=[4,4,4]",
                "belongs to",
            ),
            (
                "model='linear'\nbox='nope'\nnodes=[6,6,6]\norder=[4,4,4]",
                "unknown box preset",
            ),
            (
                "model='linear'\nbox='paper_table_1'\nnodes=[3,6,6]\norder=[4,4,4]",
                "at least 4",
            ),
            (
                "model='linear'\nbox='paper_table_1'\nnodes=[6,6,6]\norder=[5,4,4]",
                "one of 2, 4",
            ),
            (
                "model='linear'\nnodes=[6,6,6]\norder=[4,4,4]\n[box]\nk=[1.0,2.0]",
                "unknown box",
            ),
            (
                "model='linear'\nbox='paper_table_1'\nnodes=[6,6,6]\norder=[4,4,4]\nm_min=-9.0",
                "can only cut",
            ),
            (
                "model='linear'\nbox='paper_table_1'\nnodes=[6,6,6]\norder=[4,4,4]\n[stretch]\nq=[1.0,1.0]",
                "axes a, b or c",
            ),
            (
                "model='linear'\nbox='paper_table_1'\nnodes=[6,6,6]\norder=[4,4,4]\n[stretch]\nb=[1.0,0.0]",
                "knee > 0",
            ),
        ];
        for (text, want) in cases {
            let err = Spec::parse(text).unwrap_err();
            assert!(err.contains(want), "{text}: {err}");
        }
    }
}
