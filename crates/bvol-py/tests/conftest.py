"""What the tests share: the shipped meshes, random point clouds, and
independent float64 references (rotations, separating-axis tests)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import bvol

REPO = Path(__file__).resolve().parents[3]
MESHES = sorted((REPO / "tests" / "meshes").glob("*.obj"))


def mesh_points(path: Path) -> np.ndarray:
    """Every object's vertices of an OBJ file, together."""
    return np.concatenate([m.vertices for m in bvol.load_obj(path)])


def rotation(q) -> np.ndarray:
    """The rotation matrix of quaternion q = (x, y, z, w), normalised, in float64."""
    x, y, z, w = np.asarray(q, dtype=np.float64) / np.linalg.norm(q)
    return np.array(
        [
            [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
            [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
            [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)],
        ]
    )


def clouds() -> dict[str, np.ndarray]:
    """Random and degenerate point sets, float64, by name."""
    rng = np.random.default_rng(7)
    stretched = rng.uniform(-1, 1, size=(2000, 3)) * [1, 2, 5] @ rotation(rng.normal(size=4)).T
    flat = rng.normal(size=(500, 3)) * [3, 1, 0]
    line = np.outer(rng.uniform(-2, 2, size=300), [1.0, 2.0, -0.5]) + 10
    return {
        "normal": rng.normal(size=(3000, 3)),
        "stretched": stretched + [1e3, -2e3, 5e2],
        "flat": flat,
        "line": line,
        "one point": np.array([[1.5, -2.0, 3.25]]),
        "repeated": np.repeat(rng.normal(size=(4, 3)), 50, axis=0),
        "tiny": rng.normal(size=(200, 3)) * 1e-3,
    }


@pytest.fixture(params=list(clouds()) + [p.stem for p in MESHES])
def points(request) -> np.ndarray:
    """Each random cloud and each shipped mesh's vertices."""
    if request.param in clouds():
        return clouds()[request.param]
    return mesh_points(REPO / "tests" / "meshes" / f"{request.param}.obj").astype(np.float64)


def random_quaternions(rng, n: int) -> np.ndarray:
    """n unit quaternions (x, y, z, w), uniformly distributed, float32."""
    q = rng.normal(size=(n, 4))
    return (q / np.linalg.norm(q, axis=1, keepdims=True)).astype(np.float32)


def box_separation(ca, ra, ha, cb, rb, hb) -> np.ndarray:
    """For M pairs of boxes (centres (M, 3), rotations (M, 3, 3) whose columns
    are the axes, half extents (M, 3)), the largest gap over the 15 axes of
    the separating-axis test (Gottschalk 1996), in float64: > 0 apart,
    <= 0 overlapping or touching."""
    ca, ra, ha, cb, rb, hb = (np.asarray(x, dtype=np.float64) for x in (ca, ra, ha, cb, rb, hb))
    d = cb - ca
    axes = [ra[:, :, i] for i in range(3)] + [rb[:, :, j] for j in range(3)]
    axes += [np.cross(ra[:, :, i], rb[:, :, j]) for i in range(3) for j in range(3)]
    gap = np.full(len(d), -np.inf)
    for axis in axes:
        length = np.linalg.norm(axis, axis=1)
        usable = length > 1e-9
        axis = axis / np.where(usable, length, 1.0)[:, None]
        reach_a = np.einsum("mi,mi->m", np.abs(np.einsum("mki,mk->mi", ra, axis)), ha)
        reach_b = np.einsum("mi,mi->m", np.abs(np.einsum("mki,mk->mi", rb, axis)), hb)
        along = np.abs(np.einsum("mk,mk->m", d, axis)) - reach_a - reach_b
        gap = np.where(usable, np.maximum(gap, along), gap)
    return gap
