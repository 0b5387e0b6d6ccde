//! Each capsule's nearest partner on every strand passing by, for rod–rod
//! detection ([`super::rods`]). A few strands per capsule are kept inline;
//! a capsule that more strands pass (a dense knit, a knot's braid) keeps
//! the rest in a map. Offers of equal distance keep the first one.
use std::collections::HashMap;

/// Strands kept inline per capsule.
const SLOTS: usize = 4;

#[derive(Debug, Default)]
pub(crate) struct Nearest {
    slots: Vec<[Entry; SLOTS]>,
    count: Vec<u8>,
    /// Per block of `size` capsules, the partners past the inline slots.
    overflow: Vec<HashMap<usize, Vec<Entry>>>,
    size: usize,
}

/// A pair within reach: capsules `i` < `j`, their distance, and the
/// parameters in [0, 1] of the closest points on `i` and on `j` (kept so
/// that the seeds need not find them again).
pub(crate) type Hit = (usize, usize, f64, [f64; 2]);

/// A partner as kept: its capsule, the distance, and the closest points'
/// parameters on the pair's lower and higher capsule (as in its [`Hit`]).
pub(crate) type Entry = (usize, f64, [f64; 2]);

impl Nearest {
    /// For `n` capsules, none with a partner yet, in `blocks` blocks (more
    /// than one: [`Nearest::take`] works block by block on rayon's pool).
    #[cfg(test)]
    pub fn new(n: usize, blocks: usize) -> Nearest {
        let mut near = Nearest::default();
        near.reset(n, blocks);
        near
    }

    /// [`Nearest::new`] in place, keeping the buffers.
    pub fn reset(&mut self, n: usize, blocks: usize) {
        self.size = n.div_ceil(blocks.max(1)).max(1);
        // Slots are read only below their count: sized, not cleared.
        self.slots.resize(n, [(0, 0.0, [0.0; 2]); SLOTS]);
        self.count.clear();
        self.count.resize(n, 0);
        self.overflow.resize_with(n.div_ceil(self.size).max(1), HashMap::new);
        self.overflow.iter_mut().for_each(HashMap::clear);
    }

    /// Partner `new` = (j, distance, closest points) offered to capsule
    /// `i`: it replaces the first entry `k` on its strand (`same_strand(k)`)
    /// if strictly closer, and opens a strand when there is none.
    #[cfg(test)]
    pub fn offer(&mut self, i: usize, new: Entry, same_strand: impl Fn(usize) -> bool) {
        offer_into(&mut self.slots[i], &mut self.count[i], &mut self.overflow[i / self.size], i, new, same_strand);
    }

    /// The pairs within reach `hits` offered to both their capsules, in
    /// the order given (the lists one after the other). `same_strand(i, k,
    /// j)`: partners `k` and `j` of capsule `i` are on one pass of a rod.
    /// With more than one block, the blocks take their capsules' offers on
    /// rayon's pool: each capsule still sees its offers in the order
    /// given, so the result is the serial one.
    pub fn take(&mut self, hits: &[impl AsRef<[Hit]> + Sync], same_strand: impl Fn(usize, usize, usize) -> bool + Sync) {
        let size = self.size;
        let block = |(b, ((slots, count), overflow)): (usize, ((&mut [[Entry; SLOTS]], &mut [u8]), &mut HashMap<usize, Vec<Entry>>))| {
            let range = b * size..b * size + slots.len();
            for &(i, j, d, st) in hits.iter().flat_map(|b| b.as_ref()) {
                if range.contains(&i) {
                    offer_into(&mut slots[i - range.start], &mut count[i - range.start], overflow, i, (j, d, st), |k| same_strand(i, k, j));
                }
                if range.contains(&j) {
                    offer_into(&mut slots[j - range.start], &mut count[j - range.start], overflow, j, (i, d, st), |k| same_strand(j, k, i));
                }
            }
        };
        if self.overflow.len() > 1 {
            use rayon::prelude::*;
            self.slots.par_chunks_mut(size).zip(self.count.par_chunks_mut(size)).zip(self.overflow.par_iter_mut()).enumerate().for_each(block);
        } else {
            self.slots.chunks_mut(size).zip(self.count.chunks_mut(size)).zip(self.overflow.iter_mut()).enumerate().for_each(block);
        }
    }

    /// Capsule `i`'s nearest partners (one per strand), with their
    /// distances and closest points ([`Entry`]).
    pub fn of(&self, i: usize) -> impl Iterator<Item = Entry> + '_ {
        let more = if self.count[i] as usize == SLOTS { self.overflow[i / self.size].get(&i).map(|v| v.as_slice()) } else { None };
        self.slots[i][..self.count[i] as usize].iter().chain(more.unwrap_or(&[])).copied()
    }

    /// The distance of `j` when it is `i`'s nearest partner on its strand.
    pub fn get(&self, i: usize, j: usize) -> Option<f64> {
        self.of(i).find(|e| e.0 == j).map(|e| e.1)
    }
}

/// [`Nearest::offer`] of partner `new` on capsule `i`'s slots, count and
/// the overflow map.
fn offer_into(slots: &mut [Entry; SLOTS], count: &mut u8, overflow: &mut HashMap<usize, Vec<Entry>>, i: usize, new: Entry, same_strand: impl Fn(usize) -> bool) {
    let n = *count as usize;
    if let Some(e) = slots[..n].iter_mut().find(|e| same_strand(e.0)) {
        if new.1 < e.1 {
            *e = new;
        }
        return;
    }
    if n < SLOTS {
        slots[n] = new;
        *count += 1;
        return;
    }
    let more = overflow.entry(i).or_default();
    match more.iter_mut().find(|e| same_strand(e.0)) {
        Some(e) if new.1 < e.1 => *e = new,
        Some(_) => {}
        None => more.push(new),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Against a plain list per capsule: partners on strands keyed by
    /// `partner / 10`, more strands than the inline slots, equal distances.
    #[test]
    fn keeps_the_first_closest_per_strand() {
        let mut lcg = crate::linalg::synthetic::Lcg(7);
        // An integer in [0, 2^20) from the project's generator in [−1, 1).
        let mut rnd = || ((lcg.next() + 1.0) * (1 << 19) as f64) as usize;
        let n = 5;
        let mut near = Nearest::new(n, 1);
        let mut plain: Vec<Vec<(usize, f64)>> = vec![Vec::new(); n];
        for _ in 0..2000 {
            let (i, j, d) = (rnd() % n, rnd() % 70, (rnd() % 9) as f64);
            near.offer(i, (j, d, [0.0; 2]), |k| k / 10 == j / 10);
            match plain[i].iter_mut().find(|e| e.0 / 10 == j / 10) {
                Some(e) if d < e.1 => *e = (j, d),
                Some(_) => {}
                None => plain[i].push((j, d)),
            }
        }
        for i in 0..n {
            assert_eq!(near.of(i).map(|e| (e.0, e.1)).collect::<Vec<_>>(), plain[i], "capsule {i}");
            for &(j, d) in &plain[i] {
                assert_eq!(near.get(i, j), Some(d));
            }
        }
        assert!(near.of(0).count() > SLOTS, "the overflow should be exercised");
    }

    /// Offers taken from lists of hits, in blocks on the pool or in one
    /// block, equal the offers made one by one in the lists' order.
    #[test]
    fn offers_from_hits_in_blocks_equal_the_serial_ones() {
        let mut lcg = crate::linalg::synthetic::Lcg(11);
        let mut rnd = || ((lcg.next() + 1.0) * (1 << 19) as f64) as usize;
        let n = 50;
        // Each hit's parameters name it, so that the entry kept is checked too.
        let hits: Vec<Vec<Hit>> = (0..7)
            .map(|c| (0..400).map(|k| (rnd() % n, rnd() % n, (rnd() % 9) as f64, [c as f64, k as f64])).filter(|h| h.0 != h.1).collect())
            .collect();
        let same = |_: usize, k: usize, j: usize| k / 10 == j / 10;
        let mut one = Nearest::new(n, 1);
        for &(i, j, d, st) in hits.iter().flatten() {
            one.offer(i, (j, d, st), |k| same(i, k, j));
            one.offer(j, (i, d, st), |k| same(j, k, i));
        }
        // Taken in two calls, as detection takes them chunk by chunk.
        let take = |blocks: usize| {
            let mut near = Nearest::new(n, blocks);
            near.take(&hits[..3], same);
            near.take(&hits[3..], same);
            near
        };
        let serial = take(1);
        let pooled = rayon::ThreadPoolBuilder::new().num_threads(3).build().unwrap().install(|| take(3));
        for i in 0..n {
            let want: Vec<_> = one.of(i).collect();
            assert_eq!(serial.of(i).collect::<Vec<_>>(), want, "capsule {i}, one block");
            assert_eq!(pooled.of(i).collect::<Vec<_>>(), want, "capsule {i}, three blocks");
        }
        assert!((0..n).any(|i| one.of(i).count() > SLOTS), "the overflow should be exercised");
    }
}
