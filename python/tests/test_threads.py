"""Worlds and Python threads: World.step and QuasiDynamic.step release the
GIL, and a world that another thread is stepping answers with a
WorldBusyError (never pyo3's "Already borrowed")."""
import threading
import time

import pytest

import strandkit as sk

BUSY = "is being stepped in another thread"


def big_world(n=5000):
    """A clamped rod of n control points: a step takes ~20 ms at n = 5000,
    ~120 ms at n = 20000."""
    w = sk.World(gravity=(0, -9.81, 0), parallel=False)
    rod = w.add_rod(sk.straight((0, 0, 0), (10, 0, 0), n_control_points=n, section=0.01, material="nylon"))
    handles = sk.clamp(w, rod)
    return w, rod, handles


class Spinner:
    """A Python thread counting as fast as it can (it needs the GIL to count)."""

    def __init__(self):
        self.count, self.stop = 0, False
        self.thread = threading.Thread(target=self._spin, daemon=True)
        self.thread.start()

    def _spin(self):
        while not self.stop:
            self.count += 1

    def progress_during(self, f):
        """(counts while f runs, counts in the same time right after, alone)."""
        c0, t0 = self.count, time.perf_counter()
        f()
        dt = time.perf_counter() - t0
        c1 = self.count
        time.sleep(dt)
        return c1 - c0, self.count - c1

    def close(self):
        self.stop = True
        self.thread.join()


@pytest.mark.parametrize("clock", ["wall", "python"])
def test_quasidynamic_step_releases_the_gil(clock):
    # Long frames: between two of them the GIL changes hands anyway (the
    # 5 ms switch interval), which would blur the contrast for short ones.
    w, _, _ = big_world(20000)
    qd = sk.QuasiDynamic(w, dt0=1e-3, time_budget=10.0)
    qd.step()
    # A Python clock is called with the GIL taken back for the call only.
    step = qd.step if clock == "wall" else (lambda: qd.step(clock=time.perf_counter))
    spinner = Spinner()
    try:
        time.sleep(0.05)
        during, alone = spinner.progress_during(lambda: [step() for _ in range(3)])
    finally:
        spinner.close()
    # Holding the GIL, the frames left the spinner ~5 % of its rate; released, ~100 %.
    assert during > 0.3 * alone, (during, alone)
    assert w.n_steps == 4 and qd.mode == "dynamic"


def test_world_step_releases_the_gil():
    w, _, _ = big_world(20000)
    w.step()
    spinner = Spinner()
    try:
        time.sleep(0.05)
        during, alone = spinner.progress_during(lambda: [w.step() for _ in range(3)])
    finally:
        spinner.close()
    assert during > 0.3 * alone, (during, alone)


def _accessors(w, rod, handle, qd):
    """Every kind of access to a world, its rods, handles and driver."""
    return {
        "World.time": lambda: w.time,
        "World.n_steps": lambda: w.n_steps,
        "World.dt": lambda: w.dt,
        "World.dt=": lambda: setattr(w, "dt", 1e-3),
        "World.gravity": lambda: w.gravity,
        "World.gravity=": lambda: setattr(w, "gravity", (0, -9.81, 0)),
        "World.params": lambda: w.params,
        "World.set_params": lambda: w.set_params(dt=1e-3),
        "World.n_rods": lambda: w.n_rods,
        "World.n_constraints": lambda: w.n_constraints,
        "World.groups": lambda: w.groups,
        "World.rods": lambda: w.rods(),
        "World.constraints": lambda: w.constraints(),
        "World.loads": lambda: w.loads(),
        "World.step": lambda: w.step(),
        "World.relax": lambda: w.relax(),
        "World.to_json": lambda: w.to_json(),
        "World.copy": lambda: w.copy(),
        "World.reaction": lambda: w.reaction(handle),
        "World.add_load": lambda: w.add_load(sk.point_force(rod, 0.5, (0, 0, 0))),
        "Rod.control_points": lambda: rod.control_points,
        "Rod.control_points=": lambda: setattr(rod, "control_points", rod.control_points),
        "Rod.position": lambda: rod.position(0.0),
        "Rod.label": lambda: rod.label,
        "ConstraintHandle.alive": lambda: handle.alive,
        "ConstraintHandle.kind": lambda: handle.kind,
        "ConstraintHandle.reaction": lambda: handle.reaction(),
        "bead_positions": lambda: sk.bead_positions(w),
        "QuasiDynamic.mode": lambda: qd.mode,
        "QuasiDynamic.params": lambda: qd.params,
        "QuasiDynamic.step": lambda: qd.step(),
    }


def test_every_access_during_a_step_in_another_thread_is_a_busy_error():
    """Deterministic: the stepping thread is held inside its frame (its
    Python clock waits) while this thread tries every access."""
    w, rod, (handle, *_) = big_world(n=50)
    qd = sk.QuasiDynamic(w, dt0=1e-3, time_budget=10.0)
    inside, resume = threading.Event(), threading.Event()

    def clock():
        if not inside.is_set():
            inside.set()
            resume.wait(30)
        return time.perf_counter()

    result = {}
    stepper = threading.Thread(target=lambda: result.setdefault("frame", qd.step(clock=clock)))
    stepper.start()
    assert inside.wait(30)
    try:
        errors = {}
        for name, f in _accessors(w, rod, handle, qd).items():
            with pytest.raises(sk.WorldBusyError, match=BUSY) as e:
                f()
            errors[name] = e.value
        # Reprs never raise; they say the world is busy.
        assert "another thread" in repr(w) and "another thread" in repr(qd)
    finally:
        resume.set()
        stepper.join(30)
    assert result["frame"].mode == "dynamic" and w.n_steps == 1
    assert all(isinstance(e, RuntimeError) and isinstance(e, sk.StrandkitError) for e in errors.values())
    assert "world" in str(errors["World.time"]) and "QuasiDynamic" in str(errors["QuasiDynamic.mode"])
    # Once the step is over, every access works again.
    for name, f in _accessors(w, rod, handle, qd).items():
        f()


def test_racing_threads_get_results_or_busy_errors_only():
    """One thread steps a big world in a loop while this one reads it and
    steps it too: each call succeeds or raises WorldBusyError."""
    w, rod, (handle, *_) = big_world()
    qd = sk.QuasiDynamic(w, dt0=1e-3, time_budget=10.0)
    stop, outcomes = threading.Event(), {"stepper": [], "main": []}

    def record(who, f):
        try:
            f()
            outcomes[who].append("ok")
        except sk.WorldBusyError as e:
            assert BUSY in str(e)
            outcomes[who].append("busy")
        except Exception as e:  # noqa: BLE001 (any other error fails the test below)
            outcomes[who].append(f"{type(e).__name__}: {e}")

    def loop():
        while not stop.is_set():
            record("stepper", w.step)

    t = threading.Thread(target=loop)
    t.start()
    try:
        deadline = time.perf_counter() + 1.5
        accessors = list(_accessors(w, rod, handle, qd).values())
        k = 0
        while time.perf_counter() < deadline:
            record("main", accessors[k % len(accessors)])
            k += 1
    finally:
        stop.set()
        t.join(30)
    other = [o for who in outcomes for o in outcomes[who] if o not in ("ok", "busy")]
    assert not other, other[:5]
    assert "busy" in outcomes["main"] and outcomes["stepper"].count("ok") > 5
