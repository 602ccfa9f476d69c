"""World: add / set_pose / step / remove / set_ccd, every broad phase giving the same contacts, and the broad
phases alone against brute force."""
import numpy as np
import pytest

import cdkit
from conftest import cube, translation


def spheres_on_a_line(kind):
    world = cdkit.World(cdkit.WorldOptions(broad_phase=kind))
    ids = [world.add(cdkit.Sphere(0.5), translation(0.9 * k)) for k in range(10)]
    return world, ids


@pytest.mark.parametrize("kind", list(cdkit.BroadPhaseKind.__members__.values()))
def test_step_finds_neighbours(kind):
    world, ids = spheres_on_a_line(kind)
    assert len(world) == 10
    r = world.step()
    assert r.pairs.tolist() == [[k, k + 1] for k in range(9)]
    for c in r.contacts:
        assert c.has_depth and c.depth == pytest.approx(0.1, rel=1e-6)
        assert c.method == cdkit.PairMethod.convex_convex
        assert abs(c.normal[0]) == pytest.approx(1.0, abs=1e-9)
    assert r.stats.contacts == 9 and r.stats.tested_pairs >= 9
    # Move one away: its two contacts go.
    world.set_pose(ids[4], translation(0.9 * 4, 5.0))
    assert [c.a for c in world.step().contacts] == [0, 1, 2, 5, 6, 7, 8]
    world.remove(ids[0])
    assert len(world) == 9 and not world.contains(ids[0])
    assert [c.a for c in world.step().contacts] == [1, 2, 5, 6, 7, 8]


def test_shapes_of_every_kind(shapes, bunny):
    world = cdkit.World()
    v, f = cube()
    a = world.add(cdkit.MeshModel(v, f, bv="rss"), translation(0.0))  # built again as an OBB tree for the World
    b = world.add(cdkit.MeshModel(v, f), translation(0.9))
    c = world.add(cdkit.Box([0.5, 0.5, 0.5]), translation(-0.9))
    d = world.add(cdkit.Capsule(0.2, 0.5), translation(0.0, 0.6))
    e = world.add(shapes[7], translation(0.0, -0.6))
    assert [world.shape_kind(i) for i in (a, b, c, d, e)] == [cdkit.ShapeKind.mesh, cdkit.ShapeKind.mesh,
                                                              cdkit.ShapeKind.box, cdkit.ShapeKind.capsule,
                                                              cdkit.ShapeKind.convex_hull]
    r = world.step()
    pairs = set(map(tuple, r.pairs.tolist()))
    assert {(a, b), (a, c), (a, d), (a, e)} <= pairs
    methods = {(x.a, x.b): x.method for x in r.contacts}
    assert methods[(a, b)] == cdkit.PairMethod.mesh_mesh and methods[(a, c)] == cdkit.PairMethod.convex_mesh
    with pytest.raises(TypeError):
        world.add("a cone", None)  # not a shape


def test_ccd_catches_a_tunnelling_sphere():
    world = cdkit.World()
    wall = world.add(cdkit.Box([0.05, 2, 2]), None)
    ball = world.add(cdkit.Sphere(0.1), translation(-1.0))
    world.set_ccd(ball, True)
    assert world.ccd(ball)
    assert world.step().contacts == []
    world.set_pose(ball, translation(1.0))  # jumps through the wall in one step
    r = world.step()
    assert len(r.contacts) == 1 and (r.contacts[0].a, r.contacts[0].b) == (wall, ball)
    assert 0.0 < r.contacts[0].toi < 1.0
    assert r.contacts[0].toi == pytest.approx(0.425, abs=1e-3)  # centre at -0.15 = -1 + 2t


def test_rounded_shapes():
    """A box rounded by 0.05 resting 0.02 into a slab: depth 0.02 in closed form; bad radii raise cdkit.Error."""
    world = cdkit.World()
    ground = world.add(cdkit.Box([5, 5, 1]), translation(0.0, 0.0, -1.0))  # top face at z = 0
    box = world.add(cdkit.Box([0.3, 0.3, 0.1]), translation(0.0, 0.0, 0.13), rounding=0.05)
    r = world.step()
    assert len(r.contacts) == 1 and (r.contacts[0].a, r.contacts[0].b) == (ground, box)
    assert r.contacts[0].depth == pytest.approx(0.02, abs=1e-12)
    assert r.contacts[0].normal[2] == pytest.approx(1.0, abs=1e-12)
    with pytest.raises(cdkit.Error):
        world.add(cdkit.Box([1, 1, 1]), None, rounding=-0.1)
    v, f = cube()
    with pytest.raises(cdkit.Error):
        world.add(cdkit.MeshModel(v, f), None, rounding=0.1)  # only convex shapes round
    assert cdkit.ToiRequest(separation=0.5).separation == 0.5


def test_filters():
    world, ids = spheres_on_a_line(cdkit.BroadPhaseKind.sweep_and_prune)
    world.set_pair_tested(ids[0], ids[1], False)
    assert not world.pair_tested(ids[0], ids[1])
    assert [c.a for c in world.step().contacts] == list(range(1, 9))


@pytest.mark.parametrize("cls", [cdkit.SweepAndPrune, cdkit.UniformGrid, cdkit.SortedCellGrid, cdkit.DynamicAabbTree])
def test_broad_phases_equal_brute_force(cls):
    rng = np.random.default_rng(3)
    bp, ref = cls(), cdkit.BruteForceBroadPhase()
    ids = []
    for _ in range(200):
        lo = rng.uniform(0, 10, 3)
        hi = lo + rng.uniform(0.5, 1.5, 3)
        ids.append(bp.insert(lo, hi))
        assert ref.insert(lo, hi) == ids[-1]
    for frame in range(3):
        got, want = bp.pairs(), ref.pairs()
        assert got.shape[1] == 2 and got.tolist() == want.tolist() and len(want) > 20
        for i in ids[::3]:
            lo = rng.uniform(0, 10, 3)
            bp.move(i, lo, lo + 0.5)
            ref.move(i, lo, lo + 0.5)
    bp.remove(ids[0])
    assert len(bp) == 199 and not bp.contains(ids[0])
