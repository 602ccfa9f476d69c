"""penetration_depth between two meshes: known depths of boxes, the inner-sphere-tree variant, bad input."""
import math

import numpy as np
import pytest

import cdkit
from conftest import cube, translation


def test_boxes_give_the_face_depth_and_normal():
    a = cdkit.MeshModel(*cube(half=0.5))
    b = cdkit.MeshModel(*cube(half=0.4))
    r = cdkit.penetration_depth(a, translation(0), b, translation(0.7))
    assert r.status == cdkit.QueryStatus.ok and r.colliding
    assert r.depth == pytest.approx(0.2, abs=1e-9)
    assert np.allclose(r.normal, [1, 0, 0], atol=1e-9)
    assert r.direction == cdkit.DepthDirection.surface_normal
    assert np.allclose(np.asarray(r.point_a) - np.asarray(r.point_b), r.depth * np.asarray(r.normal), atol=1e-9)
    diag = cdkit.penetration_depth(a, translation(0), b, translation(0.7), direction=[1, 1, 0])
    assert diag.depth == pytest.approx(0.2 * math.sqrt(2), abs=1e-9)
    assert diag.direction == cdkit.DepthDirection.given
    refined = cdkit.penetration_depth(a, translation(0), b, translation(0.7), refine_steps=3)
    assert refined.depth <= r.depth + 1e-12
    apart = cdkit.penetration_depth(a, translation(0), b, translation(1.2))
    assert not apart.colliding and apart.depth == 0


def test_inner_sphere_trees_add_the_volume_and_force_direction():
    v, f = cube(half=0.5)
    a = cdkit.MeshModel(v, f)
    ist = cdkit.build_inner_sphere_tree(v, f, max_spheres=200, grid_resolution=24)
    r = cdkit.penetration_depth(a, translation(0), a, translation(0.6), ist_a=ist, ist_b=ist)
    assert r.colliding and r.volume > 0
    assert np.allclose(r.force_direction, [1, 0, 0], atol=0.1)
    assert r.depth == pytest.approx(0.4, abs=1e-6)


def test_bad_input_is_refused():
    a = cdkit.MeshModel(*cube(half=0.5))
    ist = cdkit.build_inner_sphere_tree(*cube(half=0.5), max_spheres=50, grid_resolution=16)
    with pytest.raises(ValueError):
        cdkit.penetration_depth(a, translation(0), a, translation(0.5), ist_a=ist)
    with pytest.raises(ValueError):
        cdkit.penetration_depth(a, translation(0), a, translation(float("nan")))
    r = cdkit.penetration_depth(a, translation(0), a, translation(0.5), direction=[0, 0, 0])
    assert r.status == cdkit.QueryStatus.invalid_input


def test_world_mesh_contacts_carry_the_depth_unless_switched_off():
    for depth_on in (True, False):
        world = cdkit.World(cdkit.WorldOptions(mesh_depth=depth_on))
        a = world.add(cdkit.MeshModel(*cube(half=0.5)), translation(0))
        b = world.add(cdkit.MeshModel(*cube(half=0.4)), translation(0.7))
        (c,) = world.step().contacts
        assert (c.a, c.b) == (a, b) and c.method == cdkit.PairMethod.mesh_mesh
        assert c.has_depth == depth_on
        assert c.depth == (pytest.approx(0.2, abs=1e-9) if depth_on else 0)
