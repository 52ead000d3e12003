//! A calendar (bounded) priority queue after Paul, J. Comput. Phys. 221, 615 (2007), as
//! used by DynamO: keys fall into buckets of width w over a window of `nb` buckets;
//! only the current bucket is kept sorted (in a small binary heap), later buckets are
//! unsorted linked lists and keys beyond the window wait in an overflow list until the
//! window has been used up. Average O(1) per operation; the order of events (by key,
//! then id) is exactly that of [`crate::IndexedHeap`].

use crate::queue::{EventQueue, check_heap_order};

const NONE: u32 = u32::MAX;
const IN_HEAP: u32 = u32::MAX - 1;
const OVERFLOW: u32 = u32::MAX - 2;
const NEVER: u32 = u32::MAX - 3;

/// The calendar queue.
#[derive(Debug, Clone, serde::Serialize, serde::Deserialize)]
pub struct CalendarQueue {
    /// Each id's key and place, in one record (one cache miss per id touched).
    node: Vec<Node>,
    /// Heads of the bucket lists, then of OVERFLOW and NEVER (last two slots).
    heads: Vec<u32>,
    /// The sorted current bucket: (key, id) binary heap, with positions.
    heap: Vec<(f64, u32)>,
    t0: f64,
    width: f64,
    current: usize,
    /// Keys set since the buckets were last sized.
    sets: u64,
    /// Number of finite keys.
    finite: usize,
}

/// An id's key, where it is filed and its list links or heap slot.
#[derive(Debug, Clone, Copy, serde::Serialize, serde::Deserialize)]
#[repr(C, align(32))]
struct Node {
    key: f64,
    /// Bucket index, IN_HEAP, OVERFLOW or NEVER.
    loc: u32,
    next: u32,
    prev: u32,
    heap_pos: u32,
}

#[inline(always)]
fn less(a: (f64, u32), b: (f64, u32)) -> bool {
    a.0 < b.0 || (a.0 == b.0 && a.1 < b.1)
}

impl CalendarQueue {
    /// Keys in the current bucket that trigger a resize.
    const CROWDED: usize = 32;

    fn buckets(&self) -> usize {
        self.heads.len() - 2
    }

    fn list_head(&mut self, loc: u32) -> &mut u32 {
        let nb = self.buckets();
        match loc {
            OVERFLOW => &mut self.heads[nb],
            NEVER => &mut self.heads[nb + 1],
            b => &mut self.heads[b as usize],
        }
    }

    fn link(&mut self, id: usize, loc: u32) {
        let head = *self.list_head(loc);
        self.node[id].next = head;
        self.node[id].prev = NONE;
        if head != NONE {
            self.node[head as usize].prev = id as u32;
        }
        *self.list_head(loc) = id as u32;
        self.node[id].loc = loc;
    }

    fn unlink(&mut self, id: usize) {
        let (p, n) = (self.node[id].prev, self.node[id].next);
        if p == NONE {
            *self.list_head(self.node[id].loc) = n;
        } else {
            self.node[p as usize].next = n;
        }
        if n != NONE {
            self.node[n as usize].prev = p;
        }
    }

    fn heap_place(&mut self, k: usize, item: (f64, u32)) {
        self.heap[k] = item;
        self.node[item.1 as usize].heap_pos = k as u32;
    }

    fn heap_fix(&mut self, mut k: usize) {
        let item = self.heap[k];
        while k > 0 && less(item, self.heap[(k - 1) / 2]) {
            let p = self.heap[(k - 1) / 2];
            self.heap_place(k, p);
            k = (k - 1) / 2;
        }
        let n = self.heap.len();
        loop {
            let l = 2 * k + 1;
            if l >= n {
                break;
            }
            let c = if l + 1 < n && less(self.heap[l + 1], self.heap[l]) {
                l + 1
            } else {
                l
            };
            if !less(self.heap[c], item) {
                break;
            }
            let x = self.heap[c];
            self.heap_place(k, x);
            k = c;
        }
        self.heap_place(k, item);
    }

    fn heap_push(&mut self, id: usize) {
        self.node[id].loc = IN_HEAP;
        self.heap.push((self.node[id].key, id as u32));
        let k = self.heap.len() - 1;
        self.node[id].heap_pos = k as u32;
        self.heap_fix(k);
    }

    fn heap_remove(&mut self, id: usize) {
        let k = self.node[id].heap_pos as usize;
        let last = self.heap.pop().expect("id is in the heap");
        if k < self.heap.len() {
            self.heap_place(k, last);
            self.heap_fix(k);
        }
    }

    /// Files `id` by its key.
    fn insert(&mut self, id: usize) {
        let t = self.node[id].key;
        if !t.is_finite() {
            self.link(id, NEVER);
            return;
        }
        // The bucket is ⌊b⌋; comparisons on b and the truncating cast (b ≥ 1 there)
        // give it without a call to floor.
        let b = (t - self.t0) / self.width;
        if b < self.current as f64 + 1.0 {
            self.heap_push(id);
        } else if b < self.buckets() as f64 {
            self.link(id, b as u32);
        } else {
            self.link(id, OVERFLOW);
        }
    }

    /// Starts a new window at the earliest finite key, with buckets sized from the
    /// keys' spread, and refiles every finite key. Returns false if none is left.
    fn rebuild(&mut self) -> bool {
        let nb = self.buckets();
        let mut ids: Vec<usize> = self.heap.drain(..).map(|(_, id)| id as usize).collect();
        for head in &mut self.heads[..=nb] {
            let mut id = std::mem::replace(head, NONE);
            while id != NONE {
                ids.push(id as usize);
                id = self.node[id as usize].next;
            }
        }
        if ids.is_empty() {
            return false;
        }
        let min = ids
            .iter()
            .map(|&i| self.node[i].key)
            .fold(f64::INFINITY, f64::min);
        let mean = ids.iter().map(|&i| self.node[i].key - min).sum::<f64>() / ids.len() as f64;
        // Each particle holds one key, so the keys' mean lead over the earliest is
        // about N mean event intervals: about two keys per bucket near the front.
        self.width = (4.0 * mean / nb as f64).max(f64::MIN_POSITIVE);
        self.t0 = min;
        self.current = 0;
        self.sets = 0;
        for i in ids {
            self.insert(i);
        }
        true
    }
}

impl EventQueue for CalendarQueue {
    fn new(len: usize) -> Self {
        assert!(len < NEVER as usize, "too many ids for the calendar queue");
        let nb = len.next_power_of_two().max(16);
        let mut q = Self {
            node: vec![
                Node {
                    key: f64::INFINITY,
                    loc: NEVER,
                    next: NONE,
                    prev: NONE,
                    heap_pos: 0,
                };
                len
            ],
            heads: vec![NONE; nb + 2],
            heap: Vec::with_capacity(64),
            t0: 0.0,
            width: 1.0,
            current: 0,
            sets: 0,
            finite: 0,
        };
        for id in (0..len).rev() {
            q.link(id, NEVER);
        }
        q
    }

    fn set(&mut self, id: usize, time: f64) {
        self.sets += 1;
        self.finite = self.finite + usize::from(time.is_finite())
            - usize::from(self.node[id].key.is_finite());
        if self.node[id].loc == IN_HEAP {
            self.heap_remove(id);
        } else {
            self.unlink(id);
        }
        self.node[id].key = time;
        self.insert(id);
    }

    fn peek(&mut self) -> (usize, f64) {
        if self.finite == 0 {
            // Only keys at +∞: the smallest id, as the heap reports (in O(1)).
            return (0, f64::INFINITY);
        }
        while self.heap.is_empty() {
            self.current += 1;
            if self.current >= self.buckets() && !self.rebuild() {
                debug_assert!(false, "finite keys are counted but none is filed");
                return (0, f64::INFINITY);
            }
            let b = self.current as u32;
            let mut id = self.heads[b as usize];
            self.heads[b as usize] = NONE;
            while id != NONE {
                let next = self.node[id as usize].next;
                self.heap_push(id as usize);
                id = next;
            }
        }
        // A crowded current bucket means badly sized buckets (the first window is
        // sized before any key is known, and event rates drift): resize, at most
        // once per 2·(number of buckets) keys set, which keeps it O(1) amortised.
        if self.heap.len() > Self::CROWDED && self.sets > 2 * self.buckets() as u64 {
            self.rebuild();
        }
        let (t, id) = self.heap[0];
        (id as usize, t)
    }

    fn key(&self, id: usize) -> f64 {
        self.node[id].key
    }

    /// The rest of the current bucket's first heap levels: the next earliest is among
    /// them unless the bucket runs out.
    fn upcoming(&self) -> &[(f64, u32)] {
        &self.heap[self.heap.len().min(1)..self.heap.len().min(3)]
    }

    fn check(&self, len: usize) -> Result<(), String> {
        let bad = |why: String| Err(format!("calendar queue: {why}"));
        if self.node.len() != len || self.heads.len() < 3 {
            return bad(format!(
                "{} ids and {} lists",
                self.node.len(),
                self.heads.len()
            ));
        }
        let nb = self.buckets();
        if self.current > nb || !(self.width > 0.0 && self.width.is_finite() && self.t0.is_finite())
        {
            return bad("its window is not a finite range of buckets".into());
        }
        let mut filed = vec![false; len];
        // Every list: linked both ways, each id once, each filed under its own list.
        for (list, &head) in self.heads.iter().enumerate() {
            let loc = match list {
                b if b < nb => b as u32,
                b if b == nb => OVERFLOW,
                _ => NEVER,
            };
            let (mut id, mut prev) = (head, NONE);
            while id != NONE {
                let Some(node) = self.node.get(id as usize) else {
                    return bad(format!("list {list} names id {id}"));
                };
                if filed[id as usize] || node.loc != loc || node.prev != prev {
                    return bad(format!("id {id} is linked twice or inconsistently"));
                }
                filed[id as usize] = true;
                (prev, id) = (id, node.next);
            }
        }
        for (k, &(key, id)) in self.heap.iter().enumerate() {
            match self.node.get(id as usize) {
                Some(node)
                    if !filed[id as usize]
                        && node.loc == IN_HEAP
                        && node.heap_pos as usize == k
                        && node.key.to_bits() == key.to_bits() =>
                {
                    filed[id as usize] = true
                }
                _ => return bad(format!("heap entry {k} (id {id}) is inconsistent")),
            }
        }
        if let Some(id) = filed.iter().position(|&f| !f) {
            return bad(format!("id {id} is filed nowhere"));
        }
        if self.node.iter().any(|n| n.key.is_nan()) {
            return bad("a key is NaN".into());
        }
        if self.node.iter().filter(|n| n.key.is_finite()).count() != self.finite {
            return bad("the count of finite keys is wrong".into());
        }
        check_heap_order(&self.heap, 2)
    }
}
