"""Shared fixtures: the bundled meshes, the C++ reference answers (python/tests/cpp_reference.cpp, run once per
session), small exact meshes, and the convex shapes the reference uses."""
import json
import math
import os
import pathlib
import subprocess

import numpy as np
import pytest

import cdkit

ROOT = pathlib.Path(__file__).resolve().parents[2]
DATA = pathlib.Path(os.environ.get("CDKIT_DATA_DIR", ROOT / "data"))


@pytest.fixture(scope="session")
def bunny():
    """(vertices, faces) of data/bunny.obj."""
    return cdkit.load_mesh(str(DATA / "bunny.obj"))


@pytest.fixture(scope="session")
def reference():
    """The C++ answers on fixed inputs, as JSON (CDKIT_PYTHON_REFERENCE: the helper's path; ctest sets it)."""
    exe = os.environ.get("CDKIT_PYTHON_REFERENCE")
    if not exe or not os.path.exists(exe):
        pytest.fail("CDKIT_PYTHON_REFERENCE must name the built cdkit_python_reference executable (ctest sets it)")
    out = subprocess.run([exe], check=True, capture_output=True, text=True).stdout
    return json.loads(out)


def cube(center=(0.0, 0.0, 0.0), half=0.5):
    """An axis-aligned closed cube of 12 outward-oriented triangles."""
    c = np.asarray(center, float)
    v = np.array([[x, y, z] for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)], float) * half + c
    f = np.array([[0, 1, 3], [0, 3, 2], [4, 6, 7], [4, 7, 5], [0, 4, 5], [0, 5, 1],
                  [2, 3, 7], [2, 7, 6], [0, 2, 6], [0, 6, 4], [1, 5, 7], [1, 7, 3]], np.int64)
    return v, f


def translation(x, y=0.0, z=0.0):
    return cdkit.pose(None, [x, y, z])


def rotation_z(angle, t=(0.0, 0.0, 0.0)):
    c, s = math.cos(angle), math.sin(angle)
    return cdkit.pose([[c, -s, 0], [s, c, 0], [0, 0, 1]], t)


def reference_shapes(hull_points=None):
    """The eight shapes of cpp_reference.cpp, in its order (the hull from the reference's points when given: numpy's
    cos may differ from libm's in the last bit)."""
    k = np.arange(12)
    pts = np.stack([0.4 * np.cos(k * 0.5236), 0.3 * np.sin(k * 0.5236), np.where(k % 2 == 1, 0.35, -0.35)], axis=1)
    if hull_points is not None:
        pts = np.array(hull_points)
    return [cdkit.Sphere(0.5), cdkit.Box([0.3, 0.4, 0.5]), cdkit.Capsule(0.2, 0.5), cdkit.Cylinder(0.3, 0.4),
            cdkit.Cone(0.3, 0.5), cdkit.Ellipsoid([0.3, 0.4, 0.5]),
            cdkit.ConvexTriangle([0, 0, 0], [0.6, 0, 0.1], [0, 0.5, -0.1]), cdkit.ConvexPolyhedron(pts)]


@pytest.fixture(scope="session")
def shapes():
    return reference_shapes()
