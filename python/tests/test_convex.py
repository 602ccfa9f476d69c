"""Convex shapes on exact constructions (sphere–sphere, axis-aligned boxes), warm caches giving the cold answers,
and the shapes' support functions."""
import math

import numpy as np
import pytest

import cdkit
from conftest import rotation_z, translation


def test_spheres_at_known_distances():
    a, b = cdkit.Sphere(0.5), cdkit.Sphere(0.25)
    for d in (2.0, 1.0, 0.8):
        g = cdkit.gjk_distance(a, None, b, translation(d))
        assert g.distance == pytest.approx(d - 0.75, abs=1e-12)
        assert g.status == cdkit.GjkStatus.separated and not g.colliding
        assert np.allclose(g.point_a, [0.5, 0, 0]) and np.allclose(g.point_b, [d - 0.25, 0, 0])
        assert np.allclose(g.normal, [1, 0, 0])
    p = cdkit.penetration(a, None, b, translation(0.5))
    assert p.colliding and p.status == cdkit.GjkStatus.intersecting
    assert p.depth == pytest.approx(0.25, rel=1e-6) and p.depth_lower <= p.depth
    assert abs(p.normal[0]) == pytest.approx(1.0, abs=1e-6)
    assert cdkit.gjk_intersect(a, None, b, translation(0.5)).colliding


def test_boxes_axis_aligned():
    a = cdkit.Box([0.5, 0.5, 0.5])
    for gap in (0.5, 0.1, 0.001):
        assert cdkit.gjk_distance(a, None, a, translation(1 + gap)).distance == pytest.approx(gap, abs=1e-12)
        assert cdkit.gjk_intersect(a, None, a, translation(1 + gap)).status == cdkit.GjkStatus.separated
    p = cdkit.penetration(a, None, a, translation(0.8, 0.1))
    assert p.depth == pytest.approx(0.2, rel=1e-6)


def test_distance_within_a_bound():
    a = cdkit.Box([0.5, 0.5, 0.5])
    # Within the bound: the exact distance, as gjk_distance gives it; beyond: a lower bound above the bound.
    for gap, bound in ((0.05, 0.1), (0.3, 0.1), (0.1, math.inf)):
        w = cdkit.gjk_distance_within(a, None, a, translation(1 + gap), bound)
        assert w.status == cdkit.GjkStatus.separated and not w.colliding
        if gap <= bound:
            assert w.distance == pytest.approx(gap, abs=1e-12)
        else:
            assert bound < w.distance <= gap + 1e-12
    assert cdkit.gjk_distance_within(a, None, a, translation(0.9), 0.1).colliding


def test_every_shape_pair_runs(shapes):
    for a in shapes:
        for b in shapes:
            far = cdkit.gjk_distance(a, None, b, translation(5.0))
            assert far.status == cdkit.GjkStatus.separated and 3.0 < far.distance < 5.0
            if isinstance(a, cdkit.ConvexTriangle) and isinstance(b, cdkit.ConvexTriangle):
                continue  # two flat triangles near each other need not meet
            near = cdkit.gjk_intersect(a, rotation_z(0.2), b, translation(0.05))
            assert near.colliding  # each solid holds a ball about its origin; the triangle has a corner there


def test_caches_give_the_cold_answers(shapes):
    hull = shapes[7]
    gc, pc, fc = cdkit.GjkCache(), cdkit.SeparatingPlaneCache(), cdkit.ClosestFeatureCache()
    for k in range(60):
        pb = rotation_z(0.05 * k, (1.2 - 0.02 * k, 0.1, 0.0))
        cold = cdkit.gjk_distance(hull, None, hull, pb)
        warm = cdkit.gjk_distance(hull, None, hull, pb, cache=gc)
        assert warm.status == cold.status
        assert warm.distance == pytest.approx(cold.distance, abs=1e-9)
        assert cdkit.separating_plane_intersect(hull, None, hull, pb, cache=pc).colliding == cold.colliding
        cf = cdkit.closest_features(hull, None, hull, pb, cache=fc)
        assert cf.colliding == cold.colliding
        if not cold.colliding:
            assert cf.distance == pytest.approx(cold.distance, abs=1e-9)
    assert gc.size > 0 and fc.valid
    gc.reset()
    assert gc.size == 0


def test_shape_properties_and_support():
    s = cdkit.Sphere(2.0)
    assert s.radius == 2.0 and np.allclose(s.support([0, 0, 3]), [0, 0, 2])
    b = cdkit.Box([1, 2, 3])
    assert np.array_equal(b.half_extents, [1, 2, 3]) and np.array_equal(b.support([1, -1, 1]), [1, -2, 3])
    assert np.allclose(cdkit.Capsule(0.5, 1.0).support([0, 0, 1]), [0, 0, 1.5])
    assert np.allclose(cdkit.Ellipsoid([1, 2, 3]).support([0, 1, 0]), [0, 2, 0])
    cube_points = np.array([[x, y, z] for x in (0, 1) for y in (0, 1) for z in (0, 1)], float)
    h = cdkit.ConvexPolyhedron(np.vstack([cube_points, [[0.5, 0.5, 0.5]]]))
    assert h.vertices.shape == (8, 3) and h.face_count == 6 and h.triangles.shape == (12, 3)
    assert h.bounding_radius == pytest.approx(math.sqrt(3) / 2)


def test_convex_toi_exact():
    a = cdkit.Sphere(0.5)
    r = cdkit.convex_toi(a, None, None, a, translation(3.0), translation(-1.0))
    # Centres close from 3 to -1 (distance 3 - 4t); contact at distance 1 when t = 0.5.
    assert r.colliding and r.toi == pytest.approx(0.5, abs=1e-5) and r.toi <= 0.5
    assert not cdkit.convex_toi(a, None, None, a, translation(3.0), translation(2.0)).colliding
