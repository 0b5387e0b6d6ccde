"""Overhead of a Python ``World.step()`` call versus the same step in Rust.

A 100-control-point rod (steel, clamped at one end, gravity, dynamic
steps). ``World._time_steps(n)`` runs n steps in a Rust loop inside the
extension (same binary, same world), so the difference is the cost of the
Python call: argument handling, GIL release/reacquire, the StepReport object.

    python python/benchmarks/step_overhead.py [--parallel]
"""
import argparse
import statistics
import time

import strandkit as sk


def make_world(n_ctrl: int, parallel: bool) -> sk.World:
    w = sk.World(dt=1e-3, gravity=(0, -9.81, 0), parallel=parallel)
    rod = w.add_rod(sk.straight((0, 0, 0), (4, 0, 0), section=0.05, material="carbon_steel",
                                n_control_points=n_ctrl))
    sk.clamp(w, rod)
    return w


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--n", type=int, default=100, help="control points")
    ap.add_argument("--steps", type=int, default=100)
    ap.add_argument("--repeats", type=int, default=40)
    ap.add_argument("--parallel", action="store_true", help="rayon assembly (default: serial)")
    a = ap.parse_args()
    py_w, rs_w = make_world(a.n, a.parallel), make_world(a.n, a.parallel)
    py_w._time_steps(50), rs_w._time_steps(50)  # warm up
    py, rs = [], []

    def python_block():
        t = time.perf_counter()
        for _ in range(a.steps):
            py_w.step()
        py.append((time.perf_counter() - t) / a.steps)

    def rust_block():
        rs.append(rs_w._time_steps(a.steps) / a.steps)

    # Alternate the order so that drifts in machine load hit both alike.
    for k in range(a.repeats):
        for f in (python_block, rust_block) if k % 2 == 0 else (rust_block, python_block):
            f()
    p, r = statistics.median(py), statistics.median(rs)
    ratio = statistics.median(x / y for x, y in zip(py, rs))
    print(f"{a.n} control points, parallel={a.parallel}: Python step {p * 1e6:.1f} µs, Rust step {r * 1e6:.1f} µs "
          f"(medians of {a.repeats} blocks of {a.steps} steps; minima {min(py) * 1e6:.1f} / {min(rs) * 1e6:.1f} µs); "
          f"overhead {100 * (ratio - 1):+.2f} % (median of paired block ratios), {100 * (min(py) / min(rs) - 1):+.2f} % (minima)")
    # Pure call cost: a trivial method on the same object.
    t = time.perf_counter()
    for _ in range(100000):
        py_w.time
    print(f"a trivial binding call (World.time): {(time.perf_counter() - t) / 1e5 * 1e9:.0f} ns")


if __name__ == "__main__":
    main()
