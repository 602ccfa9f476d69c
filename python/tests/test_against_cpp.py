"""The module against the C++ library on the same inputs: cpp_reference.cpp prints the inputs (poses with 17
significant digits, exact) and the C++ answers; the Python answers must be equal (the same code on the same
doubles gives the same bits)."""
import numpy as np
import pytest

import cdkit
from conftest import reference_shapes


@pytest.fixture(scope="module")
def models(bunny):
    v, f = bunny
    return cdkit.MeshModel(v, f, bv="obb"), cdkit.MeshModel(v, f, bv="rss")


def test_mesh_pairs_equal_cpp(reference, models):
    obb, rss = models
    rows = reference["mesh_pairs"]
    hits = 0
    all_mode = cdkit.CollisionRequest(cdkit.ContactMode.all)
    for row in rows:
        pa, pb = np.array(row["pose_a"]), np.array(row["pose_b"])
        first = cdkit.collide(obb, pa, obb, pb)
        assert first.status == cdkit.QueryStatus.ok
        assert first.colliding == row["colliding"]
        if first.colliding:
            assert list(first.triangle_pairs[0]) == row["first"]
            hits += 1
        every = cdkit.collide(obb, pa, obb, pb, all_mode)
        assert len(every.contacts) == row["all_count"]
        assert every.triangle_pairs.tolist() == row["all_pairs"]
        d = cdkit.distance(rss, pa, rss, pb)
        assert d.distance == row["distance"]
        assert [d.triangle_a, d.triangle_b] == row["triangles"]
        assert d.point_a.tolist() == row["point_a"]
        assert d.point_b.tolist() == row["point_b"]
    # The inputs exercise both answers.
    assert 5 <= hits <= len(rows) - 5


def test_batches_equal_cpp_batch(reference, models):
    obb, rss = models
    pa = np.array([r["pose_a"] for r in reference["mesh_pairs"]])
    pb = np.array([r["pose_b"] for r in reference["mesh_pairs"]])
    assert cdkit.collide_many(obb, pa, obb, pb).tolist() == reference["batch_colliding"]
    assert cdkit.distance_many(rss, pa, rss, pb).distance.tolist() == reference["batch_distance"]
    assert cdkit.collide_many(obb, pa, obb, pb, threads=1).tolist() == reference["batch_colliding"]


def test_convex_pairs_equal_cpp(reference):
    shapes = reference_shapes(reference["hull_points"])
    seen_status = set()
    for row in reference["convex_pairs"]:
        a, b = shapes[row["a"]], shapes[row["b"]]
        pa, pb = np.array(row["pose_a"]), np.array(row["pose_b"])
        g = cdkit.gjk_distance(a, pa, b, pb)
        assert g.distance == row["distance"], (row["a"], row["b"])
        assert int(g.status) == row["status"]
        assert int(cdkit.gjk_intersect(a, pa, b, pb).status) == row["intersect_status"]
        assert cdkit.penetration(a, pa, b, pb).depth == row["depth"]
        assert cdkit.separating_plane_intersect(a, pa, b, pb).colliding == row["plane_colliding"]
        toi = cdkit.convex_toi(a, pa, pa, b, pb, (pb[:3, :3], pa[:3, 3]))
        assert toi.toi == row["toi"]
        seen_status.add(row["status"])
    assert int(cdkit.GjkStatus.separated) in seen_status and int(cdkit.GjkStatus.intersecting) in seen_status
    cf = reference["closest_features"]
    r = cdkit.closest_features(shapes[7], np.array(cf["pose_a"]), shapes[7], np.array(cf["pose_b"]))
    assert r.distance == cf["distance"] and int(r.status) == cf["status"]


def test_world_equals_cpp(reference, bunny):
    shapes = reference_shapes(reference["hull_points"])
    world = cdkit.World()
    objects = [cdkit.Sphere(0.5)] * 6 + [cdkit.Box([0.3, 0.4, 0.5]), shapes[7], cdkit.MeshModel(*bunny)]
    ids = [world.add(o, np.array(p)) for o, p in zip(objects, reference["world_poses"])]
    assert ids == list(range(len(objects)))
    step = world.step()
    got = [[c.a, c.b, c.depth] for c in step.contacts]
    assert got == reference["world_contacts"]
    assert len(got) >= 5  # the neighbouring spheres and the box touch


def test_rays_equal_cpp(reference, models):
    obb, _ = models
    rays = reference["rays"]
    origins = np.array([r["origin"] for r in rays])
    directions = np.array([r["direction"] for r in rays])
    batch = cdkit.ray_cast_many(obb, None, origins, directions)
    assert batch.hit.tolist() == [r["hit"] for r in rays]
    assert sum(batch.hit) > 10
    for k, r in enumerate(rays):
        if r["hit"]:
            assert batch.t[k] == r["t"] and batch.triangle[k] == r["triangle"]
            one = cdkit.ray_cast(obb, None, origins[k], directions[k])
            assert one.hit and one.hits[0].t == r["t"] and one.hits[0].triangle == r["triangle"]
        else:
            assert batch.triangle[k] == -1


def test_mesh_ccd_equals_cpp(reference, models):
    obb, _ = models
    ref = reference["mesh_ccd"]
    r = cdkit.mesh_ccd(obb, None, None, obb, np.array(ref["b_start"]), np.array(ref["b_end"]))
    assert r.colliding == ref["colliding"] and r.toi == ref["toi"]
    assert r.colliding and 0 < r.toi < 1
