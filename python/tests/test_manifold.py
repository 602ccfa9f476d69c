"""Contact manifolds: a box on the ground touches at its four corners, ids persist through a ManifoldCache, the
World reports the manifold's points and speculative contacts within its margin; bad requests raise."""
import numpy as np
import pytest

import cdkit
from conftest import translation


def ground():
    return cdkit.Box([10.0, 10.0, 0.5]), translation(0.0, 0.0, -0.5)


def test_box_on_ground_has_four_corners():
    g, gp = ground()
    box = cdkit.Box([0.5, 0.3, 0.2])
    m = cdkit.contact_manifold(g, gp, box, translation(0.2, 0.1, 0.19))
    assert m.colliding and m.count == 4
    assert np.allclose(m.normal, [0, 0, 1])
    corners = np.array(sorted((p.point_b[0], p.point_b[1]) for p in m.points))
    expected = np.array(sorted((0.2 + sx * 0.5, 0.1 + sy * 0.3) for sx in (-1, 1) for sy in (-1, 1)))
    assert np.allclose(corners, expected, atol=1e-12)
    for p in m.points:
        assert p.depth == pytest.approx(0.01, abs=1e-12)
        assert np.dot(p.point_a - p.point_b, m.normal) == pytest.approx(p.depth, abs=1e-12)
    assert len({p.id for p in m.points}) == 4
    single = cdkit.contact_manifold(g, gp, box, translation(0.2, 0.1, 0.19), cdkit.ManifoldRequest(single_point=True))
    assert single.count == 1


def test_ids_persist_with_a_cache():
    g, gp = ground()
    box = cdkit.Box([0.5, 0.5, 0.5])
    cache = cdkit.ManifoldCache()
    first = cdkit.contact_manifold(g, gp, box, translation(0.0, 0.0, 0.49), cache=cache)
    moved = cdkit.contact_manifold(g, gp, box, translation(1e-4, -1e-4, 0.4899), cache=cache)
    assert cache.count == 4
    by_corner = lambda m: {(np.sign(p.point_b[0]), np.sign(p.point_b[1])): p.id for p in m.points}
    assert len(by_corner(first)) == 4 and by_corner(first) == by_corner(moved)


def test_speculative_points_and_bad_requests():
    g, gp = ground()
    box = cdkit.Box([0.5, 0.5, 0.5])
    apart = translation(0.0, 0.0, 0.51)
    assert cdkit.contact_manifold(g, gp, box, apart).count == 0
    m = cdkit.contact_manifold(g, gp, box, apart, cdkit.ManifoldRequest(margin=0.02))
    assert not m.colliding and m.count == 4 and m.distance == pytest.approx(0.01, abs=1e-9)
    assert all(p.depth == pytest.approx(-0.01, abs=1e-9) for p in m.points)
    with pytest.raises(ValueError):
        cdkit.contact_manifold(g, gp, box, apart, cdkit.ManifoldRequest(margin=-1.0))


def test_world_manifolds_and_margin():
    for manifolds, count in ((True, 4), (False, 1)):
        world = cdkit.World(cdkit.WorldOptions(manifolds=manifolds))
        world.add(cdkit.Box([5.0, 5.0, 0.5]), translation(0.0, 0.0, -0.5))
        world.add(cdkit.Box([0.5, 0.5, 0.5]), translation(0.0, 0.0, 0.49))
        (c,) = world.step().contacts
        assert c.colliding and len(c.points) == count
    world = cdkit.World(cdkit.WorldOptions(contact_margin=0.05))
    world.add(cdkit.Box([5.0, 5.0, 0.5]), translation(0.0, 0.0, -0.5))
    world.add(cdkit.Sphere(0.2), translation(0.0, 0.0, 0.23))
    (c,) = world.step().contacts
    assert not c.colliding and c.distance == pytest.approx(0.03, abs=1e-9)
    assert c.points[0].depth == pytest.approx(-0.03, abs=1e-9)
    with pytest.raises(cdkit.Error):
        cdkit.World(cdkit.WorldOptions(contact_margin=-1.0))


def test_world_takes_every_convex_kind():
    world = cdkit.World()
    world.add(cdkit.Box([20.0, 20.0, 0.5]), translation(0.0, 0.0, -0.5))
    shapes = [cdkit.Cylinder(0.4, 0.5), cdkit.Cone(0.4, 0.5), cdkit.Ellipsoid([0.3, 0.4, 0.5]),
              cdkit.ConvexTriangle([0, 0, 0], [1, 0, 0], [0, 1, 0])]
    heights = [0.49, 0.49, 0.49, -0.01]
    for k, (s, z) in enumerate(zip(shapes, heights)):
        world.add(s, translation(3.0 * k, 0.0, z))
    contacts = world.step().contacts
    assert [len(c.points) for c in contacts] == [4, 4, 1, 3]
    assert all(c.depth == pytest.approx(0.01, abs=1e-9) for c in contacts)


def test_world_compound_reports_its_children():
    world = cdkit.World()
    world.add(cdkit.Box([10.0, 10.0, 0.5]), translation(0.0, 0.0, -0.5))
    l_shape = [cdkit.Box([1.0, 0.25, 0.25]), (cdkit.Box([0.25, 0.25, 0.75]), translation(0.75, 0.0, 1.01))]
    l = world.add(l_shape, translation(0.0, 0.0, 0.24))
    ball = world.add(cdkit.Sphere(0.3), translation(1.29, 0.0, 1.2))
    contacts = world.step().contacts
    assert [(c.a, c.b, c.child_a, c.child_b) for c in contacts] == [(0, l, None, 0), (l, ball, 1, None)]
    with pytest.raises(cdkit.Error):
        world.add([], None)
