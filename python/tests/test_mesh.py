"""MeshModel, collide, distance on exact constructions (unit cubes a known gap apart, every BV type), the result
arrays' shapes and dtypes, load_mesh, and the brute-force references."""
import numpy as np
import pytest

import cdkit
from conftest import DATA, cube, rotation_z, translation

BVS = ["aabb", "obb", "rss", "kdop18", "sphere"]


@pytest.mark.parametrize("bv", BVS)
def test_cubes_at_known_gaps(bv):
    v, f = cube()
    m = cdkit.MeshModel(v, f, bv=bv)
    assert m.bv == getattr(cdkit.BV, bv) and m.num_triangles == 12 and m.num_vertices == 8
    m.validate()
    for gap in (0.25, 0.125, 1.0 / 1024):
        pb = translation(1.0 + gap)
        r = cdkit.collide(m, None, m, pb)
        assert r.status == cdkit.QueryStatus.ok and not r.colliding and not r
        assert r.triangle_pairs.shape == (0, 2) and r.points.shape == (0, 3)
        d = cdkit.distance(m, None, m, pb)  # every BV has a distance bound
        assert d.distance == pytest.approx(gap, abs=1e-15)
        assert d.point_a[0] == pytest.approx(0.5) and d.point_b[0] == pytest.approx(0.5 + gap)
    # Overlapping by a quarter, and touching face to face (touching counts).
    for x in (0.75, 1.0):
        r = cdkit.collide(m, None, m, translation(x), cdkit.CollisionRequest(cdkit.ContactMode.all))
        assert r.colliding and len(r.contacts) > 0
        assert r.triangle_pairs.dtype == np.int64 and r.triangle_pairs.shape == (len(r.contacts), 2)
        assert r.points.shape == (len(r.contacts), 3)
        assert np.all(np.abs(r.points[:, 0] - x / 2) <= 0.5 - x / 2 + 1e-12)  # witnesses inside both cubes' overlap
        assert cdkit.distance(m, None, m, translation(x)).distance == 0


def test_all_contacts_equal_brute_force(bunny):
    v, f = bunny
    m = cdkit.MeshModel(v, f[::6])  # a 613-triangle soup of the bunny: brute force stays quick
    req = cdkit.CollisionRequest(cdkit.ContactMode.all)
    for k in range(6):
        pb = rotation_z(0.3 * k, (1.0 * k, 0.5, 0.0))
        fast = cdkit.collide(m, None, m, pb, req)
        ref = cdkit.collide_brute_force(m, None, m, pb, req)
        assert sorted(map(tuple, fast.triangle_pairs.tolist())) == sorted(map(tuple, ref.triangle_pairs.tolist()))
        assert fast.colliding
        assert fast.stats.primitive_tests < m.num_triangles ** 2


def test_distance_equals_brute_force_on_small_meshes():
    v, f = cube()
    m = cdkit.MeshModel(v, f, bv="rss")
    for k in range(5):
        pb = rotation_z(0.4 * k + 0.1, (1.3 + 0.1 * k, 0.2, -0.1))
        assert cdkit.distance(m, None, m, pb).distance == cdkit.distance_brute_force(m, None, m, pb).distance


def test_distance_max_distance():
    """Unit cubes 0.5 apart: within max_distance the unbounded answer, beyond it inf; a bad bound is refused."""
    v, f = cube()
    m = cdkit.MeshModel(v, f, bv="obb")
    pb = translation(1.5)
    assert cdkit.distance(m, None, m, pb).distance == pytest.approx(0.5, abs=1e-12)
    assert cdkit.distance(m, None, m, pb, cdkit.DistanceRequest(max_distance=0.6)).distance == pytest.approx(0.5, abs=1e-12)
    assert cdkit.distance(m, None, m, pb, cdkit.DistanceRequest(max_distance=0.4)).distance == np.inf
    assert cdkit.DistanceRequest().max_distance == np.inf
    with pytest.raises(ValueError, match="max_distance"):
        cdkit.DistanceRequest(max_distance=-1.0)
    with pytest.raises(ValueError, match="max_distance"):
        cdkit.DistanceRequest(max_distance=float("nan"))


def test_pose_forms_agree():
    v, f = cube()
    m = cdkit.MeshModel(v, f)
    R = rotation_z(0.3)[:3, :3]
    t = np.array([1.4, 0.1, 0.0])
    as_4x4 = cdkit.distance(m, None, m, cdkit.pose(R, t)).distance
    assert cdkit.distance(m, np.eye(4), m, (R, t)).distance == as_4x4
    assert cdkit.distance(m, np.eye(4).tolist(), m, (R.tolist(), t.tolist())).distance == as_4x4
    # A scaled "pose" is not a rigid motion: the query's status says so (as in C++), no answer.
    bad = np.eye(4)
    bad[0, 0] = 2.0
    assert cdkit.collide(m, bad, m, None).status == cdkit.QueryStatus.invalid_pose
    assert not cdkit.pose_is_usable(bad) and cdkit.pose_is_usable(cdkit.pose(R, t))


def test_models_of_every_dtype_agree():
    v, f = cube()
    ref = cdkit.MeshModel(v, f)
    pb = translation(1.25)
    for vv in (v.astype(np.float32), v.astype(np.int64) * 0 + v.astype(np.float64)):
        for ff in (f.astype(np.int32), f.astype(np.uint32), f.astype(np.uint64)):
            m = cdkit.MeshModel(vv, ff)
            assert cdkit.distance(m, None, m, pb).distance == cdkit.distance(ref, None, ref, pb).distance
    # float32 vertices and int32 faces in C order are read in place (no float64 / int64 temporary): the model's mesh
    # is exactly the float32 values widened, and their bad entries are named as for any dtype.
    vb, fb64 = cdkit.load_mesh(str(DATA / "bunny.obj"))
    b, fb = vb.astype(np.float32), fb64.astype(np.int32)
    m32 = cdkit.MeshModel(b, fb)
    assert m32.vertices.dtype == np.float64 and np.array_equal(m32.vertices, b.astype(np.float64))
    assert np.array_equal(m32.faces, fb.astype(np.int64))
    bad = b.copy()
    bad[7, 1] = np.nan
    with pytest.raises(ValueError, match="vertices: entry 22 is NaN or infinite"):
        cdkit.MeshModel(bad, fb)
    bad_faces = fb.copy()
    bad_faces[3, 2] = len(b)
    with pytest.raises(ValueError, match="faces: triangle 3 has vertex index"):
        cdkit.MeshModel(b, bad_faces)
    # Non-contiguous (transposed views) arrays are read correctly too.
    m = cdkit.MeshModel(np.asfortranarray(v), np.asfortranarray(f))
    assert np.array_equal(m.vertices, v) and np.array_equal(m.faces, f)


def test_load_mesh_and_from_file(bunny):
    v, f = bunny
    assert v.dtype == np.float64 and v.shape[1] == 3 and f.dtype == np.int64 and f.shape == (3674, 3)
    assert f.min() >= 0 and f.max() < len(v)
    from conftest import DATA
    m = cdkit.MeshModel.from_file(str(DATA / "bunny.obj"), bv="rss")
    assert m.num_triangles == 3674 and np.array_equal(m.faces, f) and np.array_equal(m.vertices, v)
    assert "bunny" in repr(m) or "3674" in repr(m)


def test_models_of_different_bv_types_do_not_mix():
    v, f = cube()
    with pytest.raises(ValueError, match="same bounding volume"):
        cdkit.collide(cdkit.MeshModel(v, f, bv="obb"), None, cdkit.MeshModel(v, f, bv="rss"), None)


def test_build_options():
    v, f = cube()
    for split in (cdkit.SplitStrategy.median, cdkit.SplitStrategy.mean, cdkit.SplitStrategy.sah, cdkit.SplitStrategy.pca_volume):
        m = cdkit.MeshModel(v, f, bv=cdkit.BV.obb, split=split, leaf_size=2)
        m.validate()
        assert cdkit.collide(m, None, m, translation(0.9)).colliding
