#!/usr/bin/env bash
# Whole-pipeline throughput (odometry + scoring + mapping + writing) on a 10 Hz synthetic
# stream with 131k points per scan: 64 x 2368 rays, as 13% of the rays of the street see the
# sky and return nothing (64 x 2048 = 131,072 rays give 114k points). Default settings (the
# paper's relative d_v, N = 10), this machine's cores. Runs the same stream `runs` times and
# prints each run (scans/s overall and in the steady state, CPU per scan, each stage's busy
# time, peak memory), then the median over the runs: timings on a shared VM vary by +-15%.
# Fresh output folders each run (builds from before --overwrite run too).
# `run` is offline (two passes) by default; a live sensor needs `--online`: extra options after
# `--` go to every run, e.g. compare the two back to back:
#   bash bench/pipeline_bench.sh build 60 2368 3 -- --online; bash bench/pipeline_bench.sh build 60
#   bash bench/pipeline_bench.sh [build-dir] [scans] [columns] [runs] [-- run options]
set -euo pipefail
build="${1:-build}"
scans="${2:-60}"
columns="${3:-2368}"
runs="${4:-3}"
shift $(( $# < 4 ? $# : 4 ))
[ "${1:-}" = "--" ] && shift
extra=("$@")
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
"$build/apps/cleanmap" demo --generate-only --scans "$scans" --columns "$columns" --out "$work/demo" > /dev/null 2>&1
for r in $(seq 1 "$runs"); do
  /usr/bin/time -v "$build/apps/cleanmap" run --input "$work/demo/sequence" --out "$work/run$r" "${extra[@]}" \
    > /dev/null 2> "$work/time$r.txt"
done
/usr/bin/python3 - "$work" "$runs" <<'PY'
import json, re, statistics, sys
work, runs = sys.argv[1], int(sys.argv[2])
rows = []
for r in range(1, runs + 1):
    s = json.load(open(f"{work}/run{r}/summary.json"))
    t = open(f"{work}/time{r}.txt").read()
    rss = int(re.search(r"Maximum resident set size \(kbytes\): (\d+)", t).group(1)) / 1024
    cpu = sum(float(re.search(p + r": ([\d.]+)", t).group(1))
              for p in (r"User time \(seconds\)", r"System time \(seconds\)"))
    # Offline runs have no live rate: NaN.
    row = {"overall": s["scans_per_second"], "sustained": s.get("sustained_scans_per_second", float("nan")),
           "cpu_ms": 1e3 * cpu / s["scans"], "rss": rss}
    row.update({k: 1e3 * v / s["scans"] for k, v in s["stage_seconds"].items()})
    rows.append(row)
    print(f"run {r}: {row['overall']:.2f} scans/s overall, {row['sustained']:.2f} steady state, "
          f"CPU {row['cpu_ms']:.0f} ms/scan, peak RSS {rss:.0f} MiB")
med = {k: statistics.median(row[k] for row in rows) for k in rows[0]}
print(f"scans {s['scans']}, points/scan {s['points'] / s['scans']:.0f}; median of {runs} runs: "
      f"{med['overall']:.2f} scans/s overall (incl. start-up and writing the maps), "
      f"{med['sustained']:.2f} scans/s in the steady state, CPU {med['cpu_ms']:.0f} ms/scan "
      f"(all threads), peak RSS {med['rss']:.0f} MiB")
stages = [k for k in ["read", "odometry", "scoring", "visibility", "judging", "mapping", "write"] if k in med]
total = sum(med[k] for k in stages)
for k in sorted(stages, key=lambda k: -med[k]):
    print(f"  {k:9s} {med[k]:7.1f} ms/scan busy ({100 * med[k] / total:4.1f}% of stage time)")
m = s.get("moving")
if m:
    print(f"  moving class (all ranges): IoU {m['iou']:.3f} precision {m['precision']:.3f} recall {m['recall']:.3f}")
PY
