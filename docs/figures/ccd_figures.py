#!/usr/bin/env python3
"""Draws the pictures of docs/ccd.md: the primitive queries' time against false positives over the tolerance sweep
(from results/ccd_tolerance.csv, written by scripts/ccd-tolerance-sweep); the time of impact of a turning box cast
past a capsule, with the conservative-advancement steps (cdkit's convex_toi); and how mesh_ccd bounds a rigid
motion with swept boxes (a ribbon mesh stepping onto a ledge; the contact from cdkit's mesh_ccd).
Usage: PYTHONPATH=build/python /usr/bin/python3 docs/figures/ccd_figures.py [out_dir=docs/images]"""
import csv
import io
import math
import pathlib
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

import cdkit
from poses import pose, rot_z

ROOT = pathlib.Path(__file__).resolve().parent.parent.parent


def read_results(path):
    """Rows of a results CSV (lines starting with '#' are its provenance)."""
    text = "\n".join(l for l in path.read_text().splitlines() if not l.startswith("#"))
    return list(csv.DictReader(io.StringIO(text)))


def time_vs_fp(out_dir):
    """The tolerance sweep: false positives against median and p99 µs per query, one point per tolerance."""
    rows = read_results(ROOT / "results/ccd_tolerance.csv")
    # The combined file must hold the totals of the per-tolerance checker files it was made from.
    for r in rows:
        per = read_results(ROOT / f"results/ccd_tolerance/handcrafted_{r['tolerance']}.csv")
        total = next(p for p in per if p["file"].startswith("total") and p["kind"] == r["kind"])
        assert all(total[k] == r[k] for k in ("queries", "false_negatives", "false_positives", "median_us", "p99_us"))
    false_negatives = sum(int(r["false_negatives"]) for r in rows)
    fig, ax = plt.subplots(figsize=(7.2, 4.6))
    styles = {"vf": ("#3182bd", "vertex–face"), "ee": ("#e6550d", "edge–edge")}
    for kind, (colour, name) in styles.items():
        rs = [r for r in rows if r["kind"] == kind]
        fp = [int(r["false_positives"]) for r in rs]
        for stat, marker, ls in (("p99_us", "o", "-"), ("median_us", "s", ":")):
            us = [float(r[stat]) for r in rs]
            ax.plot(fp, us, marker=marker, ls=ls, color=colour, ms=5, label=f"{name}, {stat.split('_')[0]}")
        # One label per cluster of p99 points at the same count and nearly the same time (they would overprint).
        clusters = []
        for r in rs:
            x, y = int(r["false_positives"]), float(r["p99_us"])
            near = [c for c in clusters if c[0] == x and abs(math.log10(y / c[1][-1])) < 0.1]
            if near:
                near[0][1].append(y), near[0][2].append(r["tolerance"])
            else:
                clusters.append((x, [y], [r["tolerance"]]))
        for x, ys, tols in clusters:
            ax.annotate("δ=" + ", ".join(tols), (x, max(ys)), fontsize=7, color=colour, textcoords="offset points",
                        xytext=(5, 2))
    ax.set_yscale("log")
    ax.set_xlabel(f"false positives (of {rows[0]['queries']} vertex–face / {rows[1]['queries']} edge–edge queries)")
    ax.set_ylabel("µs per query (warm)")
    title = "Handcrafted CCD queries: time against false positives over the tolerance δ"
    if false_negatives == 0:  # said only when every row of the sweep has none
        title += "\n(0 false negatives at every δ)"
    ax.set_title(title, fontsize=10)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8, loc="center right")
    fig.tight_layout()
    fig.savefig(f"{out_dir}/ccd_time_vs_fp.png", dpi=100)


def box_outline(half, T):
    """The box's outline seen along z (its xy rectangle, posed)."""
    c = np.array([[-1, -1, 0], [1, -1, 0], [1, 1, 0], [-1, 1, 0], [-1, -1, 0]]) * [half[0], half[1], 0]
    return (c @ T[:3, :3].T + T[:3, 3])[:, :2]


def capsule_outline(radius, half_length, T, n=24):
    """A capsule lying in the xy plane (its axis along its frame's x after the pose), seen along z."""
    pts = [[half_length + radius * math.cos(a), radius * math.sin(a), 0] for a in np.linspace(-math.pi / 2, math.pi / 2, n)]
    pts += [[-half_length + radius * math.cos(a), radius * math.sin(a), 0]
            for a in np.linspace(math.pi / 2, 3 * math.pi / 2, n)]
    pts = np.array(pts + pts[:1])
    return (pts @ T[:3, :3].T + T[:3, 3])[:, :2]


def cast_figure(out_dir):
    """A box moving right and turning by 2 rad over the step, past a capsule that lies tilted across its path. The
    advancement steps are cdkit's own: convex_toi capped after k steps reports the time it had reached."""
    half = np.array([0.5, 0.2, 0.3])
    box = cdkit.Box(half)
    radius, half_length = 0.3, 0.6
    capsule = cdkit.Capsule(radius, half_length)
    # The capsule's axis is its frame's z: turn it into the xy plane, then tilt it by 0.5 rad.
    lay = np.array([[0, 0, 1], [0, 1, 0], [-1, 0, 0]], dtype=float)  # frame z -> world x
    Rc = rot_z(0.5) @ lay
    pc = pose(Rc, [0.2, -0.6, 0])
    a0, a1 = pose(np.eye(3), [-3.0, 0.5, 0]), pose(rot_z(2.0), [3.0, 0.0, 0])
    r = cdkit.convex_toi(box, a0, a1, capsule, pc, pc)
    assert r.status == cdkit.QueryStatus.ok and r.colliding and not r.capped
    steps = []
    for k in range(1, r.iterations + 1):
        s = cdkit.convex_toi(box, a0, a1, capsule, pc, pc, cdkit.ToiRequest(max_iterations=k))
        steps.append((s.toi, np.linalg.norm(np.asarray(s.point_b) - np.asarray(s.point_a)), s))
    at = lambda t: pose(rot_z(2.0 * t), (1 - t) * a0[:3, 3] + t * a1[:3, 3])  # the query's motion
    fig, (ax, bx) = plt.subplots(1, 2, figsize=(10.5, 4.2), gridspec_kw=dict(width_ratios=[1.6, 1]))
    cap2 = capsule_outline(radius, half_length, pose(rot_z(0.5), [0.2, -0.6, 0]))
    ax.fill(cap2[:, 0], cap2[:, 1], color="#bdbdbd", label="capsule (still)")
    s0, s1 = box_outline(half, a0), box_outline(half, a1)
    ax.plot(s0[:, 0], s0[:, 1], color="#3182bd", lw=1.5, label="box at t = 0")
    ax.plot(s1[:, 0], s1[:, 1], color="#3182bd", lw=1.2, ls="--", label="box at t = 1 (not reached)")
    ax.plot([a0[0, 3], a1[0, 3]], [a0[1, 3], a1[1, 3]], color="#3182bd", lw=0.6, ls=":")
    for i, (t, d, s) in enumerate(steps[1:-1]):
        o = box_outline(half, at(t))
        ax.plot(o[:, 0], o[:, 1], color="#9ecae1", lw=0.9, label="box at the advancement steps" if i == 0 else None)
    o = box_outline(half, at(r.toi))
    ax.plot(o[:, 0], o[:, 1], color="#de2d26", lw=2, label=f"box at toi = {r.toi:.4f}")
    pa, pb, n = np.asarray(r.point_a)[:2], np.asarray(r.point_b)[:2], np.asarray(r.normal)[:2]
    ax.plot(*pa, "k^", ms=6, label="witness points at toi")
    ax.plot(*pb, "ko", ms=4)
    ax.annotate("", xy=pa + 0.7 * n, xytext=pa, arrowprops=dict(arrowstyle="->", lw=1.5, color="k"))
    ax.text(*(pa + 0.7 * n + [0.08, -0.05]), "normal\n(A to B)", fontsize=7)
    ax.set_aspect("equal")
    ax.set_xlim(-3.8, 3.8)
    ax.set_ylim(-1.5, 2.3)
    ax.set_title("convex_toi: a box cast right while turning 2 rad, past a capsule (seen along z)", fontsize=9)
    ax.legend(fontsize=7, loc="upper center", ncol=3)
    ts = [t for t, _, _ in steps]
    ds = [d for _, d, _ in steps]
    bx.step(ts + [r.toi], ds + [ds[-1]], where="post", color="#9ecae1", lw=1)
    bx.plot(ts, ds, "o", color="#3182bd", ms=5)
    for k, (t, d) in enumerate(zip(ts, ds)):
        bx.annotate(str(k + 1), (t, d), fontsize=7, textcoords="offset points", xytext=(4, 4))
    bx.axvline(r.toi, color="#de2d26", lw=1, ls="--", label=f"toi = {r.toi:.4f} ({r.iterations} steps)")
    bx.set_yscale("log")
    bx.set_xlim(-0.02, 1.0)
    bx.set_xlabel("t (time in the step)")
    bx.set_ylabel("GJK distance at the step")
    bx.set_title("Each step advances to t + d/μ, a lower bound", fontsize=9)
    bx.legend(fontsize=7, loc="lower left")
    bx.grid(True, which="both", alpha=0.3)
    fig.tight_layout()
    fig.savefig(f"{out_dir}/ccd_cast.png", dpi=100)


def ribbon(profile, z):
    """A polyline in the xy plane extruded over z in [-z, z]: two triangles per segment (a vertical ribbon, seen
    along z it is the polyline)."""
    n = len(profile)
    v = np.array([[x, y, -z] for x, y in profile] + [[x, y, z] for x, y in profile], dtype=float)
    f = []
    for i in range(n - 1):
        f += [[i, i + 1, n + i + 1], [i, n + i + 1, n + i]]
    return v, np.array(f, dtype=np.int64)


def split_groups(v, f, levels):
    """Triangle groups by halving at the median centroid along the longest axis, `levels` times: the script's own
    stand-in for a tree's nodes (the Python module does not expose cdkit's tree, which splits by SAH)."""
    groups = [np.arange(len(f))]
    for _ in range(levels):
        out = []
        for g in groups:
            c = v[f[g]].mean(axis=1)
            axis = int(np.argmax(c.max(0) - c.min(0)))
            order = g[np.argsort(c[:, axis], kind="stable")]
            out += [order[: len(order) // 2], order[len(order) // 2:]]
        groups = out
    return groups


def box_of(points):
    return points.min(0)[:2], points.max(0)[:2]


def rect(ax, lo, hi, **kw):
    ax.add_patch(matplotlib.patches.Rectangle(lo, *(hi - lo), **kw))


def swept_tree_figure(out_dir):
    """A ribbon moving down and right (and turning a little) onto a ledge; mesh_ccd gives the first contact. The
    boxes: each group's box at t = 0 and t = 1 and the box covering both, which holds the group over the step
    (every vertex moves on a segment between its two posed positions)."""
    xs = np.linspace(-1.2, 1.2, 13)
    va, fa = ribbon([(x, 0.25 * math.sin(2.2 * x)) for x in xs], 0.3)
    vb, fb = ribbon([(-3.0, -1.0), (0.0, -1.0), (0.0, -0.4), (3.0, -0.4)], 0.6)  # a step up at x = 0
    ma, mb = cdkit.MeshModel(va, fa, bv="aabb"), cdkit.MeshModel(vb, fb, bv="aabb")
    a0, a1 = pose(np.eye(3), [-1.4, 1.0, 0]), pose(rot_z(-0.35), [0.6, -0.3, 0])
    r = cdkit.mesh_ccd(ma, a0, a1, mb, None, None)
    assert r.status == cdkit.QueryStatus.ok and r.colliding
    contact = r.contacts[0].ccd
    posed = lambda T: va @ T[:3, :3].T + T[:3, 3]
    p0, p1 = posed(a0), posed(a1)
    ptoi = (1 - r.toi) * p0 + r.toi * p1  # mesh_ccd's motion: every vertex on its chord
    fig, axes = plt.subplots(1, 2, figsize=(10.5, 4.6), sharey=True)
    for ax, levels in zip(axes, (1, 2)):
        ax.plot(vb[:4, 0], vb[:4, 1], color="#636363", lw=2.5, label="ledge (B, still)")
        for pts, style, label in ((p0, dict(color="#3182bd"), "A at t = 0"),
                                  (p1, dict(color="#3182bd", ls="--"), "A at t = 1"),
                                  (ptoi, dict(color="#de2d26", lw=2), f"A at toi = {r.toi:.3f}")):
            ax.plot(pts[:13, 0], pts[:13, 1], label=label, **style)
        b_lo, b_hi = box_of(vb)
        rect(ax, b_lo, b_hi, fill=False, edgecolor="#636363", lw=0.8, ls=":", label="B's box")
        for g in split_groups(va, fa, levels):
            ids = np.unique(fa[g])
            lo0, hi0 = box_of(p0[ids])
            lo1, hi1 = box_of(p1[ids])
            lo, hi = np.minimum(lo0, lo1), np.maximum(hi0, hi1)
            hits = bool(np.all(lo <= b_hi) and np.all(b_lo <= hi))
            rect(ax, lo, hi, facecolor="#fdae6b" if hits else "#e0e0e0", alpha=0.35,
                 edgecolor="#e6550d" if hits else "#969696", lw=1,
                 label="swept box: meets B's box" if hits else "swept box: misses B's box")
            rect(ax, lo0, hi0, fill=False, edgecolor="#3182bd", lw=0.8, ls="-")
            rect(ax, lo1, hi1, fill=False, edgecolor="#3182bd", lw=0.8, ls="--")
        ax.plot(*np.asarray(contact.point)[:2], "k*", ms=10, label="contact point (mesh_ccd)")
        ax.set_aspect("equal")
        ax.set_xlim(-3.0, 2.2)
        ax.set_ylim(-1.2, 1.9)
        ax.set_title(f"{2 ** levels} triangle groups of A: boxes at t = 0 (solid), t = 1 (dashed)\nand the swept "
                     "box covering both (filled)", fontsize=9)
    handles, labels = axes[1].get_legend_handles_labels()
    seen = dict(zip(labels, handles))
    fig.legend(seen.values(), seen.keys(), fontsize=7, loc="lower center", ncol=5)
    fig.suptitle("mesh_ccd's bound on a rigid motion (groups by the script's median split, not cdkit's own tree)",
                 fontsize=10)
    fig.tight_layout(rect=(0, 0.09, 1, 1))
    fig.savefig(f"{out_dir}/ccd_swept_tree.png", dpi=100)


if __name__ == "__main__":
    out = sys.argv[1] if len(sys.argv) > 1 else "docs/images"
    time_vs_fp(out)
    cast_figure(out)
    swept_tree_figure(out)
