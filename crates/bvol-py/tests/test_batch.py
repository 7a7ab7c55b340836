"""Batched tests of bounds against float64 references in numpy."""

from __future__ import annotations

import numpy as np

import bvol
from conftest import box_separation, random_quaternions, rotation

M = 20_000


def random_boxes(rng, n, spread):
    """n boxes: centres, rotations (columns are the axes), half extents."""
    centers = rng.uniform(-spread, spread, size=(n, 3)).astype(np.float32)
    axes = np.array([rotation(q) for q in random_quaternions(rng, n)]).astype(np.float32)
    half = rng.uniform(0.05, 1.0, size=(n, 3)).astype(np.float32)
    return centers, axes, half


def test_spheres_overlap_as_their_distances_say():
    rng = np.random.default_rng(11)
    ca, cb = (rng.uniform(-1.2, 1.2, size=(M, 3)).astype(np.float32) for _ in range(2))
    ra, rb = (rng.uniform(0, 1.5, size=M).astype(np.float32) for _ in range(2))
    got = bvol.spheres_overlap(ca, ra, cb, rb)
    gap = np.linalg.norm(cb.astype(np.float64) - ca, axis=1) - ra - rb
    clear = np.abs(gap) > 1e-5
    assert got.shape == (M,) and clear.sum() > 0.99 * M
    assert (got[clear] == (gap[clear] <= 0)).all()
    assert 0.2 * M < got.sum() < 0.8 * M


def test_boxes_overlap_as_the_separating_axis_test_says():
    rng = np.random.default_rng(12)
    a, b = random_boxes(rng, M, 1.5), random_boxes(rng, M, 1.5)
    got = bvol.boxes_overlap(*a, *b)
    gap = box_separation(*a, *b)
    clear = np.abs(gap) > 1e-4
    assert got.shape == (M,) and clear.sum() > 0.99 * M
    assert (got[clear] == (gap[clear] <= 0)).all()
    assert 0.2 * M < got.sum() < 0.8 * M


def test_ray_entries_into_spheres_solve_the_quadratic():
    rng = np.random.default_rng(13)
    origins = rng.uniform(-3, 3, size=(M, 3)).astype(np.float32)
    centers = rng.uniform(-1, 1, size=(M, 3)).astype(np.float32)
    directions = (centers - origins + rng.normal(size=(M, 3))).astype(np.float32)
    radii = rng.uniform(0.1, 1.5, size=M).astype(np.float32)
    got = bvol.ray_spheres(origins, directions, centers, radii, max_t=2.0)
    o, d = origins.astype(np.float64) - centers, directions.astype(np.float64)
    a, b, c = (d * d).sum(1), (o * d).sum(1), (o * o).sum(1) - radii.astype(np.float64) ** 2
    disc = b * b - a * c
    root = np.sqrt(np.maximum(disc, 0))
    enter, leave = (-b - root) / a, (-b + root) / a
    hit = (disc >= 0) & (leave >= 0) & (enter <= 2.0)
    want = np.where(hit, np.maximum(enter, 0), np.inf)
    clear = (np.abs(disc) > 1e-4 * a) & (np.abs(enter - 2.0) > 1e-4) & (np.abs(leave) > 1e-4)
    assert clear.sum() > 0.99 * M and 0.1 * M < hit.sum() < 0.9 * M
    assert (np.isinf(got[clear]) == ~hit[clear]).all()
    both = clear & hit
    assert np.allclose(got[both], want[both], rtol=1e-4, atol=1e-4)
    assert (got[both] <= want[both] + 1e-6).all()  # never late


def test_ray_entries_into_boxes_clip_the_slabs():
    rng = np.random.default_rng(14)
    centers, axes, half = random_boxes(rng, M, 1.0)
    origins = rng.uniform(-3, 3, size=(M, 3)).astype(np.float32)
    directions = (centers - origins + rng.normal(size=(M, 3))).astype(np.float32)
    got = bvol.ray_boxes(origins, directions, centers, axes, half)
    a64 = axes.astype(np.float64)
    o = np.einsum("mki,mk->mi", a64, origins.astype(np.float64) - centers)
    d = np.einsum("mki,mk->mi", a64, directions.astype(np.float64))
    with np.errstate(divide="ignore", invalid="ignore"):
        t0, t1 = (-half - o) / d, (half - o) / d
    enter = np.maximum(np.minimum(t0, t1).max(1), 0)
    leave = np.maximum(t0, t1).min(1)
    hit = enter <= leave
    clear = np.abs(leave - enter) > 1e-4
    assert clear.sum() > 0.99 * M and 0.1 * M < hit.sum() < 0.9 * M
    assert (np.isinf(got[clear]) == ~hit[clear]).all()
    both = clear & hit
    assert np.allclose(got[both], enter[both], rtol=1e-4, atol=1e-4)
