#!/usr/bin/python3
"""Draws the plots of a cleanmap output folder and writes a self-contained report.html.

Called by `cleanmap report OUT`, which computes the numbers and writes OUT/report/data.json;
this script only draws (matplotlib) and lays out the page (PNG files embedded as base64).
"""
import base64
import html
import json
import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def save(fig, path):
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


def trajectory_plot(d, out):
    fig, ax = plt.subplots(figsize=(6, 5))
    est = d.get("estimate") or []
    ref = d.get("reference") or []
    if ref:
        ax.plot([p[0] for p in ref], [p[1] for p in ref], "k-", lw=2, label="reference")
    if est:
        ax.plot([p[0] for p in est], [p[1] for p in est], "r--", lw=1.5, label="estimate")
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    ax.set_title("Trajectory, top view")
    ax.axis("equal")
    if ref or est:  # matplotlib warns on stderr about a legend without entries
        ax.legend()
    return save(fig, out / "trajectory.png")


def error_plot(d, out):
    fig, ax = plt.subplots(figsize=(6, 3.5))
    errors = d.get("ape_per_pose") or []
    dist = d.get("distance") or []
    if errors:
        ax.plot(dist, errors, "b.-")
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


def map_plot(d, out):
    fig, (a1, a2) = plt.subplots(1, 2, figsize=(11, 5), sharex=True, sharey=True)
    s = d.get("static_xy") or [[], []]
    dyn = d.get("dynamic_xy") or [[], []]
    a1.scatter(s[0], s[1], s=0.2, c="0.3", linewidths=0)
    a1.set_title("Clean map (static points)")
    a2.scatter(s[0], s[1], s=0.2, c="0.3", linewidths=0)
    a2.scatter(dyn[0], dyn[1], s=0.6, c="red", linewidths=0)
    a2.set_title("Raw map: removed points in red")
    for a in (a1, a2):
        a.set_aspect("equal")
        a.set_xlabel("x [m]")
    a1.set_ylabel("y [m]")
    return save(fig, out / "maps.png")


def cell(c):
    return "n/a" if c is None else html.escape(str(c))  # null: a metric with nothing to measure


def table(rows, head):
    h = "".join(f"<th>{cell(c)}</th>" for c in head)
    body = "".join("<tr>" + "".join(f"<td>{cell(c)}</td>" for c in r) + "</tr>" for r in rows)
    return f"<table><tr>{h}</tr>{body}</table>"


def main(out_dir):
    out = Path(out_dir)
    d = json.loads((out / "report" / "data.json").read_text())
    pngs = [trajectory_plot(d, out / "report"), error_plot(d, out / "report"),
            scans_plot(d, out / "report"), map_plot(d, out / "report")]
    images = "".join(
        f'<figure><img alt="{p.stem}" src="data:image/png;base64,{base64.b64encode(p.read_bytes()).decode()}"></figure>'
        for p in pngs)
    tables = ""
    if d.get("kitti"):
        k = d["kitti"]
        tables += "<h2>KITTI segment errors</h2>" + table(
            [[r["length"], r["t_err_percent"], r["r_err_deg_per_100m"]] for r in k["by_length"]]
            + [["overall", k["t_err_percent"], k["r_err_deg_per_100m"]]],
            ["length [m]", "t_err [%]", "r_err [deg/100 m]"])
    if d.get("ape"):
        tables += "<h2>Trajectory errors</h2>" + table(
            [["APE (SE3) translation", d["ape"]["rmse"], d["ape"]["mean"], d["ape"]["median"], d["ape"]["max"]],
             ["RPE (1 frame) translation", d["rpe"]["rmse"], d["rpe"]["mean"], d["rpe"]["median"], d["rpe"]["max"]]],
            ["metric [m]", "RMSE", "mean", "median", "max"])
    summary = d.get("summary", {})
    counts = [[k, summary[k]] for k in ("scans", "points", "static_points", "dynamic_points",
                                         "unscored_points", "seconds", "scans_per_second") if k in summary]
    if "moving" in summary:
        m = summary["moving"]
        counts += [["moving IoU", m["iou"]], ["moving precision", m["precision"]], ["moving recall", m["recall"]]]
    tables += "<h2>Run</h2>" + table(counts, ["", "value"])
    banner = ""
    if d.get("complete") is False:
        problems = "".join(f"<li>{html.escape(p)}</li>" for p in d.get("problems", []))
        banner = (f'<div class="failed"><b>This run did not complete.</b> {html.escape(d.get("error", ""))}'
                  f'<br>The numbers and plots below show only what it wrote before it stopped.'
                  f'{"<ul>" + problems + "</ul>" if problems else ""}</div>')
    page = f"""<!DOCTYPE html><html><head><meta charset="utf-8"><title>cleanmap report</title>
<style>body{{font-family:sans-serif;margin:2em;max-width:1200px}}table{{border-collapse:collapse;margin:1em 0}}
td,th{{border:1px solid #bbb;padding:3px 8px;text-align:right}}img{{max-width:100%}}
.failed{{background:#fdd;border:2px solid #c00;padding:1em;margin:1em 0}}</style></head>
<body><h1>cleanmap report</h1>{banner}<p>{html.escape(str(out.resolve()))}</p>{tables}{images}</body></html>"""
    (out / "report.html").write_text(page)


if __name__ == "__main__":
    main(sys.argv[1])
