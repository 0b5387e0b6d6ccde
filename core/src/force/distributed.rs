//! A uniform force per unit rest length along a whole rod: ∫ f b_k ds0.
use crate::constraint::catalogue::{FieldInfo, FieldType::*};
use super::{finite_all, spread, ForceField, LoadInfo, LoadLaw, OnRupture};
use crate::error::Result;
use crate::handles::RodHandle;
use crate::rod::Rod;
use serde::{Deserialize, Serialize};

/// Force per unit rest length (force/length), uniform along the rod.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Distributed {
    pub rod: RodHandle,
    pub force_per_length: [f64; 3],
}

impl ForceField for Distributed {
    fn add_force(&self, rod: &Rod, _time: f64, f: &mut [f64]) -> Result<()> {
        let c = rod.cache();
        for (s, ctrl) in c.seg_ctrl.iter().enumerate() {
            spread(f, rod.dofs(), ctrl, &c.seg_len_weight[s], &self.force_per_length);
        }
        Ok(())
    }
    fn potential(&self, rod: &Rod, time: f64) -> Result<f64> {
        super::linear_potential(self, rod, time)
    }
}

impl LoadLaw for Distributed {
    const INFO: LoadInfo = LoadInfo {
        name: "Distributed",
        helper: "distributed",
        doc: "Uniform force per unit rest length (force/length, 3 values) along the whole rod.",
        fields: &[
            FieldInfo::new("rod", Rod, "", "the rod it acts on"),
            FieldInfo::new("force_per_length", Vec3, "force/length", "force per unit rest length"),
        ],
    };
    fn rod(&self) -> RodHandle {
        self.rod
    }
    fn rod_mut(&mut self) -> &mut RodHandle {
        &mut self.rod
    }
    fn on_rupture(&self) -> OnRupture {
        OnRupture::Copy
    }
    fn validate(&self, _rod: &Rod) -> Result<()> {
        finite_all("distributed force", &self.force_per_length)
    }
}
