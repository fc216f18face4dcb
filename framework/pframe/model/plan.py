"""Buildings in plan: where a building stands on the site, its floor plan, named plan points
and the geometry of elements that act along a direction at a point (docs/plan.md).

A floor is a rigid diaphragm whose degrees of freedom are the translations u_x, u_y of its
centre of mass and its rotation theta about the vertical axis, in the site's axes. A point P
of the floor moves by (small rotations)

    u_P = (u_x - theta (P_y - c_y), u_y + theta (P_x - c_x)),

so an element acting at P along the unit direction n sees n . u_P = a . (u_x, u_y, theta) with
a = (n_x, n_y, (P - c) x n), the 2-D cross product (P - c)_x n_y - (P - c)_y n_x (Chopra,
Dynamics of Structures, ch. 9, torsionally coupled systems). Nothing here is numerical beyond
that geometry: the definitions are pydantic models, the geometry plain functions.
"""

from __future__ import annotations

import math
from typing import Annotated, Literal

from pydantic import Field, model_validator

from pframe.objects import Frozen

Finite = Annotated[float, Field(allow_inf_nan=False)]
#: a point or vector of the plan, [x, y] (m)
Point = tuple[Finite, Finite]
Positive = Annotated[float, Field(gt=0, allow_inf_nan=False)]
#: the components of a plan floor's motion: translations along the site's x and y, rotation
COMPONENTS = ("x", "y", "rz")


class FloorPlan(Frozen):
    """The plan of a building's floors, in the building's own axes (m): a rectangle from the
    building's origin (``size``) or a polygon (``outline``). It gives the floors' centre of
    mass and polar moment of inertia when they are not given (a uniform slab), the corners
    named for outputs (``SW``, ``SE``, ``NE``, ``NW`` of a rectangle; ``c1``, ``c2``, ... of a
    polygon) and the extent that contact points must lie within."""

    size: tuple[Positive, Positive] | None = Field(
        None, description="[L_x, L_y]: a rectangle from (0, 0) to (L_x, L_y) (m).")
    outline: list[Point] | None = Field(
        None, min_length=3, description="The floor's outline, its corners in order "
        "[[x, y], ...] (m): a simple polygon.")

    @model_validator(mode="after")
    def _one_shape(self):
        if (self.size is None) == (self.outline is None):
            raise ValueError("give size ([L_x, L_y], a rectangle) or outline (a polygon), "
                             "not both and not neither")
        if self.outline is not None and abs(_area(self.corners())) <= 0.0:
            raise ValueError("the outline encloses no area (its corners are on one line)")
        return self

    def corners(self) -> list[tuple[float, float]]:
        if self.size is not None:
            lx, ly = self.size
            return [(0.0, 0.0), (lx, 0.0), (lx, ly), (0.0, ly)]
        return [(float(x), float(y)) for x, y in self.outline]

    def corner_names(self) -> dict[str, tuple[float, float]]:
        """The corners as named points: SW, SE, NE, NW of a rectangle, c1, c2, ... of an
        outline (x east, y north in the building's axes)."""
        corners = self.corners()
        names = ("SW", "SE", "NE", "NW") if self.size is not None else tuple(
            f"c{i + 1}" for i in range(len(corners)))
        return dict(zip(names, corners))

    def centroid(self) -> tuple[float, float]:
        """The centroid of the plan (m): the centre of mass of a uniform slab."""
        corners = self.corners()
        area = _area(corners)
        cx = cy = 0.0
        for (x0, y0), (x1, y1) in _edges(corners):
            cross = x0 * y1 - x1 * y0
            cx += (x0 + x1) * cross
            cy += (y0 + y1) * cross
        return cx / (6.0 * area), cy / (6.0 * area)

    def polar_radius2(self) -> float:
        """r^2 = J / m of a uniform slab about its centroid (m^2): (L_x^2 + L_y^2) / 12 for a
        rectangle; the polygon's second moments of area over its area otherwise."""
        corners = self.corners()
        area = _area(corners)
        ixx = iyy = 0.0  # about the origin (the shoelace sums)
        for (x0, y0), (x1, y1) in _edges(corners):
            cross = x0 * y1 - x1 * y0
            ixx += (y0 * y0 + y0 * y1 + y1 * y1) * cross
            iyy += (x0 * x0 + x0 * x1 + x1 * x1) * cross
        cx, cy = self.centroid()
        polar = (ixx + iyy) / (12.0 * area)  # about the origin, per unit area
        return polar - (cx * cx + cy * cy)

    def extent(self) -> float:
        """The largest distance between two corners (m): the plan's size for the small-rotation
        check."""
        corners = self.corners()
        return max(math.dist(p, q) for p in corners for q in corners)

    def contains(self, point, tolerance: float) -> bool:
        """Whether ``point`` is inside the plan or within ``tolerance`` (m) of its edge."""
        x, y = point
        inside = False
        for (x0, y0), (x1, y1) in _edges(self.corners()):
            if (y0 > y) != (y1 > y) and x < x0 + (y - y0) * (x1 - x0) / (y1 - y0):
                inside = not inside
        return inside or min(_segment_distance(point, p, q)
                             for p, q in _edges(self.corners())) <= tolerance


def _edges(corners):
    return zip(corners, corners[1:] + corners[:1])


def _area(corners) -> float:
    return 0.5 * sum(x0 * y1 - x1 * y0 for (x0, y0), (x1, y1) in _edges(corners))


def _segment_distance(point, p, q) -> float:
    (x, y), (x0, y0), (x1, y1) = point, p, q
    dx, dy = x1 - x0, y1 - y0
    length2 = dx * dx + dy * dy
    t = 0.0 if length2 == 0.0 else min(1.0, max(0.0, ((x - x0) * dx + (y - y0) * dy) / length2))
    return math.hypot(x - x0 - t * dx, y - y0 - t * dy)


#: a direction in the plan: an axis of the building ('x', 'y') or an angle in degrees from its
#: x axis, counter-clockwise
Direction = Literal["x", "y"] | Finite


def unit(direction) -> tuple[float, float]:
    """The unit vector of a :data:`Direction` in the frame it is given in."""
    if direction == "x":
        return 1.0, 0.0
    if direction == "y":
        return 0.0, 1.0
    angle = math.radians(float(direction))
    return math.cos(angle), math.sin(angle)


def normalised(vector) -> tuple[float, float]:
    """``vector`` scaled to unit length (ValueError for a zero vector)."""
    x, y = map(float, vector)
    length = math.hypot(x, y)
    if not length > 0.0 or not math.isfinite(length):
        raise ValueError(f"the vector [{x:g}, {y:g}] has no direction (zero length)")
    return x / length, y / length


class Placement:
    """Where a building stands on the site: its plan origin (site coordinates, m) and the
    angle of its x axis from the site's x axis (degrees, counter-clockwise)."""

    def __init__(self, origin=(0.0, 0.0), angle: float = 0.0):
        self.origin = (float(origin[0]), float(origin[1]))
        self.angle = float(angle)
        if self.angle == 0.0:  # exact for the common case: no rounding of cos/sin
            self.cos, self.sin = 1.0, 0.0
        else:
            self.cos, self.sin = math.cos(math.radians(self.angle)), math.sin(
                math.radians(self.angle))

    def vector(self, v) -> tuple[float, float]:
        """A vector of the building's axes in the site's axes."""
        return self.cos * v[0] - self.sin * v[1], self.sin * v[0] + self.cos * v[1]

    def point(self, p) -> tuple[float, float]:
        """A point of the building's plan in site coordinates (m)."""
        x, y = self.vector(p)
        return self.origin[0] + x, self.origin[1] + y


def coefficients(point, centre, direction) -> tuple[float, float, float]:
    """a = (n_x, n_y, (P - c) x n): the weights of a floor's (u_x, u_y, theta) in the motion
    of its point P along the unit direction n (all in site axes; centre c its centre of mass)."""
    nx, ny = direction
    rx, ry = point[0] - centre[0], point[1] - centre[1]
    return nx, ny, rx * ny - ry * nx
