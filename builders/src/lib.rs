//! Structure builders on top of strandkit-core (SPEC §9): each builder is a
//! pure function from parameters (SI units) to an
//! [`strandkit_core::Assembly`], inserted into a world with
//! `World::insert`; experiments are separate functions.
//!
//! - [`rope_bridge`]: floor ropes, handrails, planks, verticals (§9.2).
//! - [`necklace`]: beads on a string, over a peg or from two points (§9.4).
//! - [`beads_on_spring`]: beads sliding down a hanging helical spring (§9.4).
//! - [`cable_on_clips`]: a cable on a structure, held by clips (§9.5).
//! - [`harness`]: cables of several radii joined at junctions (§9.5).
//! - [`dna::duplex`]: a B-DNA duplex from a sequence: two strands, hydrogen
//!   bonds, breakable stacking (§9.1); [`dna_elasticity`]: its elastic
//!   constants measured at zero temperature; [`dna_harmonic`]: its exact
//!   thermal statistics in the harmonic approximation.
//! - [`knit::fabric`]: weft-knit fabrics (jersey, rib, garter, seed, any
//!   knit/purl grid) of naturally straight yarns held by contact (§9.3).
//! - [`rope::Rope`]: a rope given by linear density, EA and EI.
//! - [`curves`]: catenary and loaded-cable shapes (initial shapes and the
//!   closed forms of the tests).
pub mod cable;
pub mod curves;
pub mod dna;
pub mod dna_elasticity;
pub mod dna_harmonic;
pub mod harness;
pub mod knit;
pub mod necklace;
pub mod rope;
pub mod rope_bridge;
pub mod spring;

pub use cable::{cable_on_clips, CableLayout, CableOnClips};
pub use dna::{duplex, Duplex, DuplexLayout, Elasticity, Stacking, Strand};
pub use harness::{harness, BranchEnd, Harness, HarnessLayout, JunctionLink};
pub use knit::{fabric, Boundary, Fabric, FabricLayout, LoopModel, LoopSpan, Pattern, Stitch, StitchGrid, Yarn};
pub use necklace::{necklace, Hang, Necklace, NecklaceLayout};
pub use rope::Rope;
pub use rope_bridge::{rope_bridge, BridgeLayout, PlankModel, RopeBridge};
pub use spring::{beads_on_spring, BeadsOnSpring, SpringLayout};
pub use strandkit_core::Assembly;
