"""Type stubs of bvol's native module; import `bvol`, which re-exports it."""

from os import PathLike
from typing import Optional, Sequence, Tuple, Union

import numpy as np
import numpy.typing as npt
from typing_extensions import disjoint_base, final

_FloatArray = npt.NDArray[Union[np.float32, np.float64]]
_IntArray = npt.NDArray[np.integer]
_Vector3 = Union[Sequence[float], npt.NDArray[np.floating]]
_Quaternion = Union[Sequence[float], npt.NDArray[np.floating]]
_Pose = Tuple[_Vector3, _Quaternion]

__all__ = [
    "Aabb",
    "BEGAN",
    "ENDED",
    "Kdop",
    "MAX_COORDINATE",
    "Mesh",
    "NO_BODY",
    "OBB_METHODS",
    "OrientedBox",
    "PERSISTING",
    "SPHERE_METHODS",
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

NO_BODY: int
"""The id that names no body: a ray hit's id where the ray met nothing."""
BEGAN: int
"""An event's kind: the pair touches now and did not at the update before."""
PERSISTING: int
"""An event's kind: the pair touched at the update before and still does."""
ENDED: int
"""An event's kind: the pair touched at the update before and does not now (or a
body was removed); its contact fields are zero."""
MAX_COORDINATE: float
"""The largest magnitude a coordinate may have."""
SPHERE_METHODS: list[str]
"""The names `bounding_sphere` takes."""
OBB_METHODS: list[str]
"""The names `oriented_box` takes."""

@final
class Sphere:
    """A bounding sphere: the points within `radius` of `center`."""

    @property
    def center(self) -> npt.NDArray[np.float32]:
        """The centre, a (3,) float32 array."""
    @property
    def radius(self) -> float:
        """The radius."""
    @property
    def volume(self) -> float:
        """The volume, in float64."""
    def contains(self, points: _FloatArray) -> npt.NDArray[np.bool_]:
        """Whether each of the (N, 3) points lies inside or on the sphere."""

@final
class OrientedBox:
    """An oriented bounding box: the points p with
    abs((p - center) @ axes[:, i]) <= half_extents[i]."""

    @property
    def center(self) -> npt.NDArray[np.float32]:
        """The centre, a (3,) float32 array."""
    @property
    def axes(self) -> npt.NDArray[np.float32]:
        """The unit axes as the columns of a (3, 3) float32 rotation matrix."""
    @property
    def half_extents(self) -> npt.NDArray[np.float32]:
        """Half the size along each axis, a (3,) float32 array."""
    @property
    def volume(self) -> float:
        """The volume, in float64."""
    def corners(self) -> npt.NDArray[np.float32]:
        """The eight corners, an (8, 3) float32 array."""
    def contains(self, points: _FloatArray) -> npt.NDArray[np.bool_]:
        """Whether each of the (N, 3) points lies inside or on the box."""

@final
class Aabb:
    """An axis-aligned box from `min` to `max`."""

    @property
    def min(self) -> npt.NDArray[np.float32]:
        """The lower corner, a (3,) float32 array."""
    @property
    def max(self) -> npt.NDArray[np.float32]:
        """The upper corner, a (3,) float32 array."""
    @property
    def volume(self) -> float:
        """The volume, in float64."""
    def contains(self, points: _FloatArray) -> npt.NDArray[np.bool_]:
        """Whether each of the (N, 3) points lies inside or on the box."""

@final
class Kdop:
    """A discrete oriented polytope: the points whose projection on each slab
    direction directions[i] lies within [min[i], max[i]]."""

    @property
    def k(self) -> int:
        """The number of faces: 6, 14, 18 or 26."""
    @property
    def directions(self) -> npt.NDArray[np.float32]:
        """The slab directions (not normalised), a (k/2, 3) float32 array."""
    @property
    def min(self) -> npt.NDArray[np.float32]:
        """The lower bound on each slab, a (k/2,) float32 array."""
    @property
    def max(self) -> npt.NDArray[np.float32]:
        """The upper bound on each slab, a (k/2,) float32 array."""
    @property
    def volume(self) -> float:
        """The volume, in float64."""
    def contains(self, points: _FloatArray) -> npt.NDArray[np.bool_]:
        """Whether each of the (N, 3) points lies inside or on the polytope."""

@final
class Mesh:
    """One object of an OBJ file."""

    name: str
    """The object's name in the file, or "unnamed_object"."""
    vertices: npt.NDArray[np.float32]
    """Vertex positions, an (N, 3) float32 array."""
    faces: npt.NDArray[np.uint32]
    """Triangles as indices into vertices, an (F, 3) uint32 array."""

@final
class Shape:
    """A body's geometry in its own frame, shared by every body given it."""

    @staticmethod
    def box(half_extents: _Vector3) -> Shape:
        """A box centred on the origin."""
    @staticmethod
    def sphere(radius: float) -> Shape:
        """A ball centred on the origin."""
    @staticmethod
    def capsule(radius: float, half_height: float) -> Shape:
        """A capsule along y: a segment from -half_height to half_height swept by a ball."""
    @staticmethod
    def convex(points: _FloatArray) -> Shape:
        """The convex hull of the (N, 3) points; flat points are made a thin slab."""
    @staticmethod
    def from_obj(
        path: Union[str, PathLike[str]],
        sphere_method: str = "exact",
        obb_method: str = "min-volume",
    ) -> Shape:
        """Every object of an OBJ file, one convex part each."""
    def scaled(self, factor: Union[float, _Vector3]) -> Shape:
        """The same shape scaled by one factor, or one per axis."""
    @property
    def bounding_sphere(self) -> Sphere:
        """The shape's bounding sphere, in its own frame."""
    @property
    def oriented_box(self) -> OrientedBox:
        """The shape's oriented bounding box, in its own frame."""
    @property
    def volume(self) -> float:
        """The volume enclosed."""
    @property
    def center_of_mass(self) -> npt.NDArray[np.float32]:
        """The centre of mass at uniform density, a (3,) float32 array."""

@disjoint_base
class World:
    """Bodies and what touches among them (use `bvol.World`, which adds
    `events` and `ray_cast`)."""

    def __new__(cls, threads: Optional[int] = None, margin: float = 0.0, reuse: float = 0.0) -> World:
        """A world with no bodies; update runs on `threads` threads (by default, one per core);
        bodies apart by at most `margin` are in contact too, with negative depths; touching
        pairs that moved by at most `reuse` of their size reuse their contact feature."""
    def add_body(
        self,
        *,
        vertices: Optional[_FloatArray] = None,
        primitive: Optional[tuple[object, ...]] = None,
        shape: Optional[Shape] = None,
        pose: Optional[_Pose] = None,
        kind: str = "dynamic",
        user_data: int = 0,
        layers: int = 1,
        mask: int = 0xFFFFFFFF,
    ) -> int:
        """Adds a body of exactly one of vertices, primitive or shape; returns its id."""
    def add_bodies(
        self,
        positions: _FloatArray,
        quaternions: Optional[_FloatArray] = None,
        *,
        vertices: Optional[_FloatArray] = None,
        primitive: Optional[tuple[object, ...]] = None,
        shape: Optional[Shape] = None,
        kind: str = "dynamic",
        user_data: Optional[_IntArray] = None,
    ) -> npt.NDArray[np.uint64]:
        """Adds one body of one shape per row; all or none."""
    def remove(self, id: int) -> None:
        """Removes a body."""
    def set_poses(
        self, ids: _IntArray, positions: _FloatArray, quaternions: Optional[_FloatArray] = None
    ) -> None:
        """Moves bodies; if any pose is refused, none is set."""
    def pose(self, id: int) -> Tuple[npt.NDArray[np.float32], npt.NDArray[np.float32]]:
        """The body's position and quaternion (x, y, z, w)."""
    def set_poses_f64(
        self, ids: _IntArray, positions: _FloatArray, quaternions: Optional[_FloatArray] = None
    ) -> None:
        """Moves bodies to positions kept in float64; if any pose is refused, none is set."""
    def pose_f64(self, id: int) -> Tuple[npt.NDArray[np.float64], npt.NDArray[np.float32]]:
        """The body's position as given (float64) and its quaternion (x, y, z, w)."""
    def contact_points_f64(self, a: int, b: int) -> npt.NDArray[np.float64]:
        """The points of a and b's contact at their poses now, a (K, 3) float64 array."""
    def set_kind(self, id: int, kind: str) -> None:
        """Makes the body "dynamic", "static" or "sleeping"."""
    def kind(self, id: int) -> str:
        """The body's kind."""
    def user_data(self, id: int) -> int:
        """The body's user data."""
    def ids(self) -> npt.NDArray[np.uint64]:
        """Every body's id, in slot order."""
    def __len__(self) -> int: ...
    def snapshot(self) -> bytes:
        """The world saved as JSON bytes, to load with World.from_snapshot or pickle."""
    def _load_snapshot(self, data: bytes) -> None:
        """Becomes the world the bytes saved."""
    def __getstate__(self) -> bytes: ...
    def __setstate__(self, state: bytes) -> None: ...
    def update(self) -> dict[str, float]:
        """Runs one frame; returns each stage's pair count and time in seconds."""
    def pairs(self) -> npt.NDArray[np.uint64]:
        """The pairs touching (or within the margin) at the last update, an (M, 2) array of ids."""
    def contact(self, a: int, b: int) -> Optional[dict[str, object]]:
        """How a and b touched at the last update (normal from a to b), or None."""
    def _event_columns(self) -> dict[str, npt.NDArray[np.generic]]:
        """The last update's events as columns, for bvol.World.events."""
    def _ray_columns(
        self, origins: _FloatArray, directions: _FloatArray, max_t: float
    ) -> dict[str, npt.NDArray[np.generic]]:
        """Each ray's nearest hit as columns, for bvol.World.ray_cast."""

def bounding_sphere(points: _FloatArray, method: str = "exact") -> Sphere:
    """The bounding sphere of the (N, 3) points, by method (see SPHERE_METHODS)."""

def oriented_box(points: _FloatArray, method: str = "min-volume") -> OrientedBox:
    """The oriented bounding box of the (N, 3) points, by method (see OBB_METHODS)."""

def aabb(points: _FloatArray) -> Aabb:
    """The axis-aligned bounding box of the (N, 3) points."""

def kdop(points: _FloatArray, k: int = 26) -> Kdop:
    """The k-DOP (k = 6, 14, 18 or 26) of the (N, 3) points."""

def convex_hull(points: _FloatArray) -> Tuple[npt.NDArray[np.float32], npt.NDArray[np.uint32]]:
    """The convex hull's vertices (V, 3) and triangles (F, 3)."""

def spheres_overlap(
    centers_a: _FloatArray, radii_a: _FloatArray, centers_b: _FloatArray, radii_b: _FloatArray
) -> npt.NDArray[np.bool_]:
    """Whether sphere i of A overlaps or touches sphere i of B, for every row."""

def boxes_overlap(
    centers_a: _FloatArray,
    axes_a: _FloatArray,
    half_extents_a: _FloatArray,
    centers_b: _FloatArray,
    axes_b: _FloatArray,
    half_extents_b: _FloatArray,
) -> npt.NDArray[np.bool_]:
    """Whether box i of A overlaps or touches box i of B, for every row."""

def ray_spheres(
    origins: _FloatArray,
    directions: _FloatArray,
    centers: _FloatArray,
    radii: _FloatArray,
    max_t: float = ...,
) -> npt.NDArray[np.float32]:
    """Where ray i enters sphere i: the ray parameter, inf for a miss."""

def ray_boxes(
    origins: _FloatArray,
    directions: _FloatArray,
    centers: _FloatArray,
    axes: _FloatArray,
    half_extents: _FloatArray,
    max_t: float = ...,
) -> npt.NDArray[np.float32]:
    """Where ray i enters box i: the ray parameter, inf for a miss."""

def load_obj(path: Union[str, PathLike[str]]) -> list[Mesh]:
    """Every object of an OBJ file."""
