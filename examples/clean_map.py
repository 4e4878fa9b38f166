"""A clean static map from a KITTI folder: python3 examples/clean_map.py SEQUENCE OUT.pcd [PRESET]

Pushes every scan, with its pose, through the online mapper and writes the static points it
kept (x y z, ASCII PCD). Needs the module on PYTHONPATH (build/python, or installed)."""
import sys

import numpy as np

import cleanmap

sequence, out = sys.argv[1], sys.argv[2]
cfg = cleanmap.Config.from_preset(sys.argv[3] if len(sys.argv) > 3 else None)
mapper = cleanmap.OnlineMapper(cfg)
removed = 0
for scan in cleanmap.read_log(sequence):
    for result in mapper.push(scan.points, times=scan.times, pose=scan.pose, stamp=scan.stamp):
        removed += int((result.labels == 251).sum())
removed += sum(int((r.labels == 251).sum()) for r in mapper.finish())
static = mapper.static_points()
header = f"VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\nWIDTH {len(static)}\nHEIGHT 1\nPOINTS {len(static)}\nDATA ascii\n"
np.savetxt(out, static, fmt="%.4f", header=header.rstrip("\n"), comments="")
print(f"{out}: {len(static)} static points; {removed} moving points removed")
