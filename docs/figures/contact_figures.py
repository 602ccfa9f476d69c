#!/usr/bin/env python3
"""Draws the pictures of docs/contacts.md from cdkit's own answers (the Python module): a box lying turned on a
smaller box, seen from above, with the two touching faces, the region where they overlap and the four points
contact_manifold keeps; and a tilted box dipping into the ground, seen from the side, with its points and depths.
Usage: PYTHONPATH=build/python /usr/bin/python3 docs/figures/contact_figures.py [out_dir=docs/images]"""
import math
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

import cdkit


def pose(R, t):
    T = np.eye(4)
    T[:3, :3] = R
    T[:3, 3] = t
    return T


def rot_z(a):
    c, s = math.cos(a), math.sin(a)
    return np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]])


def rot_x(a):
    c, s = math.cos(a), math.sin(a)
    return np.array([[1, 0, 0], [0, c, -s], [0, s, c]])


def clip(subject, clipper):
    """Sutherland-Hodgman in 2D (for the drawing only: the overlap region to shade)."""
    out = subject
    for i in range(len(clipper)):
        a, b = clipper[i], clipper[(i + 1) % len(clipper)]
        inside = lambda p: (b[0] - a[0]) * (p[1] - a[1]) - (b[1] - a[1]) * (p[0] - a[0]) >= 0
        src, out = out, []
        for j in range(len(src)):
            p, q = src[j - 1], src[j]
            if inside(q):
                if not inside(p):
                    out.append(cross(p, q, a, b))
                out.append(q)
            elif inside(p):
                out.append(cross(p, q, a, b))
    return out


def cross(p, q, a, b):
    d1, d2 = q - p, b - a
    t = ((a[0] - p[0]) * d2[1] - (a[1] - p[1]) * d2[0]) / (d1[0] * d2[1] - d1[1] * d2[0])
    return p + t * d1


def main(out_dir):
    # Top view: a 1.2 x 0.8 box (the reference: its top face) under a 1.0 x 1.0 box turned by 35 degrees.
    lower_half, upper_half = np.array([0.6, 0.4, 0.3]), np.array([0.5, 0.5, 0.3])
    lower, upper = cdkit.Box(lower_half), cdkit.Box(upper_half)
    pl = pose(np.eye(3), [0, 0, -0.3])
    pu = pose(rot_z(math.radians(35)), [0.25, 0.1, 0.3 - 0.01])
    m = cdkit.contact_manifold(lower, pl, upper, pu)
    top = np.array([[-0.6, -0.4], [0.6, -0.4], [0.6, 0.4], [-0.6, 0.4]])
    corners = np.array([[-1, -1], [1, -1], [1, 1], [-1, 1]]) * 0.5
    bottom = np.array([(pu[:3, :3] @ np.array([c[0], c[1], -0.3]) + pu[:3, 3])[:2] for c in corners])
    overlap = np.array(clip(list(bottom), list(top)))
    fig, ax = plt.subplots(1, 2, figsize=(10, 4.2))
    a = ax[0]
    a.fill(*np.vstack([top, top[:1]]).T, color="#9ecae1", alpha=0.5, label="reference face (lower box's top)")
    a.plot(*np.vstack([bottom, bottom[:1]]).T, color="#de2d26", lw=2, label="incident face (upper box's bottom)")
    a.fill(*np.vstack([overlap, overlap[:1]]).T, color="#fdae6b", alpha=0.6, label=f"overlap ({len(overlap)} corners)")
    pts = np.array([p.point_b[:2] for p in m.points])
    a.scatter(pts[:, 0], pts[:, 1], s=70, color="k", zorder=5, label=f"manifold: {m.count} points kept")
    a.set_aspect("equal")
    a.set_title("Face on face, from above: the overlap's corners, reduced to four")
    a.legend(loc="lower left", fontsize=7)
    a.set_xlim(-1.0, 1.3)
    a.set_ylim(-1.0, 1.0)
    # Side view: a unit box tilted by 0.06 rad about x, dipping 1 cm into the ground: its lowest edge touches.
    ground = cdkit.Box([3.0, 3.0, 0.5])
    pg = pose(np.eye(3), [0, 0, -0.5])
    box = cdkit.Box([0.5, 0.5, 0.5])
    R = rot_x(0.06)
    low = min((R @ np.array([x, y, -0.5]))[2] for x in (-0.5, 0.5) for y in (-0.5, 0.5))
    pb = pose(R, [0, 0, -low - 0.01])
    side = cdkit.contact_manifold(ground, pg, box, pb, cdkit.ManifoldRequest(margin=0.08))
    b = ax[1]
    b.fill_between([-1.2, 1.2], -0.3, 0, color="#bdbdbd", label="ground")
    yz = [(R @ np.array([0, y, z]) + pb[:3, 3])[1:] for y, z in ((-0.5, -0.5), (0.5, -0.5), (0.5, 0.5), (-0.5, 0.5))]
    yz = np.array(yz + yz[:1])
    b.plot(yz[:, 0], yz[:, 1], color="#de2d26", lw=2, label="box (tilted 0.06 rad)")
    for p in side.points:
        colour = "k" if p.depth > 0 else "#3182bd"
        b.annotate("", xy=p.point_a[1:], xytext=p.point_b[1:], arrowprops=dict(arrowstyle="-", color=colour, lw=1.5))
        b.scatter([p.point_b[1]], [p.point_b[2]], color=colour, s=40, zorder=5)
        b.text(p.point_b[1] + 0.03, p.point_b[2] + 0.02, f"depth {p.depth:+.3f}", fontsize=7, color=colour)
    b.set_aspect("equal")
    b.set_xlim(-1.0, 1.0)
    b.set_ylim(-0.3, 1.1)
    b.set_title("From the side, margin 0.08:\ndipping points (black), speculative (blue)")
    b.legend(loc="upper left", fontsize=7)
    fig.tight_layout()
    fig.savefig(f"{out_dir}/contact_manifold.png", dpi=110)


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else "docs/images")
