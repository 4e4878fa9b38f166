#!/usr/bin/env bash
# Builds the libFuzzer targets (tests/fuzz, clang, ASan + UBSan) and runs each for SECONDS.
# Usage: bash scripts/fuzz.sh [SECONDS per target, default 60] [TARGET ...]
#   JOBS=2 runs two targets at a time. Corpora grow in build-fuzz/corpus/<target> (seeded from
#   ../shared/data and small hand-written files); crashes, leaks and timeouts are kept in
#   build-fuzz/findings/ and make the script exit non-zero. CI runs it for a few seconds each.
set -euo pipefail
cd "$(dirname "$0")/.."
seconds="${1:-60}"
shift || true
targets=("$@")
[ ${#targets[@]} -gt 0 ] || targets=(fuzz_pcd fuzz_ply fuzz_kitti_bin fuzz_label fuzz_pose_file fuzz_calib
                                     fuzz_point_cloud2 fuzz_ros2_cdr fuzz_mcap fuzz_png fuzz_preset fuzz_sqlite_bag
                                     fuzz_depth_files)
build=build-fuzz
data="${CLEANMAP_SHARED_DATA:-../shared/data}"
CC=clang CXX=clang++ cmake -S . -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release -DCLEANMAP_FUZZ=ON \
  -DCLEANMAP_WITH_ROSBAG=OFF -DCLEANMAP_BUILD_BENCH=OFF -DCLEANMAP_PYTHON=OFF > /dev/null
cmake --build "$build" -j "$(nproc)" --target "${targets[@]}"

# Seeds: the first 200 points of real scans (a whole header, a body the size it claims), the
# first lines of real pose, time, calib and label files, the presets, and hand-written edge cases.
seed() { mkdir -p "$build/corpus/$1"; cat > "$build/corpus/$1/$2"; }
first_points() {  # PCD with binary data cut to its first N points, header rewritten to match
  /usr/bin/python3 - "$1" "$2" <<'PY'
import sys
raw = open(sys.argv[1], "rb").read()
end = raw.index(b"DATA binary\n") + len(b"DATA binary\n")
head = raw[:end].decode().splitlines()
sizes = [int(x) for x in next(l for l in head if l.startswith("SIZE")).split()[1:]]
n = int(sys.argv[2])
out = []
for l in head:
    k = l.split(" ")[0]
    out.append(f"{k} {n}" if k in ("WIDTH", "POINTS") else l)
sys.stdout.buffer.write(("\n".join(out) + "\n").encode() + raw[end:end + n * sum(sizes)])
PY
}
if [ -d "$data" ]; then
  for s in balm_campus/scans/000008.pcd pandar64_street/scans/000000.pcd; do
    [ -f "$data/$s" ] && first_points "$data/$s" 200 | seed fuzz_pcd "$(echo "$s" | tr / _)"
  done
  [ -f "$data/kitti00/velodyne/000000.bin" ] && head -c 3200 "$data/kitti00/velodyne/000000.bin" | seed fuzz_kitti_bin kitti00.bin
  [ -f "$data/kitti00/labels/000000.label" ] && head -c 800 "$data/kitti00/labels/000000.label" | seed fuzz_label kitti00.label
  for f in kitti00/poses.txt balm_campus/poses.txt kitti00/times.txt; do
    [ -f "$data/$f" ] && head -n 5 "$data/$f" | seed fuzz_pose_file "$(echo "$f" | tr / _)"
  done
  [ -f "$data/kitti00/calib.txt" ] && seed fuzz_calib calib.txt < "$data/kitti00/calib.txt"
fi
printf 'VERSION 0.7\nFIELDS x y z intensity t\nSIZE 4 4 4 2 8\nTYPE F F F U F\nCOUNT 1 1 1 1 1\nWIDTH 2\nHEIGHT 1\nVIEWPOINT 1 2 3 1 0 0 0\nPOINTS 2\nDATA ascii\n1 2 3 4 0.05\nnan 5 6 7 1e9\n' | seed fuzz_pcd ascii.pcd
printf 'ply\nformat ascii 1.0\ncomment x\nelement vertex 2\nproperty float x\nproperty float y\nproperty double z\nproperty uchar intensity\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n1 2 3 4\n5 6 7 8\n3 0 1 1\n' | seed fuzz_ply ascii.ply
printf 'ply\nformat binary_little_endian 1.0\nelement vertex 1\nproperty float x\nproperty float y\nproperty float z\nelement camera 1\nproperty float view_px\nproperty float view_py\nproperty float view_pz\nend_header\n\0\0\x80\x3f\0\0\0\x40\0\0\x40\x40\0\0\0\0\0\0\0\0\0\0\0\0' | seed fuzz_ply binary.ply
printf '1 0 0 0 0 1 0 0 0 0 1 0\n1 0 0 1 0 1 0 0 0 0 1 0\n' | seed fuzz_pose_file kitti.txt
printf '# timestamp tx ty tz qx qy qz qw\n0.0 0 0 0 0 0 0 1\n0.1 1 0 0 0 0 0.0998 0.995\n' | seed fuzz_pose_file tum.txt
printf '\3\0\0\0\0\0\7\1\4\0\0\0\7\2\x08\0\0\0\7\x0c\0\0\0\2\0\0\0\0\0\x80\x3f\0\0\0\x40\0\0\x40\x40\0\0\x80\x3f\0\0\0\x40\0\0\x40\x40' | seed fuzz_point_cloud2 xyz.bin
for p in config/*.yaml; do seed fuzz_preset "$(basename "$p")" < "$p"; done
# A 4 x 2 16-bit greyscale PNG (depth 0 .. 7000), written by Python's zlib as the format says.
/usr/bin/python3 -c '
import struct, sys, zlib
def chunk(t, d): return struct.pack(">I", len(d)) + t + d + struct.pack(">I", zlib.crc32(t + d))
rows = b"".join(b"\0" + b"".join(struct.pack(">H", 1000 * (4 * y + x)) for x in range(4)) for y in range(2))
sys.stdout.buffer.write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", 4, 2, 16, 0, 0, 0, 0))
                        + chunk(b"IDAT", zlib.compress(rows)) + chunk(b"IEND", b""))' | seed fuzz_png depth.png
# A one-point PointCloud2 in CDR (tests/io/ros2_bag_support.hpp's fixture), and an MCAP file
# holding it in an uncompressed chunk, laid out as the MCAP specification says.
cdr='\0\1\0\0\1\0\0\0\0\x65\xcd\x1d\2\0\0\0l\0\0\0\1\0\0\0\1\0\0\0\1\0\0\0\2\0\0\0x\0\0\0\0\0\0\0\7\0\0\0\1\0\0\0\0\0\0\0\4\0\0\0\4\0\0\0\4\0\0\0\0\0\x80\x3f\1'
printf "$cdr" | seed fuzz_ros2_cdr point_cloud2.cdr
printf "$cdr" | /usr/bin/python3 -c '
import struct, sys
msg = sys.stdin.buffer.read()
s = lambda t: struct.pack("<I", len(t)) + t
rec = lambda op, c: bytes([op]) + struct.pack("<Q", len(c)) + c
inner = (rec(3, struct.pack("<H", 1) + s(b"sensor_msgs/msg/PointCloud2") + s(b"ros2msg") + struct.pack("<I", 0))
         + rec(4, struct.pack("<HH", 1, 1) + s(b"/points") + s(b"cdr") + struct.pack("<I", 0))
         + rec(5, struct.pack("<HIQQ", 1, 0, 1500000000, 1500000000) + msg))
chunk = struct.pack("<QQQI", 1500000000, 1500000000, len(inner), 0) + s(b"") + struct.pack("<Q", len(inner)) + inner
magic = b"\x89MCAP0\r\n"
sys.stdout.buffer.write(magic + rec(1, s(b"ros2") + s(b"cleanmap")) + rec(6, chunk) + rec(15, struct.pack("<I", 0))
                        + rec(2, struct.pack("<QQI", 0, 0, 0)) + magic)' | seed fuzz_mcap one.mcap

# A rosbag2 sqlite3 file (its two tables, one message), built by Python's sqlite3 module, and
# the depth sequence's text files plus a rosbag2 metadata.yaml for fuzz_depth_files.
rm -f "$build/corpus/seed.db3"
/usr/bin/python3 -c '
import sqlite3, sys
db = sqlite3.connect(sys.argv[1])
db.executescript("CREATE TABLE topics(id INTEGER PRIMARY KEY, name TEXT NOT NULL, type TEXT NOT NULL, serialization_format TEXT NOT NULL, offered_qos_profiles TEXT NOT NULL);"
                 "CREATE TABLE messages(id INTEGER PRIMARY KEY, topic_id INTEGER NOT NULL, timestamp INTEGER NOT NULL, data BLOB NOT NULL);")
db.execute("INSERT INTO topics VALUES (1, ?, ?, ?, ?)", ("/points", "sensor_msgs/msg/PointCloud2", "cdr", ""))
db.execute("INSERT INTO messages VALUES (1, 1, 1500000000, ?)", (bytes(64),))
db.commit()' "$build/corpus/seed.db3"
seed fuzz_sqlite_bag one.db3 < "$build/corpus/seed.db3"
rm -f "$build/corpus/seed.db3"
printf 'fx: 525.0\nfy: 525.0\ncx: 319.5\ncy: 239.5\ndepth_scale: 5000\nmax_depth: 4.0\nmin_depth: 0.1\ndistortion: [0.1, -0.2, 0, 0, 0]\n' | seed fuzz_depth_files camera.yaml
printf '# depth maps\n# timestamp filename\n1305031102.160407 depth/1305031102.160407.png\n1305031102.194330 depth/1305031102.194330.png\n' | seed fuzz_depth_files depth.txt
printf 'rosbag2_bagfile_information:\n  version: 5\n  storage_identifier: sqlite3\n  relative_file_paths: [log_0.db3]\n  duration: {nanoseconds: 100}\n  starting_time: {nanoseconds_since_epoch: 1}\n  message_count: 1\n  topics_with_message_count:\n    - topic_metadata: {name: /points, type: sensor_msgs/msg/PointCloud2, serialization_format: cdr}\n      message_count: 1\n  compression_format: zstd\n  compression_mode: MESSAGE\n' | seed fuzz_depth_files metadata.yaml

mkdir -p "$build/findings"
status=0
run_one() {
  local t=$1 log="$build/findings/$1.log"
  # -rss_limit_mb / -malloc_limit_mb: a reader must never allocate what its input cannot justify.
  if "$build/tests/fuzz/$t" "$build/corpus/$t" -max_total_time="$seconds" -max_len=65536 -timeout=10 \
       -rss_limit_mb=2048 -malloc_limit_mb=1024 -artifact_prefix="$build/findings/$t-" \
       -dict=tests/fuzz/keywords.dict -print_final_stats=1 > "$log" 2>&1; then
    printf '%-18s clean   %8s runs  %6s exec/s  %s\n' "$t" "$(grep -m1 -o 'stat::number_of_executed_units: *[0-9]*' "$log" | grep -o '[0-9]*$')" \
      "$(grep -m1 -o 'stat::average_exec_per_sec: *[0-9]*' "$log" | grep -o '[0-9]*$')" "$(grep -c '' "$build/corpus/$t"/* 2>/dev/null | wc -l) corpus files"
  else
    printf '%-18s FINDING (see %s)\n' "$t" "$log"
    grep -m3 -E 'ERROR|SUMMARY|==[0-9]+==' "$log" || true
    return 1
  fi
}
jobs="${JOBS:-1}"
pids=()
for t in "${targets[@]}"; do
  run_one "$t" &
  pids+=($!)
  if [ ${#pids[@]} -ge "$jobs" ]; then
    wait "${pids[0]}" || status=1
    pids=("${pids[@]:1}")
  fi
done
for p in "${pids[@]}"; do wait "$p" || status=1; done
exit $status
