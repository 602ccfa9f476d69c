"""A World: a row of spheres, a box, a hull and a mesh; step() reports the contacts; a fast ball with continuous
collision does not tunnel through a thin wall.

Run from the repository root (ctest does):  /usr/bin/python3 examples/python/world.py
"""
import os

import numpy as np

import cdkit

world = cdkit.World(cdkit.WorldOptions(broad_phase=cdkit.BroadPhaseKind.sweep_and_prune))
balls = [world.add(cdkit.Sphere(0.5), cdkit.pose(None, [0.9 * k, 0, 0])) for k in range(5)]
crate = world.add(cdkit.Box([0.3, 0.4, 0.5]), cdkit.pose(None, [0.5, 0.7, 0]))
rock = world.add(cdkit.ConvexPolyhedron(np.random.default_rng(1).normal(size=(30, 3)) * 0.3), cdkit.pose(None, [2.2, 0.6, 0]))
vertices, faces = cdkit.load_mesh(os.path.join(os.environ.get("CDKIT_DATA_DIR", "data"), "bunny.obj"))
bunny = world.add(cdkit.MeshModel(0.1 * vertices, faces), cdkit.pose(None, [3.6, 0.0, 0]))  # scaled to 1 across

result = world.step()
for c in result.contacts:
    print(f"{c.a} - {c.b}: {c.method.name}, depth {c.depth:.4f}")
print(f"{result.stats.broad_pairs} broad-phase pairs, {result.stats.tested_pairs} tested, {len(result.contacts)} contacts")

# Continuous collision: the ball jumps through the wall in one step; set_ccd reports when it first touches.
wall = world.add(cdkit.Box([0.05, 1, 1]), cdkit.pose(None, [0, -5, 0]))
ball = world.add(cdkit.Sphere(0.1), cdkit.pose(None, [-1, -5, 0]))
world.set_ccd(ball, True)
world.step()
world.set_pose(ball, cdkit.pose(None, [1, -5, 0]))
hits = [c for c in world.step().contacts if ball in (c.a, c.b)]
print(f"the fast ball hits the wall at t = {hits[0].toi:.4f} of the step")
assert len(result.contacts) >= 4 and hits and hits[0].b == ball and hits[0].a == wall
