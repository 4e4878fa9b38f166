#!/usr/bin/env bash
# The quality table every detection change is judged by: `cleanmap run` on every data set with
# ground truth (the real sequences in ../shared/data and the synthetic street), scored against
# that ground truth, all ranges and within 20 m of the sensor, plus the run's speed; and the
# false dynamic points of a synthetic street where nothing moves but the sensor.
#
# A second table scores the cleaned maps in the DynamicMap benchmark's way (SA/DA/AA/HA of
# `cleanmap eval map`): the real labelled sequences are first written in its layout
# (build/bench/dynamicmap_layout; the Pandar64 street with the poses of its run above).
# "DA max" is the DA of the static truth itself as the output: no method that keeps every
# static point removes more (dynamic points within 5 cm of static ones cannot be told apart).
# The Pandar64 street is scored on three truths: the boxes' centre speeds, moving per scan (the
# shipped truth); speeds measured by registering each object's own points (--box-speed points:
# a parked truck whose interpolated boxes creep is standing there; evaluation/object_motion.hpp);
# and those with a mover's whole track moving once it moved (--box-moving track: a truck that
# brakes to a stop beside the sensor, as a clean map of the log wants it gone).
# A third table scores the clean OctoMaps against the same truths (build/bench/map_occupancy).
#
# Usage: bash bench/quality.sh [BUILD_DIR] [WORK_DIR] [-- extra run options]
#   BUILD_DIR: the build to measure (default build); WORK_DIR: where the runs go (default a
#   temporary folder, removed afterwards). Extra options after `--` go to every `run`.
# Compare two builds with the same command on each (or two WORK_DIRs), one after the other.
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
build="$(cd "${1:-$here/build}" && pwd)"
shift || true
work="${1:-}"
[ $# -gt 0 ] && shift
[ "${1:-}" = "--" ] && shift
extra=("$@")
data="${CLEANMAP_SHARED_DATA:-$here/../shared/data}"
cm="$build/apps/cleanmap"
[ -x "$cm" ] || { echo "quality: $cm: not built" >&2; exit 1; }
[ -d "$data" ] || { echo "quality: $data: no shared data" >&2; exit 1; }
if [ -z "$work" ]; then
  work="$(mktemp -d)"
  trap 'rm -rf "$work"' EXIT
fi
mkdir -p "$work"

# name | input | run options | eval options (besides --pred/--gt)
sets=(
  "semantickitti/01|$data/semantickitti/01|--config $here/config/kitti-hdl64.yaml --use-given-poses|"
  "semantickitti/04|$data/semantickitti/04|--config $here/config/kitti-hdl64.yaml --use-given-poses|"
  "semantickitti/07|$data/semantickitti/07|--config $here/config/kitti-hdl64.yaml --use-given-poses|"
  "kitti00 (0-2, odometry)|$data/kitti00|--config $here/config/kitti-hdl64.yaml|"
  "pandar64_street (boxes)|$data/pandar64_street|--config $here/config/pandar64.yaml|--poses @OUT@/poses.txt"
  "synthetic street|@SYNTH@|--voxel-size 0.1|"
  "synthetic depth (arm)|@DEPTH@|--config $here/config/rgbd-arm.yaml|"
)

"$cm" demo --generate-only --overwrite --out "$work/synthetic" > /dev/null 2>&1
"$cm" demo --sensor depth --generate-only --overwrite --out "$work/depth" > /dev/null 2>&1

metric() {  # metric JSON FIELD
  python3 -c "import json,sys; d=json.load(open(sys.argv[1])); v = d[sys.argv[2]]; print('n/a' if v is None else '%.3f' % v)" "$1" "$2"
}

printf '%-26s %6s %6s %6s   %6s %6s %6s   %7s\n' "data set" "IoU" "prec" "recall" "IoU20" "prec20" "rec20" "scans/s"
printf '%-26s %6s %6s %6s   %6s %6s %6s   %7s\n' "" "(all" "ranges)" "" "(within" "20 m)" "" ""
for entry in "${sets[@]}"; do
  IFS='|' read -r name input run_opts eval_opts <<< "$entry"
  input="${input//@SYNTH@/$work/synthetic/sequence}"
  input="${input//@DEPTH@/$work/depth/sequence}"
  out="$work/$(echo "$name" | tr -c 'a-zA-Z0-9\n' '_')"
  rm -rf "$out"
  # shellcheck disable=SC2086
  if ! "$cm" run --overwrite --input "$input" --out "$out" $run_opts "${extra[@]}" > "$out.log" 2>&1; then
    printf '%-26s run failed: %s\n' "$name" "$(tail -n 1 "$out.log")"
    continue
  fi
  eval_opts="${eval_opts//@OUT@/$out}"
  # shellcheck disable=SC2086
  "$cm" eval dynamic --pred "$out" --gt "$input" $eval_opts --json "$out/all.json" > /dev/null
  # shellcheck disable=SC2086
  "$cm" eval dynamic --pred "$out" --gt "$input" $eval_opts --max-range 20 --json "$out/near.json" > /dev/null
  rate=$(python3 -c "import json,sys; print('%.1f' % json.load(open(sys.argv[1]))['scans_per_second'])" "$out/summary.json")
  printf '%-26s %6s %6s %6s   %6s %6s %6s   %7s\n' "$name" \
    "$(metric "$out/all.json" iou)" "$(metric "$out/all.json" precision)" "$(metric "$out/all.json" recall)" \
    "$(metric "$out/near.json" iou)" "$(metric "$out/near.json" precision)" "$(metric "$out/near.json" recall)" "$rate"
done

# The Pandar64 street's labels once more, against the truths measured on the objects' points:
# moving per scan, and moving along the whole track once the object moved (--box-moving track).
p64="$work/pandar64_street__boxes_"
if [ -f "$p64/summary.json" ]; then
  for variant in "points|scan" "points|track"; do
    IFS='|' read -r speed moving <<< "$variant"
    p64_truth=(--gt "$data/pandar64_street" --poses "$p64/poses.txt" --time-from-azimuth --box-speed "$speed" --box-moving "$moving")
    "$cm" eval dynamic --pred "$p64" "${p64_truth[@]}" --json "$p64/all_$moving.json" > /dev/null
    "$cm" eval dynamic --pred "$p64" "${p64_truth[@]}" --max-range 20 --json "$p64/near_$moving.json" > /dev/null
    printf '%-26s %6s %6s %6s   %6s %6s %6s   %7s\n' "pandar64 ($speed, $moving)" \
      "$(metric "$p64/all_$moving.json" iou)" "$(metric "$p64/all_$moving.json" precision)" "$(metric "$p64/all_$moving.json" recall)" \
      "$(metric "$p64/near_$moving.json" iou)" "$(metric "$p64/near_$moving.json" precision)" "$(metric "$p64/near_$moving.json" recall)" "(same)"
  done
fi

# A street where nothing moves but the sensor (issue 12: no dynamic voxel in its map): every
# dynamic point is a false one.
"$cm" demo --generate-only --static-scene --scans 30 --overwrite --out "$work/static" > /dev/null 2>&1
static_counts=()
for poses in "odometry|" "given poses|--use-given-poses"; do
  IFS='|' read -r label opt <<< "$poses"
  # shellcheck disable=SC2086
  if "$cm" run --overwrite --input "$work/static/sequence" --out "$work/static_run" --voxel-size 0.1 $opt \
       "${extra[@]}" > "$work/static_run.log" 2>&1; then
    n=$(python3 -c "import json,sys; print(json.load(open(sys.argv[1]))['dynamic_points'])" "$work/static_run/summary.json")
  else
    n="failed"
  fi
  static_counts+=("$n with $label")
done
printf '%-26s false dynamic points: %s, %s\n' "static street (30 scans)" "${static_counts[0]}" "${static_counts[1]}"

# name | DynamicMap-layout source | converter options | run options
dm_sets=(
  "semantickitti/01|$data/semantickitti/01||--config $here/config/kitti-hdl64.yaml"
  "semantickitti/04|$data/semantickitti/04||--config $here/config/kitti-hdl64.yaml"
  "semantickitti/07|$data/semantickitti/07||--config $here/config/kitti-hdl64.yaml"
  "pandar64_street (boxes)|$data/pandar64_street|--poses $work/pandar64_street__boxes_/poses.txt --time-from-azimuth|--config $here/config/pandar64.yaml"
  "pandar64 (points, scan)|$data/pandar64_street|--poses $work/pandar64_street__boxes_/poses.txt --time-from-azimuth --box-speed points|--config $here/config/pandar64.yaml"
  "pandar64 (points, track)|$data/pandar64_street|--poses $work/pandar64_street__boxes_/poses.txt --time-from-azimuth --box-speed points --box-moving track|--config $here/config/pandar64.yaml"
  "synthetic street|$work/synthetic/sequence||--voxel-size 0.1"
)
convert="$build/bench/dynamicmap_layout"
echo
printf '%-26s %7s %7s %7s %7s %8s   %7s\n' "DynamicMap layout" "SA" "DA" "AA" "HA" "DA max" "scans/s"
for entry in "${dm_sets[@]}"; do
  IFS='|' read -r name input conv_opts run_opts <<< "$entry"
  dm="$work/dm_$(echo "$name" | tr -c 'a-zA-Z0-9\n' '_')"
  rm -rf "$dm" "$dm.run"
  # shellcheck disable=SC2086
  if ! "$convert" --input "$input" --out "$dm" $conv_opts > "$dm.log" 2>&1 ||
     ! "$cm" run --overwrite --input "$dm" --out "$dm.run" $run_opts "${extra[@]}" >> "$dm.log" 2>&1; then
    printf '%-26s failed: %s\n' "$name" "$(tail -n 1 "$dm.log")"
    continue
  fi
  "$cm" eval map --gt "$dm/gt_cloud.pcd" --output "$dm.run/map_static.pcd" --json "$dm.run/map.json" > /dev/null
  rate=$(python3 -c "import json,sys; print('%.1f' % json.load(open(sys.argv[1]))['scans_per_second'])" "$dm.run/summary.json")
  m() { python3 -c "import json,sys; print('%.2f' % json.load(open(sys.argv[1]))[sys.argv[2]])" "$dm.run/map.json" "$1"; }
  printf '%-26s %7s %7s %7s %7s %8s   %7s\n' "$name" "$(m SA)" "$(m DA)" "$(m AA)" "$(m HA)" "$(m DA_ceiling)" "$rate"
done

# The clean OctoMaps (map.ot) of the first table's runs against the layouts' truths, which share
# their poses and frame (build/bench/map_occupancy): where the truth's static points fall (a
# clean map keeps the world: occupied) and its dynamic ones (trails it should not keep); "alone":
# the dynamic points in cells without a static point of the truth, the trails a map that keeps
# the world could clear. Unknown: no point or ray of the map reached (rays are cut at
# map_max_range).
echo
printf '%-26s %-24s %-24s %s\n' "clean OctoMap" "static truth (%)" "dynamic truth (%)" "alone (%)"
printf '%-26s %7s %7s %7s  %7s %7s %7s  %7s\n' "" "occ" "free" "unkn" "occ" "free" "unkn" "occ"
for pair in "semantickitti/01|semantickitti/01" "semantickitti/04|semantickitti/04" "semantickitti/07|semantickitti/07" \
            "pandar64_street (boxes)|pandar64_street (boxes)" "pandar64_street (boxes)|pandar64 (points, track)"; do
  IFS='|' read -r run_name truth_name <<< "$pair"
  run="$work/$(echo "$run_name" | tr -c 'a-zA-Z0-9\n' '_')"
  dm="$work/dm_$(echo "$truth_name" | tr -c 'a-zA-Z0-9\n' '_')"
  [ -f "$run/map.ot" ] && [ -f "$dm/gt_cloud.pcd" ] || continue
  if ! "$build/bench/map_occupancy" --map "$run/map.ot" --gt "$dm/gt_cloud.pcd" --json "$run/occupancy.json" > /dev/null 2>&1; then
    printf '%-26s failed\n' "$truth_name"
    continue
  fi
  o() { python3 -c "import json,sys; print('%.2f' % json.load(open(sys.argv[1]))[sys.argv[2]])" "$run/occupancy.json" "$1"; }
  printf '%-26s %7s %7s %7s  %7s %7s %7s  %7s\n' "$truth_name" "$(o static_occupied)" "$(o static_free)" "$(o static_unknown)" \
    "$(o dynamic_occupied)" "$(o dynamic_free)" "$(o dynamic_unknown)" "$(o dynamic_alone_occupied)"
done
