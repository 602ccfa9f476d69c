#!/usr/bin/env python3
"""Draws the two pictures of docs/convex.md: the Minkowski difference A - B of two convex polygons with the
point of it nearest the origin (what GJK computes), and the external Voronoi regions of a convex polygon
(what closest-feature tracking walks). 2D for legibility; the 3D algorithms work the same way.
Usage: /usr/bin/python3 docs/figures/convex_figures.py [out_dir=docs/images]"""
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np
from hull2d import hull


def closest_on_segment(p, a, b):
    d = b - a
    t = np.clip(np.dot(p - a, d) / np.dot(d, d), 0.0, 1.0)
    return a + t * d, t


def closest_on_polygon(p, poly):
    best = None
    for i in range(len(poly)):
        q, t = closest_on_segment(p, poly[i], poly[(i + 1) % len(poly)])
        dist = np.linalg.norm(q - p)
        if best is None or dist < best[0]:
            best = (dist, q, i, t)
    return best


def closed(poly):
    return np.vstack([poly, poly[:1]])


def minkowski_figure(path):
    A = np.array([[0.0, 0.0], [1.6, -0.3], [2.0, 0.9], [0.7, 1.5]])
    B = np.array([[2.9, 0.4], [4.1, 0.1], [4.4, 1.3], [3.3, 1.8]])
    D = hull([a - b for a in A for b in B])
    dist, v, edge, _ = closest_on_polygon(np.zeros(2), D)
    fig, (left, right) = plt.subplots(1, 2, figsize=(10, 4.4))
    for ax in (left, right):
        ax.set_aspect("equal")
        ax.grid(True, lw=0.3)
    left.fill(*closed(A).T, alpha=0.35, color="tab:blue", label="A")
    left.fill(*closed(B).T, alpha=0.35, color="tab:orange", label="B")
    # The closest pair of A and B realises the vector v of A - B nearest the origin.
    best = None
    for i in range(len(A)):
        for j in range(len(B)):
            for (p, poly) in ((A[i], B), (B[j], A)):
                d, q, _, _ = closest_on_polygon(p, poly)
                if best is None or d < best[0]:
                    best = (d, p, q)
    _, p, q = best
    left.plot([p[0], q[0]], [p[1], q[1]], "k--", lw=1)
    left.plot(*p, "ko", ms=3)
    left.plot(*q, "ko", ms=3)
    left.set_title("A and B in the world, distance %.3f" % best[0])
    left.legend(loc="upper left")
    right.fill(*closed(D).T, alpha=0.35, color="tab:green", label="A − B = {a − b}")
    right.plot(0, 0, "k+", ms=12, mew=1.5)
    right.annotate("origin", (0, 0), textcoords="offset points", xytext=(6, -12))
    e0, e1 = D[edge], D[(edge + 1) % len(D)]
    right.plot([e0[0], e1[0]], [e0[1], e1[1]], color="tab:red", lw=2.5, label="GJK's last simplex (an edge)")
    right.annotate("", xy=v, xytext=(0, 0), arrowprops=dict(arrowstyle="->", lw=1.5))
    right.annotate("v, |v| = %.3f" % dist, v, textcoords="offset points", xytext=(6, 4))
    right.set_title("The Minkowski difference: distance = |v|")
    right.legend(loc="upper left", fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def voronoi_figure(path):
    P = np.array([[0.0, 0.0], [2.0, -0.4], [2.8, 1.0], [1.4, 2.2], [-0.4, 1.4]])
    n = len(P)
    L = 6.0
    fig, ax = plt.subplots(figsize=(6, 5.5))
    ax.set_aspect("equal")
    colours = plt.cm.tab10(np.arange(2 * n) % 10)
    normals = []
    for i in range(n):
        d = P[(i + 1) % n] - P[i]
        normals.append(np.array([d[1], -d[0]]) / np.linalg.norm(d))  # outward (counter-clockwise polygon)
    for i in range(n):
        a, b, m = P[i], P[(i + 1) % n], normals[i]
        # Edge region: the slab over the edge, bounded by the edge's two perpendiculars.
        ax.fill(*closed(np.array([a, b, b + L * m, a + L * m])).T, color=colours[2 * i], alpha=0.25, lw=0)
        # Vertex region: the wedge between the normals of the two edges that meet at vertex i + 1.
        m2 = normals[(i + 1) % n]
        ax.fill(*closed(np.array([b, b + L * m, b + L * m2])).T, color=colours[2 * i + 1], alpha=0.12, lw=0)
        ax.plot([a[0], a[0] + L * m[0]], [a[1], a[1] + L * m[1]], color="0.6", lw=0.6)
        ax.plot([b[0], b[0] + L * m[0]], [b[1], b[1] + L * m[1]], color="0.6", lw=0.6)
    ax.fill(*closed(P).T, color="0.8")
    ax.plot(*closed(P).T, "k", lw=1.2)
    for x in (np.array([3.6, 2.6]), np.array([1.0, -1.6]), np.array([-1.6, 2.6])):
        d, q, _, t = closest_on_polygon(x, P)
        kind = "vertex" if t in (0.0, 1.0) else "edge"
        ax.plot(*x, "ko", ms=4)
        ax.plot([x[0], q[0]], [x[1], q[1]], "k--", lw=1)
        ax.annotate("closest: " + kind, x, textcoords="offset points", xytext=(5, 5), fontsize=8)
    ax.set_xlim(-2.5, 4.8)
    ax.set_ylim(-2.6, 4.0)
    ax.set_title("External Voronoi regions: edge slabs and vertex wedges")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


if __name__ == "__main__":
    out = sys.argv[1] if len(sys.argv) > 1 else "docs/images"
    minkowski_figure(out + "/convex_minkowski_difference.png")
    voronoi_figure(out + "/convex_voronoi_regions.png")
    print("wrote", out + "/convex_minkowski_difference.png", out + "/convex_voronoi_regions.png")
