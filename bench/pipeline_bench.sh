#!/usr/bin/env bash
# Whole-pipeline throughput (odometry + scoring + mapping + writing) on a 10 Hz synthetic
# stream with 131k points per scan: 64 x 2368 rays, as 13% of the rays of the street see the
# sky and return nothing (64 x 2048 = 131,072 rays give 114k points). Default settings (the
# paper's relative d_v, N = 10), this machine's cores. Prints scans/s, CPU per scan, each
# stage's busy time and peak memory.
#   bash bench/pipeline_bench.sh [build-dir] [scans] [columns]
set -euo pipefail
build="${1:-build}"
scans="${2:-60}"
columns="${3:-2368}"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
"$build/apps/cleanmap" demo --generate-only --scans "$scans" --columns "$columns" --out "$work/demo" > /dev/null 2>&1
/usr/bin/time -v "$build/apps/cleanmap" run --input "$work/demo/sequence" --out "$work/run" \
  > /dev/null 2> "$work/time.txt"
/usr/bin/python3 - "$work/run/summary.json" "$work/time.txt" <<'PY'
import json, re, sys
s = json.load(open(sys.argv[1]))
t = open(sys.argv[2]).read()
rss = re.search(r"Maximum resident set size \(kbytes\): (\d+)", t)
cpu = sum(float(re.search(p + r": ([\d.]+)", t).group(1)) for p in (r"User time \(seconds\)", r"System time \(seconds\)"))
busy = s["stage_seconds"]
print(f"scans {s['scans']}, points/scan {s['points'] / s['scans']:.0f}, wall {s['seconds']:.1f} s, "
      f"{s['scans_per_second']:.2f} scans/s overall, {s['sustained_scans_per_second']:.2f} sustained (steady state), CPU {1e3 * cpu / s['scans']:.0f} ms/scan (all threads, incl. start-up), "
      f"peak RSS {int(rss.group(1)) / 1024:.0f} MiB")
total = sum(busy.values())
for k, v in sorted(busy.items(), key=lambda kv: -kv[1]):
    print(f"  {k:9s} {1e3 * v / s['scans']:7.1f} ms/scan busy ({100 * v / total:4.1f}% of stage time)")
m = s.get("moving")
if m:
    print(f"  moving class (all ranges): IoU {m['iou']:.3f} precision {m['precision']:.3f} recall {m['recall']:.3f}")
PY
