"""Two bunnies: collide (first contact, then every contact) and distance, from Python.

Run from the repository root (ctest does):  /usr/bin/python3 examples/python/mesh_pair.py [mesh file]
"""
import math
import os
import sys

import numpy as np

import cdkit

path = sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.environ.get("CDKIT_DATA_DIR", "data"), "bunny.obj")
vertices, faces = cdkit.load_mesh(path)  # (N,3) float64, (M,3) int64
bunny = cdkit.MeshModel(vertices, faces, bv="obb")  # validate + build the tree once
print(f"{path}: {len(vertices)} vertices, {len(faces)} triangles, tree {bunny.memory_bytes} bytes")

c, s = math.cos(0.5), math.sin(0.5)
pose_a = np.eye(4)  # model frame -> world
pose_b = cdkit.pose([[c, -s, 0], [s, c, 0], [0, 0, 1]], [2.0, 0.0, 0.0])  # a 4x4 array (the bunny is about 10 across)

hit = cdkit.collide(bunny, pose_a, bunny, pose_b)
if hit.colliding:
    ta, tb = hit.triangle_pairs[0]
    print(f"triangles {ta} and {tb} touch at {np.round(hit.points[0], 5)}")

every = cdkit.collide(bunny, pose_a, bunny, pose_b, cdkit.CollisionRequest(cdkit.ContactMode.all))
print(f"{len(every.contacts)} intersecting triangle pairs, {every.stats.bv_tests} BV tests")

apart = cdkit.pose(pose_b[:3, :3], [14.0, 0.0, 0.0])
d = cdkit.distance(cdkit.MeshModel(vertices, faces, bv="rss"), pose_a, cdkit.MeshModel(vertices, faces, bv="rss"), apart)
print(f"moved apart: distance {d.distance:.6f} between triangles {d.triangle_a} and {d.triangle_b}")
assert hit.colliding and len(every.contacts) > 1 and d.distance > 0
