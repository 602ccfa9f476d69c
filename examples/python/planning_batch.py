"""A planning-style batch: one robot link (the bunny) along a path of 10 000 poses past an obstacle, checked in
one call (C++ with TBB, the GIL released) instead of a Python loop; then the clearance along the path.

Run from the repository root (ctest does):  /usr/bin/python3 examples/python/planning_batch.py
"""
import os
import time

import numpy as np

import cdkit

vertices, faces = cdkit.load_mesh(os.path.join(os.environ.get("CDKIT_DATA_DIR", "data"), "bunny.obj"))
link = cdkit.MeshModel(vertices, faces, bv="rss")
obstacle = cdkit.MeshModel(vertices, faces, bv="rss")

# The path: a sweep along x with a slow turn about z (poses as an (N,4,4) array).
n = 10_000
s = np.linspace(0.0, 1.0, n)
angle = 2.0 * s
poses = np.zeros((n, 4, 4))
poses[:, 0, 0] = poses[:, 1, 1] = np.cos(angle)
poses[:, 0, 1], poses[:, 1, 0] = -np.sin(angle), np.sin(angle)
poses[:, 2, 2] = poses[:, 3, 3] = 1.0
poses[:, 0, 3] = -15.0 + 30.0 * s  # the bunny is about 10 across
poses[:, 1, 3] = 0.5

t0 = time.perf_counter()
colliding = cdkit.collide_many(link, poses, obstacle, np.eye(4))  # one pose for the obstacle, every entry
t1 = time.perf_counter()
print(f"{n} poses checked in {1e3 * (t1 - t0):.1f} ms; in collision: {colliding.sum()} "
      f"(from pose {np.argmax(colliding)} to {n - 1 - np.argmax(colliding[::-1])})")

clear = ~colliding
clearance = cdkit.distance_many(link, poses[clear], obstacle, np.eye(4), rel_err=0.05)
print(f"clearance of the free poses: min {clearance.distance.min():.5f}, max {clearance.distance.max():.5f}")
assert 0 < colliding.sum() < n and clearance.distance.min() >= 0
