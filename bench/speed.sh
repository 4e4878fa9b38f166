#!/usr/bin/env bash
# The speed table (issue 46): scans/s, CPU ms per scan by stage, peak RSS and the online
# per-scan latency, online and offline, on the real street (the 30 shared Pandar64 sweeps) and
# SemanticKITTI 01/04/07 (10 sweeps each), with `cleanmap odometry` alone on the same input as
# the reference. Each run is repeated until its repeats have taken MIN_SECONDS (default 4) and
# at least RUNS times (default 3); the table gives medians. Runs use the options the quality
# tables use (bench/quality.sh): the presets, and SemanticKITTI's given poses.
#
# Two builds run back to back, A then B for every run, so that this VM's drift (+-20 % within an
# hour) hits both alike, and the ratios B/A are printed:
#   bash bench/speed.sh BUILD [BUILD2]
# SETS="pandar64 sk07" limits the data sets (names: pandar64 sk01 sk04 sk07).
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
builds=("$(cd "$1" && pwd)")
[ $# -ge 2 ] && builds+=("$(cd "$2" && pwd)")
data="${CLEANMAP_SHARED_DATA:-$here/../shared/data}"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
min_seconds="${MIN_SECONDS:-4}"
min_runs="${RUNS:-3}"
kitti="--config $here/config/kitti-hdl64.yaml"
declare -A input=(
  [pandar64]="$data/pandar64_street" [sk01]="$data/semantickitti/01"
  [sk04]="$data/semantickitti/04" [sk07]="$data/semantickitti/07")
declare -A opts=(
  [pandar64]="--config $here/config/pandar64.yaml" [sk01]="$kitti --use-given-poses"
  [sk04]="$kitti --use-given-poses" [sk07]="$kitti --use-given-poses")
declare -A odo_opts=(
  [pandar64]="--config $here/config/pandar64.yaml" [sk01]="$kitti" [sk04]="$kitti" [sk07]="$kitti")

one() {  # one BUILD_INDEX SET MODE: one run; appends "build set mode wall cpu rss_kb summary" to runs.txt
  local b="$1" set="$2" mode="$3" out="$work/out" cmd=(run) extra=()
  rm -rf "$out"
  case "$mode" in
    odometry) cmd=(odometry); extra=(${odo_opts[$set]}) ;;
    online) extra=(${opts[$set]} --online) ;;
    offline) extra=(${opts[$set]}) ;;
  esac
  if ! /usr/bin/time -f "%e %U %S %M" -o "$work/t" "${builds[$b]}/apps/cleanmap" "${cmd[@]}" \
    --input "${input[$set]}" --out "$out" "${extra[@]}" > "$work/log" 2>&1; then
    echo "speed: $set $mode with ${builds[$b]} failed: $(tail -n 1 "$work/log")" >&2
    exit 1
  fi
  local keep="$work/s_${b}_${set}_${mode}_$(wc -l < "$work/runs.txt").json"
  cp "$out/summary.json" "$keep"
  read -r wall user sys rss < "$work/t"
  echo "$b $set $mode $wall $(echo "$user + $sys" | bc) $rss $keep" >> "$work/runs.txt"
}

: > "$work/runs.txt"
for set in ${SETS:-pandar64 sk01 sk04 sk07}; do
  for mode in odometry online offline; do
    runs=0 spent=0
    while [ "$runs" -lt "$min_runs" ] || [ "$(echo "$spent < $min_seconds" | bc)" = 1 ]; do
      for b in "${!builds[@]}"; do one "$b" "$set" "$mode"; done
      spent=$(echo "$spent + $(tail -n 1 "$work/runs.txt" | cut -d' ' -f4)" | bc)
      runs=$((runs + 1))
    done
    echo "speed: $set $mode: $runs runs per build" >&2
  done
done

python3 - "$work/runs.txt" "${builds[@]}" <<'PY'
import json, statistics, sys
rows = [l.split() for l in open(sys.argv[1])]
builds = sys.argv[2:]
med = statistics.median
table = {}
for b, s, mode, wall, cpu, rss, summary in rows:
    d = json.load(open(summary))
    scans = d.get("scans", 0) or 1
    t = table.setdefault((int(b), s, mode), {"wall": [], "cpu": [], "rss": [], "stages": [], "lat": []})
    t["wall"].append(float(wall)); t["cpu"].append(float(cpu)); t["rss"].append(int(rss) / 1024)
    t["scans"] = scans
    t["stages"].append(d.get("stage_seconds", {}))
    if "latency_seconds" in d: t["lat"].append(d["latency_seconds"])

def figures(t):
    f = {"scans/s": t["scans"] / med(t["wall"]), "cpu ms/scan": 1000 * med(t["cpu"]) / t["scans"],
         "peak MiB": med(t["rss"])}
    for k in sorted({k for st in t["stages"] for k in st}):
        f["ms " + k] = 1000 * med([st.get(k, 0.0) for st in t["stages"]]) / t["scans"]
    if t["lat"]:
        f["lat p50 ms"] = 1000 * med([l["median"] for l in t["lat"]])
        f["lat p95 ms"] = 1000 * med([l["p95"] for l in t["lat"]])
    return f

sets = sorted({k[1] for k in table}, key=lambda s: ["pandar64", "sk01", "sk04", "sk07"].index(s))
for b, build in enumerate(builds):
    print(f"\n== build {'AB'[b]}: {build}")
    print(f"{'set':9} {'mode':9} {'scans/s':>8} {'x odo':>6} {'cpu ms':>7} {'MiB':>6} {'lat50':>6} {'lat95':>6}  busy ms per scan by stage")
    for s in sets:
        odo = figures(table[(b, s, "odometry")])
        for mode in ["odometry", "online", "offline"]:
            f = figures(table[(b, s, mode)])
            stages = " ".join(f"{k[3:]} {v:.0f}" for k, v in f.items() if k.startswith("ms "))
            ratio = odo["scans/s"] / f["scans/s"]
            print(f"{s:9} {mode:9} {f['scans/s']:8.2f} {ratio:6.2f} {f['cpu ms/scan']:7.0f} {f['peak MiB']:6.0f} "
                  f"{f.get('lat p50 ms', float('nan')):6.0f} {f.get('lat p95 ms', float('nan')):6.0f}  {stages}")
if len(builds) == 2:
    print("\n== B / A (scans/s: above 1 is faster; cpu and memory: below 1 is cheaper)")
    print(f"{'set':9} {'mode':9} {'scans/s':>8} {'cpu':>6} {'MiB':>6} {'lat50':>6}")
    for s in sets:
        for mode in ["odometry", "online", "offline"]:
            a, b = figures(table[(0, s, mode)]), figures(table[(1, s, mode)])
            lat = b.get("lat p50 ms", float("nan")) / a.get("lat p50 ms", float("nan"))
            print(f"{s:9} {mode:9} {b['scans/s'] / a['scans/s']:8.3f} {b['cpu ms/scan'] / a['cpu ms/scan']:6.3f} "
                  f"{b['peak MiB'] / a['peak MiB']:6.3f} {lat:6.3f}")
PY
