"""Bad input: arrays of the wrong shape, dtype or with NaN raise ValueError before any query runs; bad data that only
the library can judge (files, hulls, World ids and poses, stored trees) raises cdkit.Error with the C++ message;
wrong types raise TypeError. Nothing crashes the interpreter."""
import numpy as np
import pytest

import cdkit
from conftest import cube


def test_error_class():
    assert issubclass(cdkit.Error, Exception)
    assert cdkit.Error.__module__.startswith("cdkit")


@pytest.mark.parametrize("vertices, faces, match", [
    (np.zeros((4, 2)), np.array([[0, 1, 2]]), r"vertices: expected shape \(N, 3\), got \(4, 2\)"),
    (np.zeros(12), np.array([[0, 1, 2]]), "vertices: expected shape"),
    (np.zeros((4, 3), dtype=complex), np.array([[0, 1, 2]]), "vertices: expected a float"),
    (np.array([["a", "b", "c"]] * 4), np.array([[0, 1, 2]]), "vertices: expected a float"),
    (np.array([[0, 0, 0], [1, 0, np.nan], [0, 1, 0]]), np.array([[0, 1, 2]]), "vertices: entry 5 is NaN"),
    (np.array([[0, 0, 0], [1, 0, np.inf], [0, 1, 0]]), np.array([[0, 1, 2]]), "NaN or infinite"),
    (np.eye(3), np.array([[0.0, 1.0, 2.0]]), "faces: expected an integer array"),
    (np.eye(3), np.array([[0, 1]]), "faces: expected shape"),
    (np.eye(3), np.array([[0, 1, 3]]), "triangle 0 has vertex index 3, out of range for 3 vertices"),
    (np.eye(3), np.array([[0, -1, 2]]), "vertex index -1"),
    (np.eye(3), np.zeros((0, 3), dtype=int), "no triangles"),
    (None, np.array([[0, 1, 2]]), "vertices: expected an array, got None"),
    ([[0, 0], [1, 0, 0]], np.array([[0, 1, 2]]), "vertices"),
])
def test_bad_mesh_arrays(vertices, faces, match):
    with pytest.raises(ValueError, match=match):
        cdkit.MeshModel(vertices, faces)


def test_bad_poses():
    m = cdkit.MeshModel(*cube())
    with pytest.raises(ValueError, match=r"pose_a: expected shape \(4, 4\), got \(3, 3\)"):
        cdkit.collide(m, np.eye(3), m, None)
    nan = np.eye(4)
    nan[1, 3] = np.nan
    with pytest.raises(ValueError, match="pose_b: entry 7 is NaN"):
        cdkit.distance(m, None, m, nan)
    row = np.eye(4)
    row[3, 0] = 1
    with pytest.raises(ValueError, match="bottom row"):
        cdkit.collide(m, row, m, None)
    with pytest.raises(ValueError, match="pose_a"):
        cdkit.collide(m, (np.eye(3), [0, 0]), m, None)
    with pytest.raises(ValueError, match="pose_a"):
        cdkit.gjk_distance(cdkit.Sphere(1), "not a pose", cdkit.Sphere(1), None)


def test_bad_batches():
    m = cdkit.MeshModel(*cube())
    P = np.repeat(np.eye(4)[None], 3, axis=0)
    with pytest.raises(ValueError, match="poses_a has 3 poses but poses_b has 2"):
        cdkit.collide_many(m, P, m, P[:2])
    scaled = P.copy()
    scaled[1, 0, 0] = 3
    with pytest.raises(ValueError, match=r"poses_b \[1\]: not a rigid motion"):
        cdkit.distance_many(m, P, m, scaled)
    with pytest.raises(ValueError, match="poses_a"):
        cdkit.collide_many(m, np.zeros((3, 4, 3)), m, P)
    with pytest.raises(ValueError, match="threads"):
        cdkit.collide_many(m, P, m, P, threads=-1)
    with pytest.raises(ValueError, match="directions"):
        cdkit.ray_cast_many(m, None, np.zeros((2, 3)), np.zeros((3, 3)))
    with pytest.raises(ValueError, match="zero vector"):
        cdkit.ray_cast_many(m, None, np.zeros((1, 3)), np.zeros((1, 3)))


def test_library_errors_become_cdkit_error(tmp_path):
    with pytest.raises(cdkit.Error, match="no/such/file.obj"):
        cdkit.load_mesh("no/such/file.obj")
    garbage = tmp_path / "garbage.stl"
    garbage.write_bytes(b"\x00\x01 not a mesh at all" * 7)
    with pytest.raises(cdkit.Error, match="garbage.stl"):
        cdkit.MeshModel.from_file(str(garbage))
    with pytest.raises(cdkit.Error):
        cdkit.ConvexPolyhedron(np.zeros((3, 3)))  # too few points / flat
    with pytest.raises(cdkit.Error):
        cdkit.Box([-1, 1, 1])  # a negative size: the C++ constructor's check
    world = cdkit.World()
    with pytest.raises(cdkit.Error, match="set_pose"):
        world.set_pose(7, None)  # unknown id
    i = world.add(cdkit.Sphere(1.0), None)
    scaled = np.eye(4)
    scaled[2, 2] = 2
    with pytest.raises(cdkit.Error, match="set_pose"):
        world.set_pose(i, scaled)
    bad_tree = tmp_path / "tree.ist"
    bad_tree.write_bytes(b"CDKITIST" + b"\x00" * 40)
    with pytest.raises(cdkit.Error, match="tree.ist"):
        cdkit.InnerSphereTree.load(str(bad_tree))
    with pytest.raises(ValueError):
        cdkit.Sphere(float("nan"))


def test_wrong_types():
    m = cdkit.MeshModel(*cube())
    with pytest.raises(TypeError):
        cdkit.gjk_distance(m, None, cdkit.Sphere(1.0), None)  # a mesh is not a convex shape
    with pytest.raises(TypeError):
        cdkit.collide(cdkit.Sphere(1.0), None, m, None)
    with pytest.raises(ValueError, match="bv"):
        cdkit.MeshModel(*cube(), bv="octree")


def test_failed_internal_check_raises_instead_of_aborting():
    # A CDKIT_ASSERT would abort a C++ program; the module installs a handler that raises cdkit.Error instead.
    with pytest.raises(cdkit.Error, match=r"internal check false: a test of the assert handler"):
        cdkit._cdkit._fail_assert_for_test()
    # The interpreter and the module go on working.
    assert cdkit.Sphere(1.0) is not None
