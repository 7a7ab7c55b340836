"""Every kind of bad input raises the right exception with a message naming
what is wrong, and leaves the world as it was."""

from __future__ import annotations

import numpy as np
import pytest

import bvol

GOOD = np.random.default_rng(31).normal(size=(20, 3))
NAN = np.array([[0.0, 0, 0], [1, np.nan, 0], [0, 1, 0], [0, 0, 1]])
HUGE = np.array([[0.0, 0, 0], [1, 0, 0], [0, 1e39, 0], [0, 0, 1]])
ONE_BOX = (np.zeros((1, 3)), np.eye(3)[None], np.ones((1, 3)))

FITTERS = {
    "bounding_sphere": bvol.bounding_sphere,
    "oriented_box": bvol.oriented_box,
    "aabb": bvol.aabb,
    "kdop": bvol.kdop,
    "convex_hull": bvol.convex_hull,
    "Shape.convex": bvol.Shape.convex,
}

BAD_POINTS = [
    ([[0.0, 1, 2]], TypeError, "points: expected a numpy array of shape (N, 3), got list"),
    (np.zeros((4, 2)), ValueError, "points: expected shape (N, 3), got (4, 2)"),
    (np.zeros(3), ValueError, "points: expected shape (N, 3), got (3,)"),
    (np.zeros((4, 3), dtype=np.int64), TypeError, "points: expected float32 or float64 values, got int64"),
    (np.zeros((4, 3), dtype=np.float16), TypeError, "got float16"),
    (np.zeros((0, 3)), ValueError, "no points"),
    (NAN, ValueError, "point 1 has a NaN or infinite coordinate"),
    (HUGE, ValueError, "point 2 has a coordinate beyond"),
]


@pytest.mark.parametrize("fitter", FITTERS.values(), ids=FITTERS.keys())
@pytest.mark.parametrize("points,error,message", BAD_POINTS)
def test_fitters_refuse_bad_points(fitter, points, error, message):
    with pytest.raises(error) as raised:
        fitter(points)
    assert message in str(raised.value)


def test_unknown_methods_list_the_known_ones():
    with pytest.raises(ValueError, match='unknown method "nope"; expected one of: aabb, centroid, ritter, exact'):
        bvol.bounding_sphere(GOOD, "nope")
    with pytest.raises(ValueError, match="expected one of: pca-points, pca-hull, dito14, dito26, min-volume"):
        bvol.oriented_box(GOOD, method="minvol")
    with pytest.raises(ValueError, match="k = 8: expected 6, 14, 18 or 26"):
        bvol.kdop(GOOD, 8)
    with pytest.raises(ValueError, match='unknown method "x"'):
        bvol.Shape.from_obj("tests/meshes/duck.obj", sphere_method="x")


@pytest.mark.parametrize(
    "call,error,message",
    [
        (lambda: bvol.spheres_overlap(np.zeros((2, 3)), np.ones(2), np.zeros((3, 3)), np.ones(3)), ValueError, "centers_b has 3 rows but centers_a has 2"),
        (lambda: bvol.spheres_overlap(np.zeros((2, 3)), np.ones(3), np.zeros((2, 3)), np.ones(2)), ValueError, "radii_a has 3 rows but centers_a has 2"),
        (lambda: bvol.spheres_overlap(np.zeros((1, 3)), -np.ones(1), np.zeros((1, 3)), np.ones(1)), ValueError, "radii_a[0]: a radius must be finite and at least 0"),
        (lambda: bvol.spheres_overlap(np.full((1, 3), np.inf), np.ones(1), np.zeros((1, 3)), np.ones(1)), ValueError, "centers_a[0]: NaN or infinite value"),
        (lambda: bvol.boxes_overlap(*ONE_BOX, np.zeros((1, 3)), 2 * np.eye(3)[None], np.ones((1, 3))), ValueError, "axes_b[0]: the columns must be orthonormal axes"),
        (lambda: bvol.boxes_overlap(*ONE_BOX, np.zeros((1, 3)), np.eye(3)[None], -np.ones((1, 3))), ValueError, "half_extents_b[0]: half extents must be finite and at least 0"),
        (lambda: bvol.boxes_overlap(*ONE_BOX, np.zeros((1, 3)), np.eye(3), np.ones((1, 3))), ValueError, "axes_b: expected shape (N, 3, 3), got (3, 3)"),
        (lambda: bvol.ray_spheres(np.zeros((1, 3)), np.ones((1, 3)), np.zeros((1, 3)), np.ones(1), max_t=-1), ValueError, "max_t = -1: must be at least 0"),
        (lambda: bvol.ray_boxes(np.zeros((1, 3)), np.full((1, 3), np.nan), *ONE_BOX), ValueError, "directions[0]: NaN or infinite value"),
        (lambda: bvol.ray_spheres(np.zeros((1, 3)), np.ones((1, 3)), np.zeros((1, 3)), "1"), TypeError, "radii: expected a numpy array of shape (N,), got str"),
    ],
)
def test_batched_tests_refuse_bad_arrays(call, error, message):
    with pytest.raises(error) as raised:
        call()
    assert message in str(raised.value)


@pytest.mark.parametrize(
    "call,error,message",
    [
        (lambda: bvol.Shape.box((1, 0, 1)), ValueError, "cuboid: sizes must be finite, greater than zero"),
        (lambda: bvol.Shape.sphere(float("nan")), ValueError, "ball: sizes must be finite"),
        (lambda: bvol.Shape.capsule(-1, 1), ValueError, "capsule: sizes must be finite"),
        (lambda: bvol.Shape.sphere(1).scaled((1, 2, 1)), ValueError, "can only be scaled by one factor on every axis"),
        (lambda: bvol.Shape.box((1, 1, 1)).scaled(0), ValueError, "scale factor [0, 0, 0]: must be finite and greater than zero"),
        (lambda: bvol.Shape.box((1, 1, 1)).scaled("big"), TypeError, "factor: expected a number or three numbers"),
        (lambda: bvol.Shape.convex(np.outer(np.arange(3.0), [1, 1, 1])), ValueError, "not a solid"),
        (lambda: bvol.Shape.from_obj("no/such.obj"), OSError, "no/such.obj: cannot read"),
        (lambda: bvol.load_obj("no/such.obj"), OSError, "no/such.obj: cannot read"),
        (lambda: bvol.load_obj("/"), OSError, "/: not a regular file"),
    ],
)
def test_shapes_and_meshes_refuse_bad_input(call, error, message):
    with pytest.raises(error) as raised:
        call()
    assert message in str(raised.value)


def test_bad_mesh_files_name_themselves(tmp_path):
    binary = tmp_path / "binary.obj"
    binary.write_bytes(b"\x00\xff\x00v 1 2 3\n")
    empty = tmp_path / "empty.obj"
    empty.write_text("# nothing\n")
    for path, message in [(binary, "not an OBJ file (not text)"), (empty, "the mesh has no vertices")]:
        with pytest.raises(ValueError) as raised:
            bvol.load_obj(path)
        assert str(raised.value) == f"{path}: {message}"


def test_world_calls_refuse_bad_input_and_change_nothing():
    world = bvol.World()
    ids = world.add_bodies(np.array([[0.0, 0, 0], [0.5, 0, 0]]), primitive=("sphere", 0.5), user_data=np.array([7, 8]))
    world.update()
    events = world.events()
    cases = [
        (lambda: world.add_body(), ValueError, "give a body exactly one of vertices=, primitive= or shape="),
        (lambda: world.add_body(primitive=("sphere", 1), vertices=GOOD), ValueError, "exactly one of"),
        (lambda: world.add_body(primitive=("cone", 1)), ValueError, "primitive=('cone', 1): expected"),
        (lambda: world.add_body(primitive=("sphere", 1), kind="asleep"), ValueError, 'kind "asleep": expected "dynamic", "static" or "sleeping"'),
        (lambda: world.add_body(primitive=("sphere", 1), pose=(0, 0, 0)), TypeError, "pose: expected (position, quaternion)"),
        (lambda: world.add_body(primitive=("sphere", 1), pose=((0, 0, 0), (0, 0, 0, 0))), ValueError, "rotation of squared length"),
        (lambda: world.add_body(primitive=("sphere", 1), pose=((0, 0, 1e30), (0, 0, 0, 1))), ValueError, "beyond"),
        (lambda: world.add_bodies(np.zeros((2, 3)), primitive=("sphere", 1), user_data=np.array([1, -1])), ValueError, "user_data[1] = -1: negative"),
        (lambda: world.add_bodies(np.zeros((2, 3)), primitive=("sphere", 1), user_data=np.ones(2)), TypeError, "user_data: expected integers, got float64"),
        (lambda: world.add_bodies(np.zeros((2, 3)), primitive=("sphere", 1), user_data=np.ones(3, dtype=int)), ValueError, "user_data has 3 rows but positions has 2"),
        (lambda: world.set_poses(ids, np.zeros((3, 3))), ValueError, "positions has 3 rows but ids has 2"),
        (lambda: world.set_poses(ids, np.zeros((2, 3)), np.zeros((2, 3))), ValueError, "quaternions: expected shape (N, 4), got (2, 3)"),
        (lambda: world.set_poses(ids, np.zeros((2, 3)), np.zeros((2, 4))), ValueError, "rotation of squared length"),
        (lambda: world.set_poses(ids.astype(np.float64), np.zeros((2, 3))), TypeError, "ids: expected integers, got float64"),
        (lambda: world.set_poses(np.array([ids[0], 12345], dtype=np.uint64), np.zeros((2, 3))), KeyError, "no such body"),
        (lambda: world.set_kind(ids[0], "frozen"), ValueError, 'kind "frozen"'),
        (lambda: world.user_data(99), KeyError, "body 99 (generation 0): no such body in this world"),
        (lambda: world.contact(ids[0], 99), KeyError, "no such body"),
        (lambda: world.ray_cast(np.zeros((1, 3)), np.ones((2, 3))), ValueError, "directions has 2 rows but origins has 1"),
        (lambda: world.ray_cast(np.zeros((1, 3)), np.ones((1, 3)), max_t=float("nan")), ValueError, "max_t = NaN: must be at least 0"),
        (lambda: bvol.World(threads=0), ValueError, "threads"),
    ]
    for call, error, message in cases:
        with pytest.raises(error) as raised:
            call()
        assert message in str(raised.value), (message, str(raised.value))
    assert len(world) == 2 and (world.ids() == ids).all()
    for body in ids:
        position, _ = world.pose(body)
        assert np.isfinite(position).all()
    world.update()
    persisting = world.events()
    assert len(persisting) == len(events) == 1 and persisting["kind"][0] == bvol.PERSISTING
