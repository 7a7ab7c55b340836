"""The World from Python against brute force in numpy: its pairs, events,
contacts and ray hits."""

from __future__ import annotations

import pickle

import numpy as np
import pytest

import bvol
from conftest import box_separation, random_quaternions, rotation

N = 500


def ball_scene(rng, n=N):
    """n balls of radii 0.2 to 0.8 in a cube holding about two contacts each."""
    radii = rng.uniform(0.2, 0.8, size=n).astype(np.float32)
    side = 1.6 * n ** (1 / 3)
    return rng.uniform(0, side, size=(n, 3)).astype(np.float32), radii


def add_balls(world, positions, radii, kind="dynamic"):
    """One body per ball (each its own shape), their ids in order."""
    return np.array(
        [
            world.add_body(primitive=("sphere", float(r)), pose=(p, (0, 0, 0, 1)), kind=kind, user_data=i)
            for i, (p, r) in enumerate(zip(positions, radii))
        ],
        dtype=np.uint64,
    )


def ball_gaps(positions, radii):
    """The gap between every two balls (i < j), float64: <= 0 touching."""
    p = positions.astype(np.float64)
    i, j = np.triu_indices(len(p), 1)
    return i, j, np.linalg.norm(p[j] - p[i], axis=1) - radii[i] - radii[j]


def as_index_pairs(world, ids):
    """The world's touching pairs as a set of (i, j) indices into ids, i < j."""
    index = {int(b): k for k, b in enumerate(ids)}
    return {tuple(sorted((index[int(a)], index[int(b)]))) for a, b in world.pairs()}


def assert_pairs_match(got, i, j, gap, band):
    """The pairs the world reports equal the brute-force ones wherever the gap
    is clear of zero by more than `band`; few pairs lie within it."""
    clear = np.abs(gap) > band
    assert clear.mean() > 0.999
    want = {(a, b) for a, b in zip(i[clear & (gap <= 0)].tolist(), j[clear & (gap <= 0)].tolist())}
    ambiguous = set(zip(i[~clear].tolist(), j[~clear].tolist()))
    assert got - ambiguous == want
    assert len(want) > len(i) / 2000  # the scene has contacts to find


def test_ball_pairs_equal_brute_force():
    rng = np.random.default_rng(21)
    positions, radii = ball_scene(rng)
    world = bvol.World()
    ids = add_balls(world, positions, radii)
    stats = world.update()
    got = as_index_pairs(world, ids)
    assert stats["touching"] == len(got)
    assert_pairs_match(got, *ball_gaps(positions, radii), band=1e-5)


def test_rotated_box_pairs_equal_the_separating_axis_test():
    rng = np.random.default_rng(22)
    sizes = [(0.5, 0.5, 0.5), (1.0, 0.2, 0.3), (0.1, 0.1, 1.2), (0.7, 0.4, 0.05)]
    world = bvol.World()
    ids, half, positions, quaternions = [], [], [], []
    side = 2.0 * N ** (1 / 3)
    for size in sizes:
        p = rng.uniform(0, side, size=(N // 4, 3)).astype(np.float32)
        q = random_quaternions(rng, N // 4)
        ids.append(world.add_bodies(p, q, primitive=("box", size)))
        half += [size] * len(p)
        positions.append(p)
        quaternions.append(q)
    ids, positions, quaternions = np.concatenate(ids), np.concatenate(positions), np.concatenate(quaternions)
    half = np.array(half, dtype=np.float32)
    world.update()
    axes = np.array([rotation(q) for q in quaternions])
    i, j = np.triu_indices(len(ids), 1)
    gap = box_separation(positions[i], axes[i], half[i], positions[j], axes[j], half[j])
    assert_pairs_match(as_index_pairs(world, ids), i, j, gap, band=1e-4)


def test_events_follow_the_pairs_frame_to_frame():
    rng = np.random.default_rng(23)
    positions, radii = ball_scene(rng, 300)
    world = bvol.World()
    ids = add_balls(world, positions, radii)
    before: set = set()
    for _ in range(4):
        world.update()
        now = as_index_pairs(world, ids)
        events = world.events()
        index = {int(b): k for k, b in enumerate(ids)}
        by_kind = {
            kind: {tuple(sorted((index[int(e["id_a"])], index[int(e["id_b"])]))) for e in events[events["kind"] == kind]}
            for kind in (bvol.BEGAN, bvol.PERSISTING, bvol.ENDED)
        }
        assert by_kind[bvol.BEGAN] == now - before
        assert by_kind[bvol.PERSISTING] == now & before
        assert by_kind[bvol.ENDED] == before - now
        assert len(events) == sum(map(len, by_kind.values()))
        # Each event carries both bodies' user data: here, their indices.
        assert (events["user_data_a"] == [index[int(a)] for a in events["id_a"]]).all()
        assert (events["user_data_b"] == [index[int(b)] for b in events["id_b"]]).all()
        touching = events[events["kind"] != bvol.ENDED]
        assert np.allclose(np.linalg.norm(touching["normal"], axis=1), 1, atol=1e-5)
        assert (touching["depth"] >= 0).all() and (touching["point_count"] >= 1).all()
        ended = events[events["kind"] == bvol.ENDED]
        assert (ended["depth"] == 0).all() and (ended["point_count"] == 0).all()
        before = now
        positions = positions + rng.normal(scale=0.15, size=positions.shape).astype(np.float32)
        world.set_poses(ids, positions)


def test_balls_within_the_margin_are_in_contact_with_their_distance():
    rng = np.random.default_rng(22)
    positions, radii = ball_scene(rng)
    margin = 0.05
    world = bvol.World(margin=margin)
    ids = add_balls(world, positions, radii)
    stats = world.update()
    got = as_index_pairs(world, ids)
    assert stats["touching"] + stats["near"] == len(got)
    i, j, gap = ball_gaps(positions, radii)
    assert_pairs_match(got, i, j, gap - margin, band=1e-5)
    near = [(a, b, g) for a, b, g in zip(i, j, gap) if 1e-5 < g <= margin - 1e-5]
    assert stats["near"] >= len(near) > 20
    for a, b, g in near:
        contact = world.contact(int(ids[a]), int(ids[b]))
        assert np.isclose(contact["depth"], -g, atol=1e-5)
    with pytest.raises(ValueError, match="margin"):
        bvol.World(margin=-1.0)


def test_reused_contacts_keep_the_pairs_and_the_depth_bound():
    """Hull boxes resting on a floor, jittering by 1e-6: a world reusing
    contact features finds the pairs a plain one does, with depths within
    the reuse's bound of its, frame after frame."""
    rng = np.random.default_rng(26)
    n = 200
    corners = np.array([[x, y, z] for x in (-0.5, 0.5) for y in (-0.5, 0.5) for z in (-0.5, 0.5)], dtype=np.float32)
    base = np.column_stack([rng.uniform(0, 40, n), np.full(n, 0.99), rng.uniform(0, 40, n)]).astype(np.float32)
    reuse = 4e-5
    worlds = [bvol.World(), bvol.World(reuse=reuse)]
    floors, bodies = [], []
    for w in worlds:
        floor = w.add_body(primitive=("box", (25.0, 0.5, 25.0)), pose=((20, 0, 20), (0, 0, 0, 1)), kind="static")
        floors.append(floor)
        bodies.append(np.array([w.add_body(vertices=corners, pose=(p, (0, 0, 0, 1))) for p in base], dtype=np.uint64))
    # The pair's size: the floor's half diagonal.
    bound = (2e-5 + 2e-5 + 2 * reuse) * float(np.linalg.norm([25.0, 0.5, 25.0]))
    compared = 0
    for _ in range(6):
        positions = base + rng.uniform(-1e-6, 1e-6, base.shape).astype(np.float32)
        for w, ids in zip(worlds, bodies):
            w.set_poses(ids, positions)
            w.update()
        plain, reusing = worlds
        assert {tuple(p) for p in plain.pairs().tolist()} == {tuple(p) for p in reusing.pairs().tolist()}
        for k in range(n):
            want = plain.contact(floors[0], int(bodies[0][k]))
            got = reusing.contact(floors[1], int(bodies[1][k]))
            assert (want is None) == (got is None)
            if want is not None:
                assert abs(got["depth"] - want["depth"]) <= bound
                compared += 1
    assert compared > 1000
    with pytest.raises(ValueError, match="reuse"):
        bvol.World(reuse=-1.0)


def test_a_saved_world_runs_on_with_the_same_events():
    rng = np.random.default_rng(23)
    positions, radii = ball_scene(rng, n=300)
    world = bvol.World(margin=0.02)
    ids = add_balls(world, positions, radii)
    world.update()
    pickled = pickle.loads(pickle.dumps(world))
    loaded = bvol.World.from_snapshot(world.snapshot())
    assert type(pickled) is bvol.World and type(loaded) is bvol.World
    compared = 0
    for _ in range(3):
        positions = positions + rng.normal(0, 0.05, positions.shape).astype(np.float32)
        for w in (world, pickled, loaded):
            w.set_poses(ids, positions)
            w.update()
        want = world.events()
        for w in (pickled, loaded):
            got = w.events()
            for name in want.dtype.names:
                np.testing.assert_array_equal(got[name], want[name])
        compared += len(want)
    assert compared > 300
    for bad in (b"{}", b"not json", world.snapshot()[:-10]):
        with pytest.raises(ValueError):
            bvol.World.from_snapshot(bad)


def test_far_worlds_keep_positions_and_contacts_in_float64():
    offset = np.array([1e8, -3e7, 5e6])
    worlds = []
    for at in (np.zeros(3), offset):
        world = bvol.World()
        ids = world.add_bodies(np.zeros((2, 3), dtype=np.float32), primitive=("box", (0.5, 0.5, 0.5)))
        world.set_poses_f64(ids, np.array([at, at + [0.9, 0.0, 0.0]]))
        world.update()
        worlds.append((world, ids))
    (near, ids), (far, _) = worlds
    a, b = int(ids[0]), int(ids[1])
    position, _ = far.pose_f64(b)
    assert position.dtype == np.float64 and np.array_equal(position, offset + [0.9, 0.0, 0.0])
    assert np.isclose(far.contact(a, b)["depth"], 0.1, atol=1e-5)
    assert np.isclose(far.contact(a, b)["depth"], near.contact(a, b)["depth"], atol=1e-6)
    points = far.contact_points_f64(a, b) - offset
    assert points.dtype == np.float64 and len(points) == 4
    np.testing.assert_allclose(points, near.contact_points_f64(a, b), atol=1e-6)
    with pytest.raises(ValueError):
        far.set_poses_f64(ids, np.full((2, 3), np.nan))
    assert np.array_equal(far.pose_f64(b)[0], position)


def test_contacts_of_two_balls_are_the_exact_ones():
    world = bvol.World()
    a = world.add_body(primitive=("sphere", 1.0), pose=((0, 0, 0), (0, 0, 0, 1)))
    b = world.add_body(primitive=("sphere", 0.5), pose=((1.2, 0.4, 0), (0, 0, 0, 1)))
    world.update()
    contact = world.contact(a, b)
    d = np.hypot(1.2, 0.4)
    assert np.allclose(contact["normal"], np.array([1.2, 0.4, 0]) / d, atol=1e-6)
    assert np.isclose(contact["depth"], 1.5 - d, atol=1e-6)
    assert np.allclose(world.contact(b, a)["normal"], -contact["normal"])
    world.set_poses(np.array([b]), np.array([[3.0, 0, 0]]))
    world.update()
    assert world.contact(a, b) is None and len(world.pairs()) == 0


def test_static_bodies_meet_only_dynamic_ones():
    world = bvol.World()
    cube = bvol.Shape.box((0.5, 0.5, 0.5))
    floor = world.add_body(primitive=("box", (10, 0.5, 10)), kind="static")
    wall = world.add_body(shape=cube, pose=((0, 0.9, 0), (0, 0, 0, 1)), kind="static")
    ball = world.add_body(primitive=("sphere", 0.5), pose=((3, 0.9, 0), (0, 0, 0, 1)))
    world.update()
    assert {tuple(p) for p in world.pairs().tolist()} == {(floor, ball)}
    world.set_kind(wall, "dynamic")
    world.update()
    assert {tuple(p) for p in world.pairs().tolist()} == {(floor, wall), (floor, ball)}
    assert world.kind(wall) == "dynamic" and world.kind(floor) == "static"


def test_rays_hit_the_nearest_ball():
    rng = np.random.default_rng(24)
    positions, radii = ball_scene(rng, 300)
    world = bvol.World()
    ids = add_balls(world, positions, radii)
    world.update()
    origins = rng.uniform(-2, 12, size=(500, 3)).astype(np.float32)
    directions = rng.normal(size=(500, 3)).astype(np.float32)
    directions /= np.linalg.norm(directions, axis=1, keepdims=True)
    hits = world.ray_cast(origins, directions, max_t=8.0)
    # Brute force: every ray against every ball, in float64.
    o = origins[:, None, :].astype(np.float64) - positions[None, :, :]
    b = np.einsum("rnk,rk->rn", o, directions.astype(np.float64))
    c = (o * o).sum(2) - radii.astype(np.float64) ** 2
    disc = b * b - c
    root = np.sqrt(np.maximum(disc, 0))
    first = np.maximum(-b - root, 0)
    enter = np.where((disc >= 0) & (-b + root >= 0) & (first <= 8.0), first, np.inf)
    nearest = enter.argmin(1)
    t = enter[np.arange(500), nearest]
    hit = np.isfinite(t)
    # A ray is clear when no ball grazes it, none is entered near max_t,
    # and the nearest is nearer than the next by more than rounding.
    grazing = ((np.abs(disc) < 1e-4) | (np.abs(first - 8.0) < 1e-4)).any(1)
    second = np.partition(enter, 1, axis=1)[:, 1]
    to_next = np.subtract(second, t, out=np.full_like(t, np.inf), where=hit)
    clear = ~grazing & (to_next > 1e-4)
    assert clear.mean() > 0.99 and 0.1 < hit.mean() < 0.9
    assert (hits["hit"][clear] == hit[clear]).all()
    both = clear & hit
    assert (hits["id"][both] == ids[nearest[both]]).all()
    assert (hits["user_data"][both] == nearest[both]).all()
    assert np.allclose(hits["t"][both], t[both], atol=1e-4)
    assert (hits["id"][~hits["hit"]] == bvol.NO_BODY).all() and np.isinf(hits["t"][~hits["hit"]]).all()


def test_any_number_of_threads_gives_the_same_events():
    rng = np.random.default_rng(25)
    positions, radii = ball_scene(rng, 400)
    runs = []
    for threads in (1, 2, 3):
        world = bvol.World(threads=threads)
        ids = add_balls(world, positions, radii)
        frames = []
        moved = positions
        for _ in range(3):
            world.update()
            frames.append(world.events())
            moved = moved + np.float32(0.1)
            world.set_poses(ids, moved)
        runs.append(frames)
    for frames in runs[1:]:
        assert all(np.array_equal(a, b) for a, b in zip(frames, runs[0]))


def test_add_bodies_adds_all_or_none():
    world = bvol.World()
    good = world.add_bodies(np.zeros((3, 3)), primitive=("sphere", 1.0), user_data=np.arange(3))
    positions = np.zeros((5, 3))
    positions[3] = np.nan
    with pytest.raises(ValueError, match="not finite"):
        world.add_bodies(positions, primitive=("sphere", 1.0))
    assert len(world) == 3 and (world.ids() == good).all()
    assert [world.user_data(i) for i in good] == [0, 1, 2]


def test_removed_bodies_end_their_contacts_and_are_unknown():
    world = bvol.World()
    a, b = world.add_bodies(np.array([[0, 0, 0], [0.5, 0, 0]]), primitive=("sphere", 0.5))
    world.update()
    world.remove(b)
    world.update()
    events = world.events()
    assert events["kind"].tolist() == [bvol.ENDED] and int(events["id_b"][0]) == b
    with pytest.raises(KeyError, match="no such body"):
        world.remove(b)
    with pytest.raises(KeyError, match="no such body"):
        world.set_poses(np.array([a, b]), np.zeros((2, 3)))
    c = world.add_body(primitive=("sphere", 0.5))
    assert c != b  # the slot is reused under a new generation
    with pytest.raises(KeyError):
        world.pose(b)


def test_poses_come_back_as_given():
    world = bvol.World()
    q = random_quaternions(np.random.default_rng(26), 1)[0]
    body = world.add_body(vertices=np.vstack([np.eye(3), np.zeros(3)]), pose=((1, 2, 3), q))
    position, rotation_back = world.pose(body)
    assert (position == [1, 2, 3]).all() and (rotation_back == q).all()
