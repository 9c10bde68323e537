#!/usr/bin/env bash
# The README's event-driven speed figures (issue 12's targets: >= 2e6
# collisions per second on one core at N = 1e5, packing 0.5, periodic box,
# and within 2x of that from N = 1e3 to 1e6): RUNS runs of
# `carom bench --methods events --sizes SIZES` (each figure the median of its
# run's 7 samples, timed after at least 3 collisions per disk), then per N
# the median over the runs of collisions, particle-time (N x simulated time)
# and events per wall-clock second, and collisions/s over the figure at 1e5.
# Prints the machine and its load before and after: the runs share it.
#   bench/events.sh [CAROM] [RUNS] [SIZES]   (default build/carom 3 1e3,1e4,1e5,1e6)
# Python 3 reads the JSON.
set -euo pipefail
carom=${1:-build/carom} runs=${2:-3} sizes=${3:-1e3,1e4,1e5,1e6}
echo "machine: $(lscpu | sed -n 's/^Model name: *//p'), $(nproc --all) cores"
export OMP_NUM_THREADS=1  # the event-driven engine runs on one thread whatever this says
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
echo "load before: $(uptime)"
for r in $(seq "$runs"); do
    "$carom" bench --methods events --sizes "$sizes" --json "$work/run$r.json" > "$work/run$r.txt" 2>&1 ||
        { cat "$work/run$r.txt" >&2; exit 1; }
done
echo "load after: $(uptime)"
python3 - "$work"/run*.json <<'EOF'
import json, statistics, sys
rates = {}  # N -> (collisions/s, particle-time/s, events/s) per run
for name in sys.argv[1:]:
    for r in json.load(open(name))["results"]:
        rates.setdefault(r["particles"], []).append(
            (r["collisions_per_second"], r["particle_time_per_second"], r["events_per_second"]))
median = {n: [statistics.median(x[k] for x in runs) for k in range(3)] for n, runs in rates.items()}
print("N,collisions_per_second,particle_time_per_second,events_per_second,over_1e5,runs_collisions_per_second")
for n in sorted(rates):
    c, t, e = median[n]
    ratio = "%.2f" % (c / median[100000][0]) if 100000 in median else ""
    print("%d,%.4g,%.4g,%.4g,%s,%s" % (n, c, t, e, ratio, " ".join("%.4g" % x[0] for x in rates[n])))
EOF
