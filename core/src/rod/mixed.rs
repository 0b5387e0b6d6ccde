//! Relax's mixed-integration-point state: the unit tangents at the stretch
//! samples of the last two Newton iterates
//! ([`crate::energy::stretch::mixed_geometric_stiffness`]). Set only
//! while `relax` runs; the rod's energy and forces are never changed by it.
use super::samples::local_state;
use super::Rod;
use crate::energy::stretch::mixed_merit_shift;

#[derive(Clone, Debug, Default)]
pub(crate) struct MixedTangents {
    /// At the previous iterate: the stiffness's predicted strain.
    pub previous: Vec<[f64; 3]>,
    /// At the current iterate: the line search's merit.
    pub current: Vec<[f64; 3]>,
}

impl Rod {
    /// Unit tangents at the stretch samples (Gauss samples, then Greville
    /// ones); zero where r′ vanishes.
    fn stretch_tangents(&self, out: &mut Vec<[f64; 3]>) {
        out.clear();
        if !self.opts.terms.stretch {
            return;
        }
        let c = &self.cache;
        for seg in 0..c.seg_ctrl.len() {
            let ctrl = &c.seg_ctrl[seg];
            for s in &c.samples[c.seg_start[seg]..c.seg_start[seg + 1]] {
                out.push(unit(&local_state(&self.q, self.dofs, ctrl, &s.basis).r1));
            }
        }
        for seg in 0..c.seg_ctrl.len() {
            let ctrl = &c.seg_ctrl[seg];
            for s in &c.stretch[c.seg_stretch_start[seg]..c.seg_stretch_start[seg + 1]] {
                out.push(unit(&local_state(&self.q, self.dofs, ctrl, &s.basis).r1));
            }
        }
    }

    /// Starts (or moves on) the mixed iteration at the present coordinates.
    /// `predict`: the stiffness predicts the stretch from the last iterate's
    /// tangents (after a step that turned samples and was taken on the
    /// merit); otherwise it is the exact one.
    pub(crate) fn advance_mixed(&mut self, predict: bool) {
        if !self.opts.terms.stretch {
            return; // no stretch energy: nothing to predict nor forgive
        }
        let mut m = self.mixed.take().unwrap_or_default();
        std::mem::swap(&mut m.previous, &mut m.current);
        self.stretch_tangents(&mut m.current);
        if !predict || m.previous.len() != m.current.len() {
            m.previous.clone_from(&m.current);
        }
        self.mixed = Some(m);
    }

    /// Ends the mixed iteration (the exact stiffness again).
    pub(crate) fn end_mixed(&mut self) {
        self.mixed = None;
    }

    /// The merit's shift from the elastic energy (≤ 0; zero without a
    /// mixed iteration or at its current iterate).
    pub(crate) fn mixed_merit_shift(&self) -> f64 {
        let Some(m) = self.mixed.as_deref() else { return 0.0 };
        let c = &self.cache;
        let mut shift = 0.0;
        let n_gauss = c.samples.len();
        for seg in 0..c.seg_ctrl.len() {
            let ctrl = &c.seg_ctrl[seg];
            for i in c.seg_start[seg]..c.seg_start[seg + 1] {
                let s = &c.samples[i];
                let r1 = local_state(&self.q, self.dofs, ctrl, &s.basis).r1;
                shift += m.current.get(i).map_or(0.0, |t| s.w * mixed_merit_shift(&r1, t, &s.consts));
            }
            for j in c.seg_stretch_start[seg]..c.seg_stretch_start[seg + 1] {
                let s = &c.stretch[j];
                let r1 = local_state(&self.q, self.dofs, ctrl, &s.basis).r1;
                shift += m.current.get(n_gauss + j).map_or(0.0, |t| s.w * mixed_merit_shift(&r1, t, &s.consts));
            }
        }
        shift
    }

    /// The largest angle (rad) by which a stretch sample's tangent has
    /// turned since the current iterate (0 without a mixed iteration).
    pub(crate) fn mixed_turn(&self) -> f64 {
        let Some(m) = self.mixed.as_deref() else { return 0.0 };
        let mut tangents = Vec::new();
        self.stretch_tangents(&mut tangents);
        tangents.iter().zip(&m.current).fold(0.0f64, |acc, (a, b)| {
            // A tangent that vanished (a folded sample) turned all the way.
            if *a == [0.0; 3] || *b == [0.0; 3] {
                return std::f64::consts::PI;
            }
            let (a, b) = (nalgebra::Vector3::from(*a), nalgebra::Vector3::from(*b));
            acc.max(a.cross(&b).norm().atan2(a.dot(&b)))
        })
    }

    /// The previous iterate's tangent at stretch sample `k` (Gauss index,
    /// or the Gauss count plus the Greville index), when mixed.
    #[inline(always)]
    pub(crate) fn mixed_previous(&self, k: usize) -> Option<&[f64; 3]> {
        self.mixed.as_deref().and_then(|m| m.previous.get(k))
    }
}

fn unit(r1: &nalgebra::Vector3<f64>) -> [f64; 3] {
    let n = r1.norm();
    if n > 0.0 && n.is_finite() {
        (r1 / n).into()
    } else {
        [0.0; 3]
    }
}

#[cfg(test)]
mod tests {
    use crate::energy::EnergyTerms;
    use crate::prelude::*;
    use nalgebra::Vector3;

    fn rod(stretch: bool) -> crate::rod::Rod {
        let terms = EnergyTerms { stretch, ..Default::default() };
        RodBuilder::straight(Vector3::zeros(), Vector3::new(1.0, 0.0, 0.0))
            .control_points(6)
            .section(Section::circle(0.01).unwrap())
            .material(Material::new("steel", 200e9, 0.3, 7800.0).unwrap())
            .options(RodOptions { terms, ..Default::default() })
            .build()
            .unwrap()
    }

    /// A rod without stretch energy keeps no tangents (nothing to predict
    /// or forgive); one with it forgives the stretch of a bend and reports
    /// the turn: the middle control point lifted by 0.1 m turns tangents
    /// and lengthens the rod, so the shift is negative and the turn
    /// positive, both zero before the move.
    #[test]
    fn tangents_only_where_stretch_is_stored() {
        let mut r = rod(false);
        r.advance_mixed(false);
        assert!(r.mixed.is_none());
        assert_eq!((r.mixed_merit_shift(), r.mixed_turn()), (0.0, 0.0));
        let mut r = rod(true);
        r.advance_mixed(false);
        assert_eq!((r.mixed_merit_shift(), r.mixed_turn()), (0.0, 0.0));
        let d = r.dofs();
        let mut q = r.coords().to_vec();
        q[2 * d + 1] += 0.1;
        r.q.copy_from_slice(&q);
        assert!(r.mixed_merit_shift() < 0.0 && r.mixed_merit_shift().is_finite());
        let turn = r.mixed_turn();
        assert!(turn > 0.05 && turn < 1.0, "turn {turn}");
        r.end_mixed();
        assert_eq!(r.mixed_merit_shift(), 0.0);
    }
}
