#!/usr/bin/env python3
"""Draws the pictures of docs/bvh.md from the nodes the example tree_levels writes: the levels of Aabb, Obb and
sphere trees over the bunny (SAH split), and one level of the Obb tree under the three split strategies.
Each node is projected onto the xy plane (the bunny's side view) over the mesh's projected triangles.
Usage:
  build/examples/tree_levels --csv /tmp/levels.csv
  /usr/bin/python3 docs/figures/bvh_figures.py /tmp/levels.csv [mesh.obj=data/bunny.obj] [out_dir=docs/images]"""
import csv
import sys
from itertools import product

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np
from hull2d import hull as hull2d
from matplotlib.collections import PolyCollection
from matplotlib.patches import Circle, Polygon


def load_obj(path):
    """Vertices and triangles of a triangulated OBJ file (v and f lines only)."""
    vertices, triangles = [], []
    with open(path) as f:
        for line in f:
            parts = line.split()
            if not parts:
                continue
            if parts[0] == "v":
                vertices.append([float(x) for x in parts[1:4]])
            elif parts[0] == "f":
                triangles.append([int(p.split("/")[0]) - 1 for p in parts[1:4]])
    return np.array(vertices), np.array(triangles)


def node_patch(row, color):
    """The node's outline projected onto xy: a ball's circle, or the hull of a box's eight projected corners."""
    c = np.array([row["cx"], row["cy"], row["cz"]], dtype=float)
    half = np.array([row["hx"], row["hy"], row["hz"]], dtype=float)
    if row["bv"] == "sphere":
        return Circle(c[:2], half[0], fill=False, edgecolor=color, linewidth=0.8)
    axes = np.array([[float(row[f"a{r}{k}"]) for k in range(3)] for r in range(3)])
    corners = [c + axes @ (half * np.array(s)) for s in product((-1, 1), repeat=3)]
    return Polygon(hull2d([p[:2] for p in corners]), closed=True, fill=False, edgecolor=color, linewidth=0.8)


def draw_panel(ax, vertices, triangles, rows, title):
    ax.add_collection(PolyCollection(vertices[triangles][:, :, :2], facecolor="0.85", edgecolor="0.75", linewidth=0.1))
    colors = plt.cm.tab10(np.arange(10))
    for i, row in enumerate(rows):
        ax.add_patch(node_patch(row, colors[i % 10]))
    lo, hi = vertices[:, :2].min(axis=0), vertices[:, :2].max(axis=0)
    pad = 0.35 * (hi - lo).max()
    ax.set_xlim(lo[0] - pad, hi[0] + pad)
    ax.set_ylim(lo[1] - pad, hi[1] + pad)
    ax.set_aspect("equal")
    ax.set_xticks([])
    ax.set_yticks([])
    ax.set_title(title, fontsize=9)


def main():
    csv_path = sys.argv[1]
    mesh_path = sys.argv[2] if len(sys.argv) > 2 else "data/bunny.obj"
    out_dir = sys.argv[3] if len(sys.argv) > 3 else "docs/images"
    with open(csv_path) as f:
        nodes = list(csv.DictReader(f))
    vertices, triangles = load_obj(mesh_path)

    def select(bv, split, level):
        return [r for r in nodes if r["bv"] == bv and r["split"] == split and int(r["level"]) == level]

    levels = [2, 3, 4, 6]
    fig, axes = plt.subplots(3, len(levels), figsize=(2.6 * len(levels), 7.8))
    for i, bv in enumerate(["aabb", "obb", "sphere"]):
        for j, level in enumerate(levels):
            rows = select(bv, "sah", level)
            draw_panel(axes[i][j], vertices, triangles, rows, f"{bv}, level {level} ({len(rows)} nodes)")
    fig.suptitle("Levels of SAH-built trees over the bunny (level 1 is the root), side view", fontsize=10)
    fig.tight_layout()
    fig.savefig(f"{out_dir}/bvh_levels.png", dpi=110)

    fig, axes = plt.subplots(1, 3, figsize=(7.8, 2.9))
    for j, split in enumerate(["median", "sah", "pca_volume"]):
        rows = select("obb", split, 5)
        draw_panel(axes[j], vertices, triangles, rows, f"obb, {split}, level 5 ({len(rows)} nodes)")
    fig.tight_layout()
    fig.savefig(f"{out_dir}/bvh_splits.png", dpi=110)


if __name__ == "__main__":
    main()
