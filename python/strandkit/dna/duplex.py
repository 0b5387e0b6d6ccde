"""DNA double helix (SPEC §9.1, issue 17), in molecular units: nm, pN, ns,
ag, K — use ``World(units="molecular")``.

>>> import strandkit as sk
>>> d = sk.dna.duplex("GATTACAGATTACA")
>>> d
Duplex(14 bp, 'GATTACAGATTACA', 10.5 bp/turn, rise 0.34 nm, radius 1.0 nm, minor groove 1.26 nm, mismatches=[])
>>> d.sequences[1]
'TGTAATCTGTAATC'

Two backbone strands (rods through the nucleotides, strand a 5′→3′ up the
z axis, strand b antiparallel), one hydrogen bond per base pair (a distance
constraint, labelled ``hbond[k]``, breaking in tension above its pair's
force: A·T 9 pN, G·C 20 pN by default; with ``hbond="position"`` also the
pair's stagger, ``stagger[k]``) and stacking between consecutive
pairs (``stack[k]``: six compliant base-pair-step strains), removed as soon
as any pair it reads breaks (its two pairs and the neighbours that frame
them). Pair k is strand a's nucleotide k.

The stacking is calibrated so that the whole duplex, strands included,
has the elasticity asked for at zero temperature (B-DNA by default:
A = 50 nm, S = 1100 pN, C = 100 nm kT, g = −90 pN·nm; ``measured`` holds
what the calibration measured). Not yet checked: the same constants with
thermal noise on.

Which rung model reproduces which reference: distance rungs (the default)
the calibrated elasticity, the unzipping plateau (AFM's 9 / 20 pN with
``experiments.break_forces_for_unzipping``) and the mdtraj trajectory
checks; position rungs the same elasticity (calibrated with them) and the
shear law: rupture vs length follows de Gennes' F_c = 2 f₁ κ⁻¹ tanh(κN/2)
from the model's own Q, R, f₁ within 5 % for N ≥ 16 bp (2.6–4.4 % below)
and saturates (``tests/test_dna_shear.py``; N ≤ 12 bp rupture 9–12 %
above it).
"""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import List, Optional, Sequence

import numpy as np

from .. import _native
from ..errors import _invalid

__all__ = ["Duplex", "duplex"]


@dataclass(frozen=True)
class Duplex:
    """A built duplex: the assembly to insert and where its parts are.

    ``strands``: assembly rod indices of strand a and strand b;
    ``sequences``: both strands 5′→3′; ``abscissae``: each nucleotide's
    abscissa on its strand, 5′→3′; ``partner[k]``: strand b's nucleotide
    paired with a's k; ``hbonds[k]``/``stacks[k]``/``staggers[k]``:
    assembly constraint indices (None for a mismatch; staggers: position
    rungs only); ``break_forces``: pN per pair;
    ``rung_length``, ``pitch``, ``grooves`` (minor, major): nm;
    ``phase``: the strand offset φ (rad); ``measured``: the duplex's
    zero-temperature stretch_modulus (pN), twist_stretch (pN·nm),
    twist_stiffness and bending_stiffness (pN·nm²) as calibrated."""

    assembly: object
    strands: List[int]
    sequences: List[str]
    abscissae: List[np.ndarray]
    partner: np.ndarray
    hbonds: list
    stacks: list
    staggers: list
    mismatches: List[int]
    break_forces: np.ndarray
    rung_length: float
    phase: float
    pitch: float
    grooves: List[float]
    measured: dict = field(default_factory=dict)
    params: dict = field(default_factory=dict)

    def __len__(self) -> int:
        return len(self.partner)

    def __repr__(self) -> str:
        p = self.params
        seq = self.sequences[0] if len(self) <= 24 else self.sequences[0][:21] + "..."
        return (f"Duplex({len(self)} bp, {seq!r}, {p['bp_per_turn']} bp/turn, rise {p['rise']} nm, "
                f"radius {p['radius']} nm, minor groove {self.grooves[0]:.3g} nm, mismatches={self.mismatches})")


def duplex(sequence: str, *, complement: Optional[str] = None, bp_per_turn: float = 10.5, rise: float = 0.34,
           radius: float = 1.0, minor_groove: float = 12.0 / 34.0, hbond: str = "distance",
           hbond_compliance: float = 0.0, stagger_compliance: float = 0.04,
           break_force_at: float = 9.0, break_force_gc: float = 20.0,
           break_forces: Optional[Sequence[float]] = None,
           stagger_break_forces: Optional[Sequence[float]] = None, break_averaging_time: float = 0.0,
           strand_stretch_modulus: float = 400.0,
           strand_persistence: float = 0.75, bending_persistence: float = 50.0, stretch_modulus: float = 1100.0,
           twist_persistence: float = 100.0, twist_stretch: float = -90.0, temperature: float = 298.15,
           averaged_stacking: bool = False) -> Duplex:
    """B-DNA duplex of ``sequence`` (strand a, 5′→3′; A, C, G, T in either
    case; any other letter is refused with its position).

    complement: strand b 5′→3′ (default: the Watson–Crick complement;
    mismatched pairs get no hydrogen bond and no stacking, and are listed in
    ``mismatches``); bp_per_turn; rise: nm per base pair; radius: nm (the
    strands' helices); minor_groove: the share of the pitch the minor groove
    spans along the axis (12/34 by default, φ ≈ 127°; the thesis: 0.4 with
    bp_per_turn=10); hbond: the rung model — ``"distance"`` (one distance
    per pair; the stacking's frames then read a pair's stagger, and give
    the duplex its shear stiffness) or ``"position"`` (the distance plus the
    pair's stagger along the local axis, ``stagger[k]``, compliant, breaking
    when its force exceeds ``stagger_break_forces``; the stacking is then
    blind to stagger, and a sheared duplex is de Gennes' ladder: backbone
    Q ≈ EA h²/ℓ³ per pair, rung R = 1/stagger_compliance); hbond_compliance:
    nm/pN (0: rigid bonds); stagger_compliance: nm/pN (position rungs;
    0.04 by default: a 50 % G·C 32 bp duplex shears at 65 pN, Hatch
    et al. 2008 measured 61.4; 0.5 gives Hatch's decay length κ⁻¹ ≈ 6 bp, but
    a stagger force cannot then exceed ≈ 3.6 pN, the rung lying flat);
    stagger_break_forces: pN per pair (None: the pair's break force);
    break_force_at, break_force_gc: pN, tension that breaks an A·T / G·C
    bond (a bond's tension, not the force that unzips the duplex: the fork
    shares the pull, and ``experiments.break_forces_for_unzipping`` gives
    the break forces that unzip at AFM's 9 / 20 pN, ≈ 14.4 / 28.6 pN);
    break_forces: pN per pair, overriding them (``inf``: unbreakable);
    break_averaging_time: ns over which a bond's tension is averaged
    before it is compared with its break force (0: each step's; with
    thermal noise use ~1 ns, or every rigid bond breaks at once);
    strand_stretch_modulus: pN, strand_persistence: nm — each strand's
    material (single-stranded DNA's persistence; 400 pN, not ssDNA's ≈ 800:
    stiffer strands make the duplex unwind under tension, beyond what the
    stacking can correct); bending_persistence: nm, stretch_modulus: pN,
    twist_persistence: nm (C/kT), twist_stretch: pN·nm (< 0: overwinds when
    stretched) — the whole duplex's zero-temperature elasticity, which the
    stacking is calibrated to (once per parameter set and process, a few
    seconds; ``measured`` holds what the calibration measured, pN and nm);
    temperature: K (persistence lengths → stiffness); averaged_stacking:
    under the trapezoidal rule, average the duplex's compliant constraints
    (stacking, compliant bonds, staggers) over each step like elastic
    energies — exact base-pair-scale thermal statistics, but their stiff
    rows need steps of ~0.25 ps (at 1–10 ps the Newton iterations stall or
    diverge); False (default): held at the step's end, robust at 5–10 ps,
    the base-pair modes damped and, under noise, cooled
    (``docs/dna_calibration.md``).
    """
    params = dict(sequence=str(sequence), complement=complement, bp_per_turn=float(bp_per_turn), rise=float(rise),
                  radius=float(radius), minor_groove=float(minor_groove), hbond=str(hbond),
                  hbond_compliance=float(hbond_compliance), stagger_compliance=float(stagger_compliance),
                  break_force_at=float(break_force_at), break_force_gc=float(break_force_gc),
                  break_forces=None if break_forces is None else [float(f) for f in break_forces],
                  stagger_break_forces=(None if stagger_break_forces is None
                                        else [float(f) for f in stagger_break_forces]),
                  break_averaging_time=float(break_averaging_time),
                  strand_stretch_modulus=float(strand_stretch_modulus), strand_persistence=float(strand_persistence),
                  bending_persistence=float(bending_persistence), stretch_modulus=float(stretch_modulus),
                  twist_persistence=float(twist_persistence), twist_stretch=float(twist_stretch),
                  temperature=float(temperature), averaged_stacking=bool(averaged_stacking))
    asm, l = _native.build_duplex(**params)
    return Duplex(asm, list(l["strands"]), list(l["sequences"]), [np.asarray(a) for a in l["abscissae"]],
                  np.asarray(l["partner"]), list(l["hbonds"]), list(l["stacks"]), list(l["staggers"]), list(l["mismatches"]),
                  np.asarray(l["break_forces"]), l["rung_length"], l["phase"], l["pitch"], list(l["grooves"]),
                  dict(l["measured"]), params)


def as_duplex(sequence_or_duplex, options=None, defaults=None) -> Duplex:
    """A built Duplex as given (``options`` must then be empty), or one
    built from a sequence with ``options`` (``duplex``'s keywords) over
    ``defaults``."""
    if isinstance(sequence_or_duplex, Duplex):
        if options:
            raise _invalid(f"duplex options {sorted(options)} given with a built Duplex")
        return sequence_or_duplex
    return duplex(sequence_or_duplex, **{**(defaults or {}), **(options or {})})
