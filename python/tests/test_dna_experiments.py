"""strandkit.dna.experiments (issue 17): unzipping at zero temperature in
the quasi-static limit. Each opening comes when the fork's hydrogen bond
reaches its break force (the event's tension equals it), so the trap force
is a sawtooth set pair by pair by the sequence: a G·C block unzips at the
all-G·C plateau and an A·T block at the all-A·T one. The plateau is a
fixed share of the break force set by the fork's geometry (measured here
and stated in the module docs), and calibrated break forces unzip at
the forces measured by AFM."""
import csv
import math

import numpy as np
import pytest

import strandkit as sk
from strandkit.dna import experiments as ex

QS = dict(ex.QUASI_STATIC, progress_bar=False)


def plateau(r, pairs):
    """Mean trap force (pN) at the openings of the given pairs."""
    f = [b["trap_force"] for b in r.breaks if b["pair"] in pairs]
    assert len(f) == len(pairs), f"pairs {pairs} did not all open: {[b['pair'] for b in r.breaks]}"
    return float(np.mean(f))


@pytest.fixture(scope="module")
def runs():
    return {s: ex.unzip(s, distance=14.0, **QS) for s in ("AT" * 7, "GC" * 7)}


def test_each_opening_is_the_fork_bond_reaching_its_break_force(runs):
    for seq, fb in (("AT" * 7, 9.0), ("GC" * 7, 20.0)):
        r = runs[seq]
        assert [b["pair"] for b in r.breaks] == list(range(len(r.breaks))) and len(r.breaks) >= 8
        # Tension when the bond broke: its break force, to the step's overshoot.
        assert all(fb <= b["force"] < 1.1 * fb for b in r.breaks)
        # A sawtooth: the force drops after each opening.
        i = np.searchsorted(r.time, [b["time"] for b in r.breaks[2:]])
        assert np.all(r.force[i + 1] < r.force[i - 1])


def test_plateau_is_affine_in_the_break_force_and_quasi_static(runs):
    # Same sequence, three break forces: the plateau at the middle one lies
    # on the line through the other two (the fork's geometry does not
    # depend on the load: F = α f_b − β), and a 4× slower pull in a 10×
    # more viscous fluid gives the same plateau (the quasi-static limit).
    f = {}
    for fb in (9.0, 14.5, 20.0):
        d = sk.dna.duplex("AT" * 6, break_forces=[fb] * 12)
        f[fb] = ex.unzipping_plateau(ex.unzip(d, distance=12.0, **QS))
    assert f[14.5] == pytest.approx(f[9.0] + (f[20.0] - f[9.0]) * 5.5 / 11.0, rel=0.03)
    alpha = (f[20.0] - f[9.0]) / 11.0
    assert 0.5 < alpha < 1.0  # the fork's bond carries the pull, shared
    slow = ex.unzip("AT" * 5, distance=8.0, **{**QS, "speed": 0.05, "viscosity": 1.0})
    assert ex.unzipping_plateau(slow) == pytest.approx(plateau(runs["AT" * 7], range(3, 8)), rel=0.05)


def test_unzipping_follows_the_sequence_at_rief_forces():
    # Break forces calibrated (on alternating 12 bp probes) to unzip at
    # Rief et al.'s AFM forces, 9 pN A·T and 20 pN G·C (SPEC §9.1); a
    # mixed 24 bp sequence then unzips at each block's force (±15 %).
    fa, fg = ex.break_forces_for_unzipping(9.0, 20.0)
    assert 9.0 < fa < fg
    seq = "ATATATAT" + "GCGCGCGC" + "ATATATAT"
    r = ex.unzip(sk.dna.duplex(seq, break_force_at=fa, break_force_gc=fg), distance=36.0, **QS)
    assert plateau(r, range(3, 8)) == pytest.approx(9.0, rel=0.15)
    assert plateau(r, range(10, 16)) == pytest.approx(20.0, rel=0.15)
    assert plateau(r, range(19, 22)) == pytest.approx(9.0, rel=0.15)
    # The openings follow the sequence pair by pair: the G·C block's
    # openings all come above the A·T blocks' (after a 2-pair transition;
    # the last pairs open as the remaining stub lets go).
    at = [b["trap_force"] for b in r.breaks if 2 <= b["pair"] < 8 or 19 <= b["pair"] < 22]
    gc = [b["trap_force"] for b in r.breaks if 9 <= b["pair"] < 16]
    assert min(gc) > 1.8 * max(at)


def test_records_reach_disk_as_they_are_taken(tmp_path):
    prefix = str(tmp_path / "unzip")
    r = ex.unzip("GCGCGC", distance=4.0, out=prefix, frame_every=50, **QS)
    with open(prefix + ".csv") as f:
        rows = [row for row in csv.reader(line for line in f if not line.startswith("#"))]
    assert rows[0] == ["time_ns", "trap_nm", "extension_nm", "force_pN", "open_bp", "span_nm"]
    data = np.array(rows[1:], dtype=float)
    assert data.shape == (len(r.time), 6)
    assert np.allclose(data[:, 3], r.force, rtol=1e-8, atol=1e-8)
    assert set(r.paths) == {"csv", "pdb", "psf", "dcd"}
    import mdtraj as md
    t = md.load(r.paths["dcd"], top=r.paths["psf"])
    assert t.n_atoms == 12 and t.n_frames == 1 + len(r.time) // 5


def test_bad_input_is_refused():
    d = sk.dna.duplex("GATTACA")
    with pytest.raises(sk.InvalidInputError, match="unknown end"):
        ex.pull(d, held=["a5'"], pulled=["c3'"])
    with pytest.raises(sk.InvalidInputError, match="both held and pulled"):
        ex.pull(d, held=["a5'"], pulled=["a5'"])
    with pytest.raises(sk.InvalidInputError, match="speed"):
        ex.unzip(d, speed=0.0)
    with pytest.raises(sk.InvalidInputError, match="trap_stiffness"):
        ex.unzip(d, trap_stiffness=-1.0)
    with pytest.raises(sk.InvalidInputError, match="speed"):
        ex.unzip(d, speed=math.nan)
    with pytest.raises(sk.InvalidInputError, match="direction"):
        ex.pull(d, held=["a5'"], pulled=["b3'"], direction=(0, 0, 0))
    with pytest.raises(sk.InvalidInputError, match="steps"):
        ex.unzip(d, speed=1e-9)
    with pytest.raises(sk.InvalidInputError, match="sets"):
        ex.break_forces_for_unzipping(9.0, 20.0, break_forces=[1.0])
    with pytest.raises(sk.InvalidInputError, match="'axis'"):
        ex.pull(d, held=["a5'"], pulled=["b3'"], direction="up")
    with pytest.raises(sk.InvalidInputError, match="Duplex"):
        ex.pull("GATTACA", held=[], pulled=["a3'"])
    with pytest.raises(sk.InvalidInputError, match="position 3"):
        ex.unzip("GANT")


def test_force_clamp_and_ramp_unzip_block_by_block():
    # Zero temperature, calibrated bonds (A·T 9 pN, G·C 20 pN unzipping).
    # The end pair opens at its bond's own break force (no fork yet), so
    # a clamp below it opens nothing; above it, the A·T block unzips and
    # the G·C block (20 pN) stops the fork. A ramp opens the A·T block in
    # one avalanche at the end pair's force, then waits for the G·C block.
    fa, fg = ex.break_forces_for_unzipping(9.0, 20.0)
    d = sk.dna.duplex("ATATATAT" + "GCGCGCGC", break_force_at=fa, break_force_gc=fg)
    below = ex.force_clamp(d, 0.9 * fa, 40.0, viscosity=0.1, progress_bar=False)
    assert below.breaks == []
    between = ex.force_clamp(d, 16.0, 80.0, viscosity=0.1, progress_bar=False)
    assert [b["pair"] for b in between.breaks] == list(range(8))
    ramp = ex.force_ramp(d, rate=0.2, max_force=21.5, viscosity=0.1, progress_bar=False)
    at = [b["trap_force"] for b in ramp.breaks if b["pair"] < 8]
    gc = [b["trap_force"] for b in ramp.breaks if b["pair"] >= 8]
    assert len(at) == 8 and at[0] == pytest.approx(fa, rel=0.02) and max(at) - min(at) < 1.0
    assert gc and gc[0] == pytest.approx(20.0, rel=0.05)
    with pytest.raises(sk.InvalidInputError, match="geometry"):
        ex.force_clamp(d, 5.0, 1.0, geometry="twist")
    with pytest.raises(sk.InvalidInputError, match="force must be"):
        ex.force_clamp(d, -5.0, 1.0)
    with pytest.raises(sk.InvalidInputError, match="duration"):
        ex.pull(d, held=["a5'"], pulled=["b3'"], force=lambda t: 1.0)
    with pytest.raises(sk.InvalidInputError, match="finite"):
        ex.pull(d, held=["a5'"], pulled=["b3'"], force=lambda t: math.inf, duration=1.0)


def test_an_interrupted_run_keeps_its_records_on_disk(tmp_path):
    # The protocol raises KeyboardInterrupt 2 ns in (as Ctrl-C would): the
    # CSV holds every record taken before, and the trajectory reads.
    def force(t):
        if t > 2.005:  # asked for the step ending at 2.01 ns
            raise KeyboardInterrupt
        return 5.0

    prefix = str(tmp_path / "cut")
    with pytest.raises(KeyboardInterrupt):
        ex.pull(sk.dna.duplex("GATTACA"), held=["a5'"], pulled=["b3'"], force=force, duration=10.0, dt=0.01,
                record_every=10, frame_every=20, out=prefix, progress_bar=False)
    with open(prefix + ".csv") as f:
        rows = [l for l in f if not l.startswith(("#", "time"))]
    assert len(rows) == 21  # t = 0, 0.1, …, 2.0 ns
    assert float(rows[-1].split(",")[0]) == pytest.approx(2.0, abs=1e-9)
    import mdtraj as md
    assert md.load(prefix + ".dcd", top=prefix + ".psf").n_frames == 11


def test_a_trapped_free_duplex_with_noise_has_the_traps_equipartition():
    # A free 12 bp duplex held only by the two traps on its a3′ and b5′
    # ends (k each, static): the total trap force along z is 2k times its
    # end pair's centre displacement, and the centre is free apart from
    # the traps (trap energy k|δc|² + (k/4)|δb|², b the rung), so
    # var(F) = 2 k kT exactly at equilibrium. Measured 0.983 ± 0.080 of it
    # (10 blocks); the noise's drag, its random stream and the trapezoidal
    # rule's Gibbs-exact sampling are what this checks inside `pull`.
    kt = sk.units.kT(298.15, "molecular")
    k, steps, dt = 5.0, 10_000, 0.005
    d = sk.dna.duplex("GATTACAGATTA", break_forces=[math.inf] * 12)
    r = ex.pull(d, held=[], pulled=["a3'", "b5'"], direction=(0.0, 0.0, 1.0), speed=1e-6, distance=1e-6 * steps * dt,
                trap_stiffness=k, temperature=298.15, viscosity=0.1, dt=dt, record_every=1, progress_bar=False, seed=1)
    f = r.force[steps // 10:]
    assert float(np.var(f)) == pytest.approx(2 * k * kt, rel=0.2)


def test_noise_in_pull_is_seeded_and_off_at_zero_kelvin():
    d = sk.dna.duplex("GATTACAGATTA", break_forces=[math.inf] * 12)
    run = lambda **kw: ex.stretch(d, distance=0.02, speed=0.1, dt=0.005, viscosity=0.1, record_every=4,  # noqa: E731
                                  progress_bar=False, **kw).extension
    a, b, c = run(temperature=298.15, seed=3), run(temperature=298.15, seed=3), run(temperature=298.15, seed=4)
    cold = run()
    assert np.array_equal(a, b) and not np.array_equal(a, c)
    # The noise moves the ends by tenths of a nm; without it the slow pull
    # moves them by far less.
    assert np.std(np.diff(a)) > 20 * np.std(np.diff(cold))
    with pytest.raises(sk.InvalidInputError, match="break_averaging_time"):
        ex.stretch("GATTACAGATTA", temperature=298.15, progress_bar=False)
    for kw, what in ((dict(temperature=-1.0), "temperature"), (dict(temperature=math.nan), "temperature"),
                     (dict(seed=-1), "seed"), (dict(seed=1.5), "seed"), (dict(scheme="rk4"), "scheme")):
        with pytest.raises(sk.InvalidInputError, match=what):
            ex.stretch(d, progress_bar=False, **kw)


def test_brownian_pull_reaches_the_same_rest_and_is_seeded():
    # Overdamped dynamics: without noise a force clamp comes to the same rest
    # as with inertia (the static equilibrium of the pull); with noise a
    # seed replays its run. 12 bp stretched at 10 pN for 4 ns: 0.06972 and
    # 0.06971 nm, still creeping up by 1e-6 nm per record.
    d = sk.dna.duplex("GATTACAGATTA", break_forces=[math.inf] * 12, averaged_stacking=True)
    clamp = lambda duration=4.0, **kw: ex.force_clamp(d, 10.0, duration, geometry="stretch", dt=0.005,  # noqa: E731
                                                      viscosity=0.1, record_every=40, progress_bar=False, **kw)
    inertial, brownian = clamp(), clamp(brownian=True)
    # Different paths (with and without inertia), the same rest.
    assert np.abs(brownian.extension - inertial.extension).max() > 1e-3
    assert brownian.extension[-1] == pytest.approx(inertial.extension[-1], abs=1e-4)
    assert brownian.extension[-1] > 0.05
    a, b = (clamp(0.2, brownian=True, temperature=298.15, seed=2).extension for _ in range(2))
    assert np.array_equal(a, b) and np.std(a) > 0
    with pytest.raises(sk.InvalidInputError, match="brownian"):
        clamp(brownian="yes")
    with pytest.raises(sk.InvalidInputError, match="brownian"):
        sk.dna.fluctuations.thermal_elasticity("GATTACAGATTACAGATTAC", brownian=1, progress_bar=False)
