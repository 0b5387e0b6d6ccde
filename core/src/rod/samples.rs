//! Per-sample data of a rod, computed once from the rest shape (SPEC §2:
//! integration over the rest arc length makes it constant): Gauss points,
//! basis values, weights w = Gauss weight × span/2 × |r0'|, stiffnesses from
//! the blended section, rest curvatures and twist, and the per-segment
//! consistent mass, roll inertia and unit drag blocks (II.70–II.75, III.10).
use super::Rod;
use crate::energy::{self, invariants::LocalState, FrameState, SampleConsts, Strains};
use crate::error::{Error, Result};
use crate::quadrature::gauss_legendre;
use crate::section::Section;
use nalgebra::Vector3;

#[derive(Clone, Debug, Default)]
pub(crate) struct Sample {
    pub seg: usize,
    pub u: f64,
    /// basis[deriv][k] for the segment's 4 control points.
    pub basis: [[f64; 4]; 4],
    /// Quadrature weight in rest arc length (length unit).
    pub w: f64,
    pub consts: SampleConsts,
    /// Elastic rest values (κ1⁰, κ2⁰, ω⁰) without plastic offsets.
    pub rest: [f64; 3],
}

pub(crate) type Block4 = [[f64; 4]; 4];

/// A stretch-only sample (`RodOptions::stretch_at_greville`): basis at its
/// abscissa, weight in rest arc length, constants (EA and |r0'| only).
#[derive(Clone, Debug, Default)]
pub(crate) struct StretchSample {
    pub basis: [[f64; 4]; 4],
    pub w: f64,
    pub consts: SampleConsts,
}

/// Weights (in u) of an open rod's Greville stretch samples `points`
/// (segment, u): Σ_j w_j N_k'(ξ_j) = N_k(u_end) − N_k(u_start) for
/// k = 1..n (k = 0 follows, Σ_k N_k' = 0), a banded square system.
fn open_rod_weights(knots: &crate::spline::KnotVector, seg_ctrl: &[[usize; 4]], points: &[(usize, f64)]) -> Result<Vec<f64>> {
    use crate::linalg::band::{BandLu, BandMatrix};
    let n = knots.n_ctrl();
    let m = points.len();
    if m + 1 != n {
        return Err(Error::input(format!("stretch_at_greville: {m} samples for {n} control points (repeated interior knots are not supported)")));
    }
    let mut a = BandMatrix::new(m, 5, 5);
    for (j, &(seg, u)) in points.iter().enumerate() {
        let b = knots.basis(seg, u);
        for (l, &k) in seg_ctrl[seg].iter().enumerate() {
            if k >= 1 {
                if !a.in_band(k - 1, j) {
                    return Err(Error::input("stretch_at_greville: sample outside its band (unexpected knot vector)"));
                }
                a.add(k - 1, j, b[1][l]);
            }
        }
    }
    let (u0, u1) = knots.domain();
    let mut rhs = vec![0.0; m];
    for (u, sign) in [(u1, 1.0), (u0, -1.0)] {
        let seg = knots.locate(u)?;
        let b = knots.basis(seg, u);
        for (l, &k) in seg_ctrl[seg].iter().enumerate() {
            if k >= 1 {
                rhs[k - 1] += sign * b[0][l];
            }
        }
    }
    let mut lu = BandLu::new();
    lu.factor(&a)?;
    lu.solve_in_place(&mut rhs)?;
    if let Some(j) = rhs.iter().position(|w| !(*w > 0.0)) {
        return Err(Error::input(format!("stretch_at_greville: sample {j}'s weight is {} (not positive) on this knot vector", rhs[j])));
    }
    Ok(rhs)
}

/// What the Greville stretch does not support (checked when a rod is built
/// and when its limits change): stretch plasticity (the offsets live at the
/// Gauss samples), rupture (a cut at a Gauss point can leave an end span
/// too short for positive weights, and the Gauss samples' stretch, which
/// rupture reads, is no longer the energy's on bent rods) and the Poisson
/// update (which reads it too).
pub(crate) fn check_greville(greville: bool, m: &crate::material::Material, poisson_update: bool) -> Result<()> {
    if !greville {
        return Ok(());
    }
    let stretch_yield = m.yield_limits.is_some_and(|l| l.stretch.0.is_finite() || l.stretch.1.is_finite());
    let what = if stretch_yield {
        "a stretch yield limit"
    } else if m.rupture_limits.is_some() {
        "rupture limits"
    } else if poisson_update {
        "poisson_update"
    } else {
        return Ok(());
    };
    Err(Error::input(format!(
        "stretch_at_greville: {what} not supported (they read the stretch at the Gauss samples, which the Greville collocation replaces); disable one of them"
    )))
}

#[derive(Clone, Debug, Default)]
pub(crate) struct Cache {
    pub samples: Vec<Sample>,
    pub seg_ctrl: Vec<[usize; 4]>,
    /// First sample of each segment; segment s owns samples[seg_start[s]..seg_start[s+1]].
    pub seg_start: Vec<usize>,
    /// Rest arc length from the start of the domain to the start of each
    /// segment (length unit): `Rod::rest_arc_length` in O(1).
    pub seg_arc: Vec<f64>,
    /// Stretch-only samples (Greville collocation; empty otherwise), and
    /// the first of each segment as `seg_start`.
    pub stretch: Vec<StretchSample>,
    pub seg_stretch_start: Vec<usize>,
    /// ∫ μ b_k b_l ds0 (translation), ∫ ρ I0 b_k b_l ds0 (roll).
    pub seg_mass: Vec<Block4>,
    pub seg_inertia: Vec<Block4>,
    /// ∫ b_k b_l ds0 and ∫ r² b_k b_l ds0 (r the section's hydrodynamic
    /// radius): the drag matrices per unit coefficient (III.10; the roll's
    /// resistive-force drag 4πηr²).
    pub seg_bb: Vec<Block4>,
    pub seg_r2bb: Vec<Block4>,
    /// Lower Cholesky factors of `seg_bb` (the thermal force's, SPEC §3).
    pub seg_bb_chol: Vec<Block4>,
    /// ∫ μ b_k ds0 (for gravity) and ∫ b_k ds0 (for distributed forces).
    pub seg_mass_weight: Vec<[f64; 4]>,
    pub seg_len_weight: Vec<[f64; 4]>,
    pub rest_length: f64,
    pub mass: f64,
    /// ∫ r² ds0 / rest length, r the hydrodynamic radius (for
    /// resistive-force drag).
    pub mean_r2: f64,
}

pub(crate) fn point(q: &[f64], dofs: usize, ctrl: &[usize; 4], b: &[f64; 4]) -> [f64; 4] {
    let mut p = [0.0; 4];
    for k in 0..4 {
        let base = ctrl[k] * dofs;
        for a in 0..dofs {
            p[a] += b[k] * q[base + a];
        }
    }
    p
}

/// d = (r', r'', r''', θ, θ') from the coordinates (θ = 0 without roll).
pub(crate) fn local_state(q: &[f64], dofs: usize, ctrl: &[usize; 4], b: &[[f64; 4]; 4]) -> LocalState {
    let mut s = LocalState {
        r1: Vector3::zeros(),
        r2: Vector3::zeros(),
        r3: Vector3::zeros(),
        th: 0.0,
        th1: 0.0,
    };
    for k in 0..4 {
        // One bounds check per control point.
        let x = &q[ctrl[k] * dofs..ctrl[k] * dofs + dofs];
        let p = Vector3::new(x[0], x[1], x[2]);
        s.r1 += b[1][k] * p;
        s.r2 += b[2][k] * p;
        s.r3 += b[3][k] * p;
        if let Some(&th) = x.get(3) {
            s.th += b[0][k] * th;
            s.th1 += b[1][k] * th;
        }
    }
    s
}

impl Cache {
    pub fn build(rod: &Rod) -> Result<Cache> {
        let knots = &rod.knots;
        let (gx, gw) = gauss_legendre(rod.opts.samples_per_segment)?;
        let nseg = knots.n_segments();
        let mut c = Cache::default();
        let e = rod.material.young;
        let g = rod.material.shear_modulus();
        let rho = rod.material.density;
        // First pass: geometry of the rest shape, to get the rest length
        // (the default curvature threshold is relative to it).
        let mut raw = Vec::with_capacity(nseg * gx.len());
        for seg in 0..nseg {
            let (u0, u1) = knots.segment_interval(seg);
            let ctrl = knots.segment_ctrl(seg);
            c.seg_ctrl.push(ctrl);
            c.seg_start.push(raw.len());
            for (x, w) in gx.iter().zip(gw) {
                let u = 0.5 * (u0 + u1) + 0.5 * (u1 - u0) * x;
                let basis = knots.basis(seg, u);
                let s0 = local_state(&rod.q_rest, rod.dofs, &ctrl, &basis);
                let speed0 = s0.r1.norm();
                if !(speed0 > 0.0) || !speed0.is_finite() {
                    return Err(Error::input(format!(
                        "rest shape has zero or undefined tangent at u = {u} (coincident control points?)"
                    )));
                }
                let wt = w * 0.5 * (u1 - u0) * speed0;
                c.rest_length += wt;
                raw.push((seg, u, basis, wt, s0, speed0));
            }
        }
        c.seg_start.push(raw.len());
        let kappa_eps = if rod.opts.curvature_threshold > 0.0 {
            rod.opts.curvature_threshold
        } else {
            1.0 / c.rest_length
        };
        // The frame model's states at the rest shape (reference directors
        // along the rod): the rest values are measured in them.
        let rest_states = rod.opts.model.initial_states(&raw.iter().map(|r| (r.4, r.3)).collect::<Vec<_>>(), rod.is_closed())?;
        c.seg_mass = vec![[[0.0; 4]; 4]; nseg];
        c.seg_inertia = vec![[[0.0; 4]; 4]; nseg];
        c.seg_bb = vec![[[0.0; 4]; 4]; nseg];
        c.seg_r2bb = vec![[[0.0; 4]; 4]; nseg];
        c.seg_mass_weight = vec![[0.0; 4]; nseg];
        c.seg_len_weight = vec![[0.0; 4]; nseg];
        for (idx, (seg, u, basis, wt, s0, speed0)) in raw.into_iter().enumerate() {
            let ctrl = c.seg_ctrl[seg];
            let secs = rod.rest_sections();
            let sec = Section::blend([&secs[ctrl[0]], &secs[ctrl[1]], &secs[ctrl[2]], &secs[ctrl[3]]], basis[0])?;
            let p = sec.props()?;
            let delta = kappa_eps * speed0 * speed0 * speed0;
            let state = rest_states.get(idx).unwrap_or(&FrameState::None);
            let (k1, k2, om) = energy::rest_values(&s0, state, delta, rod.opts.model);
            let c0 = s0.invariants()[crate::energy::invariants::QC2].sqrt();
            // |C⁰| below 1e-8 δ is the round-off of a straight rest shape
            // (its curvature energy would be 1e-16 of the threshold's): no
            // rest curvature to keep, and a δ_b at round-off level would
            // make the Huber Hessian noise.
            // A naturally straight rest (`RodOptions::straight_rest`) keeps
            // no rest curvature, so it is regularised as a straight rod.
            let straight = rod.opts.straight_rest;
            let delta_bend = if c0 > 1e-8 * delta && !straight { delta.min(0.5 * c0) } else { delta };
            let mut consts = SampleConsts { speed0, delta, delta_bend, ..Default::default() };
            set_stiffness(&mut consts, &p, e, g);
            // An imposed excess link lowers the rest twist uniformly (topology.rs).
            let shift = rod.link_twist_shift(c.rest_length);
            let rest = if straight { [0.0, 0.0, -shift] } else { [k1, k2, om - shift] };
            set_plastic(&mut consts, &rest, &rod.plastic.get(idx).copied().unwrap_or_default());
            let mu = rho * p.area;
            let rho_i0 = rho * p.i0;
            c.mass += wt * mu;
            let r2 = sec.hydrodynamic_radius()?.powi(2);
            c.mean_r2 += wt * r2 / c.rest_length;
            // Sampling inertia ℓ⁴ ∫ b_k″ b_l″ ds0 (RodOptions::sampling_length),
            // with d²/ds0² ≈ d²/du² / |r0′|²: any constant symmetric positive
            // term keeps the Boltzmann distribution, so the dropped |r0′|′
            // term costs nothing but exactness of the mode frequencies. The
            // drag blocks (and with them the noise, by fluctuation–
            // dissipation) get the same term, so every mode keeps the damping
            // rate drag/mass: heavy short modes would otherwise take
            // mass/drag to reach the bath's temperature.
            let l4 = rod.opts.sampling_length.powi(4) / speed0.powi(4);
            if !l4.is_finite() {
                return Err(Error::input(format!("sampling length {} m is too large for this rod (ℓ⁴ overflows)", rod.opts.sampling_length)));
            }
            for k in 0..4 {
                c.seg_mass_weight[seg][k] += wt * mu * basis[0][k];
                c.seg_len_weight[seg][k] += wt * basis[0][k];
                for l in 0..4 {
                    let bb = wt * basis[0][k] * basis[0][l];
                    let b2 = wt * l4 * basis[2][k] * basis[2][l];
                    c.seg_mass[seg][k][l] += mu * (bb + b2);
                    c.seg_inertia[seg][k][l] += rho_i0 * (bb + b2);
                    c.seg_bb[seg][k][l] += bb + b2;
                    c.seg_r2bb[seg][k][l] += r2 * (bb + b2);
                }
            }
            c.samples.push(Sample { seg, u, basis, w: wt, consts, rest });
        }
        // cond(seg_bb) ≈ 100 (ℓ/h)⁴: past ℓ = 20 h (1.6e7) the factors
        // would lose the physical (short-range) directions to round-off and
        // the noise would no longer match the drag.
        let ell = rod.opts.sampling_length;
        if ell > 0.0 {
            let h_min = (0..nseg).map(|s| c.samples[c.seg_start[s]..c.seg_start[s + 1]].iter().map(|x| x.w).sum::<f64>()).fold(f64::INFINITY, f64::min);
            if ell > 20.0 * h_min {
                return Err(Error::input(format!(
                    "sampling length {ell} exceeds 20 segment lengths (shortest segment {h_min:.4}): the mass and drag blocks would be too ill-conditioned (≈ 100 (ℓ/h)⁴) to keep fluctuation–dissipation exact"
                )));
            }
        }
        c.seg_arc = (0..nseg)
            .scan(0.0, |acc, s| {
                let start = *acc;
                *acc += c.samples[c.seg_start[s]..c.seg_start[s + 1]].iter().map(|x| x.w).sum::<f64>();
                Some(start)
            })
            .collect();
        c.seg_bb_chol = c.seg_bb.iter().map(crate::force::thermal::cholesky4).collect();
        c.seg_stretch_start = vec![0; nseg + 1];
        if rod.opts.stretch_at_greville {
            check_greville(true, &rod.material, rod.opts.poisson_update)?;
            c.samples.iter_mut().for_each(|s| s.consts.ea = 0.0);
            c.greville_stretch(rod, e)?;
        }
        Ok(c)
    }

    /// The stretch samples at the Greville points of the quadratic
    /// (derivative) space: each segment's midpoint, and an open rod's two
    /// ends — as many as axial strain modes (n − 1 open, n on a ring). Their
    /// weights make the sum exact on that space: Σ_j w_j N_k'(ξ_j)/|r0'(ξ_j)|
    /// = ∫ N_k' du for every basis function k, so the virtual work of a
    /// uniform tension on straight segments is the Gauss stretch's and a
    /// pulled rod stretches by exactly F L / EA (weights from a banded
    /// solve; on a ring's unit spans they are 1 by symmetry). Weights must
    /// come out positive (a stiffness): an end span much shorter than its
    /// neighbour (< ≈ 0.26 of it) is refused.
    fn greville_stretch(&mut self, rod: &Rod, e: f64) -> Result<()> {
        let knots = &rod.knots;
        let ring = knots.kind() == crate::spline::KnotKind::Periodic;
        let nseg = knots.n_segments();
        // (segment, u) of each sample, in u order.
        let mut points = Vec::with_capacity(nseg + 2);
        for seg in 0..nseg {
            let (a, b) = knots.segment_interval(seg);
            if !ring && seg == 0 {
                points.push((seg, a));
            }
            points.push((seg, 0.5 * (a + b)));
            if !ring && seg + 1 == nseg {
                points.push((seg, b));
            }
        }
        let weights_u = if ring {
            // Unit spans: by symmetry each midpoint weighs its span.
            (0..nseg).map(|s| {
                let (a, b) = knots.segment_interval(s);
                b - a
            }).collect()
        } else {
            open_rod_weights(knots, &self.seg_ctrl, &points)?
        };
        let secs = rod.rest_sections();
        for (&(seg, u), wu) in points.iter().zip(weights_u) {
            let ctrl = self.seg_ctrl[seg];
            let basis = knots.basis(seg, u);
            let speed0 = local_state(&rod.q_rest, rod.dofs, &ctrl, &basis).r1.norm();
            if !(speed0 > 0.0) || !speed0.is_finite() {
                return Err(Error::input(format!("rest shape has zero or undefined tangent at u = {u} (coincident control points?)")));
            }
            let sec = Section::blend([&secs[ctrl[0]], &secs[ctrl[1]], &secs[ctrl[2]], &secs[ctrl[3]]], basis[0])?;
            let consts = SampleConsts { ea: e * sec.props()?.area, speed0, ..Default::default() };
            self.stretch.push(StretchSample { basis, w: wu * speed0, consts });
            self.seg_stretch_start[seg + 1] = self.stretch.len();
        }
        Ok(())
    }

    /// A representative axial stiffness EA (force): the first sample's.
    pub fn ea_ref(&self) -> f64 {
        self.stretch.first().map(|s| s.consts.ea).or_else(|| self.samples.first().map(|s| s.consts.ea)).unwrap_or(0.0)
    }

    /// Re-derives the plastic part of every sample's constants from the
    /// rod's offsets (after a plastic update, SPEC §6).
    pub fn refresh_plastic(&mut self, plastic: &[Strains]) {
        for (i, s) in self.samples.iter_mut().enumerate() {
            set_plastic(&mut s.consts, &s.rest, &plastic.get(i).copied().unwrap_or_default());
        }
    }

    /// The same for one sample.
    pub fn refresh_plastic_at(&mut self, i: usize, p: &Strains) {
        let s = &mut self.samples[i];
        set_plastic(&mut s.consts, &s.rest, p);
    }

    /// Re-derives the stiffnesses from the rod's current sections (after a
    /// Poisson radius update, II.59); mass and inertia stay those of the
    /// rest sections (mass is conserved).
    pub fn refresh_stiffness(&mut self, rod_sections: &[Section], e: f64, g: f64) -> Result<()> {
        for s in self.samples.iter_mut() {
            let ctrl = self.seg_ctrl[s.seg];
            let sec = Section::blend(
                [&rod_sections[ctrl[0]], &rod_sections[ctrl[1]], &rod_sections[ctrl[2]], &rod_sections[ctrl[3]]],
                s.basis[0],
            )?;
            set_stiffness(&mut s.consts, &sec.props()?, e, g);
            if !self.stretch.is_empty() {
                s.consts.ea = 0.0; // the stretch lives at the Greville samples
            }
        }
        for (seg, ctrl) in self.seg_ctrl.iter().enumerate() {
            for st in &mut self.stretch[self.seg_stretch_start[seg]..self.seg_stretch_start[seg + 1]] {
                let sec = Section::blend([&rod_sections[ctrl[0]], &rod_sections[ctrl[1]], &rod_sections[ctrl[2]], &rod_sections[ctrl[3]]], st.basis[0])?;
                st.consts.ea = e * sec.props()?.area;
            }
        }
        Ok(())
    }
}

fn set_stiffness(c: &mut SampleConsts, p: &crate::section::SectionProps, e: f64, g: f64) {
    c.ea = e * p.area;
    c.ei1 = e * p.i1;
    c.ei2 = e * p.i2;
    c.gj = g * p.j;
}

/// W uses rest + plastic offsets: κ⁰ + κ_p, ω⁰ + ω_p, ε_p (II.104).
fn set_plastic(c: &mut SampleConsts, rest: &[f64; 3], p: &Strains) {
    c.kappa1 = rest[0] + p.kappa1;
    c.kappa2 = rest[1] + p.kappa2;
    c.omega = rest[2] + p.omega;
    c.eps_p = p.eps;
}
