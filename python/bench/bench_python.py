#!/usr/bin/env python3
"""Python bindings benchmark (issue 38): what a Python call costs over the C++ call, and what a batch buys.

  /usr/bin/python3 python/bench/bench_python.py --cpp BUILD/python/cdkit_python_bench_cpp --csv results/python_bench.csv

with PYTHONPATH=BUILD/python (scripts/bench sets both). Measures, on data/bunny.obj:
  per_call  a distant pair (the trees' roots are apart: the query's floor), collide (OBB) and distance (RSS): µs per
            call from Python (poses as 4x4 numpy arrays) against the same call in C++ (cdkit_python_bench_cpp);
  batch     10^5 pose pairs near contact (a mix of hits and misses), collide first contact: µs per pose of a Python
            loop of single calls, of cdkit.collide_many on 1 and 2 TBB threads, and of the C++ collide_many on 1 and
            2 threads (same poses, passed through a binary file).
Medians of --repeats runs. Writes a CSV with a provenance header (command, machine, compiler, commit, date).
"""
import argparse
import datetime
import json
import os
import pathlib
import platform
import statistics
import subprocess
import sys
import tempfile
import time

import numpy as np

import cdkit

ROOT = pathlib.Path(__file__).resolve().parents[2]


def random_poses(n, reach, rng):
    q = rng.normal(size=(n, 4))
    q /= np.linalg.norm(q, axis=1, keepdims=True)
    w, x, y, z = q.T
    P = np.zeros((n, 4, 4))
    P[:, 0, :3] = np.stack([1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)], axis=1)
    P[:, 1, :3] = np.stack([2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)], axis=1)
    P[:, 2, :3] = np.stack([2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)], axis=1)
    P[:, :3, 3] = rng.uniform(-reach, reach, size=(n, 3))
    P[:, 3, 3] = 1
    return P


def median_time(fn, repeats):
    times = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t0)
    return statistics.median(times)


def machine():
    try:
        for line in open("/proc/cpuinfo"):
            if line.startswith("model name"):
                return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or platform.machine()


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--cpp", required=True, help="the cdkit_python_bench_cpp executable")
    ap.add_argument("--csv", default=None)
    ap.add_argument("--mesh", default=str(ROOT / "data" / "bunny.obj"))
    ap.add_argument("--poses", type=int, default=100_000)
    ap.add_argument("--repeats", type=int, default=3)
    args = ap.parse_args()

    v, f = cdkit.load_mesh(args.mesh)
    obb, rss = cdkit.MeshModel(v, f, bv="obb"), cdkit.MeshModel(v, f, bv="rss")
    rng = np.random.default_rng(38)
    pa, pb = random_poses(args.poses, 0.5, rng), random_poses(args.poses, 12.0, rng)  # the bunny is ~10 across
    with tempfile.TemporaryDirectory() as tmp:
        path = pathlib.Path(tmp) / "poses.bin"
        np.ascontiguousarray(np.stack([pa, pb], axis=1), dtype=np.float64).tofile(path)
        cpp = json.loads(subprocess.run([args.cpp, args.mesh, str(path), str(args.repeats)], check=True,
                                        capture_output=True, text=True).stdout)

    # Per call, distant pair.
    eye, far = np.eye(4), cdkit.pose(None, [100.0, 0.0, 0.0])
    calls = 20_000

    def loop_collide():
        for _ in range(calls):
            cdkit.collide(obb, eye, obb, far)

    def loop_distance():
        for _ in range(calls):
            cdkit.distance(rss, eye, rss, far)

    py_collide = 1e6 * median_time(loop_collide, args.repeats) / calls
    py_distance = 1e6 * median_time(loop_distance, args.repeats) / calls

    # Batch throughput.
    def py_loop():
        for i in range(args.poses):
            cdkit.collide(obb, pa[i], obb, pb[i])

    loop_us = 1e6 * median_time(py_loop, max(1, args.repeats - 2)) / args.poses
    hits = cdkit.collide_many(obb, pa, obb, pb)
    assert int(hits.sum()) == cpp["hits"], (int(hits.sum()), cpp["hits"])  # the same answers as the C++ batch
    batch = {t: 1e6 * median_time(lambda: cdkit.collide_many(obb, pa, obb, pb, threads=t), args.repeats) / args.poses
             for t in (1, 2)}

    rows = [
        ("per_call", "collide_distant", 1, 1, py_collide, "", cpp["collide_distant_us"]),
        ("per_call", "distance_distant", 1, 1, py_distance, "", cpp["distance_distant_us"]),
        ("batch", "collide_near", args.poses, 1, loop_us, batch[1], cpp["batch1_us"]),
        ("batch", "collide_near", args.poses, 2, loop_us, batch[2], cpp["batch2_us"]),
    ]
    header = "kind,query,poses,threads,python_loop_us,python_batch_us,cpp_us,python_over_cpp,hit_fraction"
    lines = []
    for kind, query, n, threads, loop, pbatch, c in rows:
        py = pbatch if pbatch != "" else loop
        lines.append(f"{kind},{query},{n},{threads},{loop:.4f},{'' if pbatch == '' else f'{pbatch:.4f}'},{c:.4f},"
                     f"{py / c:.3f},{(cpp['hits'] / cpp['poses']) if kind == 'batch' else 0:.4f}")
    print(f"cdkit Python bench on {pathlib.Path(args.mesh).name} ({len(f)} triangles), medians of {args.repeats}:")
    print(f"  distant collide: Python {py_collide:.3f} us/call, C++ {cpp['collide_distant_us']:.3f} us "
          f"(overhead {py_collide - cpp['collide_distant_us']:.3f} us)")
    print(f"  distant distance: Python {py_distance:.3f} us/call, C++ {cpp['distance_distant_us']:.3f} us")
    print(f"  {args.poses} near poses ({100 * cpp['hits'] / cpp['poses']:.1f}% hit): Python loop {loop_us:.3f} us/pose, "
          f"collide_many {batch[1]:.3f} (1 thread) / {batch[2]:.3f} (2 threads), C++ loop {cpp['loop_us']:.3f}, "
          f"C++ collide_many {cpp['batch1_us']:.3f} / {cpp['batch2_us']:.3f} us/pose")
    if args.csv:
        try:
            commit = subprocess.run(["git", "rev-parse", "--short", "HEAD"], cwd=ROOT, capture_output=True,
                                    text=True).stdout.strip() or "unknown"
        except OSError:
            commit = "unknown"
        try:
            compiler = subprocess.run(["c++", "-dumpfullversion"], capture_output=True, text=True).stdout.strip()
        except OSError:
            compiler = "unknown"
        meta = [f"# command: {' '.join([os.path.relpath(sys.argv[0], ROOT)] + sys.argv[1:])}",
                f"# machine: {machine()} ({os.cpu_count()} CPUs)", f"# compiler: {compiler}",
                f"# python: {sys.executable} {platform.python_version()}, numpy {np.__version__}",
                f"# commit: {commit}",
                f"# date: {datetime.datetime.now(datetime.timezone.utc).strftime('%Y-%m-%dT%H:%M:%SZ')}"]
        pathlib.Path(args.csv).write_text("\n".join(meta + [header] + lines) + "\n")
        print(f"wrote {args.csv}")


if __name__ == "__main__":
    main()
