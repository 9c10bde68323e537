#!/usr/bin/env bash
# The collision schemes side by side: the figures of the README's
# "Collision schemes" and "Pairwise against simultaneous" tables.
#   bench/schemes.sh energy CAROM [carom run options, e.g. --backend opencl --device NVIDIA --pipeline resident]
#       the relative change of the total energy (energy.total in --json) of
#       each scene under each stepped scheme, one run each; a run that goes
#       non-finite prints its error instead
#   bench/schemes.sh events CAROM
#       the same scenes under --collisions events (CPU): the relative change
#       of the total energy of the double state (energy.exact_relative_change)
#       and of the float32 samples (energy.total)
#   bench/schemes.sh ratio CAROM RUNS [carom bench options]
#       RUNS runs of `carom bench --methods cpu --sizes 1e4` (or the options
#       given), each the median of its samples; prints every run's
#       pairwise / simultaneous step time and the median over the runs
# CAROM is the carom binary (e.g. build/carom). Python 3 reads the JSON.
set -uo pipefail
mode=$1 carom=$2
shift 2

energy_change() {  # label, then carom run options; the schemes are $schemes
    local label=$1 scheme out
    shift
    for scheme in $schemes; do
        if out=$("$carom" run --collisions "$scheme" "$@" --quiet --json 2>/tmp/carom-schemes.err); then
            echo "$out" | python3 -c '
import json, sys
d = json.load(sys.stdin)
e = d["energy"]["total"]
change = (e["final"] - e["initial"]) / abs(e["initial"])
if "exact_relative_change" in d["energy"]:
    print("%s | %s | %+.2e in double, %+.2e in the float32 samples | %d collisions, %.1f s" % (sys.argv[1],
          sys.argv[2], d["energy"]["exact_relative_change"], change, d["collisions"], d["wall_seconds"]))
else:
    print("%s | %s | %+.2e | late contacts %d, max rounds %d, %d collisions, %.1f s" % (sys.argv[1], sys.argv[2],
          change, d["late_contacts"], d["max_rounds"], d["collisions"], d["wall_seconds"]))' "$label" "$scheme"
        else
            echo "$label | $scheme | $(tail -n 1 /tmp/carom-schemes.err)"
        fi
    done
}

case $mode in
energy | events)
    if [ "$mode" = events ]; then schemes=events; else schemes="simultaneous pairwise"; fi
    energy_change "1 000 disks, packing 0.7, 1 000 steps" --particles 1000 --packing 0.7 --steps 1000 "$@"
    energy_change "20 000 disks, packing 0.7, dt 0.002, 2 000 steps" --particles 20000 --packing 0.7 --dt 0.002 \
        --steps 2000 "$@"
    energy_change "10 000 disks, packing 0.6, 10 000 steps" --particles 10000 --packing 0.6 --steps 10000 "$@"
    energy_change "2 000 disks, gravity (0, -10), 5 000 steps" --particles 2000 --gravity 0 -10 --steps 5000 "$@"
    energy_change "scenes/gravity_settle.toml" --scene scenes/gravity_settle.toml "$@"
    energy_change "1 000 disks, packing 0.5, 100 000 steps" --particles 1000 --packing 0.5 --steps 100000 "$@"
    ;;
ratio)
    runs=$1
    shift
    [ $# -gt 0 ] || set -- --methods cpu --sizes 1e4
    for _ in $(seq "$runs"); do
        "$carom" bench "$@" --collisions simultaneous,pairwise --json /tmp/carom-schemes.json >/dev/null 2>&1 &&
            python3 -c '
import json
for r in json.load(open("/tmp/carom-schemes.json"))["results"]:
    if r["scheme"] == "pairwise": print(r["method"], r["particles"], r["pairwise_over_simultaneous"])'
    done | python3 -c '
import statistics, sys
ratios = {}
for line in sys.stdin:
    method, n, ratio = line.split()
    ratios.setdefault((method, n), []).append(float(ratio))
for (method, n), r in sorted(ratios.items()):
    print("%s, N = %s: pairwise / simultaneous %s; median %.2f over %d runs" % (
        method, n, " ".join("%.2f" % x for x in r), statistics.median(r), len(r)))'
    ;;
*)
    echo "usage: bench/schemes.sh energy CAROM [run options] | ratio CAROM RUNS [bench options]" >&2
    exit 2
    ;;
esac
