//! The initial yarn path: a harmonic loop model. Along course j, with
//! t ∈ [0, 2π·wales] (stitch i on [2πi, 2π(i+1)], its head at 2πi + π):
//!
//!   x = w t/2π + a sin 2t,   y = j c − h cos t,
//!   z = z_legs + (z_end − z_legs) cos² t,
//!
//! w the wale spacing, c the course spacing, h the loop's half height, a
//! the overhang that makes the head wider than the neck (the Ω shape of a
//! loop), d the depth of the crossings, s = +1 for a knit stitch and −1 for
//! a purl. A loop pulled through the loop below crosses it four times: its
//! legs pass in front of (knit) or behind (purl) the head below, and its
//! sinkers the other way round the legs below. So the legs lie at
//! z = d s(i, j), the head at −d s(i, j+1) (behind the legs of the stitch
//! pulled through it), the sinker quarters at d s(i, j−1) − 2d s(i, j);
//! each quarter blends from the legs with cos² t (C¹), and across a
//! junction between two stitches the sinker depth passes from one's value
//! to the other's within ±π/16. The crossings sit near the legs' middles
//! (t = π/2, 3π/2 mod 2π).
//! The tube (periodic boundary) wraps x round a cylinder of circumference
//! wales·w, z outwards.
use super::pattern::StitchGrid;
use nalgebra::Vector3;
use std::f64::consts::{PI, TAU};

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LoopModel {
    /// Wale spacing w (m): stitch width along the course.
    pub wale_spacing: f64,
    /// Course spacing c (m).
    pub course_spacing: f64,
    /// Loop half height h (m).
    pub loop_height: f64,
    /// Overhang a (m).
    pub overhang: f64,
    /// Crossing depth d (m).
    pub depth: f64,
}

impl LoopModel {
    /// Point of course `j` at `t` in the flat frame (x along the course, y
    /// along the wale, z out of the front).
    pub fn flat(&self, grid: &StitchGrid, periodic: bool, j: usize, t: f64) -> Vector3<f64> {
        let (d, nw) = (self.depth, grid.wales());
        let i = ((t / TAU).floor().max(0.0) as usize).min(nw - 1);
        let tau = t - TAU * i as f64;
        let s = |i: usize, j: usize| grid.get(i, j).sign();
        // Sinker depth of stitch k: under the legs below when its loop
        // passes over the head below, and over them when it passes under
        // (the cast-on course as if it had a course like it below).
        let sinker = |k: usize| d * s(k, j.saturating_sub(1)) - 2.0 * d * s(k, j);
        // Neighbour of stitch i across its left/right sinker (itself at a free edge).
        let left = if i > 0 { i - 1 } else if periodic { nw - 1 } else { 0 };
        let right = if i + 1 < nw { i + 1 } else if periodic { 0 } else { i };
        // Across a sinker the depth moves from one stitch's value to the
        // other's within ±π/16 of the junction (C¹, both values reached
        // where the sinker crosses the legs below).
        let blend = |a: f64, b: f64, sigma: f64| 0.5 * (a + b) + 0.5 * (b - a) * (8.0 * sigma.clamp(-PI / 16.0, PI / 16.0)).sin();
        let legs = d * s(i, j);
        let end = if (0.5 * PI..=1.5 * PI).contains(&tau) {
            -d * s(i, if j + 1 < grid.courses() { j + 1 } else { j })
        } else if tau < 0.5 * PI {
            blend(sinker(left), sinker(i), tau)
        } else {
            blend(sinker(i), sinker(right), tau - TAU)
        };
        let c2 = tau.cos().powi(2);
        Vector3::new(
            self.wale_spacing * t / TAU + self.overhang * (2.0 * t).sin(),
            j as f64 * self.course_spacing - self.loop_height * t.cos(),
            legs + (end - legs) * c2,
        )
    }

    /// The flat point placed in space: as is, or wrapped round the tube.
    pub fn embed(&self, grid: &StitchGrid, periodic: bool, p: Vector3<f64>) -> Vector3<f64> {
        if !periodic {
            return p;
        }
        let r0 = self.tube_radius(grid);
        let (phi, rad) = (p.x / r0, r0 + p.z);
        Vector3::new(rad * phi.sin(), p.y, rad * phi.cos())
    }

    /// Radius of the tube's mid-surface (m).
    pub fn tube_radius(&self, grid: &StitchGrid) -> f64 {
        grid.wales() as f64 * self.wale_spacing / TAU
    }

    pub fn point(&self, grid: &StitchGrid, periodic: bool, j: usize, t: f64) -> Vector3<f64> {
        self.embed(grid, periodic, self.flat(grid, periodic, j, t))
    }

    /// Mean arc length of a stitch over the fabric (m).
    pub fn mean_loop_length(&self, grid: &StitchGrid, periodic: bool) -> f64 {
        const N: usize = 96;
        let mut total = 0.0;
        for j in 0..grid.courses() {
            let mut prev = self.point(grid, periodic, j, 0.0);
            for k in 1..=N * grid.wales() {
                let p = self.point(grid, periodic, j, TAU * k as f64 / N as f64);
                total += (p - prev).norm();
                prev = p;
            }
        }
        total / (grid.wales() * grid.courses()) as f64
    }

    /// Smallest distance between yarn centrelines over twice the yarn
    /// radius: pairs of stitches within two courses and one wale of each
    /// other, points of one yarn closer than 2 diameters along it excluded.
    pub fn clearance(&self, grid: &StitchGrid, periodic: bool, radius: f64) -> f64 {
        // Dense enough for the steep sinker ramps between knit and purl
        // neighbours (±π/16 of a stitch): 32 samples missed them.
        const N: usize = 128;
        let (nw, nc) = (grid.wales(), grid.courses());
        let course = |j: usize| -> Vec<Vector3<f64>> {
            (0..N * nw).map(|k| self.point(grid, periodic, j, TAU * (k as f64 + 0.5) / N as f64)).collect()
        };
        // Arc length between neighbouring samples, for the along-yarn exclusion.
        let step = self.mean_loop_length(grid, periodic) / N as f64;
        let skip = ((4.0 * radius / step).ceil() as usize).max(1);
        let n = N * nw;
        let mut best = f64::INFINITY;
        // Three courses at a time: memory stays O(wales), not O(stitches).
        let mut window: std::collections::VecDeque<Vec<Vector3<f64>>> = (0..3.min(nc)).map(course).collect();
        for j in 0..nc {
            for (dj, other) in window.iter().enumerate() {
                let jj = j + dj;
                for i in 0..nw {
                    for di in [-1i64, 0, 1] {
                        let ii = i as i64 + di;
                        let ii = if periodic {
                            ii.rem_euclid(nw as i64) as usize
                        } else if ii < 0 || ii >= nw as i64 {
                            continue;
                        } else {
                            ii as usize
                        };
                        for ka in i * N..(i + 1) * N {
                            for kb in ii * N..(ii + 1) * N {
                                if jj == j {
                                    let sep = ka.abs_diff(kb);
                                    let sep = if periodic { sep.min(n - sep) } else { sep };
                                    if sep < skip {
                                        continue;
                                    }
                                }
                                best = best.min((window[0][ka] - other[kb]).norm());
                            }
                        }
                    }
                }
            }
            window.pop_front();
            if j + 3 < nc {
                window.push_back(course(j + 3));
            }
        }
        best / (2.0 * radius)
    }
}
