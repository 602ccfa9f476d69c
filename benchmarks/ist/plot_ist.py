#!/usr/bin/python3
"""Draws the inner sphere tree figures of docs/ist.md from the CSV files of `cdkit_bench_ist --plots DIR`.

    cdkit_bench_ist --plots /tmp/ist_plots
    /usr/bin/python3 benchmarks/ist/plot_ist.py /tmp/ist_plots docs/images

Writes ist_section_1k.png, ist_section_10k.png, ist_levels.png and ist_path.png. Needs only matplotlib.
"""
import csv
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.collections import LineCollection, PatchCollection, PolyCollection  # noqa: E402
from matplotlib.patches import Circle  # noqa: E402


def rows(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def save(fig, out_dir, name, dpi=100):
    path = os.path.join(out_dir, name)
    fig.savefig(path, dpi=dpi)
    plt.close(fig)
    # Palette PNGs are a third of the size; Pillow comes with matplotlib.
    from PIL import Image
    Image.open(path).convert("RGB").quantize(colors=64).save(path, optimize=True)
    print(path, os.path.getsize(path), "bytes")


def section(in_dir, out_dir, count, name):
    data = rows(os.path.join(in_dir, "ist_section_%d.csv" % count))
    circles = [Circle((float(r["x0"]), float(r["y0"])), float(r["x1_or_r"])) for r in data if r["kind"] == "circle"]
    segments = [((float(r["x0"]), float(r["y0"])), (float(r["x1_or_r"]), float(r["y1"])))
                for r in data if r["kind"] == "segment"]
    fig, ax = plt.subplots(figsize=(5.5, 5.5))
    ax.add_collection(PatchCollection(circles, facecolor="#9ecae1", edgecolor="#08519c", linewidth=0.3))
    ax.add_collection(LineCollection(segments, colors="black", linewidths=0.8))
    ax.set_aspect("equal")
    ax.autoscale_view()
    ax.set_title("Bunny, %d inner spheres: section z = 0\n(%d circles; black: the mesh's section)" % (count, len(circles)),
                 fontsize=10)
    fig.tight_layout()
    save(fig, out_dir, name)


def levels(in_dir, out_dir):
    data = rows(os.path.join(in_dir, "ist_levels.csv"))
    tris = [[(float(r["x0"]), float(r["y0"])), (float(r["x1_or_r"]), float(r["y1"])), (float(r["x2"]), float(r["y2"]))]
            for r in data if r["kind"] == "triangle"]
    fig, axes = plt.subplots(1, 3, figsize=(12, 4.3))
    colours = {1: "#d62728", 2: "#2ca02c", 3: "#1f77b4"}
    for ax, level in zip(axes, (1, 2, 3)):
        ax.add_collection(PolyCollection(tris, facecolor="#dddddd", edgecolor="#dddddd", linewidth=0.3, antialiased=False))
        spheres = [Circle((float(r["x0"]), float(r["y0"])), float(r["x1_or_r"]))
                   for r in data if r["kind"] == "sphere" and int(r["level"]) == level]
        ax.add_collection(PatchCollection(spheres, facecolor="none", edgecolor=colours[level], linewidth=0.6))
        ax.set_aspect("equal")
        ax.autoscale_view()
        ax.set_title("level %d: %d bounding spheres" % (level, len(spheres)), fontsize=10)
    fig.suptitle("Inner sphere tree of the bunny (10k spheres, out-degree 8), projected on the xy plane", fontsize=11)
    fig.tight_layout()
    save(fig, out_dir, "ist_levels.png", dpi=90)


def path_plot(in_dir, out_dir):
    data = rows(os.path.join(in_dir, "ist_path.csv"))
    fig, (ax1, ax2) = plt.subplots(2, 1, figsize=(7, 6), sharex=True)
    summary = []
    for steps, style in ((1000, "-"), (250, ".")):
        sel = [r for r in data if int(r["steps"]) == steps]
        x = [float(r["x"]) for r in sel]
        force = [float(r["force"]) for r in sel]
        torque = [float(r["torque"]) for r in sel]
        fvec = [(float(r["fx"]), float(r["fy"]), float(r["fz"])) for r in sel]
        jump = max(sum((a - b) ** 2 for a, b in zip(fvec[i], fvec[i - 1])) ** 0.5 for i in range(1, len(fvec)))
        fmax = max(force)
        summary.append((steps, jump, fmax))
        kw = dict(markersize=2) if style == "." else dict(linewidth=1)
        ax1.plot(x, force, style, label="%d steps: largest jump |ΔF| %.2e (%.2f%% of max |F|)" % (steps, jump, 100 * jump / fmax), **kw)
        ax2.plot(x, torque, style, label="%d steps" % steps, **kw)
    ax1.set_ylabel("|force on B|  (stiffness 1)")
    ax2.set_ylabel("|torque on B| about its origin")
    ax2.set_xlabel("x of B (moving towards -x, turning 0.5 rad about y)")
    ax1.legend(fontsize=8)
    ax2.legend(fontsize=8)
    ax1.invert_xaxis()
    ax1.set_title("Penalty force along a smooth path (bunny vs bunny, 10k spheres)", fontsize=10)
    fig.tight_layout()
    save(fig, out_dir, "ist_path.png")
    for steps, jump, fmax in summary:
        print("path, %d steps: max |F| %.6g, largest jump between adjacent steps %.6g (%.3f%%)" % (steps, fmax, jump, 100 * jump / fmax))


def main():
    if len(sys.argv) != 3:
        sys.exit("usage: plot_ist.py CSV_DIR PNG_DIR")
    in_dir, out_dir = sys.argv[1], sys.argv[2]
    os.makedirs(out_dir, exist_ok=True)
    section(in_dir, out_dir, 1000, "ist_section_1k.png")
    section(in_dir, out_dir, 10000, "ist_section_10k.png")
    levels(in_dir, out_dir)
    path_plot(in_dir, out_dir)


if __name__ == "__main__":
    main()
