#!/usr/bin/env python3
"""Draws the pictures of docs/contacts.md from cdkit's own answers (the Python module): a box lying turned on a
smaller box, seen from above, with the two touching faces, the region where they overlap and the four points
contact_manifold keeps; a tilted box dipping into the ground, seen from the side, with its points and depths; and two
crossing bunnies cut through the normal of their penetration depth.
Usage: PYTHONPATH=build/python /usr/bin/python3 docs/figures/contact_figures.py [out_dir=docs/images]"""
import math
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

import cdkit
from poses import pose, rot_z, rot_x


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


def slice_mesh(v, f, origin, normal):
    """Segments where the plane through `origin` with `normal` cuts the triangles (v: posed vertices)."""
    d = (v - origin) @ normal
    out = []
    for tri in f:
        pts = []
        for i in range(3):
            a, b = tri[i], tri[(i + 1) % 3]
            if (d[a] < 0) != (d[b] < 0):
                t = d[a] / (d[a] - d[b])
                pts.append(v[a] + t * (v[b] - v[a]))
        if len(pts) == 2:
            out.append(pts)
    return out


def mesh_depth_figure(out_dir):
    """Two bunnies crossing: the cut through the contact along the depth's normal, B where it is, and B moved by
    depth x normal (its surface just clear of A's), with the pair that separates last."""
    root = __file__.rsplit("/docs/", 1)[0]
    v, f = cdkit.load_mesh(f"{root}/data/bunny.obj")
    v = (v - (v.min(0) + v.max(0)) / 2) * (2 / (v.max(0) - v.min(0)).max())
    model = cdkit.MeshModel(v, f)
    rng = np.random.default_rng(4)
    q, _ = np.linalg.qr(rng.normal(size=(3, 3)))
    R = q * np.sign(np.linalg.det(q))
    u = np.array([1.0, 0.25, 0.1])
    u /= np.linalg.norm(u)
    pa = pose(np.eye(3), [0, 0, 0])
    lo, hi = 0.0, 4.0
    for _ in range(50):  # bisection to touching along u
        mid = (lo + hi) / 2
        lo, hi = (mid, hi) if cdkit.collide(model, pa, model, pose(R, mid * u)).colliding else (lo, mid)
    pb = pose(R, (hi - 0.15) * u)
    r = cdkit.penetration_depth(model, pa, model, pb, refine_steps=3)
    n = np.asarray(r.normal)
    side = np.cross(n, [0, 0, 1.0])
    side /= np.linalg.norm(side)
    cut_normal = np.cross(n, side)  # the cut contains n and `side`
    origin = np.asarray(r.point_b)
    vb = v @ R.T + pb[:3, 3]
    to2d = lambda p: np.array([(p - origin) @ side, (p - origin) @ n])
    fig, ax = plt.subplots(figsize=(6.4, 5.4))
    for verts, style, label in ((v, dict(color="#3182bd"), "A"), (vb, dict(color="#e6550d"), "B (crossing A)"),
                                (vb + r.depth * n, dict(color="#e6550d", ls="--", alpha=0.6), "B moved by depth·normal")):
        for k, seg in enumerate(slice_mesh(verts, f, origin, cut_normal)):
            p0, p1 = to2d(seg[0]), to2d(seg[1])
            ax.plot([p0[0], p1[0]], [p0[1], p1[1]], lw=1.2, label=label if k == 0 else None, **style)
    a2, b2 = to2d(np.asarray(r.point_a)), to2d(np.asarray(r.point_b))
    ax.annotate("", xy=a2, xytext=b2, arrowprops=dict(arrowstyle="->", lw=1.8, color="k"))
    ax.plot(*b2, "ko", ms=4)
    ax.plot(*a2, "k^", ms=5)
    ax.text(b2[0] + 0.03, (a2[1] + b2[1]) / 2, f"depth {r.depth:.3f}", fontsize=9)
    ax.set_aspect("equal")
    ax.set_title("Mesh penetration depth (cut through the normal)", fontsize=10)
    ax.legend(loc="lower left", fontsize=8)
    fig.tight_layout()
    fig.savefig(f"{out_dir}/mesh_depth.png", dpi=110)


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else "docs/images")
    mesh_depth_figure(sys.argv[1] if len(sys.argv) > 1 else "docs/images")
