"""Inner sphere trees (build, save/load, penetration volume, forces) and continuous collision primitives on exact
constructions."""
import math

import numpy as np
import pytest

import cdkit
from conftest import cube, translation


@pytest.fixture(scope="module")
def tree():
    return cdkit.build_inner_sphere_tree(*cube(half=0.5), max_spheres=200, grid_resolution=24)


def test_ist_build_and_queries(tree, tmp_path):
    assert tree.num_spheres == 200 and tree.spheres.shape == (200, 4)
    assert tree.mesh_volume == pytest.approx(1.0, rel=1e-12)
    assert 0.3 < tree.coverage <= 1.0
    assert np.all(np.abs(tree.spheres[:, :3]) + tree.spheres[:, 3:] <= 0.5 + 1e-9)  # inside the cube
    tree.validate()
    apart = cdkit.penetration_volume(tree, None, tree, translation(1.5))
    assert not apart.colliding and apart.volume == 0
    near = cdkit.sphere_distance(tree, None, tree, translation(1.5))
    assert 0.5 <= near.distance < 1.5
    hit = cdkit.penetration_volume(tree, None, tree, translation(0.6))
    assert hit.colliding and hit.complete and hit.volume > 0 and len(hit.pairs) > 0
    assert hit.volume_lower <= hit.volume <= hit.volume_upper
    assert 0 < hit.calibrated < 0.4 * 1.5  # the cubes' intersection is 0.4 (a reference, loosely)
    w = cdkit.penalty_wrench(hit, tree, None, tree, translation(0.6), 100.0)
    assert w.pairs == len(hit.pairs)
    assert np.allclose(w.on_a.force, -w.on_b.force) and w.on_b.force[0] > 0  # pushes b away along +x
    path = tmp_path / "cube.ist"
    tree.save(str(path))
    loaded = cdkit.InnerSphereTree.load(str(path))
    assert np.array_equal(loaded.spheres, tree.spheres)
    again = cdkit.penetration_volume(loaded, None, loaded, translation(0.6))
    assert again.volume == hit.volume
    assert np.array_equal(cdkit.InnerSphereTree.from_bytes(tree.to_bytes()).spheres, tree.spheres)


def test_open_mesh_is_refused():
    v, f = cube()
    with pytest.raises(cdkit.Error):
        cdkit.build_inner_sphere_tree(v, f[:-1], max_spheres=10, grid_resolution=16)


def test_vertex_face_ccd_exact():
    a, b, c = [0, 0, 0], [1, 0, 0], [0, 1, 0]
    r = cdkit.vertex_face_ccd([0.2, 0.2, 1.0], a, b, c, [0.2, 0.2, -1.0], a, b, c)
    assert r.status == cdkit.QueryStatus.ok and r.colliding and r.proven
    assert r.toi <= 0.5 <= r.toi_upper and r.toi_upper - r.toi <= 1e-5
    assert np.allclose(r.point, [0.2, 0.2, 0.0], atol=1e-5)
    miss = cdkit.vertex_face_ccd([2, 2, 1.0], a, b, c, [2, 2, -1.0], a, b, c)
    assert not miss.colliding and miss.toi == 1
    with pytest.raises(ValueError):
        cdkit.vertex_face_ccd([0, 0, np.nan], a, b, c, [0, 0, 1], a, b, c)


def test_edge_edge_ccd_exact():
    # Edge A along x at height 1 falling to -1; edge B along y at 0: they cross at t = 0.5.
    r = cdkit.edge_edge_ccd([-1, 0, 1], [1, 0, 1], [0, -1, 0], [0, 1, 0], [-1, 0, -1], [1, 0, -1], [0, -1, 0], [0, 1, 0],
                            request=cdkit.CcdRequest(tolerance=1e-7))
    assert r.colliding and r.toi <= 0.5 <= r.toi_upper
    assert r.u == pytest.approx(0.5, abs=1e-4) and r.v == pytest.approx(0.5, abs=1e-4)


def axis_rotation(axis, angle):
    k = np.asarray(axis, float) / np.linalg.norm(axis)
    K = np.array([[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]])
    return np.eye(3) + math.sin(angle) * K + (1 - math.cos(angle)) * K @ K


def test_mesh_ccd_cubes_against_convex_toi():
    # A turned cube b sweeps from x = 3 to x = -1 past the cube a at rest: mesh_ccd on the triangles against
    # conservative advancement on the same boxes (an independent method); both are lower bounds within tolerance.
    m = cdkit.MeshModel(*cube())
    box = cdkit.Box([0.5, 0.5, 0.5])
    R = axis_rotation([1, 2, 3], 0.4)
    start, end = (R, [3.0, 0.1, 0.05]), (R, [-1.0, 0.1, 0.05])
    r = cdkit.mesh_ccd(m, None, None, m, start, end)
    toi = cdkit.convex_toi(box, None, None, box, start, end, cdkit.ToiRequest(tolerance=1e-9))
    assert r.status == cdkit.QueryStatus.ok and r.colliding and toi.colliding
    assert 0.3 < toi.toi < 0.5 and r.toi == pytest.approx(toi.toi, abs=1e-4)
    assert len(r.contacts) == 1
    every = cdkit.mesh_ccd(m, None, None, m, start, end, cdkit.DeformableCcdRequest(mode=cdkit.ContactMode.all))
    assert len(every.contacts) > 1 and min(c.ccd.toi for c in every.contacts) == every.toi
    assert not cdkit.mesh_ccd(m, None, None, m, translation(3.0), translation(2.0)).colliding
