"""Mesh–convex queries (mesh_convex_collide / _distance / _penetration), convex_ray_cast, mesh_convex_toi and
mesh_toi on exact constructions (a unit cube mesh, a sphere at a known distance, a ray onto a box face, a sphere and
a cube moving onto a cube with a known time of impact), the same answers for every bounding volume, the distance
against the per-triangle GJK answers, the C++ answers of cpp_reference.cpp on the bunny (bit-equal), and bad input
raising before any query runs."""
import math

import numpy as np
import pytest

import cdkit
from conftest import cube, reference_shapes, rotation_z, translation

BVS = ["aabb", "obb", "rss", "kdop18", "sphere"]
DISTANCE_BVS = ["aabb", "obb", "rss", "kdop18", "sphere"]  # mesh_toi: the mesh–mesh distance's trees (every BV)


def cube_model(bv="obb"):
    return cdkit.MeshModel(*cube(), bv=bv)  # [-0.5, 0.5]^3, 12 triangles


def face_triangles(faces, vertices, axis, sign):
    """Indices of the triangles lying in the cube face x[axis] == sign * 0.5."""
    return {i for i, f in enumerate(faces) if np.all(vertices[f][:, axis] == sign * 0.5)}


@pytest.mark.parametrize("bv", BVS)
def test_sphere_at_known_distance(bv):
    v, f = cube()
    m = cube_model(bv)
    s = cdkit.Sphere(0.5)
    d = cdkit.mesh_convex_distance(m, None, s, translation(2.5))
    assert d.status == cdkit.QueryStatus.ok and not d.colliding
    assert d.distance == pytest.approx(1.5, abs=1e-12)
    assert np.allclose(d.point_mesh, [0.5, 0, 0], atol=1e-12)
    assert np.allclose(d.point_shape, [2.0, 0, 0], atol=1e-12)
    assert d.triangle in face_triangles(f, v, 0, +1)
    # The same under a moved mesh (pose as 4x4 and as (R, t)).
    d2 = cdkit.mesh_convex_distance(m, translation(0, 3), s, (np.eye(3), [0, 3, 2.5]))
    assert d2.distance == pytest.approx(1.5, abs=1e-12) and np.allclose(d2.point_mesh, [0, 3, 0.5], atol=1e-12)
    # Touching and crossing: distance 0, colliding.
    t = cdkit.mesh_convex_distance(m, None, s, translation(0.8))
    assert t.colliding and t.distance == 0.0


@pytest.mark.parametrize("bv", BVS)
def test_collide_and_penetration_known_depth(bv):
    v, f = cube()
    m = cube_model(bv)
    s = cdkit.Sphere(0.5)
    apart = cdkit.mesh_convex_collide(m, None, s, translation(1.2))
    assert apart.status == cdkit.QueryStatus.ok and not apart.colliding and not apart
    assert apart.triangles.shape == (0,) and apart.points.shape == (0, 3)
    # The sphere at x = 0.7 reaches 0.2 into the face x = 0.5 (and no other face: |y|, |z| stay below 0.5).
    first = cdkit.mesh_convex_collide(m, None, s, translation(0.7))
    assert first.colliding and len(first.contacts) == 1 and first.triangles.dtype == np.int64
    req = cdkit.MeshConvexRequest(mode=cdkit.ContactMode.all)
    c = cdkit.mesh_convex_collide(m, None, s, translation(0.7), req)
    assert set(c.triangles.tolist()) == face_triangles(f, v, 0, +1)
    assert c.triangles.shape == (2,) and c.points.shape == (2, 3) and not c.truncated
    for t, p in zip(c.triangles, c.points):  # each witness lies on its triangle and in the sphere
        assert p[0] == pytest.approx(0.5) and np.linalg.norm(p - [0.7, 0, 0]) <= 0.5 + 1e-9
        assert c.contacts[list(c.triangles).index(t)].triangle == t
    one = cdkit.mesh_convex_collide(m, None, s, translation(0.7), cdkit.MeshConvexRequest(cdkit.ContactMode.all, 1))
    assert one.truncated and len(one.contacts) == 1
    p = cdkit.mesh_convex_penetration(m, None, s, translation(0.7))
    assert p.colliding and p.status == cdkit.QueryStatus.ok
    assert p.deepest.depth == pytest.approx(0.3, abs=1e-6)  # the sphere's surface at x = 0.2 against the plane x = 0.5
    assert np.allclose(p.deepest.normal, [1, 0, 0], atol=1e-6)
    assert p.deepest.triangle in face_triangles(f, v, 0, +1)
    assert np.allclose(p.deepest.point_mesh - p.deepest.point_shape, p.deepest.depth * p.deepest.normal, atol=1e-6)
    pa = cdkit.mesh_convex_penetration(m, None, s, translation(0.7), req)
    assert set(pa.triangles.tolist()) == face_triangles(f, v, 0, +1) and len(pa.contacts) == 2
    assert not cdkit.mesh_convex_penetration(m, None, s, translation(1.2)).colliding


def test_every_bv_and_shape_agree_with_triangle_gjk(shapes):
    """The distance over the tree equals the minimum of GJK over the mesh's triangles (exact request), every BV the
    same answer, for every bound shape at a rotated pose."""
    v, f = cube()
    tris = [cdkit.ConvexTriangle(*v[t]) for t in f]
    models = {bv: cube_model(bv) for bv in BVS}
    mesh_pose = rotation_z(0.3, (0.1, -0.2, 0.0))
    shape_pose = rotation_z(1.1, (2.0, 0.4, 0.3))
    for s in shapes:
        expect = min(cdkit.gjk_distance(t, mesh_pose, s, shape_pose).distance for t in tris)
        answers = [cdkit.mesh_convex_distance(models[bv], mesh_pose, s, shape_pose) for bv in BVS]
        for d in answers:
            assert d.status == cdkit.QueryStatus.ok
            assert d.distance == pytest.approx(expect, rel=1e-9, abs=1e-12)
            assert d.distance == answers[0].distance  # the triangle may differ on a tie (a shared edge)
            assert cdkit.gjk_distance(tris[d.triangle], mesh_pose, s, shape_pose).distance == pytest.approx(
                d.distance, rel=1e-9, abs=1e-12)
            assert np.linalg.norm(d.point_mesh - d.point_shape) == pytest.approx(d.distance, rel=1e-9, abs=1e-12)
        for bv in BVS:  # collide and penetration run for every pair and agree with the distance
            for near in (rotation_z(0.2, (0.6, 0.0, 0.0)), rotation_z(0.2, (0.95, 0.0, 0.1))):
                touching = cdkit.mesh_convex_distance(models[bv], None, s, near).colliding
                assert cdkit.mesh_convex_collide(models[bv], None, s, near).colliding == touching
                assert cdkit.mesh_convex_penetration(models[bv], None, s, near).colliding == touching
            assert cdkit.mesh_convex_collide(models[bv], None, s, rotation_z(0.2, (0.6, 0.0, 0.0))).colliding or \
                isinstance(s, cdkit.ConvexTriangle)
            assert not cdkit.mesh_convex_collide(models[bv], None, s, translation(5.0)).colliding


def test_convex_ray_cast_box_face():
    box = cdkit.Box([1.0, 1.0, 1.0])
    r = cdkit.convex_ray_cast(box, None, [-5.0, 0.2, -0.3], [1.0, 0.0, 0.0])
    assert r.status == cdkit.QueryStatus.ok and r.hit and len(r.hits) == 1
    h = r.hits[0]
    assert h.t <= 4.0 and h.t == pytest.approx(4.0, abs=1e-8)  # never later than the exact contact
    assert np.allclose(h.point, [-1.0, 0.2, -0.3], atol=1e-8) and np.allclose(h.normal, [-1, 0, 0], atol=1e-6)
    # A moved box (pose), a slower direction (t scales) and a tighter tolerance.
    r2 = cdkit.convex_ray_cast(box, translation(0, 0, 10), [0, 0, 0], [0, 0, 2.0], request=cdkit.ConvexRayRequest(1e-12))
    assert r2.hit and r2.hits[0].t == pytest.approx(4.5, abs=1e-10) and np.allclose(r2.hits[0].normal, [0, 0, -1], atol=1e-6)
    assert not cdkit.convex_ray_cast(box, None, [-5, 3, 0], [1, 0, 0]).hit  # passes beside
    assert not cdkit.convex_ray_cast(box, None, [-5, 0, 0], [-1, 0, 0]).hit  # moves away
    assert not cdkit.convex_ray_cast(box, None, [-5, 0, 0], [1, 0, 0], t_max=3.0).hit  # ends before the face
    s = cdkit.convex_ray_cast(cdkit.Sphere(0.5), None, [0, -3, 0], [0, 1, 0])
    assert s.hit and s.hits[0].t == pytest.approx(2.5, abs=1e-8)


@pytest.mark.parametrize("bv", BVS)
def test_mesh_convex_toi_known_time(bv):
    m = cube_model(bv)
    s = cdkit.Sphere(0.5)
    req = cdkit.ToiRequest(tolerance=1e-9)
    # The sphere's centre from x = 3 to x = -1: it meets the face x = 0.5 when the centre is at 1.0, t = 0.5.
    r = cdkit.mesh_convex_toi(m, None, None, s, translation(3.0), translation(-1.0), req)
    assert r.status == cdkit.QueryStatus.ok and r.colliding
    assert r.toi <= 0.5 and r.toi == pytest.approx(0.5, abs=1e-8)
    assert np.allclose(r.point_a, [0.5, 0, 0], atol=1e-6) and np.allclose(r.point_b, [0.5, 0, 0], atol=1e-6)
    # The mesh moving instead (poses as (R, t)).
    r2 = cdkit.mesh_convex_toi(m, (np.eye(3), [-3, 0, 0]), (np.eye(3), [1, 0, 0]), s, None, None, req)
    assert r2.colliding and r2.toi == pytest.approx(0.5, abs=1e-8)
    assert not cdkit.mesh_convex_toi(m, None, None, s, translation(3.0), translation(2.0), req).colliding


@pytest.mark.parametrize("bv", DISTANCE_BVS)
def test_mesh_toi_known_time(bv):
    a = cube_model(bv)
    req = cdkit.ToiRequest(tolerance=1e-9)
    # Cube b from x = 3 to x = -1: faces meet when its centre is at 1.0, t = 0.5.
    r = cdkit.mesh_toi(a, None, None, a, translation(3.0), translation(-1.0), req)
    assert r.status == cdkit.QueryStatus.ok and r.colliding
    assert r.toi <= 0.5 and r.toi == pytest.approx(0.5, abs=1e-8)
    assert not cdkit.mesh_toi(a, None, None, a, translation(3.0), translation(2.0), req).colliding
    # A quarter turn of b about z on the way does not change a contact of its faces parallel to a's (symmetric cube).
    spun = cdkit.mesh_toi(a, None, None, a, translation(3.0), rotation_z(math.pi / 2, (-1.0, 0, 0)), req)
    assert spun.colliding and 0.0 < spun.toi <= 0.5 + 1e-8


def test_bad_input_raises():
    m = cube_model()
    s = cdkit.Sphere(0.5)
    for f in (cdkit.mesh_convex_collide, cdkit.mesh_convex_distance, cdkit.mesh_convex_penetration):
        with pytest.raises(ValueError, match="pose_shape"):
            f(m, None, s, np.full((4, 4), np.nan))
        with pytest.raises(ValueError, match="pose_mesh"):
            f(m, np.eye(3), s, None)
        with pytest.raises(TypeError, match="shape"):
            f(m, None, m, None)
    with pytest.raises(ValueError, match="rel_err"):
        cdkit.mesh_convex_distance(m, None, s, None, cdkit.DistanceRequest(rel_err=-1.0))
    with pytest.raises(ValueError, match="shape_end"):
        cdkit.mesh_convex_toi(m, None, None, s, None, np.zeros((3, 4)))
    with pytest.raises(TypeError):
        cdkit.mesh_convex_toi(s, None, None, m, None, None)
    with pytest.raises(ValueError, match="b_start"):
        cdkit.mesh_toi(m, None, None, m, [[np.inf, 0, 0, 0]], None)
    with pytest.raises(ValueError, match="same bounding volume"):
        cdkit.mesh_toi(m, None, None, cube_model("aabb"), None, None)
    box = cdkit.Box([1, 1, 1])
    with pytest.raises(ValueError, match="direction"):
        cdkit.convex_ray_cast(box, None, [0, 0, 0], [0, 0, 0])
    with pytest.raises(ValueError, match="origin"):
        cdkit.convex_ray_cast(box, None, [np.nan, 0, 0], [1, 0, 0])
    with pytest.raises(ValueError, match="NaN"):
        cdkit.convex_ray_cast(box, None, [0, 0, 0], [1, 0, 0], t_min=math.nan)
    with pytest.raises(ValueError, match="tolerance"):
        cdkit.ConvexRayRequest(tolerance=0.0)
    with pytest.raises(ValueError, match="max_iterations"):
        cdkit.ConvexRayRequest(max_iterations=0)
    with pytest.raises(TypeError):
        cdkit.convex_ray_cast(m, None, [0, 0, 0], [1, 0, 0])
    # A rotation that is not one: status invalid_pose, as in C++ (not an exception).
    skew = cdkit.pose(np.diag([2.0, 1.0, 1.0]), [0, 0, 0])
    assert cdkit.mesh_convex_distance(m, skew, s, None).status == cdkit.QueryStatus.invalid_pose
    assert cdkit.convex_ray_cast(box, skew, [-5, 0, 0], [1, 0, 0]).status == cdkit.QueryStatus.invalid_pose


def test_queries_release_the_gil():
    """Threads run the queries concurrently and get the single-thread answers."""
    import concurrent.futures as cf
    m = cube_model()
    s = cdkit.Sphere(0.5)
    want = cdkit.mesh_convex_distance(m, None, s, translation(2.5)).distance
    with cf.ThreadPoolExecutor(4) as ex:
        got = list(ex.map(lambda i: cdkit.mesh_convex_distance(m, None, s, translation(2.5)).distance, range(32)))
    assert got == [want] * 32


def test_bunny_equals_cpp(reference, bunny):
    """cpp_reference.cpp's "mesh_convex" rows (bunny on an obb tree, every shape) and "mesh_toi" (rss): the same bits."""
    obb = cdkit.MeshModel(*bunny, bv="obb")
    rss = cdkit.MeshModel(*bunny, bv="rss")
    shapes = reference_shapes(reference["hull_points"])
    all_mode = cdkit.MeshConvexRequest(cdkit.ContactMode.all)
    hits = 0
    for row in reference["mesh_convex"]:
        s = shapes[row["shape"]]
        pm, ps = np.array(row["pose_mesh"]), np.array(row["pose_shape"])
        c = cdkit.mesh_convex_collide(obb, pm, s, ps, all_mode)
        assert c.status == cdkit.QueryStatus.ok and c.colliding == row["colliding"]
        assert c.triangles.tolist() == row["triangles"]
        hits += c.colliding
        d = cdkit.mesh_convex_distance(obb, pm, s, ps)
        assert d.distance == row["distance"] and d.triangle == row["triangle"]
        assert d.point_mesh.tolist() == row["point_mesh"] and d.point_shape.tolist() == row["point_shape"]
        e = cdkit.mesh_convex_penetration(obb, pm, s, ps)
        assert e.deepest.depth == row["depth"]
        assert (e.deepest.triangle if e.colliding else -1) == row["deepest"]
        toi = cdkit.mesh_convex_toi(obb, pm, pm, s, ps, (ps[:3, :3], pm[:3, 3]))
        assert toi.toi == row["toi"] and toi.colliding == row["toi_colliding"]
        r = cdkit.convex_ray_cast(s, ps, row["ray_origin"], row["ray_direction"])
        assert r.hit == row["ray_hit"] and (r.hits[0].t if r.hit else -1) == row["ray_t"]
    assert 1 <= hits < len(reference["mesh_convex"])  # both answers occur
    mt = reference["mesh_toi"]
    r = cdkit.mesh_toi(rss, None, None, rss, np.array(mt["b_start"]), np.array(mt["b_end"]))
    assert r.colliding == mt["colliding"] and r.toi == mt["toi"] and r.point_a.tolist() == mt["point_a"]
