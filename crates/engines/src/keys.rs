//! Which engine uses which config key and option: one table. A value is checked
//! whatever the engine (the config's own checks); a key or option the chosen engine
//! does not use gets a warning naming it and the engines that do, and so does an
//! output interval whose output is not written.

use crate::options::{EngineKind, EngineOptions, HybridChoice, InterferenceChoice, MorChoice};
use crate::run::RunFiles;
use EngineKind::{Emd, EmdStar, Hybrid, Md};
use emdstar_system::Config;

/// One key of the config (`section.key`) or option of the command line (`--flag`)
/// that not every engine uses.
struct Key {
    name: &'static str,
    engines: &'static [EngineKind],
    /// Whether the config or the options set it.
    set: fn(&Config, &EngineOptions) -> bool,
}

const MD_ENGINES: &[EngineKind] = &[Md, Hybrid];
const EVENT_ENGINES: &[EngineKind] = &[Emd, EmdStar];
const MOR_ENGINES: &[EngineKind] = &[EmdStar, Hybrid];

/// Every key and option some engine does not use.
const KEYS: &[Key] = &[
    Key {
        name: "md.dt",
        engines: MD_ENGINES,
        set: |c, _| c.md.as_ref().is_some_and(|m| m.dt.is_some()),
    },
    Key {
        name: "md.skin",
        engines: MD_ENGINES,
        set: |c, _| c.md.as_ref().is_some_and(|m| m.skin.is_some()),
    },
    Key {
        name: "md.contact_end",
        engines: MD_ENGINES,
        set: |c, _| c.md.as_ref().is_some_and(|m| m.contact_end.is_some()),
    },
    Key {
        name: "box.shear_rate",
        engines: &[Md, Emd, EmdStar],
        set: |c, _| {
            c.sim_box
                .as_ref()
                .is_some_and(|b| b.shear_rate.is_some_and(|r| r != 0.0))
        },
    },
    Key {
        name: "events.tc",
        engines: EVENT_ENGINES,
        set: |c, _| c.events.as_ref().is_some_and(|e| e.tc.is_some()),
    },
    Key {
        name: "--dt",
        engines: MD_ENGINES,
        set: |_, o| o.md.dt.is_some(),
    },
    Key {
        name: "--skin",
        engines: MD_ENGINES,
        set: |_, o| o.md.skin.is_some(),
    },
    Key {
        name: "--contact-end",
        engines: MD_ENGINES,
        set: |_, o| o.md.contact_end.is_some(),
    },
    Key {
        name: "--mor",
        engines: MOR_ENGINES,
        set: |_, o| o.edmd.mor != MorChoice::default(),
    },
    Key {
        name: "--table",
        engines: MOR_ENGINES,
        set: |_, o| o.edmd.table.is_some(),
    },
    Key {
        name: "--interference",
        engines: MOR_ENGINES,
        set: |_, o| o.edmd.interference != InterferenceChoice::default(),
    },
    Key {
        name: "--broad-phase",
        engines: EVENT_ENGINES,
        set: |_, o| o.edmd.broad_phase != Default::default(),
    },
    Key {
        name: "--phi-time",
        engines: &[Hybrid],
        set: |_, o| o.hybrid.phi_time != HybridChoice::default().phi_time,
    },
    Key {
        name: "--phi-event",
        engines: &[Hybrid],
        set: |_, o| o.hybrid.phi_event != HybridChoice::default().phi_event,
    },
    Key {
        name: "--max-events-per-step",
        engines: &[Hybrid],
        set: |_, o| o.hybrid.max_events_per_step != HybridChoice::default().max_events_per_step,
    },
    Key {
        name: "--events",
        engines: &[Hybrid],
        set: |_, o| o.hybrid.events != HybridChoice::default().events,
    },
];

/// "line N: " for the key at `path` of `config`, where the text sets it.
fn at(config: &Config, path: &str) -> String {
    config
        .keys
        .line(path)
        .map_or(String::new(), |l| format!("line {l}: "))
}

/// One line for each `[output]` interval of `config` whose output `files` does not
/// write (`--log none`, `trajectory = "none"`).
pub fn unwritten_intervals(config: &Config, files: &RunFiles) -> Vec<String> {
    let output = config.output.clone().unwrap_or_default();
    [
        (
            "trajectory",
            output.trajectory_interval,
            files.trajectory.is_some(),
        ),
        ("log", output.log_interval, files.log.is_some()),
    ]
    .into_iter()
    .filter(|(_, interval, written)| interval.is_some() && !written)
    .map(|(file, _, _)| {
        format!(
            "{}[output] {file}_interval has no effect: this run writes no {file} (--{file} \
             none or {file} = \"none\")",
            at(config, &format!("output.{file}_interval"))
        )
    })
    .collect()
}

/// One line for each key of `config` and option of `options` that the chosen engine
/// does not use: the key (with its line), the engine, and the engines that use it.
pub fn unused_keys(config: &Config, options: &EngineOptions) -> Vec<String> {
    let engine = options.engine;
    KEYS.iter()
        .filter(|k| !k.engines.contains(&engine) && (k.set)(config, options))
        .map(|k| {
            let users: Vec<&str> = k.engines.iter().map(|e| e.name()).collect();
            let (what, at) = match k.name.strip_prefix("--") {
                Some(_) => (format!("option {}", k.name), String::new()),
                None => {
                    let (section, key) = k.name.split_once('.').unwrap_or(("", k.name));
                    (format!("[{section}] {key}"), at(config, k.name))
                }
            };
            format!(
                "{at}{what} is not used by --engine {} (only by {}); it has no effect on \
                 this run",
                engine.name(),
                users.join(" and ")
            )
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_key_warns_on_the_engines_that_do_not_use_it_and_only_there() {
        let config = Config::from_toml(
            "t_end = 1.0\n[material]\nmodel = \"linear\"\nstiffness = 1e4\ndensity = 1.0\n\
             [[particles]]\nradius = 0.1\nposition = [0.0, 0.0, 0.0]\n[md]\ndt = 1e-5\n\
             [events]\ntc = 1e-4\n",
        )
        .unwrap();
        let warnings = |engine| {
            let options = EngineOptions {
                engine,
                ..Default::default()
            };
            unused_keys(&config, &options)
        };
        let emd = warnings(Emd);
        assert_eq!(emd.len(), 1, "{emd:?}");
        assert!(
            emd[0].starts_with("line 10: [md] dt is not used by --engine emd")
                && emd[0].contains("only by md and hybrid"),
            "{emd:?}"
        );
        assert_eq!(warnings(EmdStar).len(), 1);
        for engine in [Md, Hybrid] {
            let w = warnings(engine);
            assert_eq!(w.len(), 1, "{w:?}");
            assert!(w[0].starts_with("line 12: [events] tc"), "{w:?}");
        }
        let options = EngineOptions {
            engine: Md,
            hybrid: HybridChoice {
                phi_time: 0.3,
                ..Default::default()
            },
            ..Default::default()
        };
        let w = unused_keys(&config, &options);
        assert!(
            w.iter().any(|w| w.starts_with("option --phi-time")),
            "{w:?}"
        );
    }
}
