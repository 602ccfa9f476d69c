#!/usr/bin/python3
"""Plots and a Markdown report from a cdkit_bench output directory.

Usage: /usr/bin/python3 benchmarks/report.py [DIR]      (DIR defaults to build/report)

Reads DIR/results.json (written by cdkit_bench, together with the CSV files) and writes into DIR:
  <mesh>_<protocol>.png   per mesh and protocol: median µs per query against the distance class (log y), and
                          the ratio median(peer) / median(method) (above 1: faster than the peer), one row
                          of panels per contact mode
  accuracy_speed.png      P6: time per triangle test against its error rate (if the accuracy benchmark wrote
                          DIR/accuracy_speed.csv)
  report.md               machine, configuration, models, summary tables, correctness, and the plots
Uses only the standard library and matplotlib (Agg backend: no display needed).
"""

import csv
import json
import math
import os
import re
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402  (the backend must be chosen first)
from matplotlib import ticker  # noqa: E402

# Same colour for the same BV across libraries, solid for cdkit, dashed for peers, hollow markers for float.
STYLE = {
    "cdkit_obb_d": ("tab:blue", "-", "o", "full"),
    "cdkit_aabb_d": ("tab:orange", "-", "s", "full"),
    "cdkit_obb_f": ("tab:blue", ":", "o", "none"),
    "cdkit_aabb_f": ("tab:orange", ":", "s", "none"),
    "cdkit_rss_d": ("tab:green", "-", "s", "full"),
    "fcl_obbrss": ("tab:green", "--", "^", "full"),
    "fcl_obb": ("tab:blue", "--", "v", "full"),
    "fcl_aabb": ("tab:orange", "--", "D", "full"),
    "fcl_rss": ("tab:green", "--", "s", "full"),
}
EXTRA_COLOURS = ["tab:red", "tab:purple", "tab:brown", "tab:pink", "tab:gray", "tab:olive", "tab:cyan"]
MODE_TITLE = {"first": "first contact", "all": "all contacts"}
PROTOCOL_TITLE = {"P1": "P1 tumbling", "P2": "P2 proximity"}


def style(method, index):
    if method in STYLE:
        return STYLE[method]
    return (EXTRA_COLOURS[index % len(EXTRA_COLOURS)], "-" if method.startswith("cdkit") else "--", "x", "full")


def slug(text):
    return re.sub(r"[^A-Za-z0-9]+", "_", text).strip("_")


def fmt_us(x):
    if x is None or (isinstance(x, float) and math.isnan(x)):
        return "–"
    if x < 10:
        return f"{x:.3f}"
    if x < 100:
        return f"{x:.2f}"
    if x < 1000:
        return f"{x:.1f}"
    return f"{x:.0f}"


def fmt_ratio(r):
    return "–" if r is None else f"{r:.2f}"


def group(rows):
    """{(mesh, protocol): {mode: {method: [rows sorted by distance]}}} in first-seen order."""
    out = {}
    for r in rows:
        out.setdefault((r["mesh"], r["protocol"]), {}).setdefault(r["mode"], {}).setdefault(r["method"], []).append(r)
    for modes in out.values():
        for methods in modes.values():
            for lst in methods.values():
                lst.sort(key=lambda r: r["distance"])
    return out


def plot(mesh, protocol, modes, methods_order, peer, out_dir):
    """One PNG: a row per mode, median µs (left) and ratio to the peer (right) against the distance class."""
    mode_names = [m for m in ("first", "all") if m in modes]
    fig, axes = plt.subplots(len(mode_names), 2, figsize=(13, 4.2 * len(mode_names)), squeeze=False)
    any_row = next(iter(next(iter(modes.values())).values()))
    kind = any_row[0]["distance_kind"]
    triangles = any_row[0]["triangles"]
    for row_i, mode in enumerate(mode_names):
        ax_t, ax_r = axes[row_i]
        for i, method in enumerate(methods_order):
            rows = modes[mode].get(method)
            if not rows:
                continue
            colour, ls, marker, fill = style(method, i)
            if kind == "delta":
                # δ values are uneven (−0.2 … +0.2 with a cluster at 0): plot them at even positions.
                xs = list(range(len(rows)))
            else:
                xs = [r["distance"] for r in rows]
            kw = dict(color=colour, linestyle=ls, marker=marker, fillstyle=fill, markersize=4, linewidth=1.4,
                      label=method)
            ax_t.plot(xs, [r["median_us"] for r in rows], **kw)
            ratios = [r["ratio_vs_peer"] for r in rows]
            if any(x is not None for x in ratios):
                ax_r.plot(xs, [math.nan if x is None else x for x in ratios], **kw)
        ax_t.set_yscale("log")
        ax_t.set_ylabel("median µs per query (log)")
        ax_r.set_yscale("log")
        # Plain-number ticks at 1-2-5 steps: a ratio reads better as "3" than as "10^0.5".
        ax_r.yaxis.set_major_locator(ticker.LogLocator(base=10, subs=(1.0, 2.0, 5.0)))
        ax_r.yaxis.set_major_formatter(ticker.FuncFormatter(lambda v, _: f"{v:g}"))
        ax_r.yaxis.set_minor_formatter(ticker.NullFormatter())
        ax_r.axhline(1.0, color="black", linewidth=0.8)
        ax_r.set_ylabel(f"median({peer}) / median(method)\n> 1: faster than {peer}")
        for ax in (ax_t, ax_r):
            ax.grid(True, which="both", alpha=0.3)
            if kind == "delta":
                ds = [r["distance"] for r in next(iter(modes[mode].values()))]
                ax.set_xticks(range(len(ds)))
                ax.set_xticklabels([f"{d:+g}" for d in ds])
                ax.set_xlabel("δ (offset from contact, in bounding-sphere radii; < 0 overlapping)")
            else:
                ax.set_xlabel("d (distance between bounding-box centres; copies span [-1, 1]³)")
                ax.invert_xaxis()  # from far (left) to deep overlap (right), as the protocol runs
        ax_t.set_title(f"{PROTOCOL_TITLE.get(protocol, protocol)}, {mesh} ({triangles} triangles), "
                       f"{MODE_TITLE.get(mode, mode)}: time")
        ax_r.set_title(f"{MODE_TITLE.get(mode, mode)}: ratio to {peer}")
    handles, labels = axes[0][0].get_legend_handles_labels()
    fig.legend(handles, labels, loc="lower center", ncol=len(labels), frameon=False)
    fig.tight_layout(rect=(0, 0.05, 1, 1))
    name = f"{slug(mesh)}_{protocol}.png"
    fig.savefig(os.path.join(out_dir, name), dpi=110)
    plt.close(fig)
    return name


def p1_table_distances(ds):
    """P1 has 56 distances; the report's tables show every 0.1 (the CSV has them all)."""
    return [d for d in ds if abs(d * 10 - round(d * 10)) < 1e-9]


def accuracy_table(out_dir):
    """Per-family disagreements with the exact oracle, from the accuracy benchmark's accuracy.csv."""
    path = os.path.join(out_dir, "accuracy.csv")
    if not os.path.exists(path):
        return []
    with open(path, encoding="utf-8") as f:
        rows = list(csv.DictReader(l for l in f if not l.startswith("#")))  # after the provenance lines
    methods = list(dict.fromkeys(r["method"] for r in rows))
    families = list(dict.fromkeys(r["family"] for r in rows))
    cell = {(r["family"], r["method"]): r for r in rows}
    md = ["## Triangle-test accuracy (hard-case corpus)", "",
          "Disagreements with CGAL's exact kernel per generator family (`cdkit_bench_accuracy`, see "
          "`docs/robustness.md`); `outside_range` holds the pairs with a subnormal coordinate, which cdkit "
          "decides in its wide-integer stage.", "",
          "| family | cases | " + " | ".join(methods) + " |", "|---|---:|" + "---:|" * len(methods)]
    for fam in families:
        first = cell[(fam, methods[0])]
        cells = []
        for m in methods:
            r = cell[(fam, m)]
            wrong = int(r["disagreements"])
            cells.append("**0**" if wrong == 0 else f"{wrong} ({100 * float(r['rate']):.2g}%)")
        md.append(f"| {fam} | {int(first['cases'])} | " + " | ".join(cells) + " |")
    return md + [""]


def plot_speed_vs_error(out_dir):
    """P6: time per triangle test (x) against its disagreement rate with the exact oracle (y), one point per
    method, from the accuracy benchmark's accuracy_speed.csv. Exact methods (rate 0) sit on the floor."""
    path = os.path.join(out_dir, "accuracy_speed.csv")
    if not os.path.exists(path):
        return None, []
    with open(path, encoding="utf-8") as f:
        rows = list(csv.DictReader(l for l in f if not l.startswith("#")))  # after the provenance lines
    floor = 1e-7
    fig, ax = plt.subplots(figsize=(6.4, 4.2))
    table = ["| method | ns / test | disagreement rate |", "|---|---:|---:|"]
    for i, r in enumerate(rows):
        ns, rate = float(r["ns_per_test"]), float(r["rate"])
        colour = "tab:green" if r["method"].startswith("fcl") else EXTRA_COLOURS[i % len(EXTRA_COLOURS)]
        ax.scatter([ns], [max(rate, floor)], color=colour, marker="^" if rate == 0 else "o", s=50, zorder=3)
        ax.annotate(r["method"] + (" (0 wrong)" if rate == 0 else ""), (ns, max(rate, floor)),
                    textcoords="offset points", xytext=(6, 5 if i % 2 == 0 else -12), fontsize=8)
        table.append(f"| {r['method']} | {ns:.0f} | {int(r['disagreements'])} of {int(r['cases'])} ({100 * rate:.3g}%) |")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_ylim(floor / 2, 1)
    xs = [float(r["ns_per_test"]) for r in rows]
    ax.set_xlim(min(xs) / 1.5, max(xs) * 3)  # room for the labels
    ax.set_xlabel("ns per triangle–triangle test (hard-case corpus sample)")
    ax.set_ylabel("disagreement rate vs exact oracle")
    ax.set_title("P6: time against error, triangle tests")
    ax.grid(True, which="both", alpha=0.3)
    fig.tight_layout()
    fig.savefig(os.path.join(out_dir, "accuracy_speed.png"), dpi=110)
    plt.close(fig)
    return "accuracy_speed.png", table


def main():
    out_dir = sys.argv[1] if len(sys.argv) > 1 else "build/report"
    with open(os.path.join(out_dir, "results.json"), encoding="utf-8") as f:
        data = json.load(f)
    machine, config, peer = data["machine"], data["config"], data["peer"]
    methods = data["methods"]
    groups = group(data["results"])

    md = ["# cdkit benchmark report", ""]
    md += ["Protocols P1 (tumbling) and P2 (proximity) of `shared/BENCHMARKS.md`; every method ran in the same "
           "process on the same poses. Times are µs per query (each pose timed as a batch of repeats, then the "
           f"median / p99 over poses). **Ratio = median({peer}) / median(method): above 1 the method is faster "
           f"than {peer}.** See `docs/benchmarks.md`.", ""]
    md += ["## Machine and configuration", "", "| | |", "|---|---|"]
    for key in ("cpu", "cores", "compiler", "build_type", "cxx_flags", "asserts", "fcl_version", "os", "date",
                "loadavg_start", "loadavg_end"):
        if key in machine:
            md.append(f"| {key} | `{machine[key]}` |")
    md.append(f"| size | {config['size']}: P1 {config['steps']} steps per d, P2 {config['rotations']} rotations, "
              f"batches ≥ {config['min_batch_us']} µs ({config.get('batches', 1)} per pose, fastest kept), seed {config['seed']}, cdkit split {config['split']} |")
    md.append(f"| run time | {data['total_seconds']:.1f} s |")
    md.append("")

    md += ["## Meshes and models", "",
           "Tree = BV nodes + index arrays (FCL: estimated from its BV count); mesh = vertices + triangle indices "
           "in the method's precision.", "",
           "| mesh | triangles | closed | method | build ms | tree bytes | bytes/tri | tree/mesh |",
           "|---|---:|---|---|---:|---:|---:|---:|"]
    for m in data["meshes"]:
        for b in m["builds"]:
            est = "" if b["family"] == "cdkit" else " (est.)"
            md.append(f"| {m['name']} | {m['triangles']} | {'yes' if m['closed'] else 'no'} | {b['method']} | "
                      f"{b['build_ms']:.2f} | {b['tree_bytes']}{est} | {b['tree_bytes'] / m['triangles']:.1f} | "
                      f"{b['tree_bytes'] / b['mesh_bytes']:.2f} |")
        if not m["identity_collides"]:
            md.append(f"\n**Warning: {m['name']}: two coincident copies did not collide — the triangle test never "
                      "reported a hit; the timings are meaningless.**\n")
    md.append("")

    md += ["## Results", ""]
    for (mesh, protocol), modes in groups.items():
        png = plot(mesh, protocol, modes, methods, peer, out_dir)
        md += [f"### {PROTOCOL_TITLE.get(protocol, protocol)} — {mesh}", "", f"![{mesh} {protocol}]({png})", ""]
        for mode in ("first", "all"):
            if mode not in modes:
                continue
            per_method = modes[mode]
            ref_rows = per_method[data["reference"]]
            kind = ref_rows[0]["distance_kind"]
            ds = [r["distance"] for r in ref_rows]
            shown = p1_table_distances(ds) if protocol == "P1" else ds
            shown = sorted(shown, reverse=True) if protocol == "P1" else shown
            note = " (every 0.1 shown; results.csv has all distances)" if protocol == "P1" else ""
            md += [f"**{MODE_TITLE[mode]}**, {ref_rows[0]['poses']} poses per {kind}{note}. "
                   "Cells: median µs / p99 µs / ratio.", ""]
            cols = [m for m in methods if m in per_method]
            md.append(f"| {kind} | colliding | " + " | ".join(cols) + " |")
            md.append("|---:|---:|" + "---:|" * len(cols))
            for d in shown:
                cells = []
                coll = None
                for m in cols:
                    r = next(x for x in per_method[m] if abs(x["distance"] - d) < 1e-9)
                    if m == data["reference"]:
                        coll = r["frac_colliding"]
                    cells.append(f"{fmt_us(r['median_us'])} / {fmt_us(r['p99_us'])} / {fmt_ratio(r['ratio_vs_peer'])}")
                md.append(f"| {d:+.3f} | {100 * coll:.0f}% | " + " | ".join(cells) + " |")
            # Geometric mean of the ratio over all distance classes (not just the rows shown).
            gm = []
            for m in cols:
                rs = [r["ratio_vs_peer"] for r in per_method[m] if r["ratio_vs_peer"]]
                gm.append(f"{math.exp(sum(map(math.log, rs)) / len(rs)):.2f}" if rs else "–")
            md.append("| geomean ratio | | " + " | ".join(gm) + " |")
            md.append("")
            work = []
            for m in cols:
                rows = per_method[m]
                bv = [r["bv_tests_mean"] for r in rows if r["bv_tests_mean"] is not None]
                tri = [r["tri_tests_mean"] for r in rows if r["tri_tests_mean"] is not None]
                if bv:
                    work.append(f"{m}: {sum(bv) / len(bv):.0f} BV tests, {sum(tri) / len(tri):.0f} triangle tests")
            if work:
                md += ["Mean work per query over all classes — " + "; ".join(work) + ".", ""]

    md += ["## Correctness", "",
           f"Booleans compared with the reference `{data['reference']}` on every pose; in all-contacts mode the "
           "number of intersecting triangle pairs too (cdkit methods of equal precision must agree exactly; FCL may "
           "differ). Non-unanimous poses are in `disagreements.csv`, ready for an exact oracle.", "",
           "| mesh | protocol | mode | method | poses | colliding | bool disagreements | pair-count mismatches |",
           "|---|---|---|---|---:|---:|---:|---:|"]
    for c in data["correctness"]:
        md.append(f"| {c['mesh']} | {c['protocol']} | {c['mode']} | {c['method']} | {c['poses']} | "
                  f"{c['colliding_poses']} | {c['bool_disagreements']} | "
                  f"{c['contact_mismatches'] if c['mode'] == 'all' else '–'} |")
    kinds = data.get("disagreement_kinds", {})
    md += ["", "Non-unanimous poses: " + (", ".join(f"{k} = {v}" for k, v in kinds.items()) or "none") + ".", ""]
    bad = [c for c in data["correctness"] if c["probe_timed_mismatches"]]
    if bad:
        md += ["**Warning: some timed batches answered unlike their untimed probe:** " +
               ", ".join(f"{c['mesh']} {c['protocol']} {c['mode']} {c['method']}" for c in bad), ""]

    md += accuracy_table(out_dir)
    png, table = plot_speed_vs_error(out_dir)
    if png:
        md += ["## P6 time against error (triangle tests)", "",
               "From `cdkit_bench_accuracy` (hard-case corpus against CGAL's exact kernel; see "
               "`docs/robustness.md`).", "", f"![P6]({png})", ""] + table + [""]

    with open(os.path.join(out_dir, "report.md"), "w", encoding="utf-8") as f:
        f.write("\n".join(md) + "\n")
    print(f"wrote {os.path.join(out_dir, 'report.md')} and {len(groups)} plots")


if __name__ == "__main__":
    main()
