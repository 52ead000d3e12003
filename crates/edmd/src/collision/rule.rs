//! The collision rules as values, chosen once per kind of contact when an engine is
//! built ([`Rules`]): hard spheres, eMD, eMD* and eMD* with the exact frictional
//! contact, the instantaneous ones with Walton's tangential rule where the contact has
//! it. Each rule has one entry for pairs ([`Rule::pair`]) and one for walls
//! ([`Rule::wall`]), the wall being the partner of infinite mass and radius that does
//! not spin; each returns a [`Decision`], which the executor (`collision::mod`)
//! applies.
//!
//! The TC model (Luding & McNamara 1998, Granular Matter 1, 113) modifies every rule:
//! with a duration t_c set ([`Rules::set_tc`]), a collision of a particle within t_c
//! of its previous collision (with a particle or a wall; for a pair, the later of
//! the two parties' previous collisions) is elastic: it takes the contact's elastic
//! rule ([`Rule::elastic`]), built with the contact's own rule. For instantaneous
//! collisions (hard spheres, eMD) that is the smooth kick with normal restitution 1;
//! for eMD* the three events of the same force law without its dissipation (damping
//! or A set to 0) and without friction: the matrix of restitution of the elastic law
//! (ε = 1, the contact's duration τ and the E^φ displacement of an elastic contact,
//! which leaves the pair at touch). Either way the collision conserves the kinetic
//! energy and leaves spins alone; eMD*'s elastic rule keeps its transient, so that
//! time advances by τ at each such collision as the contact's duration says.

use super::ahead::{Predicted, SolveAhead};
use super::frictional;
use crate::error::{EngineError, Result};
use crate::physics::{Interference, Physics};
use crate::rules::{CentralRestitution, HertzRestitution, MorSource, restitution_kick};
use crate::stats::Stats;
use emdstar_contact::vec3::{self, from_na, to_na};
use emdstar_contact::{
    HistorySpring, Impact, PairLaw, PairProperties, Rough, Tangential, Walton, rough_pair,
    rough_wall, scale,
};
use emdstar_mor::rule::{Body, resolve, resolve_wall};
use emdstar_system::{Interaction, Interactions, Method, Wall};

/// One party of a collision as the rules see it: a pair's first party is placed next
/// to its partner (the minimum image), a wall's relative to a point of the wall.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Party {
    pub position: [f64; 3],
    pub velocity: [f64; 3],
    /// Angular velocity in rad/s.
    pub spin: [f64; 3],
    pub radius: f64,
    pub mass: f64,
}

impl Party {
    pub(crate) fn body(&self) -> Body {
        Body {
            position: to_na(self.position),
            velocity: to_na(self.velocity),
            mass: self.mass,
        }
    }

    fn rough(&self) -> Rough {
        Rough {
            velocity: self.velocity,
            spin: self.spin,
            radius: self.radius,
            mass: self.mass,
        }
    }
}

/// An instantaneous change of the parties' velocities (and spins).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Kick {
    pub velocity: [[f64; 3]; 2],
    /// The spins after it; `None` leaves them as they are.
    pub spin: Option<[[f64; 3]; 2]>,
    /// True where the frictional fallback of exception (a) could not separate the pair
    /// and eMD's frictionless kick stands in (counted when applied).
    pub substitute: bool,
}

/// eMD*'s three events (Müller & Pöschel 2013, Sec. VI B): the E^φ now and the E^v τ
/// later, with eMD's kick should the rotation prove impossible (exception a).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Transient {
    /// Where the E^φ places the parties (in the frames of their [`Party`] positions).
    pub placed: [[f64; 3]; 2],
    /// The velocity of both between E^φ and E^v (the centre of mass's).
    pub moving: [f64; 3],
    /// The velocities the E^v applies (gravity over τ not included).
    pub after: [[f64; 3]; 2],
    /// The spins at E^φ (with friction).
    pub spin: Option<[[f64; 3]; 2]>,
    /// τ in s.
    pub duration: f64,
    /// The overlap at which the contact leaves a pair (l − |r| after the E^φ).
    pub overlap_left: f64,
    /// Exception (a): the kick instead.
    pub fallback: Kick,
}

/// What a rule decides for one collision.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Decision {
    Kick(Kick),
    Transient(Transient),
}

impl Decision {
    /// The decision seen from a frame moving at `u` (a vibrated wall's at impact):
    /// every velocity it sets plus `u`, positions and spins as they are.
    pub fn moved_by(self, u: [f64; 3]) -> Self {
        let shift = |v: [f64; 3]| std::array::from_fn(|k| v[k] + u[k]);
        let kick = |k: Kick| Kick {
            velocity: k.velocity.map(shift),
            ..k
        };
        match self {
            Self::Kick(k) => Self::Kick(kick(k)),
            Self::Transient(t) => Self::Transient(Transient {
                moving: shift(t.moving),
                after: t.after.map(shift),
                fallback: kick(t.fallback),
                ..t
            }),
        }
    }
}

/// A pair's impact: r = x_i − x_j (minimum image), |r|, and v = v_i − v_j.
#[derive(Debug, Clone, Copy)]
pub struct PairImpact {
    pub r: [f64; 3],
    pub distance: f64,
    pub v: [f64; 3],
}

/// What a rule may use besides the parties: the MoR source, the cache of central
/// restitutions and the counters.
pub struct RuleContext<'a> {
    pub mor: Option<&'a mut Box<dyn MorSource>>,
    /// Frictional contacts solved ahead (eMD* with friction on more than one thread).
    pub ahead: Option<&'a SolveAhead>,
    pub hertz: &'a mut HertzRestitution,
    pub stats: &'a mut Stats,
}

/// The normal part of an instantaneous rule.
#[derive(Debug, Clone)]
pub enum Restitution {
    /// Hard spheres: one ε.
    Constant(f64),
    /// eMD: the force law's central restitution at the normal impact speed.
    Central(CentralRestitution),
}

/// The collision rule of one kind of contact.
#[derive(Debug, Clone)]
pub enum Rule {
    /// An instantaneous collision (hard spheres, eMD), with Walton's tangential rule
    /// or smooth.
    Instant {
        normal: Restitution,
        walton: Option<Walton>,
    },
    /// eMD*: three events with the matrix of restitution of the pair's law.
    EmdStar { law: PairLaw, props: PairProperties },
    /// eMD* of frictional spheres: the exact contact with the history spring.
    EmdStarFrictional { law: PairLaw, spring: HistorySpring },
}

impl Rule {
    /// The rule of `interaction` under eMD (`emdstar` false) or eMD*.
    fn of(emdstar: bool, interaction: &Interaction) -> Result<Self> {
        let walton = match interaction.tangential() {
            Tangential::Walton(w) => Some(*w),
            _ => None,
        };
        Ok(match emdstar {
            false => Self::Instant {
                normal: Restitution::Central(CentralRestitution::of(
                    interaction.law(),
                    &interaction.props,
                )?),
                walton,
            },
            true => match interaction.tangential() {
                Tangential::History(spring) => Self::EmdStarFrictional {
                    law: *interaction.law(),
                    spring: *spring,
                },
                _ => Self::EmdStar {
                    law: *interaction.law(),
                    props: interaction.props,
                },
            },
        })
    }

    /// The elastic rule of `interaction` (the TC model's, module docs): eMD's smooth
    /// kick with restitution 1, or eMD*'s three events of the law without dissipation
    /// and friction.
    fn elastic_of(emdstar: bool, interaction: &Interaction) -> Self {
        if !emdstar {
            return Self::ELASTIC_KICK;
        }
        let law = match *interaction.law() {
            PairLaw::Linear { stiffness, .. } => PairLaw::Linear {
                stiffness,
                damping: 0.0,
            },
            PairLaw::Hertz { rho_el, .. } => PairLaw::Hertz {
                rho_el,
                dissipation: 0.0,
            },
        };
        Self::EmdStar {
            law,
            props: interaction.props,
        }
    }

    /// The instantaneous smooth elastic collision.
    const ELASTIC_KICK: Self = Self::Instant {
        normal: Restitution::Constant(1.0),
        walton: None,
    };

    /// The collision of the pair `parties` now.
    pub fn pair(
        &self,
        ctx: &mut RuleContext<'_>,
        parties: &[Party; 2],
        impact: &PairImpact,
    ) -> Result<Decision> {
        let PairImpact { r, distance, v } = *impact;
        Ok(match self {
            Self::Instant { normal, walton } => {
                let vn = -(r[0] * v[0] + r[1] * v[1] + r[2] * v[2]) / distance;
                let eps = match normal {
                    Restitution::Constant(e) => *e,
                    Restitution::Central(c) => c.at(vn, ctx.hertz)?,
                };
                Decision::Kick(instant_pair(parties, r, v, eps, walton.as_ref()))
            }
            Self::EmdStar { law, props } => {
                let impact = Impact::from_relative(&to_na(r), &to_na(v))?;
                let scaled = scale(law, props, &impact)?;
                let (mor, fallback) = mor_source(ctx)?.mor(law.model(), &scaled.params)?;
                ctx.stats.mor_fallbacks += u64::from(fallback);
                let out = resolve(&parties.map(|p| p.body()), props.l, &mor, scaled.time);
                let eps = -mor.eps_rdot;
                Decision::Transient(Transient {
                    placed: out.rotated_positions.map(|x| from_na(&x)),
                    moving: from_na(&out.transient_velocity),
                    after: out.post_velocities.map(|x| from_na(&x)),
                    spin: None,
                    duration: out.duration,
                    // Eq. (28): the pair overlaps by l(1 − ε_r) until it has separated.
                    overlap_left: props.l - props.l * mor.eps_r,
                    fallback: instant_pair(parties, r, v, eps, None),
                })
            }
            Self::EmdStarFrictional { law, spring } => {
                ctx.stats.frictional_solves += 1;
                Decision::Transient(frictional::pair(law, spring, parties, impact, ctx.ahead)?)
            }
        })
    }

    /// The collision of `party` (its position relative to a point of the wall) with a
    /// wall of unit normal `n` now, approaching at normal speed `v_n` > 0.
    pub fn wall(
        &self,
        ctx: &mut RuleContext<'_>,
        party: &Party,
        wall: &Wall,
        v_n: f64,
    ) -> Result<Decision> {
        let n = wall.normal;
        Ok(match self {
            Self::Instant { normal, walton } => {
                let eps = match normal {
                    Restitution::Constant(e) => *e,
                    Restitution::Central(c) => c.at(v_n, ctx.hertz)?,
                };
                Decision::Kick(instant_wall(party, n, -v_n, eps, walton.as_ref()))
            }
            Self::EmdStar { law, props } => {
                // A central collision along the normal (Sec. IV with R₂, m₂ → ∞).
                let impact = Impact {
                    normal_speed: v_n,
                    tangential_speed: 0.0,
                };
                let scaled = scale(law, props, &impact)?;
                let (mor, fallback) = mor_source(ctx)?.mor(law.model(), &scaled.params)?;
                ctx.stats.mor_fallbacks += u64::from(fallback);
                let out = resolve_wall(&party.body(), &to_na(n), props.l, &mor, scaled.time);
                let placed = from_na(&out.rotated_positions[0]);
                let after = from_na(&out.post_velocities[0]);
                Decision::Transient(Transient {
                    placed: [placed; 2],
                    moving: from_na(&out.transient_velocity),
                    after: [after; 2],
                    spin: None,
                    duration: out.duration,
                    overlap_left: 0.0,
                    fallback: instant_wall(party, n, -v_n, -mor.eps_rdot, None),
                })
            }
            Self::EmdStarFrictional { law, spring } => {
                ctx.stats.frictional_solves += 1;
                Decision::Transient(frictional::wall(law, spring, party, &n)?)
            }
        })
    }
}

fn mor_source<'a>(ctx: &'a mut RuleContext<'_>) -> Result<&'a mut Box<dyn MorSource>> {
    ctx.mor
        .as_deref_mut()
        .ok_or_else(|| EngineError::Invalid("an eMD* collision without a source of the MoR".into()))
}

/// The instantaneous collision of a pair with normal restitution `eps`: Walton's rule
/// where given (`emdstar_contact::rough_pair`), else the central kick
/// ([`restitution_kick`]); `r` = x_i − x_j, `v` = v_i − v_j.
pub(crate) fn instant_pair(
    parties: &[Party; 2],
    r: [f64; 3],
    v: [f64; 3],
    eps: f64,
    walton: Option<&Walton>,
) -> Kick {
    let [a, b] = parties;
    if let Some(w) = walton {
        let n = vec3::scale(1.0 / vec3::norm(r), r);
        let out = rough_pair(n, &a.rough(), &b.rough(), eps, w);
        return Kick {
            velocity: out.velocity,
            spin: Some(out.spin),
            substitute: false,
        };
    }
    let (di, dj) = restitution_kick(r, v, a.mass, b.mass, eps);
    let (vi, vj) = (a.velocity, b.velocity);
    Kick {
        velocity: [
            std::array::from_fn(|k| vi[k] + di[k]),
            std::array::from_fn(|k| vj[k] + dj[k]),
        ],
        spin: None,
        substitute: false,
    }
}

/// The instantaneous collision of `party` with a wall of unit normal `n`, its normal
/// velocity `vn` < 0, with normal restitution `eps` (and Walton's rule where given).
pub(crate) fn instant_wall(
    party: &Party,
    n: [f64; 3],
    vn: f64,
    eps: f64,
    walton: Option<&Walton>,
) -> Kick {
    if let Some(w) = walton {
        let out = rough_wall(n, &party.rough(), eps, w);
        return Kick {
            velocity: [out.velocity[0]; 2],
            spin: Some([out.spin[0]; 2]),
            substitute: false,
        };
    }
    let kick = (1.0 + eps) * vn;
    let v = party.velocity;
    let after = std::array::from_fn(|k| v[k] - kick * n[k]);
    Kick {
        velocity: [after; 2],
        spin: None,
        substitute: false,
    }
}

/// The rule of every kind of contact of a run, the MoR source of eMD*, the cache of
/// central restitutions, and eMD*'s variant of exception (b).
#[derive(Default)]
pub struct Rules {
    /// "hard-spheres", "emd" or "emdstar".
    method: &'static str,
    /// In the order of [`Interactions::all`]; one rule for all with hard spheres.
    rules: Vec<Rule>,
    /// The elastic rule of each (the TC model's), in the same order.
    elastic: Vec<Rule>,
    interactions: Interactions,
    mor: Option<Box<dyn MorSource>>,
    pub(crate) hertz: HertzRestitution,
    interference: Option<Interference>,
    /// The TC model's t_c in s (module docs); `None`: off.
    tc: Option<f64>,
    /// Frictional contacts solved ahead on a thread of their own: eMD* with friction
    /// in a pool of more than one thread.
    ahead: Option<SolveAhead>,
}

impl Rules {
    /// The rules of `physics` for a domain of `walls` walls, each contact checked
    /// against what its method can run (`Interactions::check_runs_on`).
    pub fn new(physics: Physics, walls: usize) -> Result<Self> {
        let (interactions, mor, interference) = match physics {
            Physics::HardSpheres {
                restitution,
                walton,
            } => {
                if !(0.0..=1.0).contains(&restitution) {
                    return Err(EngineError::Invalid(format!(
                        "coefficient of restitution {restitution} must lie in [0, 1]"
                    )));
                }
                if let Some(w) = walton {
                    Walton::new(w.friction, w.tangential_restitution)?;
                }
                let walton = walton.filter(|w| w.friction > 0.0);
                return Ok(Self {
                    method: "hard-spheres",
                    rules: vec![Rule::Instant {
                        normal: Restitution::Constant(restitution),
                        walton,
                    }],
                    elastic: vec![Rule::ELASTIC_KICK],
                    ..Self::default()
                });
            }
            Physics::Emd(interactions) => {
                interactions.check_runs_on(Method::Emd, walls)?;
                (interactions, None, None)
            }
            Physics::EmdStar {
                interactions,
                mor,
                interference,
            } => {
                interactions.check_runs_on(Method::EmdStar, walls)?;
                (interactions, Some(mor), Some(interference))
            }
        };
        let emdstar = mor.is_some();
        let rules: Vec<Rule> = interactions
            .all()
            .map(|i| Rule::of(emdstar, i))
            .collect::<Result<_>>()?;
        let ahead = (rayon::current_num_threads() > 1
            && rules
                .iter()
                .any(|r| matches!(r, Rule::EmdStarFrictional { .. })))
        .then(SolveAhead::default);
        let elastic = interactions
            .all()
            .map(|i| Rule::elastic_of(emdstar, i))
            .collect();
        Ok(Self {
            method: if emdstar { "emdstar" } else { "emd" },
            rules,
            elastic,
            interactions,
            mor,
            hertz: HertzRestitution::default(),
            interference,
            tc: None,
            ahead,
        })
    }

    /// Turns the TC model on with duration `tc` in s (`None`: off). Refuses a `tc`
    /// that is not a finite number greater than zero.
    pub fn set_tc(&mut self, tc: Option<f64>) -> Result<()> {
        if let Some(t) = tc
            && !(t.is_finite() && t > 0.0)
        {
            return Err(EngineError::Invalid(format!(
                "the TC model's t_c = {t:e} s must be a finite number greater than zero"
            )));
        }
        self.tc = tc;
        Ok(())
    }

    /// The TC model's t_c in s, if it is on.
    pub fn tc(&self) -> Option<f64> {
        self.tc
    }

    /// Whether the TC model makes a collision `since` s after the parties' previous
    /// one elastic; counted.
    fn tc_elastic(&self, since: f64, stats: &mut Stats) -> bool {
        let elastic = self.tc.is_some_and(|tc| since < tc);
        stats.tc_elastic += u64::from(elastic);
        elastic
    }

    /// The rule of species `a` against species `b` for a collision `since` s after
    /// the later of the parties' previous collisions (the TC model's elastic rule
    /// within t_c), with what it may use.
    #[inline]
    pub fn pair<'a>(
        &'a mut self,
        a: u32,
        b: u32,
        since: f64,
        stats: &'a mut Stats,
    ) -> (&'a Rule, RuleContext<'a>) {
        let k = self.pair_index(a, b);
        self.with_context(k, since, stats)
    }

    /// The rule of species `a` against wall `w` for a collision `since` s after the
    /// particle's previous one, with what it may use.
    #[inline]
    pub fn wall<'a>(
        &'a mut self,
        a: u32,
        w: usize,
        since: f64,
        stats: &'a mut Stats,
    ) -> (&'a Rule, RuleContext<'a>) {
        let k = match self.rules.len() {
            1 => 0,
            _ => self.interactions.wall_index(a, w),
        };
        self.with_context(k, since, stats)
    }

    /// The index of the rule of species `a` against species `b`.
    fn pair_index(&self, a: u32, b: u32) -> usize {
        match self.rules.len() {
            1 => 0,
            _ => self.interactions.pair_index(a, b),
        }
    }

    fn with_context<'a>(
        &'a mut self,
        k: usize,
        since: f64,
        stats: &'a mut Stats,
    ) -> (&'a Rule, RuleContext<'a>) {
        let rule = match self.tc_elastic(since, stats) {
            true => &self.elastic[k],
            false => &self.rules[k],
        };
        let ctx = RuleContext {
            mor: self.mor.as_mut(),
            ahead: self.ahead.as_ref(),
            hertz: &mut self.hertz,
            stats,
        };
        (rule, ctx)
    }

    /// The contacts the rules were built for (empty for hard spheres).
    pub fn interactions(&self) -> &Interactions {
        &self.interactions
    }

    /// The method: "hard-spheres", "emd" or "emdstar".
    pub fn method(&self) -> &'static str {
        self.method
    }

    /// eMD*'s variant of exception (b), `None` for instantaneous collisions.
    pub fn interference(&self) -> Option<Interference> {
        self.interference
    }

    /// Whether collisions take eMD*'s three events (pairs may then be left overlapping).
    pub fn is_emdstar(&self) -> bool {
        self.interference.is_some()
    }

    /// True if any collision changes spins.
    pub fn is_frictional(&self) -> bool {
        self.rules.iter().any(|r| match r {
            Rule::Instant { walton, .. } => walton.is_some(),
            Rule::EmdStar { .. } => false,
            Rule::EmdStarFrictional { .. } => true,
        })
    }

    /// Whether predicted frictional collisions are solved ahead ([`Rules::solve_ahead`]).
    pub fn solves_ahead(&self) -> Option<&SolveAhead> {
        self.ahead.as_ref()
    }

    /// Solves every frictional contact on the engine's thread (the hybrid's event core,
    /// whose time-driven part keeps the other cores busy).
    pub(crate) fn solve_on_one_thread(&mut self) {
        self.ahead = None;
    }

    /// Hands the worker of [`SolveAhead`] the collision `predicted` of `parties`
    /// (species `a` and `b`), if it is frictional (not under the TC model, which may
    /// make it elastic).
    pub fn solve_ahead(&mut self, predicted: Predicted, (a, b): (u32, u32), parties: &[Party; 2]) {
        let k = self.pair_index(a, b);
        let Some(ahead) = self.ahead.as_mut() else {
            return;
        };
        if let (None, Rule::EmdStarFrictional { law, spring }) = (self.tc, &self.rules[k]) {
            ahead.submit(predicted, law, spring, frictional::contact(parties));
        }
    }

    /// The name of the MoR source ("table+exact", …; empty without eMD*).
    pub fn mor_name(&self) -> &'static str {
        self.mor.as_ref().map_or("", |m| m.name())
    }
}
