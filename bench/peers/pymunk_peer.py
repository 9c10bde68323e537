#!/usr/bin/env python3
"""pymunk on carom's benchmark scene, in carom bench's units.

pymunk (https://www.pymunk.org, `pip install pymunk`) wraps the Chipmunk2D
engine, a 2D physics library people pick for games. This script takes the
very particles `carom run` starts from (same N, packing, radius, speed, seed),
puts them in a box of four static walls, makes the contacts elastic and
frictionless, and times space.step(dt): the median ms per step over several
samples after a warm-up (5 steps, then doubling batches until one lasts
0.1 s, which sets the steps a sample), as particle-steps per second. With --carom-bench it
also runs `carom bench --methods cpu` on the same scene (under --collisions,
the simultaneous scheme unless given), in the same run, and prints the ratio.
With --carom-python it also times carom's Python API (`import carom`) on the
same scene: a carom.World on the CPU engine with carom.make_scene's disks,
world.step(n) timed the way pymunk's steps are (a warm-up of 5 steps, batches
of 1, 2, 4, ... steps until one lasts 0.1 s to find the speed, then samples
of n steps lasting about --sample-seconds each; the median ms per step); its
samples alternate with pymunk's, so that drift in the machine's speed falls on
both, and it prints the ratio carom-python / pymunk with the machine, N and
samples. Without --carom the scene comes from carom.make_scene (the same disks
as `carom run`; with both, the script checks that they agree).

Chipmunk is an iterative impulse solver with its own contact model, so its
trajectories differ from carom's: this compares the cost of a step of the
same scene, not the physics.

    bench/peers/pymunk_peer.py --carom build/carom --particles 10000 --carom-bench
    bench/peers/pymunk_peer.py --carom build/carom --particles 10000 --carom-python --carom-bench
    bench/peers/pymunk_peer.py --carom build/carom --particles 10000 --packing 0.3 --collisions pairwise \
        --carom-bench --busy-loops 1    # both beside one busy process
"""
import argparse
import json
import os
import platform
import statistics
import struct
import subprocess
import sys
import tempfile
import time

try:
    import pymunk
except ImportError:
    sys.exit("pymunk_peer: pymunk is not installed; run: python3 -m pip install pymunk")
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), os.pardir))
from machine import machine  # noqa: E402  (bench/machine.py)

try:
    import carom  # carom's Python API (pip install . from the repository): --carom-python
    carom_import_error = None
except ImportError as error:
    carom, carom_import_error = None, error


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


def python_scene(args):
    """The same particles from carom's Python API (carom.make_scene), as (width, height, particles)."""
    scene = carom.make_scene(particles=args.particles, packing=args.packing, radius=args.radius, speed=args.speed,
                             seed=args.seed)
    columns = [scene.positions[:, 0], scene.positions[:, 1], scene.velocities[:, 0], scene.velocities[:, 1],
               scene.masses, scene.radii]
    particles = [tuple(float(v) for v in row) for row in zip(*(c.tolist() for c in columns))]
    return float(scene.box[0]), float(scene.box[1]), particles, scene


def cpu_seconds():
    """(busy CPU seconds of the whole machine, this process's and its children's): Linux /proc/stat."""
    t = os.times()
    own = t.user + t.system + t.children_user + t.children_system
    try:
        with open("/proc/stat") as f:
            fields = [int(v) for v in f.readline().split()[1:]]
    except (OSError, ValueError):
        return None, own
    idle = fields[3] + (fields[4] if len(fields) > 4 else 0)
    guest = sum(fields[8:10]) if len(fields) > 9 else 0
    return (sum(fields) - idle - guest) / os.sysconf("SC_CLK_TCK"), own


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


def steps_per_sample(timed, sample_seconds):
    """Warms up (5 steps), then times batches of 1, 2, 4, ... steps until one lasts 0.1 s (or the sample's
    length): the steps a sample of `sample_seconds` takes at that speed. `timed(n)` steps n times and returns
    the seconds per step."""
    timed(5)
    batch = 1
    while True:
        per_step = timed(batch)
        if per_step * batch >= min(0.1, sample_seconds):
            return max(1, round(sample_seconds / per_step))
        batch *= 2


def carom_world(args, scene):
    world = carom.World(box=scene.box, dt=args.dt, collisions=args.collisions, engine="cpu")
    world.set_disks(scene.positions, scene.velocities, scene.masses, scene.radii)
    return world


def time_world_steps(world, steps):
    start = time.perf_counter()
    world.step(steps)
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
    parser.add_argument("--carom", help="the carom binary (makes the scene; needed by --carom-bench; without it "
                                        "the scene comes from carom.make_scene)")
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
    parser.add_argument("--carom-python", action="store_true",
                        help="also time carom's Python API (carom.World, CPU engine) on the same scene, its samples "
                             "alternating with pymunk's, and print the ratio")
    parser.add_argument("--collisions", choices=["simultaneous", "pairwise"], default="simultaneous",
                        help="carom's collision scheme for --carom-bench and --carom-python")
    parser.add_argument("--busy-loops", type=int, default=0,
                        help="keep this many other processes busy (shell loops) while pymunk and carom are timed, "
                             "as bench/under_load.sh does: the figures under load")
    parser.add_argument("--json", help="write the result as JSON to this file")
    args = parser.parse_args()
    if args.carom_bench and not args.carom:
        parser.error("--carom-bench needs --carom (the carom binary)")
    if (args.carom_python or not args.carom) and carom is None:
        parser.error("cannot import carom" + (" (--carom-python)" if args.carom_python else
                                              "; give --carom to make the scene with the binary") +
                     f": {carom_import_error}")

    loops = [subprocess.Popen(["sh", "-c", "while :; do :; done"]) for _ in range(max(0, args.busy_loops))]
    try:
        result = measure(args, len(loops))
    finally:
        for loop in loops:
            loop.kill()
            loop.wait()
    if args.json:
        with open(args.json, "w") as f:
            json.dump(result, f, indent=2)
            f.write("\n")


def measure(args, busy_loops):
    with tempfile.TemporaryDirectory() as workdir:
        scene = None
        if args.carom:
            width, height, particles = carom_scene(args, workdir)
            if carom is not None and args.carom_python:
                _, _, same, scene = python_scene(args)
                # The CSV holds the engine's float32 numbers printed shortest: equal when read back as float32.
                if (struct.pack("2f", width, height) != struct.pack("2f", *scene.box) or len(same) != len(particles) or
                        any(struct.pack("6f", *a) != struct.pack("6f", *b) for a, b in zip(particles, same))):
                    sys.exit("pymunk_peer: carom.make_scene and `carom run` disagree on the scene")
        else:
            width, height, particles, scene = python_scene(args)
        space = pymunk_space(width, height, particles, args.index)
        world = carom_world(args, scene) if args.carom_python else None
        steps = steps_per_sample(lambda n: time_steps(space, args.dt, n), args.sample_seconds)
        if world is not None:
            world_steps = steps_per_sample(lambda n: time_world_steps(world, n), args.sample_seconds)
            world_warmup = world.step_count
        samples, world_samples = [], []
        (busy, own), began = cpu_seconds(), time.perf_counter()
        for _ in range(args.samples):  # pymunk's and carom's samples alternate
            samples.append(time_steps(space, args.dt, steps))
            if world is not None:
                world_samples.append(time_world_steps(world, world_steps))
        (busy_end, own_end), wall = cpu_seconds(), time.perf_counter() - began
        # The share of the machine's CPU time that other processes took while the samples ran.
        other_load = (None if busy is None else
                      max(0.0, (busy_end - busy) - (own_end - own)) / (wall * (os.cpu_count() or 1)))
        carom_bench = carom_cpu_bench(args, workdir) if args.carom_bench else None

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
        "scene_from": "carom run" if args.carom else "carom.make_scene",
        "machine": machine(),
        "other_processes_load_during_samples": other_load,
        "busy_loops": busy_loops,
        "date": time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime()),
    }
    m = result["machine"]
    print(f"{result['date']}, {m['cpu']}, {m['cores']} cores, OMP_NUM_THREADS={m['omp_num_threads'] or 'unset'}, "
          f"load average {m['load_average_1min']}, Python {result['python']}; other processes took "
          + ("?" if other_load is None else f"{100 * other_load:.0f} %") + " of the machine during the samples"
          + (f" ({busy_loops} busy loops of this script among them)" if busy_loops else ""))
    print(f"pymunk {pymunk.version} ({args.index}), N = {args.particles}: {seconds * 1e3:.4g} ms/step, "
          f"{args.particles / seconds:.3g} particle-steps/s (median of {args.samples} samples of {steps} steps)")
    if world is not None:
        world_seconds = statistics.median(world_samples)
        result["carom_python"] = {
            "carom": getattr(carom, "__version__", None),
            "engine": "cpu",
            "scheme": args.collisions,
            "ms_per_step": world_seconds * 1e3,
            "sample_ms_per_step": [s * 1e3 for s in world_samples],
            "steps_per_sample": world_steps,
            "warmup_steps": world_warmup,
            "particle_steps_per_second": args.particles / world_seconds,
            "step_count": world.step_count,
        }
        result["carom_python_over_pymunk"] = seconds / world_seconds
        # Each pymunk sample against the carom sample right after it: how far the machine's drift moves the ratio.
        pairs = sorted(p / c for p, c in zip(samples, world_samples))
        result["carom_python_over_pymunk_per_sample_pair"] = {"median": statistics.median(pairs),
                                                              "min": pairs[0], "max": pairs[-1]}
        print(f"carom python (carom.World.step, cpu, {args.collisions}), N = {args.particles}: "
              f"{world_seconds * 1e3:.4g} ms/step, {args.particles / world_seconds:.3g} particle-steps/s "
              f"(median of {args.samples} samples of world.step({world_steps}), alternating with pymunk's)")
        print(f"carom python / pymunk = {result['carom_python_over_pymunk']:.1f}x at N = {args.particles} "
              f"(ratio of the medians; per sample pair: median {statistics.median(pairs):.1f}x, "
              f"{pairs[0]:.1f}x to {pairs[-1]:.1f}x); issue 14's target: >= 10x at N = 10^4")
    if carom_bench:
        result["carom_cpu"] = carom_bench
        result["carom_cpu_over_pymunk"] = (carom_bench["particle_steps_per_second"] /
                                           result["particle_steps_per_second"])
        print(f"carom cpu ({carom_bench['scheme']}, carom bench), N = {args.particles}: "
              f"{carom_bench['ms_per_step']:.4g} ms/step, "
              f"{carom_bench['particle_steps_per_second']:.3g} particle-steps/s: "
              f"{result['carom_cpu_over_pymunk']:.1f}x pymunk")
    return result


if __name__ == "__main__":
    main()
