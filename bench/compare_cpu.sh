#!/usr/bin/env bash
# CPU time (user + system, all threads, /usr/bin/time) of two `cleanmap run` set-ups on the
# same 131k-point synthetic stream, runs interleaved (A, B, A, B, ...) so that this VM's
# drift (+-20% within an hour) hits both alike; prints each one's median and the ratio B/A.
# A set-up is a build folder, optionally with run options after a colon:
#   bash bench/compare_cpu.sh A B [runs] [scans]
#   bash bench/compare_cpu.sh /tmp/old/build build 5        # two builds, offline
#   bash bench/compare_cpu.sh "build:--online" build 5      # offline against online
# INPUT=DIR runs on a recorded log instead (every scan of it; ms/scan divides by the scans the
# runs report), with RUN_OPTS for both set-ups:
#   INPUT=../shared/data/pandar64_street RUN_OPTS="--config config/pandar64.yaml" \
#     bash bench/compare_cpu.sh "build:--online" build 3
set -euo pipefail
a="$1"; b="$2"; runs="${3:-5}"; scans="${4:-60}"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
input="${INPUT:-}"
if [ -z "$input" ]; then
  "${b%%:*}/apps/cleanmap" demo --generate-only --overwrite --scans "$scans" --columns 2368 --out "$work/demo" > /dev/null 2>&1
  input="$work/demo/sequence"
fi
cpu() {  # cpu SETUP: CPU seconds of one run (a fresh output folder: older builds lack --overwrite)
  local build="${1%%:*}" opts=""
  [ "$build" != "$1" ] && opts="${1#*:}"
  rm -rf "$work/run"
  # shellcheck disable=SC2086
  if ! /usr/bin/time -f "%U %S" -o "$work/t" "$build/apps/cleanmap" run --input "$input" \
    --out "$work/run" ${RUN_OPTS:-} $opts > "$work/log" 2>&1; then
    echo "compare_cpu: run with $1 failed: $(tail -n 1 "$work/log")" >&2
    return 1
  fi
  awk '{print $1 + $2}' "$work/t"
  [ -z "${INPUT:-}" ] || python3 -c "import json,sys; print(json.load(open(sys.argv[1]))['scans'])" \
    "$work/run/summary.json" > "$work/scans"
}
for r in $(seq 1 "$runs"); do
  ta=$(cpu "$a") && tb=$(cpu "$b") || exit 1
  echo "A $ta" >> "$work/cpu"
  echo "B $tb" >> "$work/cpu"
  echo "compare_cpu: pair $r of $runs done" >&2
done
[ -z "${INPUT:-}" ] || scans=$(cat "$work/scans")
/usr/bin/python3 - "$work/cpu" "$scans" "$a" "$b" <<'PY'
import statistics, sys
d = {"A": [], "B": []}
for line in open(sys.argv[1]):
    k, v = line.split(); d[k].append(float(v))
scans = int(sys.argv[2])
for k, name in (("A", sys.argv[3]), ("B", sys.argv[4])):
    m = statistics.median(d[k])
    print(f"{k} ({name}): median {m:.2f} s CPU, {1e3 * m / scans:.0f} ms/scan; runs " + " ".join(f"{v:.2f}" for v in d[k]))
print(f"B/A: {statistics.median(d['B']) / statistics.median(d['A']):.3f}")
PY
