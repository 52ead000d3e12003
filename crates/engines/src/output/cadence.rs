//! When an output is due: every interval of simulated time, k·interval for k = 0, 1, …
//! (lumol's `OutputFrequency`, in time rather than steps).

use emdstar_system::KeepUntil;

/// Output times k·interval (k = 0, 1, …). For an engine that takes steps of dt the
/// interval is a whole number of steps, at least one, and a time within half a step of
/// a tick counts as the tick.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Cadence {
    interval: f64,
    /// The number k of the next tick.
    next: u64,
    tolerance: f64,
    /// Whether the interval asked for was shorter than a step (one tick per step).
    every_step: bool,
}

impl Cadence {
    /// Ticks every `interval` s (positive and finite), on whole steps of `step` (the
    /// engine's time step; `None` for event engines, which reach any time exactly). The
    /// first tick is at time 0 until [`Cadence::start_at`] moves it.
    pub fn new(interval: f64, step: Option<f64>) -> Self {
        let (interval, tolerance, every_step) = match step {
            Some(dt) => {
                let steps = (interval / dt).round();
                ((steps.max(1.0)) * dt, 0.5 * dt, steps < 1.0)
            }
            None => (interval, 0.0, false),
        };
        Self {
            interval,
            next: 0,
            tolerance,
            every_step,
        }
    }

    /// The time between ticks (a whole number of steps for a step engine).
    pub fn interval(&self) -> f64 {
        self.interval
    }

    /// Whether the interval asked for was shorter than the engine's step, so that the
    /// output is due at every step.
    pub fn every_step(&self) -> bool {
        self.every_step
    }

    /// How close to a tick a time must be to count as the tick: half a step, or 0.
    pub fn tolerance(&self) -> f64 {
        self.tolerance
    }

    /// Makes the first tick the one at `t` (if `inclusive` and `t` is a tick) or the
    /// first after `t`.
    pub fn start_at(&mut self, t: f64, inclusive: bool) {
        self.next = (t / self.interval).floor().max(0.0) as u64;
        while self.time() < t - self.tolerance || (!inclusive && self.time() <= t + self.tolerance)
        {
            self.next += 1;
        }
    }

    /// The time of the next tick.
    pub fn time(&self) -> f64 {
        self.next as f64 * self.interval
    }

    /// Whether the next tick has come at time `t`.
    pub fn is_due(&self, t: f64) -> bool {
        t >= self.time() - self.tolerance
    }

    /// Moves the next tick past time `t`.
    pub fn pass(&mut self, t: f64) {
        while self.time() <= t + self.tolerance {
            self.next += 1;
        }
    }

    /// Whether `t` is a tick.
    pub fn is_tick(&self, t: f64) -> bool {
        let k = (t / self.interval).round();
        (t - k * self.interval).abs() <= self.tolerance
    }

    /// The ticks in [`from`, `to`], about (for size estimates).
    pub fn ticks_between(&self, from: f64, to: f64) -> f64 {
        ((to - from) / self.interval).floor().max(0.0) + 1.0
    }
}

/// When a file of records (log lines, frames) is written: at the ticks of its cadence,
/// and once more where a run ends between two; what a resumed run keeps of it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Schedule {
    cadence: Cadence,
    /// The time of the last record written (or kept).
    last: Option<f64>,
}

impl Schedule {
    pub fn new(cadence: Cadence) -> Self {
        Self {
            cadence,
            last: None,
        }
    }

    /// A fresh run from `t`: its first record is due at once.
    pub fn open(&mut self, t: f64) {
        self.cadence.start_at(t, true);
    }

    /// What a run resumed at `t` keeps of the file: the records before `t`, and the one
    /// at `t` if it is a tick (one written there only because a run stopped is cut).
    /// The next record is due after `t`.
    pub fn resume(&mut self, t: f64) -> KeepUntil {
        let keep = KeepUntil {
            t,
            at_t: self.cadence.is_tick(t),
        };
        // A record at a tick `t` is the earlier run's, kept: none is due again there.
        self.last = keep.at_t.then_some(t);
        self.cadence.start_at(t, false);
        keep
    }

    /// The time the next record is due.
    pub fn next_due(&self) -> f64 {
        self.cadence.time()
    }

    /// Notes a record written at `t`; `due` moves on to the next tick.
    pub fn wrote(&mut self, t: f64, due: bool) {
        self.last = Some(t);
        if due {
            self.cadence.pass(t);
        }
    }

    /// Whether a run ending at `t` still needs its last record.
    pub fn needs_last(&self, t: f64) -> bool {
        self.last != Some(t)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_step_engine_ticks_on_whole_steps_and_never_twice_at_one_time() {
        // Steps of 0.3 ms, ticks asked for every 1 ms: every 3 steps (0.9 ms).
        let dt = 3e-4;
        let mut c = Cadence::new(1e-3, Some(dt));
        assert!((c.interval() - 9e-4).abs() < 1e-18 && !c.every_step());
        // Resumed at step 6 (0.0018 s, a tick, with round-off in the step count): the
        // next tick is the one of step 9, not the one the run wrote before stopping.
        let t = 6.0 * dt * (1.0 - 1e-15);
        c.start_at(t, false);
        assert!((c.time() - 9.0 * dt).abs() < 1e-15, "{}", c.time());
        assert!(c.is_tick(t) && !c.is_tick(7.0 * dt));
        // A fresh start at 0 is due at once.
        let mut fresh = Cadence::new(1e-3, Some(dt));
        fresh.start_at(0.0, true);
        assert!(fresh.is_due(0.0));
        fresh.pass(0.0);
        assert!(!fresh.is_due(2.0 * dt) && fresh.is_due(3.0 * dt - 1e-12));
    }

    #[test]
    fn an_interval_shorter_than_a_step_is_one_step_and_says_so() {
        let c = Cadence::new(1e-30, Some(1e-6));
        assert!(c.every_step());
        assert_eq!(c.interval(), 1e-6);
    }

    #[test]
    fn an_event_engine_ticks_exactly() {
        // 3 × 0.1 is 0.30000000000000004: a run stopped at 0.3 has its next tick
        // there, 1 ulp later, where a run that went through writes it.
        let mut c = Cadence::new(0.1, None);
        c.start_at(0.3, false);
        assert_eq!(c.time(), 3.0 * 0.1);
        assert!(c.time() > 0.3 && !c.is_tick(0.3));
        c.start_at(0.5, false);
        assert_eq!(c.time(), 6.0 * 0.1);
        assert!(c.is_tick(5.0 * 0.1));
    }
}
