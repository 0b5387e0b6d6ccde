//! Structure builders on top of strandkit-core (SPEC §9). So far: the
//! reference scenarios of SPEC §10; the DNA, knit, bridge, necklace, spring
//! and cable builders are open issues.
pub mod scenarios;
