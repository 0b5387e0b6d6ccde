//! Each capsule's nearest partner on every strand passing by, for rod–rod
//! detection ([`super::rods`]). A few strands per capsule are kept inline;
//! a capsule that more strands pass (a dense knit, a knot's braid) keeps
//! the rest in a map. Offers of equal distance keep the first one.
use std::collections::HashMap;

/// Strands kept inline per capsule.
const SLOTS: usize = 4;

pub(crate) struct Nearest {
    slots: Vec<[(usize, f64); SLOTS]>,
    count: Vec<u8>,
    overflow: HashMap<usize, Vec<(usize, f64)>>,
}

impl Nearest {
    /// For `n` capsules, none with a partner yet.
    pub fn new(n: usize) -> Nearest {
        Nearest { slots: vec![[(0, 0.0); SLOTS]; n], count: vec![0; n], overflow: HashMap::new() }
    }

    /// Partner `j` at distance `d` (length unit) offered to capsule `i`:
    /// it replaces the first entry `k` on its strand (`same_strand(k)`) if
    /// strictly closer, and opens a strand when there is none.
    pub fn offer(&mut self, i: usize, j: usize, d: f64, same_strand: impl Fn(usize) -> bool) {
        let n = self.count[i] as usize;
        if let Some(e) = self.slots[i][..n].iter_mut().find(|e| same_strand(e.0)) {
            if d < e.1 {
                *e = (j, d);
            }
            return;
        }
        if n < SLOTS {
            self.slots[i][n] = (j, d);
            self.count[i] += 1;
            return;
        }
        let more = self.overflow.entry(i).or_default();
        match more.iter_mut().find(|e| same_strand(e.0)) {
            Some(e) if d < e.1 => *e = (j, d),
            Some(_) => {}
            None => more.push((j, d)),
        }
    }

    /// Capsule `i`'s nearest partners (one per strand) and their distances.
    pub fn of(&self, i: usize) -> impl Iterator<Item = (usize, f64)> + '_ {
        let more = if self.count[i] as usize == SLOTS { self.overflow.get(&i).map(|v| v.as_slice()) } else { None };
        self.slots[i][..self.count[i] as usize].iter().chain(more.unwrap_or(&[])).copied()
    }

    /// The distance of `j` when it is `i`'s nearest partner on its strand.
    pub fn get(&self, i: usize, j: usize) -> Option<f64> {
        self.of(i).find(|e| e.0 == j).map(|e| e.1)
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
        let mut near = Nearest::new(n);
        let mut plain: Vec<Vec<(usize, f64)>> = vec![Vec::new(); n];
        for _ in 0..2000 {
            let (i, j, d) = (rnd() % n, rnd() % 70, (rnd() % 9) as f64);
            near.offer(i, j, d, |k| k / 10 == j / 10);
            match plain[i].iter_mut().find(|e| e.0 / 10 == j / 10) {
                Some(e) if d < e.1 => *e = (j, d),
                Some(_) => {}
                None => plain[i].push((j, d)),
            }
        }
        for i in 0..n {
            assert_eq!(near.of(i).collect::<Vec<_>>(), plain[i], "capsule {i}");
            for &(j, d) in &plain[i] {
                assert_eq!(near.get(i, j), Some(d));
            }
        }
        assert!(near.of(0).count() > SLOTS, "the overflow should be exercised");
    }
}
