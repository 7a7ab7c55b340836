"""bvol: exact bounding volumes, a dynamic BV tree and contacts, numpy in and out.

Fitting bounds to an (N, 3) float32 or float64 point array::

    import numpy as np, bvol
    points = np.random.default_rng(1).normal(size=(10_000, 3))
    sphere = bvol.bounding_sphere(points)            # the exact minimum sphere
    box = bvol.oriented_box(points)                  # near-minimum volume
    assert sphere.contains(points).all() and box.contains(points).all()

Finding what touches among many bodies::

    world = bvol.World()
    ids = world.add_bodies(points[:1000] * 10, primitive=("box", (0.5, 0.5, 0.5)))
    world.update()
    pairs = world.pairs()                           # (M, 2) ids of touching bodies
    events = world.events()                         # a structured array

Points are rounded to float32 first: every bound holds the rounded points.
Quaternions are (x, y, z, w). Bad input raises TypeError (wrong kind or dtype
of array), ValueError (wrong shape, NaN, an unknown method, a bad size) or
KeyError (an id that names no body), with the Rust library's messages.
"""

from __future__ import annotations

import numpy as np

from ._bvol import (
    BEGAN,
    ENDED,
    MAX_COORDINATE,
    NO_BODY,
    OBB_METHODS,
    PERSISTING,
    SPHERE_METHODS,
    Aabb,
    Kdop,
    Mesh,
    OrientedBox,
    Shape,
    Sphere,
    aabb,
    bounding_sphere,
    boxes_overlap,
    convex_hull,
    kdop,
    load_obj,
    oriented_box,
    ray_boxes,
    ray_spheres,
    spheres_overlap,
)
from ._bvol import World as _NativeWorld

__all__ = [
    "BEGAN",
    "ENDED",
    "EVENT_DTYPE",
    "MAX_COORDINATE",
    "NO_BODY",
    "OBB_METHODS",
    "PERSISTING",
    "RAY_HIT_DTYPE",
    "SPHERE_METHODS",
    "Aabb",
    "Kdop",
    "Mesh",
    "OrientedBox",
    "Shape",
    "Sphere",
    "World",
    "aabb",
    "bounding_sphere",
    "boxes_overlap",
    "convex_hull",
    "kdop",
    "load_obj",
    "oriented_box",
    "ray_boxes",
    "ray_spheres",
    "spheres_overlap",
]

#: One contact event: what happened, the two bodies (`id_a` has the lower
#: slot) and their user data, the unit normal from a to b, the depth, and up
#: to four contact points with their depths (`point_count` of them).
EVENT_DTYPE = np.dtype(
    [
        ("kind", np.uint8),
        ("id_a", np.uint64),
        ("id_b", np.uint64),
        ("user_data_a", np.uint64),
        ("user_data_b", np.uint64),
        ("normal", np.float32, (3,)),
        ("depth", np.float32),
        ("point_count", np.uint8),
        ("points", np.float32, (4, 3)),
        ("point_depths", np.float32, (4,)),
    ]
)

#: One ray's nearest hit: whether it hit, the body (NO_BODY for a miss), the
#: ray parameter (inf for a miss), the point and the body's user data.
RAY_HIT_DTYPE = np.dtype(
    [
        ("hit", np.bool_),
        ("id", np.uint64),
        ("t", np.float32),
        ("point", np.float32, (3,)),
        ("user_data", np.uint64),
    ]
)


class World(_NativeWorld):
    """Bodies and what touches among them.

    Add bodies (`add_body`, `add_bodies`), move them (`set_poses`), run a
    frame (`update`), then read what touches (`pairs`, `events`,
    `contact`) or cast rays (`ray_cast`). Bodies are named by integer ids.
    Touching exactly, a contact of depth 0, counts as touching. A world made
    with `margin=` counts bodies apart by at most that distance as in
    contact too: their depths are negative, minus their distance. One made
    with `reuse=` (4e-5 keeps depths within 1e-4 of the size) lets a
    touching pair that moved by at most that fraction of its size since its
    last full test reuse its contact feature: which pairs touch is the same,
    depths are within 2e-5 + 2 * reuse of the size of the least.
    """

    @classmethod
    def from_snapshot(cls, data: bytes) -> "World":
        """The world `snapshot()` saved, to run on exactly as it would have,
        event for event (pickling a World does the same). Bad data raises
        ValueError."""
        world = cls()
        world._load_snapshot(data)
        return world

    def events(self) -> np.ndarray:
        """The last update's contact events, an array of `EVENT_DTYPE`.

        Pairs come in slot order, the same on any number of threads.
        """
        columns = self._event_columns()
        events = np.empty(len(columns["kind"]), dtype=EVENT_DTYPE)
        events["kind"] = columns["kind"]
        events["id_a"] = columns["ids"][:, 0]
        events["id_b"] = columns["ids"][:, 1]
        events["user_data_a"] = columns["user_data"][:, 0]
        events["user_data_b"] = columns["user_data"][:, 1]
        events["normal"] = columns["normal"]
        events["depth"] = columns["depth"]
        events["point_count"] = columns["point_count"]
        events["points"] = columns["points"].reshape(-1, 4, 3)
        events["point_depths"] = columns["point_depths"]
        return events

    def ray_cast(self, origins: np.ndarray, directions: np.ndarray, max_t: float = np.inf) -> np.ndarray:
        """The nearest body each ray meets within `max_t`, as of the last update.

        `origins` and `directions` are (R, 3) float arrays; returns an (R,)
        array of `RAY_HIT_DTYPE`. `t` is the ray parameter: a distance for unit
        directions.
        """
        columns = self._ray_columns(origins, directions, float(max_t))
        hits = np.empty(len(columns["hit"]), dtype=RAY_HIT_DTYPE)
        for name in RAY_HIT_DTYPE.names or ():
            hits[name] = columns[name]
        return hits
