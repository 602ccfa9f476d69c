"""Batches: collide_many / distance_many / ray_cast_many equal loops of single calls, on 1 and 2 TBB threads; one
pose broadcast for a side; and Python threads calling single queries concurrently (the GIL released) get the
sequential answers."""
import concurrent.futures

import numpy as np
import pytest

import cdkit
from conftest import rotation_z


def random_poses(n, reach, seed):
    rng = np.random.default_rng(seed)
    q = rng.normal(size=(n, 4))
    q /= np.linalg.norm(q, axis=1, keepdims=True)
    w, x, y, z = q.T
    R = np.stack([
        np.stack([1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)], axis=1),
        np.stack([2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)], axis=1),
        np.stack([2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)], axis=1)], axis=1)
    P = np.zeros((n, 4, 4))
    P[:, :3, :3] = R
    P[:, :3, 3] = rng.uniform(-reach, reach, size=(n, 3))
    P[:, 3, 3] = 1
    return P


@pytest.fixture(scope="module")
def models(bunny):
    return cdkit.MeshModel(*bunny), cdkit.MeshModel(*bunny, bv="rss")


def test_batches_equal_loops(models):
    obb, rss = models
    pa, pb = random_poses(300, 0.5, 1), random_poses(300, 12.0, 2)
    loop = np.array([cdkit.collide(obb, a, obb, b).colliding for a, b in zip(pa, pb)])
    dloop = np.array([cdkit.distance(rss, a, rss, b).distance for a, b in zip(pa, pb)])
    assert 30 < loop.sum() < 270
    for threads in (0, 1, 2):
        got = cdkit.collide_many(obb, pa, obb, pb, threads=threads)
        assert got.dtype == np.bool_ and got.shape == (300,) and np.array_equal(got, loop)
        d = cdkit.distance_many(rss, pa, rss, pb, threads=threads)
        assert len(d) == 300 and np.array_equal(d.distance, dloop)
        assert d.point_a.shape == (300, 3) and d.triangle_a.shape == (300,)
    # The error bounds of an approximate batch hold.
    approx = cdkit.distance_many(rss, pa, rss, pb, rel_err=0.1)
    assert np.all(approx.distance <= 1.1 * dloop + 1e-15) and np.all(approx.distance >= dloop - 1e-15)
    # A range of interest: the unbounded answer within it, inf beyond it.
    bound = float(np.median(dloop[dloop > 0]))
    ranged = cdkit.distance_many(rss, pa, rss, pb, max_distance=bound)
    assert np.array_equal(ranged.distance[dloop <= bound], dloop[dloop <= bound])
    assert np.all(np.isinf(ranged.distance[dloop > bound])) and (dloop > bound).sum() >= 10
    with pytest.raises(ValueError, match="max_distance"):
        cdkit.distance_many(rss, pa, rss, pb, max_distance=-1.0)


def test_one_pose_for_every_entry(models):
    obb, _ = models
    pb = random_poses(50, 12.0, 3)
    fixed = rotation_z(0.3)
    assert np.array_equal(cdkit.collide_many(obb, fixed, obb, pb),
                          cdkit.collide_many(obb, np.repeat(fixed[None], 50, axis=0), obb, pb))
    assert np.array_equal(cdkit.collide_many(obb, pb, obb, None),
                          [cdkit.collide(obb, p, obb, None).colliding for p in pb])
    assert cdkit.collide_many(obb, np.zeros((0, 4, 4)), obb, None).shape == (0,)


def test_rays_batch_equals_single(models):
    obb, _ = models
    rng = np.random.default_rng(4)
    origins = rng.uniform(-20, 20, size=(200, 3))
    directions = rng.uniform(-4, 4, size=(200, 3)) + [0, 5, 0] - origins  # the bunny spans about 10
    pose = rotation_z(0.2, (0.5, 0.0, 0.0))
    for threads in (1, 2):
        b = cdkit.ray_cast_many(obb, pose, origins, directions, threads=threads)
        for k in range(200):
            r = cdkit.ray_cast(obb, pose, origins[k], directions[k])
            assert r.hit == b.hit[k]
            if r.hit:
                assert r.hits[0].t == b.t[k] and r.hits[0].triangle == b.triangle[k]
                assert np.array_equal(r.hits[0].point, b.point[k])
    assert 20 < b.hit.sum() < 200
    every = cdkit.ray_cast(obb, pose, origins[0], directions[0], mode=cdkit.RayMode.all)
    assert [h.t for h in every.hits] == sorted(h.t for h in every.hits)


def test_python_threads_get_sequential_answers(models):
    obb, rss = models
    pa, pb = random_poses(200, 0.5, 5), random_poses(200, 12.0, 6)
    seq = [(cdkit.collide(obb, a, obb, b).colliding, cdkit.distance(rss, a, rss, b).distance) for a, b in zip(pa, pb)]
    with concurrent.futures.ThreadPoolExecutor(4) as pool:
        par = list(pool.map(lambda ab: (cdkit.collide(obb, ab[0], obb, ab[1]).colliding,
                                        cdkit.distance(rss, ab[0], rss, ab[1]).distance), zip(pa, pb)))
    assert par == seq
    # Batches from several Python threads at once.
    with concurrent.futures.ThreadPoolExecutor(2) as pool:
        outs = list(pool.map(lambda _: cdkit.collide_many(obb, pa, obb, pb, threads=1), range(4)))
    for o in outs:
        assert o.tolist() == [c for c, _ in seq]
