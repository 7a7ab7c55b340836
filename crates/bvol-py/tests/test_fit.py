"""Fitting from Python: every bound holds every point, on every layout of
array, and equals what the Rust command line fits to the same mesh."""

from __future__ import annotations

import json
import os
import subprocess

import numpy as np
import pytest

import bvol
from conftest import MESHES, REPO, mesh_points

KDOP_SIZES = [6, 14, 18, 26]


def every_bound(points):
    """Every bound bvol fits, by name."""
    bounds = {f"sphere {m}": bvol.bounding_sphere(points, m) for m in bvol.SPHERE_METHODS}
    bounds |= {f"obb {m}": bvol.oriented_box(points, m) for m in bvol.OBB_METHODS}
    bounds |= {f"{k}-dop": bvol.kdop(points, k) for k in KDOP_SIZES}
    bounds["aabb"] = bvol.aabb(points)
    return bounds


def test_every_bound_holds_every_point(points):
    for name, bound in every_bound(points).items():
        inside = bound.contains(points)
        assert inside.dtype == np.bool_ and inside.shape == (len(points),)
        assert inside.all(), f"{name}: points {np.flatnonzero(~inside)[:5]} outside"


def test_contains_agrees_with_the_bounds_own_numbers(points):
    """`contains` is checked against a float64 test on the returned fields,
    on the points and on points pushed just outside each bound."""
    p32 = points.astype(np.float32).astype(np.float64)
    sphere = bvol.bounding_sphere(points)
    assert (np.linalg.norm(p32 - sphere.center, axis=1) <= sphere.radius * (1 + 1e-6) + 1e-30).all()
    box = bvol.oriented_box(points)
    local = np.abs((p32 - box.center) @ box.axes.astype(np.float64))
    slack = 1e-5 * max(box.half_extents.max(), 1e-30)
    assert (local <= box.half_extents + slack).all()
    outside = box.center + box.axes @ (box.half_extents * 1.01 + 1e-3 * box.half_extents.max() + 1e-6)
    assert not box.contains(outside[None].astype(np.float32))[0]
    far = sphere.center + [sphere.radius * 1.01 + 1e-6, 0, 0]
    assert not sphere.contains(far[None])[0]


def test_axes_are_a_rotation(points):
    box = bvol.oriented_box(points)
    axes = box.axes.astype(np.float64)
    assert np.allclose(axes.T @ axes, np.eye(3), atol=1e-5)
    assert (box.half_extents >= 0).all()
    assert np.isclose(box.volume, 8 * np.prod(box.half_extents.astype(np.float64)), rtol=1e-6)
    signs = np.array([[(i >> k & 1) * 2 - 1 for k in range(3)] for i in range(8)])
    corners = box.center + (signs * box.half_extents.astype(np.float64)) @ axes.T
    assert np.allclose(box.corners(), corners, rtol=0, atol=1e-5 * np.abs(corners).max())


def test_every_layout_gives_the_same_bounds():
    """float32 C order (read in place), float64, Fortran order, strided
    views: the same values after rounding to float32, so the same bounds."""
    base = np.random.default_rng(3).normal(size=(4000, 3))
    c32 = base.astype(np.float32)
    wide = np.zeros((4000, 6), dtype=np.float32)
    wide[:, ::2] = c32
    layouts = {
        "float64": c32.astype(np.float64),
        "fortran": np.asfortranarray(c32),
        "strided": wide[:, ::2],
        "reversed": c32[::-1][::-1],
    }
    want = (bvol.bounding_sphere(c32), bvol.oriented_box(c32, "dito14"), bvol.kdop(c32))
    for name, points in layouts.items():
        got = (bvol.bounding_sphere(points), bvol.oriented_box(points, "dito14"), bvol.kdop(points))
        assert repr(got) == repr(want), name


def test_the_minimum_sphere_is_no_larger_than_any_other(points):
    exact = bvol.bounding_sphere(points, "exact").radius
    for method in bvol.SPHERE_METHODS:
        assert exact <= bvol.bounding_sphere(points, method).radius * (1 + 1e-6), method


@pytest.mark.parametrize("mesh", MESHES, ids=lambda p: p.stem)
def test_fits_equal_the_command_lines(mesh):
    """Each bound equals, to the last bit of float32, the one `bvol fit --json`
    gives for the same mesh."""
    binary = os.environ.get("BVOL_BIN", str(REPO / "target" / "debug" / "bvol"))
    out = subprocess.run([binary, "fit", "--json", str(mesh)], check=True, capture_output=True)
    rows = json.loads(out.stdout)
    points = mesh_points(mesh)
    f32 = lambda v: np.asarray(v, dtype=np.float32)  # noqa: E731
    assert len(rows) == len(bvol.SPHERE_METHODS) + len(bvol.OBB_METHODS) + 1 + len(KDOP_SIZES)
    for row in rows:
        bound, kind, method = row["bound"], row["kind"], row["method"]
        if kind == "sphere":
            s = fitted = bvol.bounding_sphere(points, method)
            assert (s.center == f32(bound["center"])).all() and s.radius == f32(bound["radius"])
        elif kind == "obb":
            o = fitted = bvol.oriented_box(points, method)
            assert (o.center == f32(bound["center"])).all(), method
            assert (o.axes == f32(bound["axes"]).T).all(), method
            assert (o.half_extents == f32(bound["half_extents"])).all(), method
        elif kind == "aabb":
            a = fitted = bvol.aabb(points)
            assert (a.min == f32(bound["min"])).all() and (a.max == f32(bound["max"])).all()
        else:
            k = fitted = bvol.kdop(points, int(method.split("-")[0]))
            assert (k.directions == f32(bound["directions"])).all()
            assert (k.min == f32(bound["min"])).all() and (k.max == f32(bound["max"])).all()
        assert np.isclose(fitted.volume, row["volume"], rtol=1e-12), (kind, method)


def test_convex_hull_is_a_closed_surface_around_every_point(points):
    vertices, faces = bvol.convex_hull(points)
    assert vertices.dtype == np.float32 and faces.dtype == np.uint32
    assert (faces < len(vertices)).all()
    p32 = points.astype(np.float32)
    # Every hull vertex is one of the points, exactly.
    assert np.isin(vertices.view([("", np.float32)] * 3), p32.view([("", np.float32)] * 3)).all()
    if len(faces) == 0:
        return
    a, b, c = (vertices[faces[:, i]].astype(np.float64) for i in range(3))
    normals = np.cross(b - a, c - a)
    size = np.ptp(p32, axis=0).max()
    # Each point lies behind (or on) each face's plane, to rounding.
    heights = np.einsum("fk,nk->fn", normals, p32.astype(np.float64)) - np.einsum(
        "fk,fk->f", normals, a
    )[:, None]
    lengths = np.linalg.norm(normals, axis=1)[:, None]
    solid = lengths[:, 0] > 1e-12 * size * size
    assert (heights[solid] / lengths[solid] <= 1e-5 * size).all()
    # Every edge of a closed triangulated surface is used once each way.
    edges = np.concatenate([faces[:, [0, 1]], faces[:, [1, 2]], faces[:, [2, 0]]])
    forward = {tuple(e) for e in edges.tolist()}
    assert len(forward) == len(edges) and all((b, a) in forward for a, b in forward)
