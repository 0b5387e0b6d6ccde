//! Closest points of two segments (the axes of two capsules), in closed
//! form (thesis III.75–81; Ericson, Real-Time Collision Detection §5.1.9),
//! with the parallel case placed at the middle of the overlap so that
//! strands lying side by side touch where they overlap, not at an end.

use nalgebra::Vector3;

/// Parameters (s, t) ∈ [0, 1]² of the closest points p1 + s d1 and
/// p2 + t d2 of segments [p1, q1] and [p2, q2], and their distance.
pub fn closest_on_segments(p1: &Vector3<f64>, q1: &Vector3<f64>, p2: &Vector3<f64>, q2: &Vector3<f64>) -> (f64, f64, f64) {
    let (d1, d2) = (q1 - p1, q2 - p2);
    let (s, t, gap2) = closest_on_axes(p1, &d1, d1.norm_squared(), p2, &d2, d2.norm_squared());
    (s, t, gap2.sqrt())
}

/// [`closest_on_segments`] of segments given as p1 + s d1 and p2 + t d2
/// with |d1|² = `a` and |d2|² = `e` known (a detector keeps them per
/// capsule): (s, t) and the squared distance.
#[inline]
pub fn closest_on_axes(p1: &Vector3<f64>, d1: &Vector3<f64>, a: f64, p2: &Vector3<f64>, d2: &Vector3<f64>, e: f64) -> (f64, f64, f64) {
    let r = p1 - p2;
    let f = d2.dot(&r);
    let tiny = 1e-300;
    let (s, t) = if a <= tiny && e <= tiny {
        (0.0, 0.0)
    } else if a <= tiny {
        (0.0, (f / e).clamp(0.0, 1.0))
    } else {
        let c = d1.dot(&r);
        if e <= tiny {
            ((-c / a).clamp(0.0, 1.0), 0.0)
        } else {
            let b = d1.dot(d2);
            let denom = a * e - b * b; // ≥ 0, zero when parallel
            if denom <= 1e-12 * a * e {
                parallel(a, b, c, e, f)
            } else {
                let s = ((b * f - c * e) / denom).clamp(0.0, 1.0);
                let t = (b * s + f) / e;
                if t < 0.0 {
                    ((-c / a).clamp(0.0, 1.0), 0.0)
                } else if t > 1.0 {
                    (((b - c) / a).clamp(0.0, 1.0), 1.0)
                } else {
                    (s, t)
                }
            }
        }
    };
    let gap = (p1 + d1 * s) - (p2 + d2 * t);
    (s, t, gap.norm_squared())
}

/// Parallel segments: the middle of the overlap of segment 2 projected on
/// segment 1 (or the nearest end points when they do not overlap).
fn parallel(a: f64, b: f64, c: f64, e: f64, f: f64) -> (f64, f64) {
    // Segment 2's ends on segment 1's line: s = (b t − c)/a at t = 0, 1.
    let (s0, s1) = (-c / a, (b - c) / a);
    let (lo, hi) = (s0.min(s1).max(0.0), s0.max(s1).min(1.0));
    let s = if lo <= hi { 0.5 * (lo + hi) } else if s0.max(s1) < 0.0 { 0.0 } else { 1.0 };
    let t = ((b * s + f) / e).clamp(0.0, 1.0);
    (s, t)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Brute force on a fine grid of both parameters.
    fn brute(p1: &Vector3<f64>, q1: &Vector3<f64>, p2: &Vector3<f64>, q2: &Vector3<f64>) -> f64 {
        let n = 400;
        let mut best = f64::INFINITY;
        for i in 0..=n {
            for j in 0..=n {
                let (s, t) = (i as f64 / n as f64, j as f64 / n as f64);
                best = best.min(((p1 + (q1 - p1) * s) - (p2 + (q2 - p2) * t)).norm());
            }
        }
        best
    }

    #[test]
    fn closest_points_match_brute_force() {
        // A fixed-seed linear congruential generator.
        let mut state = 12345u64;
        let mut rnd = || {
            state = state.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            (state >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
        };
        for k in 0..200 {
            let mut v = || Vector3::new(rnd(), rnd(), rnd());
            let (p1, q1, p2, mut q2) = (v(), v(), v(), v());
            if k % 4 == 0 {
                q2 = p2 + (q1 - p1) * 0.7; // parallel
            }
            let (s, t, d) = closest_on_segments(&p1, &q1, &p2, &q2);
            assert!((0.0..=1.0).contains(&s) && (0.0..=1.0).contains(&t));
            let b = brute(&p1, &q1, &p2, &q2);
            // The grid's own error is at most half a cell's diagonal.
            assert!(d <= b + 1e-12 && d >= b - 0.01, "case {k}: {d} vs brute {b}");
        }
    }

    #[test]
    fn parallel_overlap_touches_in_the_middle() {
        let (p1, q1) = (Vector3::new(0.0, 0.0, 0.0), Vector3::new(1.0, 0.0, 0.0));
        let (p2, q2) = (Vector3::new(0.5, 0.1, 0.0), Vector3::new(2.0, 0.1, 0.0));
        let (s, t, d) = closest_on_segments(&p1, &q1, &p2, &q2);
        assert!((s - 0.75).abs() < 1e-12 && (t - 0.25 / 1.5).abs() < 1e-12 && (d - 0.1).abs() < 1e-12, "{s} {t} {d}");
        // Reversed direction, and disjoint along the line.
        let (s, t, d) = closest_on_segments(&p1, &q1, &q2, &p2);
        assert!((s - 0.75).abs() < 1e-12 && (d - 0.1).abs() < 1e-12, "{s} {t} {d}");
        let (p3, q3) = (Vector3::new(1.5, 0.1, 0.0), Vector3::new(3.0, 0.1, 0.0));
        let (s, t, d) = closest_on_segments(&p1, &q1, &p3, &q3);
        assert!(s == 1.0 && t == 0.0 && (d - (0.25f64 + 0.01).sqrt()).abs() < 1e-12, "{s} {t} {d}");
    }
}
