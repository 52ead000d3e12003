//! Exact frictional contacts solved ahead, on a thread of their own.
//!
//! eMD*'s frictional collision is one exact contact solve ([`PairContact::solve`]), a pure
//! function of the pair as it meets, which is known as soon as the collision is
//! predicted (the spheres fly freely until then). The engine hands predicted
//! collisions here ([`SolveAhead::submit`]); a worker solves them, earliest first. When
//! a collision is executed, [`SolveAhead::solve`] takes the worker's result if its
//! inputs are the executed contact's to the bit, and solves the contact itself
//! otherwise: the outcome is the same to the bit whoever solved it, so a run gives the
//! same output with or without the worker. A prediction that turns stale costs the
//! worker a solve and nothing else.

use emdstar_contact::{HistorySpring, PairLaw};
use emdstar_mor::SolveError;
use emdstar_mor::frictional::{CONTACT_OPTIONS, FrictionalEnd};
use emdstar_mor::rule::PairContact;
use std::collections::{BTreeMap, HashMap};
use std::sync::atomic::{AtomicBool, AtomicU64, AtomicUsize, Ordering};
use std::sync::{Arc, Condvar, Mutex, MutexGuard};
use std::thread::JoinHandle;

/// Bits of what a solve depends on: the law (kind and two constants), the spring, the
/// two spheres, the separation and the velocity.
type Key = [u64; 22];

/// At most this many predictions are held (about 10 MB), the earliest: the worker
/// keeps a few collisions ahead of the engine, and far predictions mostly turn stale.
/// Beyond it (gases of more than some 10⁴ particles) a collision predicted far ahead
/// is solved by the engine's thread.
const DEPTH: usize = 16_384;

/// Spins of the engine's thread between looks at a job the worker is on, and of the
/// idle worker before it sleeps (about 0.1 ms).
const SPIN: usize = 64;
const IDLE_SPINS: usize = 20_000;

fn key(law: &PairLaw, spring: &HistorySpring, c: &PairContact) -> Key {
    let (kind, a, b) = match *law {
        PairLaw::Linear { stiffness, damping } => (0, stiffness, damping),
        PairLaw::Hertz {
            rho_el,
            dissipation,
        } => (1, rho_el, dissipation),
    };
    let [s, t] = c.spheres;
    let values = [
        a,
        b,
        spring.friction,
        spring.stiffness,
        spring.damping,
        s.radius,
        s.mass,
        s.spin[0],
        s.spin[1],
        s.spin[2],
        t.radius,
        t.mass,
        t.spin[0],
        t.spin[1],
        t.spin[2],
        c.separation[0],
        c.separation[1],
        c.separation[2],
        c.velocity[0],
        c.velocity[1],
        c.velocity[2],
    ];
    let mut k = [kind; 22];
    for (slot, v) in k[1..].iter_mut().zip(values) {
        *slot = v.to_bits();
    }
    k
}

type Solved = Result<FrictionalEnd, SolveError>;

/// A multiply–rotate hash of a few words (the keys are exact bits, and no key comes
/// from outside the process): the standard library's SipHash costs more than the rest
/// of a submission.
#[derive(Default, Clone, Copy)]
struct WordHasher(u64);

impl std::hash::Hasher for WordHasher {
    fn finish(&self) -> u64 {
        self.0
    }

    fn write(&mut self, bytes: &[u8]) {
        let mut words = bytes.chunks_exact(8);
        for word in &mut words {
            self.write_u64(u64::from_le_bytes(word.try_into().unwrap_or_default()));
        }
        for &byte in words.remainder() {
            self.write_u64(u64::from(byte));
        }
    }

    fn write_u64(&mut self, x: u64) {
        self.0 = (self.0.rotate_left(5) ^ x).wrapping_mul(0x517c_c1b7_2722_0a95);
    }

    fn write_u32(&mut self, x: u32) {
        self.write_u64(u64::from(x));
    }

    fn write_usize(&mut self, x: usize) {
        self.write_u64(x as u64);
    }
}

type Map<K, V> = HashMap<K, V, std::hash::BuildHasherDefault<WordHasher>>;

enum Progress {
    Waiting,
    Running,
    Done(Solved),
}

/// A collision as predicted: its time, its two particles (original number and
/// collision counter, the predicting particle first) and the slot of the first.
#[derive(Debug, Clone, Copy)]
pub struct Predicted {
    pub time: f64,
    pub parties: [(u32, u32); 2],
    pub slot: u32,
}

struct Job {
    law: PairLaw,
    spring: HistorySpring,
    contact: PairContact,
    /// Its place in [`Board::order`]: (time bits, sequence).
    at: (u64, u64),
    /// The two particles (original numbers, the smaller first) and their collision
    /// counters when predicted: a change of either makes the prediction stale.
    pair: (u32, u32),
    counters: (u32, u32),
    /// The particle whose prediction this is: its original number and its slot in
    /// the engine when predicted.
    owner: u32,
    slot: u32,
    progress: Progress,
}

/// The jobs, shared by the engine's thread and the worker.
#[derive(Default)]
struct Board {
    jobs: Map<Key, Job>,
    /// Every job by (time, submission), and the waiting ones: the worker takes the
    /// earliest of these.
    order: BTreeMap<(u64, u64), Key>,
    waiting: BTreeMap<(u64, u64), Key>,
    /// The job of each pair (by its two particles): a pair's collision is predicted
    /// once from each side, and only the earlier is executed.
    pairs: Map<(u32, u32), Key>,
    /// The jobs that name each particle as the partner of another's prediction.
    named: Map<u32, Vec<Key>>,
    /// Each particle's collision counter, as last told ([`SolveAhead::note`]).
    counters: Vec<u32>,
    submitted: u64,
    stop: bool,
}

impl Job {
    fn partner(&self) -> u32 {
        if self.pair.0 == self.owner {
            self.pair.1
        } else {
            self.pair.0
        }
    }
}

impl Board {
    fn remove(&mut self, k: &Key) -> Option<Job> {
        let job = self.jobs.remove(k)?;
        self.order.remove(&job.at);
        self.waiting.remove(&job.at);
        if self.pairs.get(&job.pair) == Some(k) {
            self.pairs.remove(&job.pair);
        }
        if let Some(keys) = self.named.get_mut(&job.partner())
            && let Some(at) = keys.iter().position(|x| x == k)
        {
            keys.swap_remove(at);
        }
        Some(job)
    }

    /// Files the prediction unless the board has it, holds the pair's earlier one from
    /// its other particle, or is full of earlier ones; true if filed.
    fn insert(
        &mut self,
        predicted: Predicted,
        law: &PairLaw,
        spring: &HistorySpring,
        contact: PairContact,
    ) -> bool {
        let k = key(law, spring, &contact);
        let Predicted {
            time,
            parties,
            slot,
        } = predicted;
        let owner = parties[0].0;
        let [first, second] = if parties[0].0 < parties[1].0 {
            parties
        } else {
            [parties[1], parties[0]]
        };
        let (pair, counters) = ((first.0, second.0), (first.1, second.1));
        let time = (time + 0.0).to_bits();
        self.set_counter(first.0, first.1);
        self.set_counter(second.0, second.1);
        if self.jobs.contains_key(&k) {
            return false;
        }
        if let Some(other) = self.pairs.get(&pair).copied() {
            // A particle's new prediction replaces its old one; of the pair's two, the
            // earlier is the one executed.
            if let Some(old) = self.jobs.get(&other)
                && old.owner != owner
                && old.at.0 <= time
            {
                return false;
            }
            self.remove(&other);
        }
        if self.order.len() >= DEPTH {
            match self.order.last_key_value() {
                Some((&last, &k)) if last.0 > time => {
                    self.remove(&k);
                }
                _ => return false,
            }
        }
        self.submitted += 1;
        let at = (time, self.submitted);
        self.order.insert(at, k);
        self.waiting.insert(at, k);
        self.pairs.insert(pair, k);
        self.named.entry(parties[1].0).or_default().push(k);
        self.jobs.insert(
            k,
            Job {
                law: *law,
                spring: *spring,
                contact,
                at,
                pair,
                counters,
                owner,
                slot,
                progress: Progress::Waiting,
            },
        );
        true
    }

    fn counter(&self, id: u32) -> Option<u32> {
        self.counters.get(id as usize).copied()
    }

    fn set_counter(&mut self, id: u32, counter: u32) {
        let k = id as usize;
        if k >= self.counters.len() {
            self.counters.resize(k + 1, 0);
        }
        self.counters[k] = counter;
    }

    /// Claims the earliest waiting job that is not stale; stale ones go.
    fn claim(&mut self) -> Option<(Key, PairLaw, HistorySpring, PairContact)> {
        while let Some((_, k)) = self.waiting.pop_first() {
            let Some(job) = self.jobs.get(&k) else {
                continue;
            };
            let (a, b) = job.pair;
            if self.counter(a) != Some(job.counters.0) || self.counter(b) != Some(job.counters.1) {
                self.remove(&k);
                continue;
            }
            let job = self.jobs.get_mut(&k)?;
            job.progress = Progress::Running;
            return Some((k, job.law, job.spring, job.contact));
        }
        None
    }

    fn finish(&mut self, k: &Key, solved: Solved) {
        if let Some(job) = self.jobs.get_mut(k) {
            job.progress = Progress::Done(solved);
        }
    }
}

struct Shared {
    board: Mutex<Board>,
    /// Wakes the worker when it sleeps (without work for a while) and a job comes, or
    /// to stop.
    changed: Condvar,
    asleep: AtomicBool,
    /// How many jobs wait (the worker looks here without the lock while it spins).
    waiting: AtomicUsize,
    /// Results taken from the worker, and solves the engine's thread did itself.
    taken: AtomicU64,
    inline: AtomicU64,
}

impl Shared {
    fn lock(&self) -> MutexGuard<'_, Board> {
        // A panic on the other thread leaves the board as consistent as before it.
        self.board.lock().unwrap_or_else(|e| e.into_inner())
    }
}

/// The worker and its board (see the module docs). The worker starts with the first
/// submission and stops when this is dropped.
pub struct SolveAhead {
    shared: Arc<Shared>,
    worker: Option<JoinHandle<()>>,
}

impl Default for SolveAhead {
    fn default() -> Self {
        Self {
            shared: Arc::new(Shared {
                board: Mutex::default(),
                changed: Condvar::new(),
                asleep: AtomicBool::new(false),
                waiting: AtomicUsize::new(0),
                taken: AtomicU64::new(0),
                inline: AtomicU64::new(0),
            }),
            worker: None,
        }
    }
}

impl SolveAhead {
    /// Hands the worker the contact `contact` of the collision `predicted`, under `law`
    /// and `spring`.
    pub fn submit(
        &mut self,
        predicted: Predicted,
        law: &PairLaw,
        spring: &HistorySpring,
        contact: PairContact,
    ) {
        if self.worker.is_none() {
            let shared = Arc::clone(&self.shared);
            self.worker = std::thread::Builder::new()
                .name("emdstar-contacts".into())
                .spawn(move || work(&shared))
                .ok();
        }
        let mut board = self.shared.lock();
        if board.insert(predicted, law, spring, contact) {
            self.shared
                .waiting
                .store(board.waiting.len(), Ordering::Release);
            drop(board);
            // A futex call only when the worker sleeps: one per submission would cost
            // the engine's thread more than the rest of it.
            if self.shared.asleep.load(Ordering::Acquire) {
                self.shared.changed.notify_one();
            }
        }
    }

    /// Drops the jobs predicted before `now` (their collisions did not happen), and
    /// takes the collision counters `changed` (original number, counter) of particles
    /// predicted anew: the worker skips predictions they made stale. Puts in `again`
    /// the slots of the particles whose waiting predictions name one of them as the
    /// partner: its state was moved on, so their inputs are to be taken anew.
    pub fn note(&self, now: f64, changed: impl Iterator<Item = (u32, u32)>, again: &mut Vec<u32>) {
        let now = (now + 0.0).to_bits();
        let mut board = self.shared.lock();
        while let Some((&at, &k)) = board.order.first_key_value()
            && at.0 < now
        {
            board.remove(&k);
        }
        for (id, counter) in changed {
            board.set_counter(id, counter);
            if let Some(keys) = board.named.get(&id) {
                again.extend(keys.iter().filter_map(|k| {
                    let job = board.jobs.get(k)?;
                    matches!(job.progress, Progress::Waiting).then_some(job.slot)
                }));
            }
        }
    }

    /// The exact contact `contact` under `law` and `spring` (to [`CONTACT_OPTIONS`]):
    /// the worker's result if it has this contact, else solved here. While the worker
    /// is still on it, this thread solves the next waiting job.
    pub fn solve(&self, law: &PairLaw, spring: &HistorySpring, contact: &PairContact) -> Solved {
        if self.worker.is_some() {
            let k = key(law, spring, contact);
            let mut board = self.shared.lock();
            loop {
                match board.jobs.get(&k).map(|j| &j.progress) {
                    Some(Progress::Done(_)) => {
                        if let Some(Progress::Done(solved)) = board.remove(&k).map(|j| j.progress) {
                            self.shared.taken.fetch_add(1, Ordering::Relaxed);
                            return solved;
                        }
                    }
                    Some(Progress::Running) => match board.claim() {
                        Some((other, law, spring, c)) => {
                            drop(board);
                            let solved = c.solve(&law, &spring, &CONTACT_OPTIONS);
                            board = self.shared.lock();
                            board.finish(&other, solved);
                        }
                        None if self.worker.as_ref().is_some_and(|w| w.is_finished()) => {
                            // The worker is gone (a panic): nobody else will solve it.
                            board.remove(&k);
                            break;
                        }
                        None => {
                            // The worker is on it: it ends within a solve.
                            drop(board);
                            for _ in 0..SPIN {
                                std::hint::spin_loop();
                            }
                            board = self.shared.lock();
                        }
                    },
                    Some(Progress::Waiting) => {
                        board.remove(&k);
                        break;
                    }
                    None => break,
                }
            }
        }
        self.shared.inline.fetch_add(1, Ordering::Relaxed);
        contact.solve(law, spring, &CONTACT_OPTIONS)
    }

    /// Solves taken from the worker and solved on the engine's thread so far.
    pub fn counts(&self) -> (u64, u64) {
        (
            self.shared.taken.load(Ordering::Relaxed),
            self.shared.inline.load(Ordering::Relaxed),
        )
    }
}

impl Drop for SolveAhead {
    fn drop(&mut self) {
        self.shared.lock().stop = true;
        self.shared.changed.notify_all();
        if let Some(worker) = self.worker.take() {
            let _ = worker.join();
        }
    }
}

/// The worker: the earliest waiting job, solved, until stopped.
fn work(shared: &Shared) {
    loop {
        let mut board = shared.lock();
        if board.stop {
            return;
        }
        if let Some((k, law, spring, c)) = board.claim() {
            shared.waiting.store(board.waiting.len(), Ordering::Release);
            drop(board);
            let solved = c.solve(&law, &spring, &CONTACT_OPTIONS);
            shared.lock().finish(&k, solved);
            continue;
        }
        shared.waiting.store(0, Ordering::Release);
        drop(board);
        // Without work: spin a while (the next submission is usually a few
        // microseconds away, and waking a sleeping thread costs more), then sleep.
        let mut spins = 0;
        while shared.waiting.load(Ordering::Acquire) == 0 && spins < IDLE_SPINS {
            std::hint::spin_loop();
            spins += 1;
        }
        if spins == IDLE_SPINS {
            let mut board = shared.lock();
            shared.asleep.store(true, Ordering::Release);
            while board.waiting.is_empty() && !board.stop {
                board = shared
                    .changed
                    .wait(board)
                    .unwrap_or_else(|e| e.into_inner());
            }
            shared.asleep.store(false, Ordering::Release);
        }
    }
}

#[cfg(test)]
mod tests;
