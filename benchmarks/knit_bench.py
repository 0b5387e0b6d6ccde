"""Knit step cost (BENCHMARKS §24): plain jersey swatches of n × n
stitches (0.1 mm nylon, loop length 5 mm, one continuous yarn), built,
then overdamped steps of the relaxation flow (fixed dt, frictionless and
μ = 0.3; above 20 × 20 frictionless only) timed after 3 warm-up steps. Prints, per size: build time, the
system's unknowns, the factorisation the step used, ms per step and µs per
loop and step.

    python benchmarks/knit_bench.py [sizes...]     # default: 10 20 50
"""
import sys
import time

import strandkit as sk


def bench(n, friction, steps):
    t = time.perf_counter()
    f = sk.knit.fabric("jersey", wales=n, courses=n)
    built = time.perf_counter() - t
    # Fixed steps, no reach guard: a step of 3e-8 s moves the as-built
    # yarn farther than the contact margin, which Fabric.world's guard
    # (max_move) refuses; relax would shorten it.
    w = f.world(friction=friction, overdamped=True, viscosity=1.0, dt=3e-8, max_move=None)
    for _ in range(3):
        rep = w.step()
    t = time.perf_counter()
    for _ in range(steps):
        rep = w.step()
    per = (time.perf_counter() - t) / steps
    print(f"{n:3d} × {n:<3d} μ={friction:<4} build {built:7.2f} s  unknowns {rep.n_unknowns:7d} "
          f"multipliers {rep.n_multipliers:6d}  {rep.factorisation:>10s}  {per * 1e3:9.1f} ms/step  "
          f"{per / (n * n) * 1e6:8.1f} µs/loop/step", flush=True)


def main():
    sizes = [int(a) for a in sys.argv[1:]] or [10, 20, 50]
    for n in sizes:
        for mu in (0.0, 0.3) if n <= 20 else (0.0,):
            bench(n, mu, steps=10 if n <= 20 else 3)


if __name__ == "__main__":
    main()
