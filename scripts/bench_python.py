#!/usr/bin/env python3
"""Benchmark bvol's Python package against the Python tools in use today.

Everything runs in one process and prints markdown tables, side by side:

1. Minimum bounding spheres: bvol ``bounding_sphere(method="exact")`` against
   trimesh ``nsphere.minimum_nsphere``: time, each radius relative to the
   smallest sphere that holds every point (to a relative 1e-6), and any
   point left outside.
2. Oriented bounding boxes: bvol ``oriented_box`` ("min-volume", and
   "dito14" as the fast option) against trimesh ``bounds.oriented_bounds``
   and Open3D: the PCA of the hull (``OrientedBoundingBox.create_from_points``),
   the minimal box (``PointCloud.get_minimal_oriented_bounding_box``) and the
   tensor API's ``MINIMAL_APPROX`` (the best box on a hull face): time,
   volume relative to the smallest box that holds every point, points
   outside. A peer that takes over --slow seconds on one input is skipped
   on the inputs as large or larger.
3. Broadphase among N unit boxes at random positions and rotations: a bvol
   ``World`` (default threads, and one thread) against python-fcl's
   ``DynamicAABBTreeCollisionManager`` with ``defaultCollisionCallback``:
   the first frame (the bodies and the structure built, all touching pairs
   found) and later frames (every box moved about 1% of its size and turned
   a little, the poses handed over, all pairs found again). The pair sets
   are compared; a pair found by one side only is checked by a separating
   axis test in float64.

The point sets are the meshes of tests/meshes (all objects of a file
together) and random clouds with a fixed seed: normal, and uniform in a box
of sides 1:2:5 turned by a random rotation. Points and poses are rounded to
float32 first, as bvol rounds them, so that every library gets the same
numbers. Each time is the best of --repeats runs; a measure stops repeating
once it has spent --budget seconds, so slow ones may run fewer times (at
least once). Later broadphase frames are each run once, on --repeats frames,
and the best is shown.

Set up a virtual environment outside the repository, with a release wheel
of bvol (``maturin build --release -m crates/bvol-py/Cargo.toml``) and the
peers (Open3D also needs libusb-1.0; on Debian ``apt-get install
libusb-1.0-0``)::

    python3 -m venv /work/bench-venv
    /work/bench-venv/bin/pip install numpy scipy trimesh open3d python-fcl
    /work/bench-venv/bin/pip install target/wheels/bvol-*.whl

Run, from the repository root::

    /work/bench-venv/bin/python scripts/bench_python.py            # full run
    /work/bench-venv/bin/python scripts/bench_python.py --quick    # smaller

A peer that is not installed is left out and named in the header.
"""

from __future__ import annotations

import argparse
import importlib
import importlib.metadata
import math
import os
import platform
import sys
import time
from collections.abc import Callable
from pathlib import Path
from typing import NamedTuple

import numpy as np

import bvol

MESH_DIR = Path(__file__).resolve().parents[1] / "tests" / "meshes"
MESHES = ("bunny", "teapot", "duck", "airplane", "wuson")
CLOUD_SIZES = (1_000, 100_000, 1_000_000)
QUICK_CLOUD_SIZES = (1_000, 100_000)
BOX_COUNTS = (1_000, 10_000, 100_000)
QUICK_BOX_COUNTS = (1_000, 10_000)
SEED = 20240611
#: Half extents of every box of the broadphase test.
HALF = 0.5
#: The boxes fill a cube of side SPACING * N^(1/3): about two others touch
#: each box on average.
SPACING = 2.0
#: The standard deviation of a later frame's step, and its turn in radians.
STEP = 0.01
TURN = 0.01
#: Tolerance, relative to the bound's size, for a point to count as inside.
INSIDE_TOL = 1e-6
#: Radii further apart than this, relatively, are flagged.
RADIUS_TOL = 1e-6
PACKAGES = ("numpy", "scipy", "trimesh", "open3d", "python-fcl", "bvol")


def optional_import(name: str):
    """The module `name`, or None if it cannot be imported."""
    try:
        return importlib.import_module(name)
    except ImportError:
        return None


trimesh = optional_import("trimesh")
o3d = optional_import("open3d")
fcl = optional_import("fcl")
if o3d is not None:
    # Its warnings would land amid the tables; boxes are checked here instead.
    o3d.utility.set_verbosity_level(o3d.utility.VerbosityLevel.Error)


class Box(NamedTuple):
    """An oriented box: columns of `axes` are its axes."""

    center: np.ndarray
    axes: np.ndarray
    half: np.ndarray
    volume: float


# --- timing and printing -----------------------------------------------------


def timed(fn: Callable):
    """Run `fn` once: (seconds, result)."""
    start = time.perf_counter()
    result = fn()
    return time.perf_counter() - start, result


def best_time(fn: Callable, repeats: int, budget: float):
    """The best time in seconds of `fn` and its last result.

    `fn` runs up to `repeats` times, and no more once `budget` seconds are spent.
    """
    times = []
    while len(times) < repeats and sum(times) < budget:
        seconds, result = timed(fn)
        times.append(seconds)
    return min(times), result


def table(headers, rows) -> str:
    """A markdown table of `rows` under `headers`."""
    lines = ["| " + " | ".join(headers) + " |", "|" + "---|" * len(headers)]
    lines += ["| " + " | ".join(str(cell) for cell in row) + " |" for row in rows]
    return "\n".join(lines)


def ms(seconds: float) -> str:
    """Seconds as milliseconds, three significant digits or whole."""
    value = seconds * 1e3
    return f"{value:,.0f}" if value >= 100 else f"{value:.3g}"


def ratio(value: float) -> str:
    """A speed ratio, three significant digits or whole."""
    return f"{value:,.0f}" if value >= 100 else f"{value:.3g}"


def header(args) -> str:
    """The machine, the versions and the settings of this run."""
    versions = []
    for package in PACKAGES:
        try:
            versions.append(f"{package} {importlib.metadata.version(package)}")
        except importlib.metadata.PackageNotFoundError:
            versions.append(f"{package} not installed")
    missing = [n for n, m in (("trimesh", trimesh), ("open3d", o3d), ("fcl", fcl)) if m is None]
    lines = [
        "# bvol against trimesh, Open3D and python-fcl",
        "",
        f"- Python {platform.python_version()} on {platform.machine()}, {os.cpu_count()} cores",
        "- " + ", ".join(versions),
        f"- times: best of {args.repeats} runs, fewer (at least one) once a "
        f"measure has spent {args.budget:g} s; later broadphase frames: best "
        f"of {args.repeats} frames",
    ]
    if missing:
        lines.append("- left out, not importable: " + ", ".join(missing))
    return "\n".join(lines)


# --- rotations ---------------------------------------------------------------


def random_quats(n: int, rng: np.random.Generator) -> np.ndarray:
    """`n` uniformly random unit quaternions (x, y, z, w)."""
    quats = rng.normal(size=(n, 4))
    return quats / np.linalg.norm(quats, axis=1, keepdims=True)


def quat_multiply(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """The products a * b of (n, 4) quaternions (x, y, z, w)."""
    av, aw = a[:, :3], a[:, 3:]
    bv, bw = b[:, :3], b[:, 3:]
    vector = aw * bv + bw * av + np.cross(av, bv)
    scalar = aw * bw - np.sum(av * bv, axis=1, keepdims=True)
    return np.hstack([vector, scalar])


def quat_to_matrix(q: np.ndarray) -> np.ndarray:
    """(n, 3, 3) rotation matrices of the (n, 4) quaternions (x, y, z, w)."""
    q = q / np.linalg.norm(q, axis=1, keepdims=True)
    x, y, z, w = q.T
    return np.stack(
        [
            [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
            [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
            [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)],
        ]
    ).transpose(2, 0, 1)


# --- point sets --------------------------------------------------------------


def rounded(array: np.ndarray) -> np.ndarray:
    """`array` rounded to float32, held as float64."""
    return np.asarray(array, dtype=np.float32).astype(np.float64)


def random_rotation(rng: np.random.Generator) -> np.ndarray:
    """A uniformly random 3x3 rotation matrix."""
    return quat_to_matrix(random_quats(1, rng))[0]


def mesh_points(name: str) -> np.ndarray:
    """All vertices of every object of tests/meshes/<name>.obj."""
    meshes = bvol.load_obj(str(MESH_DIR / f"{name}.obj"))
    return rounded(np.concatenate([mesh.vertices for mesh in meshes]))


def point_sets(cloud_sizes, seed: int):
    """(name, points) for the meshes and the random clouds, by size."""
    rng = np.random.default_rng(seed)
    sets = [(name, mesh_points(name)) for name in MESHES]
    for n in cloud_sizes:
        label = f"{n // 1000:,}k" if n < 1_000_000 else f"{n // 1_000_000}M"
        sets.append((f"normal {label}", rounded(rng.normal(size=(n, 3)))))
        stretched = rng.uniform(-1, 1, size=(n, 3)) * [1.0, 2.0, 5.0]
        sets.append((f"box 1:2:5 {label}", rounded(stretched @ random_rotation(rng).T)))
    return sorted(sets, key=lambda item: len(item[1]))


# --- spheres -----------------------------------------------------------------


def bvol_sphere(points):
    """bvol's exact minimum sphere: (center, radius)."""
    sphere = bvol.bounding_sphere(points, method="exact")
    return np.asarray(sphere.center, dtype=np.float64), float(sphere.radius)


def trimesh_sphere(points):
    """trimesh's minimum n-sphere: (center, radius)."""
    center, radius = trimesh.nsphere.minimum_nsphere(points)
    return np.asarray(center, dtype=np.float64), float(radius)


def sphere_outside(points, center, radius) -> int:
    """How many points lie outside the sphere by more than INSIDE_TOL."""
    distances = np.linalg.norm(points - center, axis=1)
    return int(np.count_nonzero(distances > radius * (1 + INSIDE_TOL)))


def sphere_row(name, points, args):
    """One table row comparing the spheres of `points`."""
    fitters = {"bvol": bvol_sphere, "trimesh": trimesh_sphere}
    results = {
        fitter: best_time(lambda f=fn: f(points), args.repeats, args.budget)
        for fitter, fn in fitters.items()
    }
    (bvol_time, (_, bvol_radius)), (trimesh_time, (_, trimesh_radius)) = results.values()
    outside = {
        fitter: sphere_outside(points, center, radius)
        for fitter, (_, (center, radius)) in results.items()
    }
    holding = [radius for fitter, (_, (_, radius)) in results.items() if not outside[fitter]]
    smallest = min(holding or [bvol_radius, trimesh_radius])
    notes = [
        f"{count:,} points outside {fitter}'s sphere" for fitter, count in outside.items() if count
    ]
    if trimesh_radius > bvol_radius * (1 + RADIUS_TOL):
        notes.append("trimesh's radius larger: not the minimum")
    if bvol_radius > trimesh_radius * (1 + RADIUS_TOL):
        notes.append("bvol's radius larger")
    return [
        name,
        f"{len(points):,}",
        ms(bvol_time),
        ms(trimesh_time),
        ratio(trimesh_time / bvol_time),
        f"{bvol_radius / smallest - 1:+.1e}",
        f"{trimesh_radius / smallest - 1:+.1e}",
        "; ".join(notes),
    ]


def sphere_table(sets, args) -> str:
    """The sphere comparison over every point set."""
    if trimesh is None:
        return "## Minimum bounding sphere\n\ntrimesh is not importable: left out."
    headers = [
        "input",
        "N",
        "bvol exact ms",
        "trimesh ms",
        "trimesh / bvol",
        "bvol r / min - 1",
        "trimesh r / min - 1",
        "notes",
    ]
    rows = [sphere_row(name, points, args) for name, points in sets]
    return "\n\n".join(
        [
            "## Minimum bounding sphere",
            "r / min: against the smallest sphere that holds every point.",
            table(headers, rows),
        ]
    )


# --- oriented boxes ----------------------------------------------------------


def bvol_box(method: str) -> Callable:
    """A fitter for bvol's oriented box by `method`."""

    def fit(points):
        box = bvol.oriented_box(points, method=method)
        return Box(
            np.asarray(box.center, dtype=np.float64),
            np.asarray(box.axes, dtype=np.float64),
            np.asarray(box.half_extents, dtype=np.float64),
            float(box.volume),
        )

    return fit


def trimesh_box(points) -> Box:
    """trimesh's oriented bounds, as a Box."""
    to_origin, extents = trimesh.bounds.oriented_bounds(points)
    rotation, shift = to_origin[:3, :3], to_origin[:3, 3]
    return Box(-rotation.T @ shift, rotation.T, extents / 2, float(np.prod(extents)))


def open3d_box(box) -> Box:
    """A legacy Open3D OrientedBoundingBox as a Box."""
    return Box(np.asarray(box.center), np.asarray(box.R), np.asarray(box.extent) / 2, box.volume())


def open3d_pca(points) -> Box:
    """Open3D's box from the PCA of the hull."""
    vectors = o3d.utility.Vector3dVector(points)
    return open3d_box(o3d.geometry.OrientedBoundingBox.create_from_points(vectors))


def open3d_minimal(points) -> Box:
    """Open3D's minimal box of a PointCloud (legacy API)."""
    cloud = o3d.geometry.PointCloud(o3d.utility.Vector3dVector(points))
    return open3d_box(cloud.get_minimal_oriented_bounding_box())


def open3d_approx(points) -> Box:
    """Open3D's tensor-API MINIMAL_APPROX box (the best box on a hull face)."""
    box = o3d.t.geometry.OrientedBoundingBox.create_from_points(
        o3d.core.Tensor(points), method=o3d.t.geometry.MethodOBBCreate.MINIMAL_APPROX
    )
    return Box(
        box.center.numpy().astype(np.float64),
        box.rotation.numpy().astype(np.float64),
        box.extent.numpy().astype(np.float64) / 2,
        float(box.volume()),
    )


def box_fitters() -> dict:
    """The oriented-box fitters to compare, bvol's first."""
    fitters = {"bvol min-volume": bvol_box("min-volume"), "bvol dito14": bvol_box("dito14")}
    if trimesh is not None:
        fitters["trimesh"] = trimesh_box
    if o3d is not None:
        fitters["o3d PCA"] = open3d_pca
        fitters["o3d minimal"] = open3d_minimal
        fitters["o3d t approx"] = open3d_approx
    return fitters


def box_outside(points, box: Box) -> int:
    """How many points lie outside `box` by more than INSIDE_TOL of its size."""
    local = np.abs((points - box.center) @ box.axes)
    tolerance = INSIDE_TOL * np.linalg.norm(box.half)
    return int(np.count_nonzero((local > box.half + tolerance).any(axis=1)))


def box_results(points, fitters, slow, args) -> dict:
    """{fitter: (seconds, Box)} on `points`.

    A fitter in `slow` (fitter -> the size it took too long on) is left out
    for inputs that large; one that takes too long here is added to it.
    """
    results = {}
    for fitter, fn in fitters.items():
        if len(points) >= slow.get(fitter, math.inf):
            continue
        results[fitter] = best_time(lambda f=fn: f(points), args.repeats, args.budget)
        if results[fitter][0] > args.slow:
            slow[fitter] = len(points)
    return results


def box_rows(name, points, fitters, slow, args):
    """The time row and the volume row of one point set."""
    results = box_results(points, fitters, slow, args)
    base = results["bvol min-volume"][0]
    outside = {fitter: box_outside(points, box) for fitter, (_, box) in results.items()}
    holding = [box.volume for fitter, (_, box) in results.items() if not outside[fitter]]
    smallest = min(holding or [box.volume for _, box in results.values()])
    time_row, volume_row = [name, f"{len(points):,}"], [name]
    for fitter in fitters:
        if fitter not in results:
            time_row.append("skipped")
            volume_row.append("skipped")
            continue
        seconds, box = results[fitter]
        ratio_text = "" if fitter == "bvol min-volume" else f" ({ratio(seconds / base)})"
        time_row.append(ms(seconds) + ratio_text)
        volume_row.append(f"{box.volume / smallest:.4f}")
    notes = [
        f"{count:,} points outside {fitter}'s box" for fitter, count in outside.items() if count
    ]
    return time_row, volume_row + ["; ".join(notes)]


def box_tables(sets, args) -> str:
    """The oriented-box comparison over every point set: times and volumes."""
    fitters = box_fitters()
    slow: dict = {}
    rows = [box_rows(name, points, fitters, slow, args) for name, points in sets]
    skipped = [f"{fitter} after {size:,} points" for fitter, size in slow.items()]
    return "\n\n".join(
        [
            "## Oriented bounding box: time",
            "Milliseconds; in brackets, the time over bvol min-volume's.",
            table(["input", "N", *fitters], [time_row for time_row, _ in rows]),
            "## Oriented bounding box: volume / smallest",
            "The smallest of the boxes that hold every point.",
            table(["input", *fitters, "notes"], [volume_row for _, volume_row in rows]),
            f"Over {args.slow:g} s on one input, skipped for inputs as large: "
            + (", ".join(skipped) or "none"),
        ]
    )


# --- broadphase --------------------------------------------------------------


def box_frames(n: int, moves: int, rng: np.random.Generator):
    """The poses (positions, quaternions) of `n` boxes, frame by frame.

    The first frame and `moves` later ones, each a small random step and turn
    of every box from the frame before.
    """
    positions = rng.uniform(0, SPACING * n ** (1 / 3), size=(n, 3))
    quats = random_quats(n, rng)
    frames = [(rounded(positions), rounded(quats))]
    for _ in range(moves):
        positions = positions + rng.normal(scale=STEP * 2 * HALF, size=(n, 3))
        axes = rng.normal(size=(n, 3))
        axes /= np.linalg.norm(axes, axis=1, keepdims=True)
        turns = np.hstack([axes * math.sin(TURN / 2), np.full((n, 1), math.cos(TURN / 2))])
        quats = quat_multiply(turns, quats)
        frames.append((rounded(positions), rounded(quats)))
    return frames


def pair_set(pairs: np.ndarray) -> set:
    """(M, 2) index pairs as a set of (low, high) tuples."""
    return set(map(tuple, np.sort(pairs, axis=1).tolist()))


class Run(NamedTuple):
    """One library's broadphase run over the frames of one box count."""

    first: float
    later: float
    pairs: list


def bvol_first(frame, threads):
    """bvol's first frame: a World with the boxes, updated; (world, ids, pairs)."""
    world = bvol.World(threads=threads)
    ids = world.add_bodies(frame[0], frame[1], primitive=("box", (HALF, HALF, HALF)))
    world.update()
    return world, ids, world.pairs()


def bvol_later(world, ids, frame):
    """A bvol later frame: poses handed over, updated; the pairs."""
    world.set_poses(ids, frame[0], frame[1])
    world.update()
    return world.pairs()


def bvol_run(frames, threads, args) -> Run:
    """bvol on `threads` threads (None: its default) over `frames`."""
    first, (world, ids, pairs) = best_time(
        lambda: bvol_first(frames[0], threads), args.repeats, args.budget
    )
    later = [timed(lambda f=frame: bvol_later(world, ids, f)) for frame in frames[1:]]
    found = [pairs] + [frame_pairs for _, frame_pairs in later]
    order = np.argsort(ids)
    sets = [pair_set(order[np.searchsorted(ids[order], p)]) for p in found]
    return Run(first, min(seconds for seconds, _ in later), sets)


class FclScene:
    """python-fcl's manager over one CollisionObject per box."""

    def __init__(self, frame):
        """Build the objects and the manager for the first `frame`."""
        positions, quats = frame
        # One Box each: contacts name geometries, which map back to boxes.
        self.geometries = [fcl.Box(2 * HALF, 2 * HALF, 2 * HALF) for _ in positions]
        self.objects = [
            fcl.CollisionObject(geometry, fcl.Transform(r, t))
            for geometry, r, t in zip(self.geometries, quat_to_matrix(quats), positions)
        ]
        self.manager = fcl.DynamicAABBTreeCollisionManager()
        self.manager.registerObjects(self.objects)
        self.manager.setup()

    def move(self, frame):
        """Hand over the poses of `frame` and refit the manager."""
        positions, quats = frame
        for obj, r, t in zip(self.objects, quat_to_matrix(quats), positions):
            obj.setTransform(fcl.Transform(r, t))
        self.manager.update()

    def collide(self):
        """Self-collision of every object: the contacts found."""
        request = fcl.CollisionRequest(num_max_contacts=len(self.objects) ** 2)
        data = fcl.CollisionData(request=request)
        self.manager.collide(data, fcl.defaultCollisionCallback)
        return data.result.contacts

    def later(self, frame):
        """A later frame: poses handed over, contacts found."""
        self.move(frame)
        return self.collide()

    def pairs(self, contacts) -> set:
        """The contacts as a set of box index pairs."""
        index = {id(geometry): i for i, geometry in enumerate(self.geometries)}
        pairs = [(index[id(c.o1)], index[id(c.o2)]) for c in contacts]
        return pair_set(np.array(pairs, dtype=np.int64).reshape(-1, 2))


def fcl_first(frame):
    """fcl's first frame: the scene built and its contacts."""
    scene = FclScene(frame)
    return scene, scene.collide()


def fcl_run(frames, args) -> Run:
    """python-fcl over `frames`."""
    first, (scene, contacts) = best_time(lambda: fcl_first(frames[0]), args.repeats, args.budget)
    later = [timed(lambda f=frame: scene.later(f)) for frame in frames[1:]]
    sets = [scene.pairs(c) for c in [contacts] + [frame_contacts for _, frame_contacts in later]]
    return Run(first, min(seconds for seconds, _ in later), sets)


def separation(frame, i: int, j: int) -> float:
    """The gap between boxes i and j of `frame` by separating axes, in float64.

    The largest over the 15 axes: positive when apart, zero or less when they
    touch.
    """
    positions, quats = frame
    ra, rb = quat_to_matrix(quats[[i, j]])
    offset = positions[j] - positions[i]
    gaps = []
    for axis in [*ra.T, *rb.T, *(np.cross(a, b) for a in ra.T for b in rb.T)]:
        length = np.linalg.norm(axis)
        if length < 1e-12:
            continue
        axis = axis / length
        reach = HALF * (np.abs(ra.T @ axis).sum() + np.abs(rb.T @ axis).sum())
        gaps.append(abs(offset @ axis) - reach)
    return max(gaps)


def differences(frames, fcl_sets, bvol_sets, label, examples: list) -> int:
    """How many pairs one side found and not the other over `frames`.

    Appends a line on each of the first few such pairs to `examples`.
    """
    count = 0
    for k, (frame, fcl_pairs, bvol_pairs) in enumerate(zip(frames, fcl_sets, bvol_sets)):
        for side, only in (("fcl", fcl_pairs - bvol_pairs), ("bvol", bvol_pairs - fcl_pairs)):
            count += len(only)
            for i, j in sorted(only)[: max(0, 5 - len(examples))]:
                examples.append(
                    f"{label}, frame {k}: boxes {i} and {j} found by {side} only; "
                    f"float64 separating-axis gap {separation(frame, i, j):+.3e}"
                )
    return count


def broadphase_rows(n: int, args, examples: list):
    """The first-frame and later-frame rows for `n` boxes."""
    frames = box_frames(n, args.repeats, np.random.default_rng(SEED + n))
    fcl_result = fcl_run(frames, args)
    bvol_default = bvol_run(frames, None, args)
    bvol_single = bvol_run(frames, 1, args)
    label = f"N={n:,}"
    first_differ = differences(frames[:1], fcl_result.pairs, bvol_default.pairs, label, examples)
    later_differ = differences(
        frames[1:], fcl_result.pairs[1:], bvol_default.pairs[1:], label, examples
    )
    agree = "yes" if bvol_default.pairs == bvol_single.pairs else "no"
    counts = [len(pairs) for pairs in bvol_default.pairs]
    rows = []
    for stage, pairs, differ in (
        ("first", counts[0], first_differ),
        ("later", np.mean(counts[1:]), later_differ),
    ):
        base = getattr(fcl_result, stage)
        row = [f"{n:,}", stage, f"{pairs:,.0f}", f"{2 * pairs / n:.2f}", ms(base)]
        for run in (bvol_default, bvol_single):
            seconds = getattr(run, stage)
            row.append(f"{ms(seconds)} ({ratio(base / seconds)})")
        rows.append(row + [str(differ), agree])
    return rows


def broadphase_table(box_counts, args) -> str:
    """The broadphase comparison over every box count."""
    if fcl is None:
        return "## Broadphase\n\npython-fcl is not importable: left out."
    examples: list = []
    rows = [row for n in box_counts for row in broadphase_rows(n, args, examples)]
    headers = [
        "N",
        "frame",
        "pairs",
        "touching per box",
        "fcl ms",
        "bvol default threads ms (fcl / bvol)",
        "bvol 1 thread ms (fcl / bvol)",
        "pairs differing",
        "bvol threads agree",
    ]
    text = [
        "## Broadphase: N boxes of half extent 0.5",
        "`first`: bodies and structure built, all touching pairs found. "
        f"`later`: every box stepped and turned, poses handed over, pairs found; "
        f"best of {args.repeats} frames, pairs: their mean. "
        "Pairs differing: fcl against bvol, over those frames.",
        table(headers, rows),
    ]
    if examples:
        text.append(
            "Pairs found by one side only (first few):\n\n" + "\n".join(f"- {e}" for e in examples)
        )
    return "\n\n".join(text)


def parse_args():
    """The command line."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="smaller clouds and box counts")
    parser.add_argument("--repeats", type=int, default=5, help="runs per measure (default 5)")
    parser.add_argument(
        "--budget",
        type=float,
        default=5.0,
        help="seconds after which a measure stops repeating (default 5)",
    )
    parser.add_argument(
        "--slow",
        type=float,
        default=60.0,
        help="seconds on one input after which an OBB peer is skipped on larger ones (default 60)",
    )
    parser.add_argument(
        "--only", choices=("spheres", "boxes", "broadphase"), help="run one part only"
    )
    return parser.parse_args()


def main():
    """Run the comparisons and print the tables."""
    args = parse_args()
    print(header(args), flush=True)
    sets = point_sets(QUICK_CLOUD_SIZES if args.quick else CLOUD_SIZES, SEED)
    parts = {
        "spheres": lambda: sphere_table(sets, args),
        "boxes": lambda: box_tables(sets, args),
        "broadphase": lambda: broadphase_table(
            QUICK_BOX_COUNTS if args.quick else BOX_COUNTS, args
        ),
    }
    for name, part in parts.items():
        if args.only in (None, name):
            print("\n" + part(), flush=True)


if __name__ == "__main__":
    sys.exit(main())
