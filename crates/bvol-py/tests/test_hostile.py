"""Random and hostile arguments to every call: each one either answers or
raises TypeError, ValueError, KeyError or OSError. A Rust panic would come
through as pyo3's PanicException, a BaseException that `except Exception`
does not catch, so it fails the test."""

from __future__ import annotations

import numpy as np

import bvol

EXPECTED = (TypeError, ValueError, KeyError, OSError)
SPECIALS = [np.nan, np.inf, -np.inf, 0.0, -0.0, 1e-45, 1e38, 3e38, 1e300, -1e18, 1e19]


def hostile_array(rng, rows=None, tail=(3,)):
    """An array meant to be of shape (rows, *tail) that may be of another
    shape, dtype or layout, holding ordinary values and specials."""
    rows = int(rng.integers(0, 6)) if rows is None else rows
    shapes = [(rows, *tail), (rows,), (rows, 4), (rows, 3, 3), ()]
    shape = shapes[rng.choice(5, p=[0.7, 0.1, 0.1, 0.05, 0.05])]
    values = rng.normal(scale=10.0 ** rng.integers(-3, 4), size=shape)
    if values.size and rng.random() < 0.5:
        flat = values.reshape(-1)
        flat[rng.integers(0, flat.size)] = rng.choice(SPECIALS)
    dtypes = [np.float64, np.float32, np.float16, np.int64, np.uint64, np.complex64]
    dtype = dtypes[rng.choice(6, p=[0.4, 0.35, 0.05, 0.1, 0.05, 0.05])]
    with np.errstate(all="ignore"):
        values = values.astype(dtype)
    if values.ndim == 2 and rng.random() < 0.3:
        values = np.asfortranarray(values)
    return values


def hostile_calls(rng, world, ids):
    """One call of each kind with hostile arguments, as thunks."""
    a = lambda rows=None, tail=(3,): hostile_array(rng, rows, tail)  # noqa: E731
    n = int(rng.integers(0, 5))
    number = float(rng.choice(SPECIALS + [1.0, -1.0, 0.5]))
    some_ids = rng.choice(np.concatenate([ids, np.array([0, 2**40, 2**64 - 1], dtype=np.uint64)]), size=n)
    return [
        lambda: bvol.bounding_sphere(a(), rng.choice(bvol.SPHERE_METHODS + ["nope"])),
        lambda: bvol.oriented_box(a(), rng.choice(bvol.OBB_METHODS + [""])),
        lambda: bvol.aabb(a()),
        lambda: bvol.kdop(a(), int(rng.choice([6, 14, 18, 26, 0, 7]))),
        lambda: bvol.convex_hull(a()),
        lambda: bvol.spheres_overlap(a(n), a(n, ()), a(n), a(n, ())),
        lambda: bvol.boxes_overlap(a(n), a(n, (3, 3)), a(n), a(n), a(n, (3, 3)), a(n)),
        lambda: bvol.ray_boxes(a(n), a(n), a(n), a(n, (3, 3)), a(n), max_t=number),
        lambda: bvol.ray_spheres(a(n), a(n), a(n), a(n, ()), max_t=number),
        lambda: bvol.Shape.box((number, 1.0, 1.0)),
        lambda: bvol.Shape.capsule(number, abs(number)),
        lambda: bvol.Shape.convex(a()).scaled(number),
        lambda: world.add_body(primitive=("sphere", number), pose=((number, 0, 0), (0, 0, 0, number))),
        lambda: world.add_bodies(a(n), a(n, (4,)), primitive=("box", (1.0, number, 1.0))),
        lambda: world.set_poses(some_ids, a(n), a(n, (4,))),
        lambda: world.remove(int(rng.choice(some_ids)) if n else 7),
        lambda: world.contact(int(ids[0]), int(rng.choice(some_ids)) if n else 3),
        lambda: world.ray_cast(a(n), a(n), max_t=number),
    ]


def test_hostile_calls_raise_only_typed_errors():
    rng = np.random.default_rng(41)
    world = bvol.World()
    ids = world.add_bodies(np.zeros((4, 3)), primitive=("sphere", 1.0))
    answered = raised = 0
    for _ in range(300):
        for call in hostile_calls(rng, world, ids):
            try:
                call()
                answered += 1
            except EXPECTED:
                raised += 1
        stats = world.update()
        assert stats["touching"] == len(world.pairs())
        events = world.events()
        assert np.isfinite(events["normal"]).all() and np.isfinite(events["depth"]).all()
    assert answered > 500 and raised > 500
