//! Event queues holding one key (the time of its next event) per particle.
//!
//! The engine keeps each particle's earliest event in its own record and only asks the
//! queue which particle comes next; stale events are recognised by per-particle
//! collision counters (Rapaport 1980; Bannerman et al. 2011, DynamO), so the queue never
//! has to delete anything and never allocates after construction.

/// A priority queue over the fixed set of ids `0..len`, each with a time key
/// (`f64::INFINITY` for "no event").
pub trait EventQueue {
    /// A queue of `len` ids, all at time +∞.
    fn new(len: usize) -> Self
    where
        Self: Sized;
    /// Sets the key of `id`.
    fn set(&mut self, id: usize, time: f64);
    /// The id with the smallest key and that key; ties go to the smaller id so that
    /// runs are reproducible.
    fn peek(&mut self) -> (usize, f64);
    /// The key of `id`.
    fn key(&self, id: usize) -> f64;
    /// A few (key, id) entries that come soon after the earliest, in no order: a hint
    /// for asking for their records before they are needed (it may be empty).
    fn upcoming(&self) -> &[(f64, u32)] {
        &[]
    }
    /// Errors unless the queue (decoded from a checkpoint) holds exactly the ids
    /// `0..len`, each once, in a consistent structure with keys that are not NaN:
    /// what every other method relies on.
    fn check(&self, len: usize) -> Result<(), String>;
}

/// Errors unless `heap` is a min-heap of `arity` by `less` (a decoded one).
pub(crate) fn check_heap_order(heap: &[(f64, u32)], arity: usize) -> Result<(), String> {
    for (k, &item) in heap.iter().enumerate().skip(1) {
        if less(item, heap[(k - 1) / arity]) {
            return Err(format!("heap entry {k} precedes its parent"));
        }
    }
    Ok(())
}

/// An indexed 4-ary min-heap: O(log N) `set`, O(1) `peek`. Keys are stored in the
/// heap array next to their ids, so sifting touches one contiguous array, and the four
/// children of a node share a cache line (half the depth of a binary heap).
#[derive(Debug, Clone, serde::Serialize, serde::Deserialize)]
pub struct IndexedHeap {
    /// (key, id) at each heap slot.
    heap: Vec<(f64, u32)>,
    /// slot[id] = heap slot of id.
    slot: Vec<u32>,
}

const ARITY: usize = 4;

#[inline(always)]
fn less(a: (f64, u32), b: (f64, u32)) -> bool {
    a.0 < b.0 || (a.0 == b.0 && a.1 < b.1)
}

impl IndexedHeap {
    #[inline(always)]
    fn place(&mut self, k: usize, item: (f64, u32)) {
        self.heap[k] = item;
        self.slot[item.1 as usize] = k as u32;
    }

    #[inline]
    fn sift_up(&mut self, mut k: usize, item: (f64, u32)) {
        while k > 0 {
            let parent = (k - 1) / ARITY;
            let p = self.heap[parent];
            if !less(item, p) {
                break;
            }
            self.place(k, p);
            k = parent;
        }
        self.place(k, item);
    }

    #[inline]
    fn sift_down(&mut self, mut k: usize, item: (f64, u32)) {
        let n = self.heap.len();
        loop {
            let first = ARITY * k + 1;
            if first >= n {
                break;
            }
            let mut child = first;
            let mut c = self.heap[first];
            for m in first + 1..(first + ARITY).min(n) {
                let x = self.heap[m];
                if less(x, c) {
                    child = m;
                    c = x;
                }
            }
            if !less(c, item) {
                break;
            }
            self.place(k, c);
            k = child;
        }
        self.place(k, item);
    }
}

impl EventQueue for IndexedHeap {
    fn new(len: usize) -> Self {
        assert!(len < u32::MAX as usize, "too many particles for u32 ids");
        Self {
            heap: (0..len as u32).map(|i| (f64::INFINITY, i)).collect(),
            slot: (0..len as u32).collect(),
        }
    }

    #[inline]
    fn set(&mut self, id: usize, time: f64) {
        let k = self.slot[id] as usize;
        let old = self.heap[k].0;
        let item = (time, id as u32);
        if time < old {
            self.sift_up(k, item);
        } else {
            self.sift_down(k, item);
        }
    }

    #[inline]
    fn peek(&mut self) -> (usize, f64) {
        let (t, id) = self.heap[0];
        (id as usize, t)
    }

    /// The root's children: the next earliest is one of them.
    fn upcoming(&self) -> &[(f64, u32)] {
        &self.heap[self.heap.len().min(1)..self.heap.len().min(1 + ARITY)]
    }

    #[inline]
    fn key(&self, id: usize) -> f64 {
        self.heap[self.slot[id] as usize].0
    }

    fn check(&self, len: usize) -> Result<(), String> {
        if self.heap.len() != len || self.slot.len() != len {
            return Err(format!("{} heap entries for {len} ids", self.heap.len()));
        }
        for (id, &k) in self.slot.iter().enumerate() {
            match self.heap.get(k as usize) {
                Some(&(key, at)) if at as usize == id && !key.is_nan() => {}
                _ => return Err(format!("id {id} is not where the heap says")),
            }
        }
        check_heap_order(&self.heap, ARITY)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{RngExt, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    fn check_against_linear_scan<Q: EventQueue>() {
        let n = 257;
        let mut q = Q::new(n);
        let mut keys = vec![f64::INFINITY; n];
        let mut rng = ChaCha8Rng::seed_from_u64(7);
        for step in 0..20_000 {
            let id = rng.random_range(0..n);
            // Mix finite times, repeats (ties) and infinities.
            let t = match step % 7 {
                0 => f64::INFINITY,
                1 => 0.5,
                _ => rng.random::<f64>() * 10.0,
            };
            q.set(id, t);
            keys[id] = t;
            let (best, tb) = q.peek();
            let expect = (0..n)
                .min_by(|&a, &b| keys[a].total_cmp(&keys[b]).then(a.cmp(&b)))
                .unwrap();
            assert_eq!((best, tb), (expect, keys[expect]), "step {step}");
            assert_eq!(q.key(id), t);
        }
    }

    fn drains_to_infinity_and_refills<Q: EventQueue>() {
        let mut q = Q::new(5);
        assert_eq!(q.peek(), (0, f64::INFINITY));
        for id in 0..5 {
            q.set(id, 1.0 + id as f64);
        }
        assert_eq!(q.peek(), (0, 1.0));
        for id in 0..5 {
            q.set(id, f64::INFINITY);
        }
        assert_eq!(q.peek(), (0, f64::INFINITY));
        assert_eq!(q.peek(), (0, f64::INFINITY));
        q.set(3, 7.5);
        assert_eq!(q.peek(), (3, 7.5));
        q.set(4, 0.25);
        assert_eq!(q.peek(), (4, 0.25));
    }

    #[test]
    fn queues_report_only_infinite_keys_and_refill() {
        drains_to_infinity_and_refills::<IndexedHeap>();
        drains_to_infinity_and_refills::<crate::CalendarQueue>();
    }

    #[test]
    fn heap_agrees_with_a_linear_scan() {
        check_against_linear_scan::<IndexedHeap>();
    }

    #[test]
    fn calendar_agrees_with_a_linear_scan() {
        check_against_linear_scan::<crate::CalendarQueue>();
    }

    /// In event-driven use, how often the queue's hint names the id that comes next.
    fn hint_hit_rate<Q: EventQueue>() -> f64 {
        let n = 1000;
        let mut q = Q::new(n);
        let mut keys = vec![0.0; n];
        let mut rng = ChaCha8Rng::seed_from_u64(11);
        for (id, key) in keys.iter_mut().enumerate() {
            *key = rng.random::<f64>();
            q.set(id, *key);
        }
        let steps = 20_000;
        let mut hits = 0;
        for _ in 0..steps {
            let (a, ta) = q.peek();
            let next = (0..n)
                .filter(|&b| b != a)
                .min_by(|&x, &y| keys[x].total_cmp(&keys[y]).then(x.cmp(&y)))
                .unwrap();
            hits += usize::from(q.upcoming().iter().any(|&(_, id)| id as usize == next));
            keys[a] = ta + rng.random::<f64>();
            q.set(a, keys[a]);
        }
        hits as f64 / steps as f64
    }

    #[test]
    fn upcoming_names_the_next_event() {
        // The heap's next earliest is always a child of its root; the calendar's is in
        // its current bucket unless that runs out (two times in three here).
        assert_eq!(hint_hit_rate::<IndexedHeap>(), 1.0);
        let calendar = hint_hit_rate::<crate::CalendarQueue>();
        assert!(calendar > 0.3, "calendar hint right {calendar} of the time");
    }

    #[test]
    fn calendar_follows_advancing_time() {
        // Event-driven use: pop the minimum and reschedule it later, many windows on.
        let n = 100;
        let mut q = crate::CalendarQueue::new(n);
        let mut h = IndexedHeap::new(n);
        let mut rng = ChaCha8Rng::seed_from_u64(3);
        for id in 0..n {
            let t = rng.random::<f64>();
            q.set(id, t);
            h.set(id, t);
        }
        for _ in 0..100_000 {
            let (a, ta) = q.peek();
            let (b, tb) = h.peek();
            assert_eq!((a, ta), (b, tb));
            let t = ta + rng.random::<f64>() * if rng.random::<f64>() < 0.01 { 1e3 } else { 1.0 };
            q.set(a, t);
            h.set(a, t);
        }
    }

    #[test]
    fn calendar_follows_event_rates_over_many_decades() {
        // The buckets are first sized before any key is known, and then resized as
        // the lead times swing from 1e-7 to 1e5: the order must stay the heap's.
        let n = 1000;
        let mut q = crate::CalendarQueue::new(n);
        let mut h = IndexedHeap::new(n);
        let mut rng = ChaCha8Rng::seed_from_u64(5);
        for id in 0..n {
            let t = 1e-7 * rng.random::<f64>();
            q.set(id, t);
            h.set(id, t);
        }
        for step in 0..200_000 {
            let scale = [1e-7, 1e5, 1e-3, 1.0][step / 50_000];
            let (a, ta) = q.peek();
            let (b, tb) = h.peek();
            assert_eq!((a, ta), (b, tb), "step {step}");
            let t = ta + scale * rng.random::<f64>();
            q.set(a, t);
            h.set(a, t);
        }
    }
}
