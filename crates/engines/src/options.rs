//! The engine choice and its options, as plain data. With the `clap` feature they are
//! also the command-line flags of `emdstar pair` and `emdstar run` (the doc comments of
//! the fields are their help).

use std::path::PathBuf;

/// The simulation engine.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum EngineKind {
    /// Force-based DEM (time steps).
    #[default]
    Md,
    /// Classic event-driven MD with the force law's central restitution ε(v_n).
    Emd,
    /// eMD*: event-driven MD with the matrix of restitution (three events per collision).
    EmdStar,
    /// MD where the gas is dense, eMD* where it is dilute (emdstar-hybrid).
    Hybrid,
}

impl EngineKind {
    /// The engine's name as `--engine` takes it.
    pub fn name(self) -> &'static str {
        match self {
            Self::Md => "md",
            Self::Emd => "emd",
            Self::EmdStar => "emdstar",
            Self::Hybrid => "hybrid",
        }
    }
}

impl std::str::FromStr for EngineKind {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        match s {
            "md" => Ok(Self::Md),
            "emd" => Ok(Self::Emd),
            "emdstar" => Ok(Self::EmdStar),
            "hybrid" => Ok(Self::Hybrid),
            other => Err(format!(
                "unknown engine '{other}': the engines are 'md', 'emd', 'emdstar' and 'hybrid'"
            )),
        }
    }
}

/// Parses an engine name (`--engine`).
pub fn parse_engine(s: &str) -> Result<EngineKind, String> {
    s.parse()
}

/// Every engine's options.
#[derive(Debug, Clone, Default)]
#[cfg_attr(feature = "clap", derive(clap::Args))]
pub struct EngineOptions {
    /// The engine: md, emd, emdstar or hybrid.
    #[cfg_attr(feature = "clap", arg(long, value_parser = parse_engine, default_value = "md"))]
    pub engine: EngineKind,
    #[cfg_attr(feature = "clap", command(flatten))]
    pub md: MdChoice,
    #[cfg_attr(feature = "clap", command(flatten))]
    pub edmd: EventChoice,
    #[cfg_attr(feature = "clap", command(flatten))]
    pub hybrid: HybridChoice,
}

/// Options of the MD engine (they override the config's `[md]` section).
#[derive(Debug, Clone, Default)]
#[cfg_attr(feature = "clap", derive(clap::Args))]
pub struct MdChoice {
    /// Time step in s [default: 1/2000 (pair) or 1/50 (run) of the shortest expected
    /// contact time; steps above 1/10 of it are refused].
    #[cfg_attr(feature = "clap", arg(long, value_name = "S"))]
    pub dt: Option<f64>,
    /// When a contact ends: "force" (F = 0, the default) or "overlap" (ξ = 0, as LAMMPS
    /// without limit_damping; the force may then attract).
    #[cfg_attr(feature = "clap", arg(long, value_name = "RULE"))]
    pub contact_end: Option<String>,
    /// Verlet-list skin in m [default: the largest radius].
    #[cfg_attr(feature = "clap", arg(long, value_name = "M"))]
    pub skin: Option<f64>,
}

/// Where eMD* takes the matrix of restitution from.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
#[cfg_attr(feature = "clap", derive(clap::ValueEnum))]
pub enum MorChoice {
    /// The lookup table (--table, or the default table embedded in the program), with
    /// impacts outside its box solved exactly; the summary counts them.
    #[default]
    TableOrExact,
    /// The table only: an impact outside its box stops the run with an error.
    Table,
    /// The exact solver for every collision (slow, exact).
    Exact,
}

/// Which pending E^v events run early when a third particle interferes (exception b).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
#[cfg_attr(feature = "clap", derive(clap::ValueEnum))]
pub enum InterferenceChoice {
    /// Only the particle that is hit (Müller & Pöschel's default).
    #[default]
    Hit,
    /// Both partners of the interrupted collision.
    Both,
}

/// How the event engine finds the pairs it tests.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
#[cfg_attr(feature = "clap", derive(clap::ValueEnum))]
pub enum BroadPhaseChoice {
    /// Epochs in dilute gases without gravity (packing fraction below 0.02) that are
    /// periodic or held by walls along every axis, neighbour lists for hard spheres and
    /// eMD in such gases from packing fraction 0.38 on, cell crossings otherwise.
    #[default]
    Auto,
    /// A cell grid with a crossing event whenever a particle changes cell.
    Crossings,
    /// Swept boxes filed once per epoch (no gravity; along periodic axes a box at
    /// least four times the sum of the largest contact distance and a cell width). A
    /// gas that spreads into free space runs far slower on epochs than on crossings.
    Epochs,
    /// A neighbour list per particle, rebuilt when the particle leaves its shell (hard
    /// spheres and eMD without gravity, radii within a factor of two; along periodic
    /// axes a box at least 4.5 largest contact distances wide).
    Neighbours,
}

impl From<BroadPhaseChoice> for emdstar_edmd::BroadPhaseKind {
    fn from(choice: BroadPhaseChoice) -> Self {
        match choice {
            BroadPhaseChoice::Auto => Self::Auto,
            BroadPhaseChoice::Crossings => Self::Crossings,
            BroadPhaseChoice::Epochs => Self::Epochs,
            BroadPhaseChoice::Neighbours => Self::Neighbours,
        }
    }
}

/// Options of the event-driven engines (emd, emdstar; the MoR source also for the
/// hybrid).
#[derive(Debug, Clone, Default)]
#[cfg_attr(feature = "clap", derive(clap::Args))]
pub struct EventChoice {
    /// eMD*: source of the matrix of restitution.
    #[cfg_attr(feature = "clap", arg(long, value_enum, default_value_t = MorChoice::default()))]
    pub mor: MorChoice,
    /// eMD*: a MoR table file instead of the default one.
    #[cfg_attr(feature = "clap", arg(long, value_name = "FILE"))]
    pub table: Option<PathBuf>,
    /// eMD* (and the hybrid's eMD* events): exception (b) variant.
    #[cfg_attr(feature = "clap", arg(long, value_enum, default_value_t = InterferenceChoice::default()))]
    pub interference: InterferenceChoice,
    /// How candidate pairs are found (the same collisions either way; epochs are
    /// about 2.8 times faster at packing fraction 0.001, crossings win above about
    /// 0.02).
    #[cfg_attr(feature = "clap", arg(long, value_enum, default_value_t = BroadPhaseChoice::default()))]
    pub broad_phase: BroadPhaseChoice,
}

/// Options of the hybrid engine.
#[derive(Debug, Clone)]
#[cfg_attr(feature = "clap", derive(clap::Args))]
pub struct HybridChoice {
    /// Hybrid: local volume fraction from which a particle is time-driven.
    #[cfg_attr(feature = "clap", arg(long, value_name = "PHI", default_value_t = HybridChoice::default().phi_time))]
    pub phi_time: f64,
    /// Hybrid: local volume fraction below which a contact-free particle returns to
    /// event-driven (≤ --phi-time; 0 and 0 make every particle time-driven, i.e. MD).
    #[cfg_attr(feature = "clap", arg(long, value_name = "PHI", default_value_t = HybridChoice::default().phi_event))]
    pub phi_event: f64,
    /// Hybrid: events of one particle within one time step above which it becomes
    /// time-driven (inelastic collapse, resting contacts).
    #[cfg_attr(feature = "clap", arg(long, value_name = "N", default_value_t = HybridChoice::default().max_events_per_step))]
    pub max_events_per_step: u32,
    /// Hybrid: how the event-driven particles collide. "emdstar" (the default) runs
    /// eMD* as --engine emdstar does: the matrix of restitution (--mor, --table) and,
    /// where a contact has a tangential spring, the exact frictional contact; "emd"
    /// runs classic eMD, instantaneous collisions with Walton's rule for friction, its
    /// β₀ derived from the time-driven law (linear law only; HAET's events).
    #[cfg_attr(feature = "clap", arg(long, value_enum, value_name = "RULE", default_value_t = EventsChoice::default()))]
    pub events: EventsChoice,
}

/// How the hybrid's event-driven particles collide.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
#[cfg_attr(feature = "clap", derive(clap::ValueEnum))]
pub enum EventsChoice {
    /// eMD*: three events per collision, the exact frictional contact with friction.
    #[default]
    Emdstar,
    /// Classic eMD with Walton's rule (β₀ derived from the time-driven law).
    Emd,
}

impl From<EventsChoice> for emdstar_hybrid::EventRule {
    fn from(choice: EventsChoice) -> Self {
        match choice {
            EventsChoice::Emdstar => Self::EmdStar,
            EventsChoice::Emd => Self::Emd,
        }
    }
}

impl Default for HybridChoice {
    /// The hybrid engine's own defaults ([`emdstar_hybrid::HybridOptions::with_dt`]).
    fn default() -> Self {
        let d = emdstar_hybrid::HybridOptions::with_dt(1.0);
        Self {
            phi_time: d.phi_time,
            phi_event: d.phi_event,
            max_events_per_step: d.max_events_per_step,
            events: match d.events {
                emdstar_hybrid::EventRule::EmdStar => EventsChoice::Emdstar,
                emdstar_hybrid::EventRule::Emd => EventsChoice::Emd,
            },
        }
    }
}
