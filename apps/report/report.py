#!/usr/bin/python3
"""Draws the plots of a cleanmap output folder and writes a self-contained report.html.

Called by `cleanmap report OUT` as `report.py OUT DATA_JSON [VIEWER_JS]`: the binary computes the
numbers into DATA_JSON (a temporary file it removes afterwards); this script draws them
(matplotlib), embeds the PNGs as base64 and inlines VIEWER_JS, the bundled three.js 3D view,
with the clouds it shows. Nothing on the page is fetched from anywhere.
"""
import base64
import html
import json
import math
import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

# The top view shows the trajectory's surroundings: a lidar's useful returns reach some tens of
# metres, and at +-100 m (what every far return spans) a removed pedestrian is a single pixel.
TOP_VIEW_MARGIN_M = 30.0
INSET_CELL_M = 10.0  # the inset zooms to the 10 m square holding the most removed points


def fmt(v):
    """A number as a person reads it: 3 significant digits, whole numbers above 1000."""
    if v is None:
        return "n/a"  # null: a metric with nothing to measure
    if isinstance(v, bool) or not isinstance(v, (int, float)):
        return html.escape(str(v))
    if isinstance(v, int):
        return f"{v:,}"
    if not math.isfinite(v):
        return "n/a"
    if abs(v) >= 1000:
        return f"{v:,.0f}"
    return f"{v:.3g}"


def table(rows, head):
    h = "".join(f"<th>{html.escape(str(c))}</th>" for c in head)
    body = "".join("<tr>" + "".join(f"<td>{fmt(c)}</td>" for c in r) + "</tr>" for r in rows)
    return f"<table><tr>{h}</tr>{body}</table>"


def left_out(what, why):
    return f'<p class="omitted"><b>{html.escape(what)}</b>: not shown, {html.escape(why)}.</p>'


def save(fig, path):
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


def xy(points):
    return [p[0] for p in points], [p[1] for p in points]


def trajectory_plot(d, out):
    fig, ax = plt.subplots(figsize=(6, 5))
    est, ref = d.get("estimate") or [], d.get("reference") or []
    if ref:
        ax.plot(*xy(ref), "k-", lw=2, label="reference")
    if est:
        ax.plot(*xy(est), "r--", lw=1.5, label="estimate")
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    ax.set_title("Trajectory, top view")
    ax.axis("equal")
    if ref or est:  # matplotlib warns on stderr about a legend without entries
        ax.legend()
    return save(fig, out / "trajectory.png")


def error_plot(d, out):
    fig, ax = plt.subplots(figsize=(6, 3.5))
    ax.plot(d["distance"], d["ape_per_pose"], "b.-")
    ax.set_xlabel("distance travelled [m]")
    ax.set_ylabel("position error after alignment [m]")
    ax.set_title("Error vs distance")
    return save(fig, out / "error_vs_distance.png")


def scans_plot(d, out):
    scans = d.get("per_scan") or []
    fig, (a1, a2) = plt.subplots(2, 1, figsize=(6, 5), sharex=True)
    a1.bar(range(len(scans)), [s["dynamic"] for s in scans], color="tab:red")
    a1.set_ylabel("dynamic points")
    a1.set_title("Per scan")
    a2.plot(range(len(scans)), [1e3 * s.get("scoring_seconds", 0.0) for s in scans], "k.-")
    a2.set_ylabel("scoring [ms]")
    a2.set_xlabel("scan")
    return save(fig, out / "per_scan.png")


def cloud(d, key):
    c = d.get(key) or {}
    return np.array(c.get("xyz") or [], dtype=np.float64).reshape(-1, 3)


def view_box(d, static):
    """x0, x1, y0, y1 of the trajectory plus the margin, else of the static cloud."""
    traj = np.array(d.get("estimate") or [], dtype=np.float64).reshape(-1, 3)
    src = traj if len(traj) else static
    if not len(src):
        return -10.0, 10.0, -10.0, 10.0
    if len(traj):
        lo, hi, m = src[:, :2].min(axis=0), src[:, :2].max(axis=0), TOP_VIEW_MARGIN_M
    else:  # the cloud without its farthest 1% (a few returns at 120 m would set the scale)
        lo, hi, m = np.percentile(src[:, :2], 1, axis=0), np.percentile(src[:, :2], 99, axis=0), 0.0
    return lo[0] - m, hi[0] + m, lo[1] - m, hi[1] + m


def densest_cell(dyn):
    """Centre of the INSET_CELL_M square with the most removed points, or None."""
    if len(dyn) < 10:
        return None
    keys = np.floor(dyn[:, :2] / INSET_CELL_M).astype(np.int64)
    cells, counts = np.unique(keys, axis=0, return_counts=True)
    return (cells[np.argmax(counts)] + 0.5) * INSET_CELL_M


def scatter_map(ax, static, dyn, red_size):
    ax.scatter(static[:, 0], static[:, 1], s=0.3, c="0.35", linewidths=0, rasterized=True)
    if red_size:
        ax.scatter(dyn[:, 0], dyn[:, 1], s=red_size, c="red", linewidths=0, rasterized=True)


def map_plot(d, out):
    static, dyn = cloud(d, "static_cloud"), cloud(d, "dynamic_cloud")
    x0, x1, y0, y1 = view_box(d, static)
    fig, (a1, a2) = plt.subplots(1, 2, figsize=(11, 5.2), sharex=True, sharey=True)
    scatter_map(a1, static, dyn, 0)
    a1.set_title("Clean map (static points)")
    scatter_map(a2, static, dyn, 2.0)
    a2.set_title("Removed points in red")
    traj = np.array(d.get("estimate") or [], dtype=np.float64).reshape(-1, 3)
    for a in (a1, a2):
        if len(traj):
            a.plot(traj[:, 0], traj[:, 1], "-", c="tab:blue", lw=1)
        a.set_xlim(x0, x1)
        a.set_ylim(y0, y1)
        a.set_aspect("equal", adjustable="box")
        a.set_xlabel("x [m]")
    a1.set_ylabel("y [m]")
    centre = densest_cell(dyn)
    if centre is not None:
        inset = a2.inset_axes([0.63, 0.63, 0.35, 0.35])
        scatter_map(inset, static, dyn, 4.0)
        h = INSET_CELL_M / 2
        inset.set_xlim(centre[0] - h, centre[0] + h)
        inset.set_ylim(centre[1] - h, centre[1] + h)
        inset.set_aspect("equal")
        inset.set_xticks([])
        inset.set_yticks([])
        inset.text(0.03, 0.03, f"densest removals, {INSET_CELL_M:.0f} m square", fontsize=6,
                   transform=inset.transAxes, bbox={"facecolor": "white", "edgecolor": "none", "pad": 1})
        a2.indicate_inset_zoom(inset, edgecolor="black")
    return save(fig, out / "maps.png")


def packed(points, origin):
    """Base64 of float32 x, y, z triples relative to `origin` (float32 holds UTM only to metres)."""
    return base64.b64encode((points - origin).astype("<f4").tobytes()).decode()


def viewer_section(d, viewer):
    if viewer is None or not viewer.exists():
        return left_out("Interactive 3D view", "its script was not built (run scripts/install-deps.sh, "
                        "which installs three.js with npm, then build again)")
    static, dyn = cloud(d, "static_cloud"), cloud(d, "dynamic_cloud")
    if not len(static) and not len(dyn):
        return left_out("Interactive 3D view", "the output has no map cloud")
    traj = np.array(d.get("estimate") or [], dtype=np.float64).reshape(-1, 3)
    origin = traj.mean(axis=0) if len(traj) else (static if len(static) else dyn).mean(axis=0)
    blocks = "".join(f'<script type="application/octet-stream" id="cloud-{k}">{packed(p, origin)}</script>'
                     for k, p in (("static", static), ("dynamic", dyn), ("trajectory", traj)))
    code = viewer.read_text().replace("</script", "<\\/script")
    return (f"<h2>Clean map in 3D</h2><p>{fmt(len(static))} map points coloured by height, "
            f"{fmt(len(dyn))} removed points in red, the trajectory in black (a sample of each). "
            f"Drag to turn, right-drag to pan, wheel to zoom.</p><div id=\"map3d\"></div>{blocks}"
            f"<script>{code}</script>")


def kitti_section(d):
    k = d.get("kitti")
    if not k:
        return ""
    rows = [[r["length"], r["t_err_percent"], r["r_err_deg_per_100m"]] for r in k["by_length"]
            if r["t_err_percent"] is not None]
    if not rows:
        travelled = (d.get("distance") or [0])[-1]
        return left_out("KITTI segment errors", f"they need segments of 100 m or more and the reference "
                        f"trajectory is {fmt(float(travelled))} m long")
    rows.append(["overall", k["t_err_percent"], k["r_err_deg_per_100m"]])
    return "<h2>KITTI segment errors</h2>" + table(rows, ["length [m]", "t_err [%]", "r_err [deg/100 m]"])


def trajectory_section(d):
    if not d.get("ape"):
        return ""
    stats = [[name, d[key]["rmse"], d[key]["mean"], d[key]["median"], d[key]["max"]]
             for name, key in (("APE (SE3) translation", "ape"), ("RPE (1 frame) translation", "rpe"))]
    return "<h2>Trajectory errors</h2>" + table(stats, ["metric [m]", "RMSE", "mean", "median", "max"])


def run_section(d):
    summary = d.get("summary", {})
    counts = [[k, summary[k]] for k in ("scans", "points", "static_points", "dynamic_points",
                                         "unscored_points", "seconds", "scans_per_second") if k in summary]
    if "moving" in summary:
        m = summary["moving"]
        counts += [["moving IoU", m["iou"]], ["moving precision", m["precision"]], ["moving recall", m["recall"]]]
    return "<h2>Run</h2>" + table(counts, ["", "value"])


def banner(d):
    if d.get("complete") is not False:
        return ""
    problems = "".join(f"<li>{html.escape(p)}</li>" for p in d.get("problems", []))
    return (f'<div class="failed"><b>This run did not complete.</b> {html.escape(d.get("error", ""))}'
            f'<br>The numbers and plots below show only what it wrote before it stopped.'
            f'{"<ul>" + problems + "</ul>" if problems else ""}</div>')


def figure(path):
    return (f'<figure><img alt="{path.stem}" '
            f'src="data:image/png;base64,{base64.b64encode(path.read_bytes()).decode()}"></figure>')


def plots(d, folder):
    """The maps first (what a run is for), then the trajectory and per-scan plots side by side."""
    small, notes = [], ""
    if d.get("estimate") or d.get("reference"):
        small.append(figure(trajectory_plot(d, folder)))
    else:
        notes += left_out("Trajectory", "this run wrote no poses (it used given ones: see the input's pose file)")
    if d.get("ape_per_pose"):
        small.append(figure(error_plot(d, folder)))
    elif d.get("estimate"):
        notes += left_out("Error vs distance", "there are no reference poses (give --ref FILE, or keep poses.txt "
                          "in the input folder)")
    small.append(figure(scans_plot(d, folder)))
    return (f"<h2>Map, top view</h2>{figure(map_plot(d, folder))}", f'<h2>Trajectory and scans</h2>{notes}'
            f'<div class="row">{"".join(small)}</div>')


STYLE = """body{font-family:sans-serif;margin:2em auto;max-width:1180px;padding:0 1em}
table{border-collapse:collapse;margin:1em 0}td,th{border:1px solid #bbb;padding:3px 8px;text-align:right}
figure{margin:1em 0}img{max-width:100%;height:auto}.row{display:flex;flex-wrap:wrap;gap:0 1em}
.row figure{flex:1 1 360px;max-width:560px}#map3d{width:100%;border:1px solid #bbb}
#map3d canvas{display:block;max-width:100%}.omitted{color:#555}
.failed{background:#fdd;border:2px solid #c00;padding:1em;margin:1em 0}"""


def main(out_dir, data_json, viewer=None):
    out = Path(out_dir)
    d = json.loads(Path(data_json).read_text())
    folder = out / "report"
    maps, others = plots(d, folder)
    body = (banner(d) + f"<p>{html.escape(str(out.resolve()))}</p>" + run_section(d) + maps
            + viewer_section(d, Path(viewer) if viewer else None) + trajectory_section(d) + kitti_section(d)
            + others)
    page = (f'<!DOCTYPE html><html><head><meta charset="utf-8"><title>cleanmap report</title>'
            f'<style>{STYLE}</style></head><body><h1>cleanmap report</h1>{body}</body></html>')
    (out / "report.html").write_text(page)


if __name__ == "__main__":
    main(*sys.argv[1:4])
