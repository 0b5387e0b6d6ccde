//! The inelastic projection of the beads' sliding increments on one rod:
//! the increments Δs nearest the predicted ones in the mass metric,
//!   min Σ m_i (Δs_i − Δs_i⁰)²  subject to  g_i + Δs_(i+1) − Δs_i ≥ 0,
//! (g_i the gap between neighbours i and i+1 beyond r_i + r_(i+1)). With
//! z_i = Δs_i + Σ_(j<i) g_j the constraints read z_(i+1) ≥ z_i: a weighted
//! isotonic regression, solved exactly in O(n) by pooling adjacent
//! violators. Each pool is a cluster of touching beads moving together
//! with their mass-weighted mean increment: a perfectly inelastic
//! collision, momentum kept, kinetic energy only removed. A fixed bead
//! (infinite mass) pins its pool.

/// A pool of adjacent beads moving together.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Pool {
    /// Σ m_i z_i and Σ m_i over the free beads of the pool.
    sum: f64,
    weight: f64,
    /// The value of a fixed bead in the pool, which the pool takes.
    pinned: Option<f64>,
    /// Number of beads.
    len: usize,
}

impl Pool {
    fn value(&self) -> f64 {
        self.pinned.unwrap_or(self.sum / self.weight)
    }
}

/// Replaces `z` by its isotonic regression with weights `mass` (`None`: a
/// fixed bead, infinite weight); `pool_of[i]` receives the pool index of
/// bead i (neighbours in one pool touch). `pools` is caller-owned scratch.
pub(crate) fn isotonic(z: &mut [f64], mass: &[Option<f64>], pools: &mut Vec<Pool>, pool_of: &mut [usize]) {
    pools.clear();
    for (i, &zi) in z.iter().enumerate() {
        let mut p = match mass[i] {
            Some(m) => Pool { sum: m * zi, weight: m, pinned: None, len: 1 },
            None => Pool { sum: 0.0, weight: 0.0, pinned: Some(zi), len: 1 },
        };
        while let Some(last) = pools.last() {
            if last.value() <= p.value() {
                break;
            }
            // Two fixed beads pressed together cannot be separated: the
            // earlier one's value stands (the pair stays violated).
            p = Pool { sum: last.sum + p.sum, weight: last.weight + p.weight, pinned: last.pinned.or(p.pinned), len: last.len + p.len };
            pools.pop();
        }
        pools.push(p);
    }
    let mut i = 0;
    for (k, p) in pools.iter().enumerate() {
        let v = p.value();
        for _ in 0..p.len {
            z[i] = v;
            pool_of[i] = k;
            i += 1;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Against the optimality conditions of the projection: feasible
    /// (non-decreasing), each pool at its members' weighted mean, and no
    /// pool can be split (every prefix of a pool has a mean ≥ the pool's;
    /// otherwise moving it down would lower the cost). Fixed seed.
    #[test]
    fn isotonic_regression_meets_its_optimality_conditions() {
        let mut state = 0x2545_f491_4f6c_dd1du64;
        let mut rnd = || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state >> 11) as f64 / (1u64 << 53) as f64
        };
        for _ in 0..500 {
            let n = 1 + (rnd() * 12.0) as usize;
            let z0: Vec<f64> = (0..n).map(|_| rnd() - 0.5).collect();
            let m: Vec<Option<f64>> = (0..n).map(|_| Some(0.1 + rnd())).collect();
            let (mut z, mut pools, mut of) = (z0.clone(), Vec::new(), vec![0; n]);
            isotonic(&mut z, &m, &mut pools, &mut of);
            for i in 1..n {
                assert!(z[i] >= z[i - 1] - 1e-15);
            }
            for k in 0..pools.len() {
                let idx: Vec<usize> = (0..n).filter(|&i| of[i] == k).collect();
                let (sw, swz) = idx.iter().fold((0.0, 0.0), |(a, b), &i| (a + m[i].unwrap(), b + m[i].unwrap() * z0[i]));
                assert!((z[idx[0]] - swz / sw).abs() < 1e-12);
                let (mut pw, mut pz) = (0.0, 0.0);
                for &i in &idx[..idx.len() - 1] {
                    pw += m[i].unwrap();
                    pz += m[i].unwrap() * z0[i];
                    assert!(pz / pw >= swz / sw - 1e-12, "a pool that should split");
                }
            }
        }
    }

    /// A fixed bead holds its pool: a free bead pushed into it stops.
    #[test]
    fn a_fixed_bead_pins_its_pool() {
        let (mut z, mut pools, mut of) = (vec![0.3, 0.0], Vec::new(), vec![0; 2]);
        isotonic(&mut z, &[Some(1.0), None], &mut pools, &mut of);
        assert_eq!(z, vec![0.0, 0.0]);
        let mut z = vec![0.0, -0.2];
        isotonic(&mut z, &[None, Some(2.0)], &mut pools, &mut of);
        assert_eq!(z, vec![0.0, 0.0]);
    }
}
