//! Stretch energy (II.56–II.57 corrected): ε = |r'|/|r0'| − 1,
//! W_s = ½ EA (ε − ε_p)², as a function of the invariant a = |r'|².
use super::invariants::{Mat5, Vec5, QA};
use super::SampleConsts;

/// Adds F_s's derivatives with respect to the invariants; returns W_s.
#[inline(always)]
pub fn add(q: &Vec5, c: &SampleConsts, fq: &mut Vec5, fqq: &mut Mat5) -> f64 {
    let a = q[QA];
    let s = a.sqrt();
    // Two reciprocals instead of four divisions (this runs at every sample).
    let (il0, is) = (1.0 / c.speed0, 1.0 / s);
    let e = s * il0 - 1.0 - c.eps_p;
    // dε/da = 1/(2 s l0), d²ε/da² = −1/(4 l0 s³)
    let de = 0.5 * is * il0;
    fq[QA] += c.ea * e * de;
    fqq[(QA, QA)] += c.ea * (de * de - 0.5 * e * de * is * is);
    0.5 * c.ea * e * e
}

/// Engineering stretch strain ε = |r'|/|r0'| − 1.
pub fn strain(q: &Vec5, c: &SampleConsts) -> f64 {
    q[QA].sqrt() / c.speed0 - 1.0
}
