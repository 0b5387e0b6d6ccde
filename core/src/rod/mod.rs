//! A rod: cubic B-spline centreline plus roll angle (SPEC §1), with its rest
//! shape, sections, material and the per-sample data its energy needs.
//!
//! Generalised coordinates are stored flat: control point i owns
//! `q[i*dofs .. i*dofs+dofs]` = (x, y, z[, θ]). Positions are in the world's
//! length unit, θ in radians; velocities likewise per time unit.
mod arc;
mod mixed;
pub mod assemble;
pub mod build;
pub mod drag;
mod plastic;
mod poisson;
mod samples;
mod split;
pub mod topology;

pub use arc::Jet;
pub use assemble::SegBlock;
pub use build::{RodBuilder, RodShape};
pub use plastic::{PlasticUpdate, RuptureSite, StrainMode};
pub use split::Cut;
pub(crate) use samples::Cache;

use crate::energy::{self, invariants::LocalState, EnergyTerms, FrameModel, FrameState, HoldCrossSection, MaterialAngle, MaterialFrame, Strains};
use crate::error::{Error, Result};
use crate::material::Material;
use crate::section::Section;
use crate::spline::KnotVector;
use nalgebra::Vector3;
use serde::{Deserialize, Serialize};

/// Numerical and modelling options of one rod.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct RodOptions {
    /// Gauss–Legendre points per segment (the thesis' "samples per segment"), 1..=8.
    pub samples_per_segment: usize,
    /// Which energies are on. Rods without roll never carry twist energy
    /// (their roll is free, so the twist relaxes to its rest value).
    pub terms: EnergyTerms,
    /// How bending and twist are measured: the reference-frame model of
    /// SPEC §2.3 (default: twist defined on straight stretches) or the
    /// thesis' Frenet + roll model (its validations). Rods without roll
    /// always use the Frenet model (see [`Rod::new`]).
    pub model: FrameModel,
    /// Curvature κ_ε (1/length) below which the Frenet torsion is
    /// regularised (SPEC §2.2). 0 selects 1 / rest length: the Frenet torsion
    /// is exact to 2(κ_ε/κ)², and free 3-D motions stay stable (with
    /// 0.1 / length a free twisted rod blew up: τ varies like 1/κ near
    /// inflections and free ends, where the Frenet frame flips).
    pub curvature_threshold: f64,
    /// Viscous drag coefficient c_d (force per unit velocity per unit length):
    /// distributed force −c_d v, D_ij = ∫ c_d b_i b_j ds0 (III.10).
    pub drag: f64,
    /// Roll drag coefficient c_θ (torque per angular velocity per unit
    /// length): distributed torque −c_θ θ̇ (rods with roll only).
    #[serde(default)]
    pub roll_drag: f64,
    /// Poisson contraction of the section with stretch (II.59), updated
    /// after every solve; off by default.
    #[serde(default)]
    pub poisson_update: bool,
    /// Stretch energy collocated at the Greville points of the derivative
    /// space (each segment's midpoint and an open rod's two ends) instead of
    /// the Gauss points, with weights exact on that space: as many stretch
    /// samples as axial strain modes, so a bent cubic segment is not locked
    /// by stretch it cannot relax (thermal statistics at coarse resolution;
    /// see README), and a uniform tension stays exact. Bending and twist
    /// stay at the Gauss points, and so do the stretch strains `strains()`
    /// reports, which on bent rods are no longer the energy's. Refused with
    /// stretch plasticity, rupture limits and `poisson_update`, and on
    /// knots whose end span is much shorter than its neighbour.
    #[serde(default)]
    pub stretch_at_greville: bool,
    /// Sampling length ℓ (m; 0 = physical inertia): adds ℓ⁴ ∫ μ b_k″ b_l″
    /// ds0 to the mass (and ℓ⁴ ∫ ρI₀ b_k″ b_l″ ds0 to the roll inertia), so
    /// modes shorter than ℓ oscillate no faster than a bending mode of
    /// length ≈ ℓ ("Fourier acceleration"). A constant, isotropic,
    /// positive mass leaves the Boltzmann distribution of the configurations
    /// unchanged (without holonomic constraints: with them it carries the
    /// Fixman factor det(J M⁻¹ Jᵀ), which depends on M) — equilibrium
    /// averages under noise are those of the
    /// physical rod, reached with steps set by ℓ instead of the stiffest
    /// short mode — but the motion is fictitious: use it for equilibrium
    /// statistics only. The drag blocks get the same term (each mode keeps
    /// the damping rate drag/mass; the noise follows). Rigid translations
    /// keep their physical mass and drag (Σ b_k″ = 0).
    #[serde(default)]
    pub sampling_length: f64,
    /// A naturally straight rod wound into its initial shape: zero rest
    /// curvatures and twist (an imposed excess link still shifts the rest
    /// twist; the rest arc length is still the initial shape's). A yarn knitted into loops, or closed into a ring (a
    /// closed curve cannot be a straight rest shape).
    #[serde(default)]
    pub straight_rest: bool,
}

impl Default for RodOptions {
    fn default() -> Self {
        RodOptions {
            samples_per_segment: 5,
            terms: EnergyTerms::default(),
            model: FrameModel::default(),
            curvature_threshold: 0.0,
            drag: 0.0,
            roll_drag: 0.0,
            poisson_update: false,
            stretch_at_greville: false,
            sampling_length: 0.0,
            straight_rest: false,
        }
    }
}

#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Rod {
    pub(crate) knots: KnotVector,
    pub(crate) dofs: usize,
    pub(crate) q: Vec<f64>,
    pub(crate) v: Vec<f64>,
    pub(crate) q_rest: Vec<f64>,
    /// One section per control point, blended with the basis (II.26).
    pub(crate) sections: Vec<Section>,
    /// Unstrained sections when a Poisson update changed `sections`
    /// (empty: same as `sections`). Mass and inertia use these.
    #[serde(default)]
    pub(crate) rest_sections: Vec<Section>,
    pub(crate) material: Material,
    pub(crate) opts: RodOptions,
    /// Per-sample plastic offsets (SPEC §6); empty when the rod never yielded.
    pub(crate) plastic: Vec<Strains>,
    /// Per-sample state of the frame model, carried in time; empty when the
    /// model keeps none (Frenet).
    #[serde(default)]
    pub(crate) frames: Vec<FrameState>,
    /// Excess link ΔLk (turns) imposed on a ring ([`Rod::set_excess_link`]).
    #[serde(default)]
    pub(crate) excess_link: f64,
    #[serde(skip)]
    pub(crate) cache: Cache,
    /// Unit tangent at each Gauss sample, frozen at the start of a dynamic
    /// step for the anisotropic drag (derived from q; empty until a step).
    #[serde(skip)]
    pub(crate) drag_frame: Vec<[f64; 3]>,
    /// Relax's mixed-integration-point tangents (None outside relax).
    #[serde(skip)]
    pub(crate) mixed: Option<Box<mixed::MixedTangents>>,
}

impl Rod {
    /// A rod from a knot vector and control points (rest shape = this shape).
    /// `ctrl` holds `knots.n_ctrl()` rows of 3 (no roll) or 4 (x, y, z, θ) values.
    /// A rod without roll carries no twist energy and is measured in the
    /// Frenet model, whatever `opts` say.
    pub fn new(
        knots: KnotVector,
        dofs: usize,
        ctrl: Vec<f64>,
        sections: Vec<Section>,
        material: Material,
        opts: RodOptions,
    ) -> Result<Rod> {
        if dofs != 3 && dofs != 4 {
            return Err(Error::input(format!("a rod has 3 or 4 coordinates per control point, got {dofs}")));
        }
        let n = knots.n_ctrl();
        if ctrl.len() != n * dofs {
            return Err(Error::input(format!(
                "expected {} control-point values ({n} points × {dofs}), got {}",
                n * dofs,
                ctrl.len()
            )));
        }
        if let Some(i) = ctrl.iter().position(|x| !x.is_finite()) {
            return Err(Error::input(format!(
                "control point {} has a non-finite coordinate ({})",
                i / dofs,
                ctrl[i]
            )));
        }
        let sections = match sections.len() {
            1 => vec![sections[0]; n],
            m if m == n => sections,
            m => {
                return Err(Error::input(format!("give 1 section or one per control point ({n}), got {m}")))
            }
        };
        for s in &sections {
            s.validate()?;
        }
        material.validate()?;
        if !(opts.curvature_threshold.is_finite() && opts.curvature_threshold >= 0.0) {
            return Err(Error::input(format!(
                "curvature_threshold must be finite and >= 0, got {}",
                opts.curvature_threshold
            )));
        }
        crate::error::non_negative("drag coefficient", opts.drag)?;
        crate::error::non_negative("roll drag coefficient", opts.roll_drag)?;
        crate::error::non_negative("sampling length", opts.sampling_length)?;
        let mut opts = opts;
        if dofs == 3 {
            opts.terms.twist = false;
            // No roll: the section is free to spin and the rod carries no
            // twist, so bending is measured from the Frenet frame (for an
            // isotropic straight rest shape the reference model's energy is
            // the same; on a curved one it would pin the section's
            // orientation to the transported director).
            opts.model = FrameModel::Frenet;
        }
        let mut rod = Rod {
            knots,
            dofs,
            v: vec![0.0; ctrl.len()],
            q_rest: ctrl.clone(),
            q: ctrl,
            sections,
            material,
            opts,
            plastic: Vec::new(),
            frames: Vec::new(),
            rest_sections: Vec::new(),
            excess_link: 0.0,
            cache: Cache::default(),
            drag_frame: Vec::new(),
            mixed: None,
        };
        rod.prepare()?;
        rod.frames = rod.initial_frames()?;
        Ok(rod)
    }

    /// The frame model's state of every sample at the current shape (empty
    /// when the model keeps none).
    fn initial_frames(&self) -> Result<Vec<FrameState>> {
        let samples: Vec<(LocalState, f64)> = self
            .cache
            .samples
            .iter()
            .map(|s| (samples::local_state(&self.q, self.dofs, &self.cache.seg_ctrl[s.seg], &s.basis), s.w))
            .collect();
        self.opts.model.initial_states(&samples, self.is_closed())
    }

    /// A closed rod (periodic knots: a ring).
    pub fn is_closed(&self) -> bool {
        self.knots.kind() == crate::spline::KnotKind::Periodic
    }

    /// The frame model's state at sample `i`.
    pub(crate) fn frame_state(&self, i: usize) -> &FrameState {
        static NONE: FrameState = FrameState::None;
        self.frames.get(i).unwrap_or(&NONE)
    }

    /// Carries the frame model's per-sample state to the current shape
    /// (after an accepted step; SPEC §2.3 parallel transport).
    pub(crate) fn transport_frames(&mut self) {
        if self.frames.is_empty() {
            return;
        }
        let model = self.opts.model;
        for (i, st) in self.frames.iter_mut().enumerate() {
            let s = &self.cache.samples[i];
            model.transport(st, &samples::local_state(&self.q, self.dofs, &self.cache.seg_ctrl[s.seg], &s.basis));
        }
    }

    /// Where the frame model's states cannot be carried to the current
    /// shape (the reference model: a sample's tangent turned by more than
    /// 150° since the last transport), said in words; checked before a step
    /// is accepted and by `set_coords`.
    pub(crate) fn transport_obstacle(&self) -> Option<String> {
        let model = self.opts.model;
        self.frames.iter().enumerate().find_map(|(i, st)| {
            let s = &self.cache.samples[i];
            let ls = samples::local_state(&self.q, self.dofs, &self.cache.seg_ctrl[s.seg], &s.basis);
            (!model.transportable(st, &ls)).then(|| format!("the tangent at sample {i} (u = {}) turned by more than 150°", s.u))
        })
    }

    /// The frame model of this rod.
    pub fn frame_model(&self) -> FrameModel {
        self.opts.model
    }

    /// The material angle at u (the angle of director d1 about the tangent
    /// from `reference`, rad) with its derivative, as the frame model
    /// defines it (see [`crate::energy::FrameKinematics::material_angle`]).
    pub fn material_angle(&self, u: f64, reference: &Vector3<f64>) -> Result<MaterialAngle> {
        let (ctrl, b) = self.basis_at(u)?;
        let s = samples::local_state(&self.q, self.dofs, &ctrl, &b);
        let s0 = samples::local_state(&self.q_rest, self.dofs, &ctrl, &b);
        let delta = self.curvature_threshold() * s0.r1.norm().powi(3);
        // The nearest sample lies in u's segment: the same four control points.
        let i = self.nearest_sample(u);
        let sample = &self.cache.samples[i];
        let at_sample = samples::local_state(&self.q, self.dofs, &self.cache.seg_ctrl[sample.seg], &sample.basis);
        let mut m = self.opts.model.material_angle(&s, &at_sample, self.frame_state(i), reference, delta)?;
        m.sample_b1 = sample.basis[1];
        Ok(m)
    }

    /// The material frame (d1, d2, d3) at abscissa u, as the frame model
    /// defines it ([`crate::energy::FrameKinematics::material_frame`]).
    pub fn material_frame(&self, u: f64) -> Result<MaterialFrame> {
        let (ctrl, b) = self.basis_at(u)?;
        let s = samples::local_state(&self.q, self.dofs, &ctrl, &b);
        let s0 = samples::local_state(&self.q_rest, self.dofs, &ctrl, &b);
        let delta = self.curvature_threshold() * s0.r1.norm().powi(3);
        self.opts.model.material_frame(&s, self.frame_state(self.nearest_sample(u)), delta)
    }

    /// How a clamp at u holds the cross-section, as the frame model says.
    pub fn hold_cross_section(&self, u: f64) -> Result<HoldCrossSection> {
        let (ctrl, b) = self.basis_at(u)?;
        let s = samples::local_state(&self.q, self.dofs, &ctrl, &b);
        let s0 = samples::local_state(&self.q_rest, self.dofs, &ctrl, &b);
        Ok(self.opts.model.hold_cross_section(&s, self.curvature_threshold() * s0.r1.norm().powi(3)))
    }

    /// Index of the sample nearest to abscissa u (in its segment).
    pub(crate) fn nearest_sample(&self, u: f64) -> usize {
        let seg = self.knots.locate(u).unwrap_or(0).min(self.cache.seg_start.len().saturating_sub(2));
        let (a, b) = (self.cache.seg_start[seg], self.cache.seg_start[seg + 1]);
        (a..b).min_by(|&i, &j| (self.cache.samples[i].u - u).abs().total_cmp(&(self.cache.samples[j].u - u).abs())).unwrap_or(a)
    }

    /// The per-sample and per-segment data (for force fields and assembly).
    pub(crate) fn cache(&self) -> &Cache {
        &self.cache
    }

    /// Checks a rod's stored state (sizes consistent, everything finite and
    /// in range): what `Rod::new` guarantees, re-checked for rods that come
    /// from a file.
    pub fn check_state(&self) -> Result<()> {
        if self.dofs != 3 && self.dofs != 4 {
            return Err(Error::invalid("rod dofs", self.dofs, "3 or 4"));
        }
        let n = self.knots.n_ctrl();
        for (what, v) in [("coordinates", &self.q), ("velocities", &self.v), ("rest coordinates", &self.q_rest)] {
            check_vec(what, v, n * self.dofs)?;
        }
        if self.sections.len() != n {
            return Err(Error::invalid("rod sections", self.sections.len(), format!("{n} (one per control point)")));
        }
        if !self.rest_sections.is_empty() && self.rest_sections.len() != n {
            return Err(Error::invalid("rod rest sections", self.rest_sections.len(), format!("0 or {n}")));
        }
        for s in self.sections.iter().chain(&self.rest_sections) {
            s.validate()?;
        }
        self.material.validate()?;
        crate::error::non_negative("curvature_threshold", self.opts.curvature_threshold)?;
        crate::error::non_negative("drag coefficient", self.opts.drag)?;
        crate::error::non_negative("roll drag coefficient", self.opts.roll_drag)?;
        crate::error::non_negative("sampling length", self.opts.sampling_length)?;
        crate::error::finite("excess link", self.excess_link)?;
        if self.excess_link != 0.0 && (self.dofs != 4 || self.knots.kind() != crate::spline::KnotKind::Periodic) {
            return Err(Error::invalid("excess link", self.excess_link, "0 unless the rod is a ring with roll coordinate"));
        }
        if !(1..=8).contains(&self.opts.samples_per_segment) {
            return Err(Error::invalid("samples_per_segment", self.opts.samples_per_segment, "in 1..=8"));
        }
        Ok(())
    }

    /// After deserialisation: checks the stored state, rebuilds the cache
    /// and checks the per-sample data against it.
    pub fn restore(&mut self) -> Result<()> {
        self.check_state()?;
        self.prepare()?;
        let ns = self.cache.samples.len();
        if !self.plastic.is_empty() {
            if self.plastic.len() != ns {
                return Err(Error::invalid("plastic offsets", self.plastic.len(), format!("0 or {ns} (one per sample)")));
            }
            for p in &self.plastic {
                for x in [p.eps, p.kappa1, p.kappa2, p.omega] {
                    crate::error::finite("plastic offset", x)?;
                }
            }
        }
        let (model, keeps) = (self.opts.model, self.opts.model.keeps_state());
        if (keeps && self.frames.len() != ns) || (!keeps && !self.frames.is_empty()) {
            return Err(Error::invalid("frame states", self.frames.len(), format!("{} for the {} model", if keeps { ns } else { 0 }, model.name())));
        }
        if let Some(f) = self.frames.iter().find(|f| !model.accepts(f)) {
            return Err(Error::invalid("frame state", format!("{f:?}"), format!("a sound state of the {} model (finite, unit and orthogonal directors)", model.name())));
        }
        Ok(())
    }

    /// Rebuilds the per-sample cache (after construction or deserialisation).
    pub fn prepare(&mut self) -> Result<()> {
        self.cache = Cache::build(self)?;
        if !self.rest_sections.is_empty() {
            self.cache.refresh_stiffness(&self.sections, self.material.young, self.material.shear_modulus())?;
        }
        Ok(())
    }

    /// Curvature κ_ε below which the Frenet torsion is regularised (1/length):
    /// the option, or 1 / rest length when the option is 0.
    pub fn curvature_threshold(&self) -> f64 {
        if self.opts.curvature_threshold > 0.0 {
            self.opts.curvature_threshold
        } else {
            1.0 / self.rest_length()
        }
    }

    /// Sections at rest (before any Poisson contraction), one per control point.
    pub fn rest_sections(&self) -> &[Section] {
        if self.rest_sections.is_empty() {
            &self.sections
        } else {
            &self.rest_sections
        }
    }

    pub fn knots(&self) -> &KnotVector {
        &self.knots
    }
    /// Coordinates per control point: 3 (x, y, z) or 4 (x, y, z, θ).
    pub fn dofs(&self) -> usize {
        self.dofs
    }
    pub fn n_ctrl(&self) -> usize {
        self.knots.n_ctrl()
    }
    pub fn n_segments(&self) -> usize {
        self.knots.n_segments()
    }
    /// Current generalised coordinates (flat, `dofs` per control point).
    pub fn coords(&self) -> &[f64] {
        &self.q
    }
    pub fn velocities(&self) -> &[f64] {
        &self.v
    }
    pub fn rest_coords(&self) -> &[f64] {
        &self.q_rest
    }
    pub fn material(&self) -> &Material {
        &self.material
    }
    pub fn options(&self) -> &RodOptions {
        &self.opts
    }
    pub fn sections(&self) -> &[Section] {
        &self.sections
    }
    /// Parameter domain [u_start, u_end] of the spline.
    pub fn domain(&self) -> (f64, f64) {
        self.knots.domain()
    }
    /// Rest length (length unit).
    pub fn rest_length(&self) -> f64 {
        self.cache.rest_length
    }
    /// Total mass (mass unit).
    pub fn mass(&self) -> f64 {
        self.cache.mass
    }

    /// Coordinates and velocities, for the pipeline to move.
    pub(crate) fn state_mut(&mut self) -> (&mut [f64], &mut [f64]) {
        (&mut self.q, &mut self.v)
    }

    /// Replace coordinates (e.g. to pre-deform a rod); checks length and
    /// finiteness. The frame model's per-sample state is carried
    /// to the new shape as after a step (a reference director follows its
    /// tangent by the smallest rotation). A change too large for one
    /// transport (a tangent turned by more than 150°) is carried along the
    /// straight path of the control points, in up to 64 equal parts; it is
    /// refused, leaving the rod as it was, if some part still turns a
    /// tangent that far or passes an undefined one.
    pub fn set_coords(&mut self, q: &[f64]) -> Result<()> {
        check_vec("coordinates", q, self.q.len())?;
        let before = std::mem::replace(&mut self.q, q.to_vec());
        let Some(mut why) = self.transport_obstacle() else {
            self.transport_frames();
            return Ok(());
        };
        let frames = self.frames.clone();
        for parts in [4usize, 16, 64] {
            let mut carried = true;
            for k in 1..=parts {
                let t = k as f64 / parts as f64;
                // The last part lands exactly on q.
                self.q.iter_mut().zip(before.iter().zip(q)).for_each(|(x, (a, b))| *x = if k == parts { *b } else { a + t * (b - a) });
                if let Some(w) = self.transport_obstacle() {
                    why = w;
                    carried = false;
                    break;
                }
                self.transport_frames();
            }
            if carried {
                return Ok(());
            }
            self.frames.clone_from(&frames);
        }
        self.q = before; // refused: the rod is as it was
        Err(Error::input(format!("coordinates: {why} along the way from the current shape, even in 64 parts; the reference directors cannot follow (move it in smaller changes)")))
    }
    pub fn set_velocities(&mut self, v: &[f64]) -> Result<()> {
        check_vec("velocities", v, self.v.len())?;
        self.v.copy_from_slice(v);
        Ok(())
    }

    /// Control point indices and basis values/derivatives at u (u checked).
    pub fn basis_at(&self, u: f64) -> Result<([usize; 4], [[f64; 4]; 4])> {
        let seg = self.knots.locate(u)?;
        Ok((self.knots.segment_ctrl(seg), self.knots.basis(seg, u)))
    }

    /// The coordinates at u and their first two u-derivatives from one
    /// basis evaluation (the closest-point iterations need all three).
    pub fn eval_012(&self, u: f64) -> Result<[[f64; 4]; 3]> {
        let (ctrl, b) = self.basis_at(u)?;
        let mut out = [[0.0; 4]; 3];
        for (k, &i) in ctrl.iter().enumerate() {
            for (d, o) in out.iter_mut().enumerate() {
                for (a, x) in o.iter_mut().enumerate().take(self.dofs) {
                    *x += b[d][k] * self.q[i * self.dofs + a];
                }
            }
        }
        Ok(out)
    }

    /// The `deriv`-th u-derivative of the generalised coordinates at u
    /// (x, y, z[, θ]).
    pub fn eval(&self, u: f64, deriv: usize) -> Result<[f64; 4]> {
        if deriv > 3 {
            return Err(Error::input(format!("derivative order must be 0..=3, got {deriv}")));
        }
        let (ctrl, b) = self.basis_at(u)?;
        let mut out = [0.0; 4];
        for (k, &i) in ctrl.iter().enumerate() {
            for (a, o) in out.iter_mut().enumerate().take(self.dofs) {
                *o += b[deriv][k] * self.q[i * self.dofs + a];
            }
        }
        Ok(out)
    }
    /// Velocity of the centreline point at u (length/time).
    pub fn eval_velocity(&self, u: f64) -> Result<Vector3<f64>> {
        self.velocity_derivative(u, 0)
    }
    /// `deriv`-th derivative in u (0..=3) of the centreline velocity at u.
    pub fn velocity_derivative(&self, u: f64, deriv: usize) -> Result<Vector3<f64>> {
        let (ctrl, b) = self.basis_at(u)?;
        let mut v = Vector3::zeros();
        for (k, &i) in ctrl.iter().enumerate() {
            for a in 0..3 {
                v[a] += b[deriv.min(3)][k] * self.v[i * self.dofs + a];
            }
        }
        Ok(v)
    }

    /// Centreline point r(u) (length unit).
    pub fn position(&self, u: f64) -> Result<Vector3<f64>> {
        let p = self.eval(u, 0)?;
        Ok(Vector3::new(p[0], p[1], p[2]))
    }
    /// Unit tangent r'(u)/|r'(u)|.
    pub fn tangent(&self, u: f64) -> Result<Vector3<f64>> {
        let (ctrl, b) = self.basis_at(u)?;
        self.tangent_from(u, &ctrl, &b[1])
    }
    /// Unit tangent at u from its basis' first derivatives `b1` on `ctrl`
    /// (from [`Rod::basis_at`]).
    pub(crate) fn tangent_from(&self, u: f64, ctrl: &[usize; 4], b1: &[f64; 4]) -> Result<Vector3<f64>> {
        let d = self.dofs;
        let t: Vector3<f64> = ctrl.iter().zip(b1).map(|(&i, &w)| Vector3::new(self.q[i * d], self.q[i * d + 1], self.q[i * d + 2]) * w).sum();
        let n = t.norm();
        if n == 0.0 {
            return Err(Error::singular(format!("zero tangent at u = {u}")));
        }
        Ok(t / n)
    }

    /// The local derivative vector d at u with the current coordinates.
    pub fn local_state(&self, u: f64) -> Result<LocalState> {
        let (ctrl, b) = self.basis_at(u)?;
        Ok(samples::local_state(&self.q, self.dofs, &ctrl, &b))
    }

    /// Strains (ε, κ1, κ2, ω) at every sample, in sample order.
    pub fn strains(&self) -> Vec<Strains> {
        self.cache
            .samples
            .iter()
            .enumerate()
            .map(|(i, s)| {
                let ls = samples::local_state(&self.q, self.dofs, &self.cache.seg_ctrl[s.seg], &s.basis);
                energy::strains(&ls, &s.consts, self.frame_state(i), self.opts.model)
            })
            .collect()
    }

    /// Number of samples (Gauss points).
    pub fn n_samples(&self) -> usize {
        self.cache.samples.len()
    }

    /// Parameter u of every sample (Gauss point), in sample order.
    pub fn sample_params(&self) -> Vec<f64> {
        self.sample_params_iter().collect()
    }

    /// [`Self::sample_params`] without allocating.
    pub(crate) fn sample_params_iter(&self) -> impl Iterator<Item = f64> + '_ {
        self.cache.samples.iter().map(|s| s.u)
    }

    /// Each sample's parameter u and centreline point (length unit), in
    /// sample order, without allocating.
    pub(crate) fn samples_at(&self) -> impl Iterator<Item = (f64, Vector3<f64>)> + '_ {
        self.cache.samples.iter().map(|s| {
            let ls = samples::point(&self.q, self.dofs, &self.cache.seg_ctrl[s.seg], &s.basis[0]);
            (s.u, Vector3::new(ls[0], ls[1], ls[2]))
        })
    }

    /// Centreline points at every sample (length unit).
    pub fn sample_points(&self) -> Vec<Vector3<f64>> {
        self.samples_at().map(|(_, p)| p).collect()
    }

    /// Kinetic energy ½ VᵀMV (allocates nothing: summed per segment).
    pub fn kinetic_energy(&self) -> f64 {
        let (d, v) = (self.dofs, &self.v);
        let mut e = 0.0;
        for (seg, ctrl) in self.cache.seg_ctrl.iter().enumerate() {
            let (m, j) = (&self.cache.seg_mass[seg], &self.cache.seg_inertia[seg]);
            // Symmetric: the diagonal once, each pair k < l twice.
            for k in 0..4 {
                for l in k..4 {
                    let (a, b) = (ctrl[k] * d, ctrl[l] * d);
                    let mut t = m[k][l] * (v[a] * v[b] + v[a + 1] * v[b + 1] + v[a + 2] * v[b + 2]);
                    if d == 4 {
                        t += j[k][l] * v[a + 3] * v[b + 3];
                    }
                    e += if k == l { t } else { 2.0 * t };
                }
            }
        }
        0.5 * e
    }

    /// Linear momentum Σ (M V) over the translational coordinates.
    pub fn momentum(&self) -> Vector3<f64> {
        let mut mv = vec![0.0; self.v.len()];
        self.mass_times(&self.v, &mut mv);
        let mut p = Vector3::zeros();
        for i in 0..self.n_ctrl() {
            for a in 0..3 {
                p[a] += mv[i * self.dofs + a];
            }
        }
        p
    }

    /// y = M x with the consistent mass matrix (II.70–II.75).
    pub fn mass_times(&self, x: &[f64], y: &mut [f64]) {
        self.blocks_times(&self.cache.seg_mass, Some(&self.cache.seg_inertia), x, y);
    }

    /// y = B x for a matrix given by per-segment 4×4 blocks on each axis
    /// (`roll`: the blocks on θ, none for zero).
    fn blocks_times(&self, blocks: &[[[f64; 4]; 4]], roll: Option<&[[[f64; 4]; 4]]>, x: &[f64], y: &mut [f64]) {
        y.iter_mut().for_each(|v| *v = 0.0);
        let d = self.dofs;
        for (seg, ctrl) in self.cache.seg_ctrl.iter().enumerate() {
            let m = &blocks[seg];
            for k in 0..4 {
                for l in 0..4 {
                    for a in 0..3 {
                        y[ctrl[k] * d + a] += m[k][l] * x[ctrl[l] * d + a];
                    }
                    if let (4, Some(j)) = (d, roll) {
                        y[ctrl[k] * d + 3] += j[seg][k][l] * x[ctrl[l] * d + 3];
                    }
                }
            }
        }
    }
}

pub(crate) fn check_vec(what: &str, x: &[f64], n: usize) -> Result<()> {
    if x.len() != n {
        return Err(Error::input(format!("{what}: expected {n} values, got {}", x.len())));
    }
    if let Some(i) = x.iter().position(|v| !v.is_finite()) {
        return Err(Error::input(format!("{what}: value {i} is not finite ({})", x[i])));
    }
    Ok(())
}
