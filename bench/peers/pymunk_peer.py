#!/usr/bin/env python3
"""pymunk on carom's benchmark scene, in carom bench's units.

pymunk (https://www.pymunk.org, `pip install pymunk`) wraps the Chipmunk2D
engine, a 2D physics library people pick for games. This script takes the
very particles `carom run` starts from (same N, packing, radius, speed, seed),
puts them in a box of four static walls, makes the contacts elastic and
frictionless, and times space.step(dt): the median ms per step over several
samples after a warm-up, as particle-steps per second. With --carom-bench it
also runs `carom bench --methods cpu` on the same scene (under --collisions,
the simultaneous scheme unless given), in the same run, and prints the ratio.

Chipmunk is an iterative impulse solver with its own contact model, so its
trajectories differ from carom's: this compares the cost of a step of the
same scene, not the physics.

    bench/peers/pymunk_peer.py --carom build/carom --particles 10000 --carom-bench
"""
import argparse
import json
import os
import platform
import statistics
import subprocess
import sys
import tempfile
import time

try:
    import pymunk
except ImportError:
    sys.exit("pymunk_peer: pymunk is not installed; run: python3 -m pip install pymunk")


def positive(kind):
    def parse(text):
        value = kind(float(text)) if kind is int else kind(text)
        if not value > 0:
            raise argparse.ArgumentTypeError(f"must be > 0, got {text}")
        return value
    return parse


def carom_scene(args, workdir):
    """The initial particles and box of carom's scene, from `carom run --steps 0`."""
    state = os.path.join(workdir, "scene.csv")
    command = [args.carom, "run", "--backend", "cpu", "--particles", str(args.particles),
               "--packing", str(args.packing), "--radius", str(args.radius), "--speed", str(args.speed),
               "--seed", str(args.seed), "--dt", str(args.dt), "--steps", "0", "--output-state", state, "--json"]
    run = subprocess.run(command, capture_output=True, text=True)
    if run.returncode != 0:
        sys.exit(f"pymunk_peer: {' '.join(command)} failed:\n{run.stderr}")
    width, height = json.loads(run.stdout)["box"]
    with open(state) as f:
        next(f)  # header id,x,y,vx,vy,mass,radius
        particles = [tuple(float(v) for v in line.split(",")[1:]) for line in f]
    return width, height, particles


def pymunk_space(width, height, particles, index):
    space = pymunk.Space()
    space.gravity = (0.0, 0.0)
    corners = [(0, 0), (width, 0), (width, height), (0, height)]
    for a, b in zip(corners, corners[1:] + corners[:1]):
        wall = pymunk.Segment(space.static_body, a, b, 0.0)
        wall.elasticity, wall.friction = 1.0, 0.0
        space.add(wall)
    largest = max(p[5] for p in particles)
    if index == "hash":  # Chipmunk's suggestion for many objects of one size
        space.use_spatial_hash(2 * largest, len(particles))
    for x, y, vx, vy, mass, radius in particles:
        body = pymunk.Body(mass, pymunk.moment_for_circle(mass, 0, radius))
        body.position, body.velocity = (x, y), (vx, vy)
        disk = pymunk.Circle(body, radius)
        disk.elasticity, disk.friction = 1.0, 0.0
        space.add(body, disk)
    return space


def time_steps(space, dt, steps):
    start = time.perf_counter()
    for _ in range(steps):
        space.step(dt)
    return (time.perf_counter() - start) / steps


def carom_cpu_bench(args, workdir):
    results = os.path.join(workdir, "carom.json")
    command = [args.carom, "bench", "--methods", "cpu", "--sizes", str(args.particles), "--packing",
               str(args.packing), "--radius", str(args.radius), "--speed", str(args.speed), "--seed",
               str(args.seed), "--dt", str(args.dt), "--samples", str(args.samples), "--collisions",
               args.collisions, "--json", results]
    run = subprocess.run(command, capture_output=True, text=True)
    if run.returncode != 0:
        sys.exit(f"pymunk_peer: {' '.join(command)} failed:\n{run.stderr}")
    with open(results) as f:
        return json.load(f)["results"][0]


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--carom", required=True, help="the carom binary (makes the scene)")
    parser.add_argument("--particles", type=positive(int), default=10000)
    parser.add_argument("--packing", type=positive(float), default=0.5)
    parser.add_argument("--radius", type=positive(float), default=1.0)
    parser.add_argument("--speed", type=float, default=1.0)
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--dt", type=positive(float), default=0.01)
    parser.add_argument("--index", choices=["bbtree", "hash"], default="bbtree",
                        help="Chipmunk's broad phase: bounding-box tree (its default) or spatial hash")
    parser.add_argument("--samples", type=positive(int), default=7)
    parser.add_argument("--sample-seconds", type=positive(float), default=1.0)
    parser.add_argument("--carom-bench", action="store_true",
                        help="also time carom's CPU backend on the same scene and print the ratio")
    parser.add_argument("--collisions", choices=["simultaneous", "pairwise"], default="simultaneous",
                        help="carom's collision scheme for --carom-bench")
    parser.add_argument("--json", help="write the result as JSON to this file")
    args = parser.parse_args()

    with tempfile.TemporaryDirectory() as workdir:
        width, height, particles = carom_scene(args, workdir)
        space = pymunk_space(width, height, particles, args.index)
        warm = time_steps(space, args.dt, 5)
        steps = max(1, round(args.sample_seconds / warm))
        samples = [time_steps(space, args.dt, steps) for _ in range(args.samples)]
        carom = carom_cpu_bench(args, workdir) if args.carom_bench else None

    seconds = statistics.median(samples)
    result = {
        "method": f"pymunk-{args.index}",
        "pymunk": pymunk.version,
        "chipmunk": pymunk.chipmunk_version,
        "python": platform.python_version(),
        "particles": args.particles,
        "box": [width, height],
        "scene": {"packing": args.packing, "radius": args.radius, "speed": args.speed, "seed": args.seed,
                  "dt": args.dt},
        "ms_per_step": seconds * 1e3,
        "sample_ms_per_step": [s * 1e3 for s in samples],
        "steps_per_sample": steps,
        "particle_steps_per_second": args.particles / seconds,
    }
    print(f"pymunk {pymunk.version} ({args.index}), N = {args.particles}: {seconds * 1e3:.4g} ms/step, "
          f"{args.particles / seconds:.3g} particle-steps/s (median of {args.samples})")
    if carom:
        result["carom_cpu"] = carom
        result["carom_cpu_over_pymunk"] = carom["particle_steps_per_second"] / result["particle_steps_per_second"]
        print(f"carom cpu ({carom['scheme']}), N = {args.particles}: {carom['ms_per_step']:.4g} ms/step, "
              f"{carom['particle_steps_per_second']:.3g} particle-steps/s: "
              f"{result['carom_cpu_over_pymunk']:.1f}x pymunk")
    if args.json:
        with open(args.json, "w") as f:
            json.dump(result, f, indent=2)
            f.write("\n")


if __name__ == "__main__":
    main()
