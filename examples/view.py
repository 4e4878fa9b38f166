"""Static points grey, removed points red, in Open3D: python3 examples/view.py RUN [--screenshot FILE]

RUN is a `cleanmap run` output folder (map_static.pcd, map_dynamic.pcd). --screenshot renders
off-screen to a PNG instead of opening a window (no display needed)."""
import argparse
import pathlib

import numpy as np
import open3d as o3d

parser = argparse.ArgumentParser()
parser.add_argument("run", type=pathlib.Path)
parser.add_argument("--screenshot", type=pathlib.Path, help="write a PNG, off-screen")
args = parser.parse_args()


def cloud(name, colour):
    pcd = o3d.io.read_point_cloud(str(args.run / name))
    pcd.paint_uniform_color(colour)
    return pcd


def render_offscreen(static, removed, png):
    renderer = o3d.visualization.rendering.OffscreenRenderer(1280, 800)
    material = o3d.visualization.rendering.MaterialRecord()
    material.shader = "defaultUnlit"
    material.point_size = 2.0
    renderer.scene.set_background([1, 1, 1, 1])
    renderer.scene.add_geometry("static", static, material)
    renderer.scene.add_geometry("removed", removed, material)
    box = static.get_axis_aligned_bounding_box()
    centre, extent = box.get_center(), box.get_extent()
    eye = centre + np.array([-0.6, -0.6, 0.8]) * float(np.max(extent))
    renderer.setup_camera(60.0, centre, eye, [0, 0, 1])
    o3d.io.write_image(str(png), renderer.render_to_image())


def render_top_down(static, removed, png):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(12.8, 8.0), dpi=100)
    for pcd, size in ((static, 0.05), (removed, 0.5)):
        xyz, rgb = np.asarray(pcd.points), np.asarray(pcd.colors)
        ax.scatter(xyz[:, 0], xyz[:, 1], s=size, c=rgb, linewidths=0)
    ax.set_aspect("equal")
    ax.set_axis_off()
    fig.savefig(png, bbox_inches="tight")


static = cloud("map_static.pcd", [0.6, 0.6, 0.6])
removed = cloud("map_dynamic.pcd", [0.9, 0.1, 0.1])
print(f"{args.run}: {len(static.points)} static points (grey), {len(removed.points)} removed (red)")
if args.screenshot is None:
    o3d.visualization.draw_geometries([static, removed], window_name=f"cleanmap: {args.run}")
else:
    try:
        render_offscreen(static, removed, args.screenshot)
    except RuntimeError as e:
        # Debian's Open3D 0.16 is built without headless EGL: draw the same view from above
        # with matplotlib (Agg, no display) instead.
        print("Open3D cannot render off-screen here (" + str(e).split("Error] ")[-1].split(":")[0] + "): matplotlib instead")
        render_top_down(static, removed, args.screenshot)
    print(f"wrote {args.screenshot}")
