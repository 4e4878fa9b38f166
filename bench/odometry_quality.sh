#!/usr/bin/env bash
# Odometry error per step (RPE, delta 1, mean / max) against the given poses of every real
# sequence that has them, and the median time per scan from odometry_log.csv.
# Usage: bash bench/odometry_quality.sh [BUILD_DIR] [-- extra odometry options]
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
build="$(cd "${1:-$here/build}" && pwd)"
shift || true
[ "${1:-}" = "--" ] && shift
data="${CLEANMAP_SHARED_DATA:-$here/../shared/data}"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
printf '%-18s %22s %24s %10s %9s\n' sequence "translation mean/max" "rotation mean/max" "median ms" recovered
for s in balm_campus semantickitti/01 semantickitti/04 semantickitti/07; do
  cfg=()
  [[ $s == semantickitti* ]] && cfg=(--config "$here/config/kitti-hdl64.yaml")
  o="$work/${s//\//_}"
  "$build/apps/cleanmap" odometry --input "$data/$s" --out "$o" "${cfg[@]}" "$@" > "$o.log" 2>&1 ||
    { echo "$s: odometry failed (see $o.log)"; continue; }
  "$build/apps/cleanmap" eval trajectory --est "$o/poses_kitti.txt" --ref "$data/$s/poses.txt" \
    --delta 1 --json "$o/t.json" > /dev/null
  /usr/bin/python3 - "$o" "$s" <<'PY'
import csv, json, sys
rpe = json.load(open(sys.argv[1] + "/t.json"))["rpe"]
rows = list(csv.DictReader(open(sys.argv[1] + "/odometry_log.csv")))[1:]
ms = sorted(1000 * float(r["seconds"]) for r in rows)
t, r = rpe["translation"], rpe["rotation_deg"]
print(f"{sys.argv[2]:18s} {100*t['mean']:9.2f} / {100*t['max']:5.2f} cm "
      f"{r['mean']:10.3f} / {r['max']:5.3f} deg {ms[len(ms)//2]:10.1f} "
      f"{sum(int(x['recovered']) for x in rows):9d}")
PY
done
