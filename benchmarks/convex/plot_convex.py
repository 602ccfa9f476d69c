#!/usr/bin/python3
"""Draws the time-against-error figure of docs/convex.md from the CSV of `cdkit_bench_convex`.

    cdkit_bench_convex 100 200000 /tmp/convex.csv
    /usr/bin/python3 benchmarks/convex/plot_convex.py /tmp/convex.csv docs/images

Writes convex_time_vs_error.png: one point per (shape family, distance class) cell of protocol P3 and per
method (cdkit, libccd, FCL 0.7's GJKSolver_indep and GJKSolver_libccd), the median time per call against the
cell's maximum relative error (distance and penetration queries, left) or against the fraction of wrong
answers (boolean queries, right). Errors below the plot floor are drawn on it.
Needs only matplotlib.
"""
import csv
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

FLOOR_REL = 1e-17    # relative errors below this (exact answers) are drawn at the floor
FLOOR_WRONG = 1e-3   # 0 wrong answers out of ~100 configurations are drawn here

STYLE = {
    "cdkit GJK distance": ("tab:blue", "o"),
    "cdkit EPA": ("tab:green", "s"),
    "libccd GJK+EPA penetration": ("tab:red", "^"),
    "cdkit GJK boolean": ("tab:blue", "o"),
    "libccd GJK boolean": ("tab:red", "^"),
    "libccd MPR boolean": ("tab:orange", "v"),
    # FCL 0.7's solvers (peer_fcl.cpp): GJKSolver_indep (FCL's GJK/EPA) and GJKSolver_libccd (MPR, GJK).
    "FCL indep GJK distance": ("tab:purple", "D"),
    "FCL libccd GJK distance": ("tab:brown", "P"),
    "FCL indep GJK+EPA penetration": ("tab:purple", "D"),
    "FCL libccd MPR penetration": ("tab:brown", "P"),
    "FCL indep GJK boolean": ("tab:purple", "D"),
    "FCL libccd MPR boolean": ("tab:brown", "P"),
}
DISTANCE_METHODS = ["cdkit GJK distance", "cdkit EPA", "libccd GJK+EPA penetration", "FCL indep GJK distance",
                    "FCL libccd GJK distance", "FCL indep GJK+EPA penetration", "FCL libccd MPR penetration"]
BOOLEAN_METHODS = ["cdkit GJK boolean", "libccd GJK boolean", "libccd MPR boolean", "FCL indep GJK boolean",
                   "FCL libccd MPR boolean"]
CLASS_FILL = {"distant": "none", "close": "full", "overlapping": "left"}


def main(csv_path, out_dir):
    with open(csv_path, newline="") as f:
        data = list(csv.DictReader(f))
    fig, (left, right) = plt.subplots(1, 2, figsize=(12, 5))
    for ax, methods, key, floor in (
        (left, DISTANCE_METHODS, "max_error", FLOOR_REL),
        (right, BOOLEAN_METHODS, "fraction_in_error", FLOOR_WRONG),
    ):
        for method in methods:
            color, marker = STYLE[method]
            for cls, fill in CLASS_FILL.items():
                # The distance query's error is only measured on separated pairs.
                if method.endswith("distance") and cls == "overlapping":
                    continue
                rows = [r for r in data if r["method"] == method and r["class"] == cls]
                if not rows:
                    continue
                x = [float(r["median_ns"]) for r in rows]
                y = [max(float(r[key]), floor) for r in rows]
                ax.plot(x, y, linestyle="none", marker=marker, color=color, fillstyle=fill, markersize=7,
                        label="%s, %s" % (method, cls))
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("median time per call [ns] (one point per shape family)")
        ax.grid(True, which="major", alpha=0.3)
        ax.legend(fontsize=7, loc="best")
    left.set_ylabel("max. relative error of distance / depth (floor %.0e)" % FLOOR_REL)
    left.axhline(1e-9, color="gray", linestyle="--", linewidth=0.8)
    left.set_title("distance and penetration queries")
    right.set_ylabel("fraction of wrong answers (0 drawn at %.0e)" % FLOOR_WRONG)
    right.set_title("boolean queries")
    fig.suptitle("P3 convex pairs: time against error (cdkit, libccd and FCL 0.7 in one process)")
    fig.tight_layout()
    os.makedirs(out_dir, exist_ok=True)
    path = os.path.join(out_dir, "convex_time_vs_error.png")
    fig.savefig(path, dpi=90)
    plt.close(fig)
    try:  # palette PNGs are a third of the size; Pillow comes with matplotlib
        from PIL import Image
        Image.open(path).convert("RGB").quantize(colors=64).save(path, optimize=True)
    except ImportError:
        pass
    print(path, os.path.getsize(path), "bytes")


if __name__ == "__main__":
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    main(sys.argv[1], sys.argv[2])
