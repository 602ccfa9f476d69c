#!/usr/bin/python3
"""Draws the "time vs N" figure of docs/broadphase.md from CSV files of `cdkit_bench_broadphase --csv FILE`.

    cdkit_bench_broadphase --csv /tmp/p4_small.csv
    cdkit_bench_broadphase --n 100000 --skip fcl_sap --skip fcl_interval_tree --skip fcl_spatial_hash \
        --csv /tmp/p4_100k.csv
    /usr/bin/python3 benchmarks/broadphase/plot_broadphase.py docs/images/broadphase_time_vs_n.png \
        /tmp/p4_small.csv /tmp/p4_100k.csv

One panel per scene, median ms per frame against N on log-log axes; cdkit's methods solid, FCL's managers
dashed. Methods with wrong pair sets (FCL's spatial hash) are left out; methods stopped by the time budget
(fewer frames run than the scene has) are drawn with open markers. Needs only matplotlib.
"""
import csv
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

SCENES = [("brownian", "Brownian (coherent)"), ("free_fall", "free fall"), ("teleport", "teleport (no coherence)")]
STYLE = {  # method: (label, colour)
    "cdkit_sorted_grid": ("cdkit sorted-cell grid", "#d62728"),
    "cdkit_dbvt": ("cdkit dynamic AABB tree", "#1f77b4"),
    "cdkit_grid": ("cdkit spatial hash", "#2ca02c"),
    "cdkit_sap": ("cdkit sweep and prune", "#9467bd"),
    "cdkit_brute_force": ("cdkit brute force", "#7f7f7f"),
    "fcl_dynamic_aabb_tree": ("FCL dynamic AABB tree", "#17becf"),
    "fcl_ssap": ("FCL SSaP", "#bcbd22"),
    "fcl_sap": ("FCL SaP", "#8c564b"),
    "fcl_interval_tree": ("FCL interval tree", "#e377c2"),
    "fcl_naive": ("FCL naive", "#000000"),
}


def main():
    if len(sys.argv) < 3:
        print(__doc__)
        return 2
    out, paths = sys.argv[1], sys.argv[2:]
    data = {}  # (scene, method) -> {n: (median, complete)}
    for path in paths:
        with open(path, newline="") as f:
            for r in csv.DictReader(l for l in f if not l.startswith("#")):  # after the provenance lines
                if int(r["wrong_frames"]) > 0:
                    continue
                run = int(r.get("frames_run") or r["frames"])
                data.setdefault((r["scene"], r["method"]), {})[int(r["n"])] = (float(r["median_ms"]), run == int(r["frames"]))
    fig, axes = plt.subplots(1, 3, figsize=(14, 4.8), sharey=True)
    for ax, (scene, title) in zip(axes, SCENES):
        for method, (label, colour) in STYLE.items():
            pts = sorted(data.get((scene, method), {}).items())
            if not pts:
                continue
            ns = [n for n, _ in pts]
            ms = [m for _, (m, _) in pts]
            ls = "-" if method.startswith("cdkit") else "--"
            ax.plot(ns, ms, ls, color=colour, label=label, linewidth=1.6 if method == "cdkit_sorted_grid" else 1.0)
            for n, (m, complete) in pts:
                ax.plot([n], [m], "o", color=colour, markerfacecolor=colour if complete else "white", markersize=4.5)
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_title(title, fontsize=10)
        ax.set_xlabel("objects N")
        ax.grid(True, which="both", linewidth=0.3, alpha=0.5)
    axes[0].set_ylabel("median CPU ms per frame (move all + find pairs)")
    handles, labels = axes[0].get_legend_handles_labels()
    seen = dict(zip(labels, handles))
    for ax in axes[1:]:
        h, lab = ax.get_legend_handles_labels()
        seen.update(zip(lab, h))
    fig.legend(seen.values(), seen.keys(), loc="lower center", ncol=5, fontsize=8, frameon=False)
    fig.suptitle("Broad phase, protocol P4: time per frame vs N (open marker: stopped by the time budget)", fontsize=11)
    fig.tight_layout(rect=(0, 0.1, 1, 0.95))
    fig.savefig(out, dpi=100)
    plt.close(fig)
    # Palette PNGs are a third of the size; Pillow comes with matplotlib.
    from PIL import Image
    Image.open(out).convert("RGB").quantize(colors=64).save(out, optimize=True)
    print(out, os.path.getsize(out), "bytes")
    return 0


if __name__ == "__main__":
    sys.exit(main())
