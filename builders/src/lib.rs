//! Structure builders (DNA double helix, knitted fabric, rope bridge, bead
//! necklace, spring, cable: SPEC §9). Not implemented yet: see the open issues.
