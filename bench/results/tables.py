#!/usr/bin/env python3
"""Writes bench/results/README.md: a Markdown table of every result file here.

    python3 bench/results/tables.py            # rewrites bench/results/README.md
    python3 bench/results/tables.py --stdout   # prints it instead

Reads the JSON that `carom bench --json FILE` writes (one run, or a list of
runs) and that bench/peers/pymunk_peer.py writes (pymunk against carom's CPU
backend), and states for each file the machine, the date, the command and the
samples. Standard library only. A test checks that the committed README.md
is what this script writes now.

Files written before the pipelines were renamed call the host-grid pipeline
`opencl-seed`; the tables use its name now, `opencl-host-grid`.
"""
import json
import math
import pathlib
import sys

HERE = pathlib.Path(__file__).resolve().parent
OLD_NAMES = {"opencl-seed": "opencl-host-grid"}
METHOD_ORDER = ["naive-cpu", "naive-opencl", "cpu", "opencl-host-grid", "opencl-resident", "events"]
SCHEME_ORDER = ["simultaneous", "pairwise", "events"]
SUPERSCRIPT = str.maketrans("-0123456789", "⁻⁰¹²³⁴⁵⁶⁷⁸⁹")
BENCH_DEFAULTS = {"packing": 0.5, "radius": 1.0, "speed": 1.0, "seed": 1, "dt": 0.01}


def sci(x, digits=3):
    """1.55·10⁷: `digits` significant figures, the exponent as a superscript."""
    if x is None:
        return "–"
    if x == 0:
        return "0"
    exponent = math.floor(math.log10(abs(x)))
    mantissa = round(x / 10**exponent, digits - 1)
    if abs(mantissa) >= 10:
        mantissa, exponent = mantissa / 10, exponent + 1
    text = f"{mantissa:.{digits - 1}f}".rstrip("0").rstrip(".")
    if exponent == 0:
        return text
    if text == "1":
        return f"10{str(exponent).translate(SUPERSCRIPT)}"
    return f"{text}·10{str(exponent).translate(SUPERSCRIPT)}"


def count(n):
    """1000 -> 10³, 16000000 -> 1.6·10⁷: particle counts as the docs write them."""
    return sci(n, 2) if n >= 1000 else str(n)


def fixed(x, digits=4):
    return "–" if x is None else f"{x:.{digits}g}"


def ratio(x):
    return "–" if x is None else f"{x:.2f}×"


def method_name(name):
    return OLD_NAMES.get(name, name)


def row_key(row):
    method = method_name(row["method"])
    scheme = row.get("scheme") or "simultaneous"
    return (row["particles"], METHOD_ORDER.index(method) if method in METHOD_ORDER else len(METHOD_ORDER),
            method, SCHEME_ORDER.index(scheme) if scheme in SCHEME_ORDER else len(SCHEME_ORDER))


def bench_command(run):
    """The `carom bench` command that the run's recorded settings give."""
    rows = run["results"]
    methods = []
    schemes = []
    for row in sorted(rows, key=row_key):
        if method_name(row["method"]) not in methods:
            methods.append(method_name(row["method"]))
    for row in rows:
        scheme = row.get("scheme")
        if scheme and scheme not in schemes:
            schemes.append(scheme)
    schemes.sort(key=lambda s: SCHEME_ORDER.index(s) if s in SCHEME_ORDER else len(SCHEME_ORDER))
    sizes = sorted({row["particles"] for row in rows})
    words = ["carom bench"]
    if run.get("opencl_device"):
        words.append(f"--device '{run['opencl_device']['name']}'")
    words.append("--methods " + ",".join(methods))
    if schemes:
        words.append("--collisions " + ",".join(schemes))
    words.append("--sizes " + ",".join(size_option(n) for n in sizes))
    scene = run.get("scene", {})
    for key, default in BENCH_DEFAULTS.items():
        value = scene.get(key, default)
        if not math.isclose(value, default, rel_tol=1e-6):
            words.append(f"--{key} {value:g}")
    timing = run.get("timing", {})
    words.append(f"--samples {timing.get('samples', 7)}")
    if timing.get("budget_ms_per_step", 1000.0) != 1000.0:
        words.append(f"--budget-ms {timing['budget_ms_per_step']:g}")
    if any("profile_ms_per_step" in row for row in rows):
        words.append("--profile")
    return " ".join(words)


def size_option(n):
    """1000 -> 1e3, 16000000 -> 1.6e7, as --sizes takes them."""
    if n < 1000:
        return str(n)
    mantissa, exponent = f"{n:e}".split("e")
    return f"{mantissa.rstrip('0').rstrip('.')}e{int(exponent)}"


def machine(run):
    host = run["host"]
    text = f"{host['cpu']}, {host['threads']} threads (load average {host['load_average_1min']:g} at the start)"
    device = run.get("opencl_device")
    if device:
        text += f"; OpenCL device {device['name']} ({device['platform']}, driver {device['driver']})"
    bandwidth = run.get("bandwidth_bytes_per_second", {})
    copies = [f"{label} {bandwidth[key] / 1e9:.1f} GB/s" for key, label in
              (("host_copy", "host copy"), ("device_copy", "device copy")) if bandwidth.get(key)]
    if copies:
        text += "; measured " + ", ".join(copies)
    return text


def bench_section(lines, run):
    timing = run.get("timing", {})
    lines.append(f"- machine: {machine(run)}")
    lines.append(f"- date: {run['date']}")
    lines.append(f"- command: `{bench_command(run)}`")
    lines.append(f"- samples: {timing.get('samples')} per method, scheme and N, each of whole steps lasting "
                 f"{timing.get('sample_seconds', 0.1):g} s after {timing.get('warmup_seconds', 0.2):g} s of "
                 f"warm-up; each figure is the median")
    lines.append("")
    stepped = [row for row in run["results"] if "ms_per_step" in row]
    events = [row for row in run["results"] if "collisions_per_second" in row]
    if stepped:
        lines.append("| N | method | scheme | ms/step | particle-steps/s | pw/sim | vs host-grid | of floor |")
        lines.append("|---:|---|---|---:|---:|---:|---:|---:|")
        for row in sorted(stepped, key=row_key):
            versus = row.get("speedup_vs_host_grid", row.get("speedup_vs_seed"))
            lines.append(f"| {count(row['particles'])} | {method_name(row['method'])} | "
                         f"{row.get('scheme') or 'simultaneous'} | {fixed(row['ms_per_step'])} | "
                         f"{sci(row['particle_steps_per_second'])} | {ratio(row.get('pairwise_over_simultaneous'))} | "
                         f"{ratio(versus)} | {100 * row['fraction_of_floor']:.1f} % |")
        lines.append("")
    if events:
        lines.append("| N | collisions/s | particle-time/s | events/s |")
        lines.append("|---:|---:|---:|---:|")
        for row in sorted(events, key=row_key):
            lines.append(f"| {count(row['particles'])} | {sci(row['collisions_per_second'])} | "
                         f"{sci(row['particle_time_per_second'])} | {sci(row['events_per_second'])} |")
        lines.append("")
    profiled = [row for row in stepped if row.get("profile_ms_per_step")]
    if profiled:
        lines.append("Where a step's time goes (`--profile`: device time per kernel and transfer, "
                     "from a separate run; the slowest first):")
        lines.append("")
        lines.append("| N | method | scheme | ms/step | parts, ms per step |")
        lines.append("|---:|---|---|---:|---|")
        for row in sorted(profiled, key=row_key):
            parts = sorted(row["profile_ms_per_step"].items(), key=lambda item: -item[1])
            lines.append(f"| {count(row['particles'])} | {method_name(row['method'])} | "
                         f"{row.get('scheme') or 'simultaneous'} | {fixed(row['ms_per_step'])} | "
                         + "; ".join(f"{name} {value:.3g}" for name, value in parts) + " |")
        lines.append("")
    for dropped in run.get("dropped", []):
        lines.append(f"{method_name(dropped['method'])} ({dropped.get('scheme', 'simultaneous')}) was dropped "
                     f"after N = {dropped['after_particles']}: a step took {dropped['ms_per_step']:.3g} ms.")
        lines.append("")


def pymunk_runs(document):
    if isinstance(document, dict) and "runs" in document:
        return [run.get("result", run) | {"carom_build": run.get("carom")} for run in document["runs"]]
    return document if isinstance(document, list) else [document]


def pymunk_section(lines, runs):
    first = runs[0]
    scene = first["scene"]
    sizes = sorted({run["particles"] for run in runs})
    options = (f"--particles {sizes[0]} " if len(sizes) == 1 else "") + f"--packing {scene['packing']:g}"
    schemes = sorted({run["carom_cpu"].get("scheme") or "simultaneous" for run in runs})
    if "pairwise" in schemes:
        options += " --collisions pairwise"
    loads = sorted({run.get("busy_loops", 0) for run in runs})
    machines = sorted({(run.get("machine") or {}).get("cpu", "") for run in runs} - {""})
    dates = sorted(run["date"] for run in runs if run.get("date"))
    lines.append(f"- machine: {', '.join(machines) or 'the 2-core Intel Xeon VM'}"
                 + (f", {first['machine']['cores']} cores" if first.get("machine") else "")
                 + f"; pymunk {first['pymunk']} (Chipmunk {first['chipmunk'].split('-')[0]}), Python {first['python']}")
    if dates:
        lines.append(f"- date: {dates[0]}" + (f" to {dates[-1]}" if dates[-1] != dates[0] else ""))
    command = f"bench/peers/pymunk_peer.py --carom build/carom {options} --carom-bench"
    if loads != [0]:
        command += " --busy-loops " + "|".join(str(load) for load in loads)
    lines.append(f"- command: `{command}`, {len(runs)} runs")
    lines.append(f"- samples: {len(first['sample_ms_per_step'])} per run for each engine; each figure is the median")
    lines.append("")
    builds = any(run.get("carom_build") for run in runs)
    header = "| run | N | busy loops | " + ("carom build | " if builds else "") + "pymunk | carom (cpu) | carom / pymunk |"
    lines.append(header)
    lines.append("|---:|---:|---:|" + ("---|" if builds else "") + "---:|---:|---:|")
    for index, run in enumerate(runs, 1):
        lines.append(f"| {index} | {count(run['particles'])} | {run.get('busy_loops', 0)} | "
                     + (f"{run.get('carom_build') or ''} | " if builds else "")
                     + f"{sci(run['particle_steps_per_second'])} | {sci(run['carom_cpu']['particle_steps_per_second'])} | "
                     f"{ratio(run['carom_cpu_over_pymunk'])} |")
    lines.append("")
    lines.append("Figures are particle-steps per second.")
    lines.append("")


def title(name, runs):
    """The file's name, with the machine and date of its first run."""
    run = runs[0]
    if "results" in run:
        device = run.get("opencl_device")
        where = device["name"] if device else run["host"]["cpu"]
        return f"{name}: {where}, {run['date'][:10]}"
    result = pymunk_runs(runs[0] if len(runs) == 1 else runs)[0]
    where = (result.get("machine") or {}).get("cpu", "Intel(R) Xeon(R) Processor")
    return f"{name}: pymunk against carom, {where}" + (f", {result['date'][:10]}" if result.get("date") else "")


def tables():
    lines = ["# Benchmark results", "",
             "Generated by `python3 bench/results/tables.py` from the JSON files in this folder; do not edit by "
             "hand. Each section is one file: the machine, the date, the command and the samples it records. "
             "Particle-steps per second count each disk once per step; `pw/sim` is a pairwise step's time over "
             "a simultaneous step's (same method and N), `vs host-grid` the speed over the `opencl-host-grid` "
             "method's (same scheme and N), `of floor` the time a step would take at the measured copy "
             "bandwidth over the time it took. Files of older runs name the host-grid method `opencl-seed`; "
             "it is shown here as `opencl-host-grid`.", "",
             "<!-- tables -->", ""]
    for path in sorted(HERE.glob("*.json")):
        document = json.loads(path.read_text())
        runs = document if isinstance(document, list) else [document]
        lines.append(f"## {title(path.name, runs)}")
        lines.append("")
        if all(isinstance(run, dict) and "results" in run for run in runs):
            for index, run in enumerate(runs, 1):
                if len(runs) > 1:
                    lines.append(f"Run {index} of {len(runs)}:")
                    lines.append("")
                bench_section(lines, run)
        else:
            pymunk_section(lines, pymunk_runs(document))
    return "\n".join(lines).rstrip("\n") + "\n"


def main(argv):
    text = tables()
    if "--stdout" in argv:
        sys.stdout.write(text)
    else:
        (HERE / "README.md").write_text(text)


if __name__ == "__main__":
    main(sys.argv[1:])
