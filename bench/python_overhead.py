#!/usr/bin/env python3
"""What carom's Python API costs over its C++ API (issue 14's targets).

1. world.step(n) through Python against the same steps through the C++ API:
   on one carom.World (N = 10^4 by default, the CPU engine, carom bench's
   scene), turns of n steps alternate between world.step(n), timed here
   around the Python call, and carom::World::step(n) called and timed inside
   the extension (`_cpp_step_seconds`, which nothing else uses). Both step
   the same world along the same trajectory, so the two sides see the same
   disks, memory and machine; the order within a pair alternates. The
   overhead is the median over the pairs of a pair's Python turn over its
   C++ turn, minus one: the two turns of a pair are milliseconds apart, so
   the machine's slow and fast phases (seconds long, on a shared VM)
   cancel, which they do not in the ratio of the two medians (also printed).
2. Reading world.positions at N = 10^6 on the CPU engine: the time a read
   takes, whether two reads share memory, and what a copy costs.

    bench/python_overhead.py                       # both, the figures of the README
    bench/python_overhead.py --pairs 400 --json overhead.json
"""
import argparse
import json
import statistics
import time

import numpy as np

import carom
from machine import machine  # bench/machine.py


def world_of(particles, packing, collisions):
    scene = carom.make_scene(particles=particles, packing=packing, seed=1)
    world = carom.World(box=scene.box, collisions=collisions, engine="cpu")
    world.set_disks(scene.positions, scene.velocities, scene.masses, scene.radii)
    return world


def python_turn(world, n):
    start = time.perf_counter()
    world.step(n)
    return time.perf_counter() - start


def step_overhead(args):
    world = world_of(args.particles, args.packing, args.collisions)
    world.step(args.warmup)
    python, cpp = [], []
    for pair in range(args.pairs):
        if pair % 2 == 0:
            python.append(python_turn(world, args.n))
            cpp.append(world._core._cpp_step_seconds(args.n))
        else:
            cpp.append(world._core._cpp_step_seconds(args.n))
            python.append(python_turn(world, args.n))
    per_step = [statistics.median(turns) / args.n * 1e3 for turns in (python, cpp)]
    quartiles = statistics.quantiles([p / c for p, c in zip(python, cpp)], n=4)
    return {"particles": args.particles, "packing": args.packing, "scheme": args.collisions, "n": args.n,
            "pairs": args.pairs, "python_ms_per_step": per_step[0], "cpp_ms_per_step": per_step[1],
            "overhead_percent": 100 * (quartiles[1] - 1), "pair_ratio_quartiles": quartiles,
            "ratio_of_medians_percent": 100 * (per_step[0] / per_step[1] - 1)}


def positions_read(particles):
    world = world_of(particles, 0.3, "pairwise")
    reads = []
    for _ in range(1000):
        start = time.perf_counter()
        positions = world.positions
        reads.append(time.perf_counter() - start)
    copies = []
    for _ in range(20):
        start = time.perf_counter()
        np.array(positions)
        copies.append(time.perf_counter() - start)
    return {"particles": particles, "read_us": statistics.median(reads) * 1e6,
            "copy_us": statistics.median(copies) * 1e6,
            "shares_memory": bool(np.shares_memory(positions, world.positions)),
            "owns_data": bool(positions.flags.owndata), "strides": positions.strides}


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--particles", type=int, default=10_000)
    parser.add_argument("--packing", type=float, default=0.5)
    parser.add_argument("--collisions", choices=["pairwise", "simultaneous"], default="pairwise")
    parser.add_argument("--n", type=int, default=100, help="steps a turn (issue 14: n >= 100)")
    parser.add_argument("--pairs", type=int, default=200)
    parser.add_argument("--warmup", type=int, default=200)
    parser.add_argument("--read-particles", type=int, default=1_000_000)
    parser.add_argument("--json", help="write the results as JSON to this file")
    args = parser.parse_args()

    result = {"date": time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime()),
              "machine": {**machine(), "numpy": np.__version__, "carom": carom.__version__},
              "step": step_overhead(args), "positions": positions_read(args.read_particles)}
    m, s, p = result["machine"], result["step"], result["positions"]
    print(f"{result['date']}, {m['cpu']}, {m['cores']} cores, OMP_NUM_THREADS={m['omp_num_threads'] or 'unset'}, "
          f"Python {m['python']}, carom {m['carom']}")
    print(f"world.step({s['n']}), N = {s['particles']}, eta {s['packing']}, {s['scheme']}, CPU: Python "
          f"{s['python_ms_per_step']:.4f} ms/step, C++ {s['cpp_ms_per_step']:.4f} ms/step (medians of {s['pairs']} "
          f"alternating turns): overhead {s['overhead_percent']:+.2f} % (median of the pairs' ratios; quartiles "
          + ", ".join(f"{q:.3f}" for q in s["pair_ratio_quartiles"])
          + f"; ratio of the medians {s['ratio_of_medians_percent']:+.2f} %)")
    print(f"world.positions, N = {p['particles']}, CPU: a read {p['read_us']:.2f} us, a copy {p['copy_us']:.0f} us; "
          f"two reads share memory: {p['shares_memory']}; owns its data: {p['owns_data']}; strides {p['strides']}")
    if args.json:
        with open(args.json, "w") as f:
            json.dump(result, f, indent=2)


if __name__ == "__main__":
    main()
