"""The focal-plane lattice: point masses on a square grid inside a circle, 8-neighbour links.

Seed 000, Section II.B.2 and Fig. 3: "231 particles forming a circular structure. Each node
interacts with its 8 neighbouring nodes". We read this as a square grid of spacing ``h`` with
the Moore neighbourhood (4 axial and 4 diagonal links, a Voigt element each); a node on the
rim has fewer links.

Why 231: a square grid centred on a node is symmetric under a quarter turn, so its disc holds
1 + 4 m nodes (..., 221, 225, 233, ...) and never 231. Shifting the grid a quarter spacing
along the pipette axis (x) keeps the mirror symmetry about that axis and, with 17 spacings
across the diameter of 115.625 um (``h`` = 6.80 um), gives exactly 231 nodes.

Coordinates: um, cell centre at the origin, the pipette comes from +x (3 o'clock).
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property

import numpy as np
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components
from scipy.spatial import Delaunay

from oocyte_fe import checks
from oocyte_fe.errors import InputError

MOORE_OFFSETS = np.array([(1, 0), (0, 1), (1, 1), (1, -1)])
"""Half of the Moore neighbourhood (the other half is the same links seen from the far end)."""

MIN_NODES = 7


@dataclass(frozen=True, eq=False)
class Lattice:
    """Reference nodes (um) and links of the NMSD lattice, validated on construction.

    ``nodes``: (n, 2) reference positions, um. ``edges``: (m, 2) node indices of each link.
    ``rest_length``: (m,) rest lengths, um. ``radius``: radius of the circle the lattice fills.
    ``cells``: optional (c, 4) node indices of the area cells of :mod:`nmsd.area` (grid
    squares counter-clockwise; a triangle has -1 in the last column), or None.
    """

    nodes: np.ndarray
    edges: np.ndarray
    radius: float
    source: str = "lattice"
    cells: np.ndarray | None = None

    def __post_init__(self) -> None:
        nodes = np.asarray(self.nodes, dtype=float)
        edges = np.asarray(self.edges, dtype=np.intp)
        n = len(nodes)
        if nodes.ndim != 2 or nodes.shape[1] != 2:
            raise InputError(self.source, "nodes", "an (n, 2) array of positions in um")
        if n < MIN_NODES:
            raise InputError(self.source, "nodes", f"at least {MIN_NODES} nodes", got=n)
        if edges.ndim != 2 or edges.shape[1] != 2 or len(edges) == 0:
            raise InputError(self.source, "edges", "an (m, 2) array of node index pairs")
        if edges.min() < 0 or edges.max() >= n or np.any(edges[:, 0] == edges[:, 1]):
            raise InputError(self.source, "edges", f"pairs of distinct node indices < {n}")
        if not np.isfinite(nodes).all() or self.radius <= 0:
            raise InputError(self.source, "radius", "finite nodes and a positive radius")
        lengths = np.linalg.norm(nodes[edges[:, 0]] - nodes[edges[:, 1]], axis=1)
        if np.any(lengths <= 0):
            raise InputError(self.source, "edges", "links between distinct positions")
        degree = np.bincount(edges.ravel(), minlength=n)
        if np.any(degree == 0):
            raise InputError(
                self.source, "edges", "every node linked", got=f"unlinked node {np.argmin(degree)}"
            )
        graph = coo_matrix((np.ones(len(edges)), (edges[:, 0], edges[:, 1])), shape=(n, n))
        n_parts, _ = connected_components(graph, directed=False)
        if n_parts > 1:
            raise InputError(self.source, "edges", "one connected lattice", got=n_parts)
        object.__setattr__(self, "nodes", nodes)
        object.__setattr__(self, "edges", edges)
        if self.cells is not None:
            object.__setattr__(self, "cells", self._checked_cells(np.asarray(self.cells)))

    def _checked_cells(self, cells: np.ndarray) -> np.ndarray:
        n = len(self.nodes)
        expected = "a (c, 4) integer array of counter-clockwise cells (-1 pads a triangle)"
        if cells.ndim != 2 or cells.shape[1] != 4 or not np.issubdtype(cells.dtype, np.integer):
            raise InputError(self.source, "cells", expected)
        cells = cells.astype(np.int64)
        first = cells[:, :3]
        if first.min(initial=0) < 0 or cells.max(initial=0) >= n or cells[:, 3].min(initial=0) < -1:
            raise InputError(self.source, "cells", f"corner indices < {n}; -1 only last")
        for row in cells:
            k = row[row >= 0]
            if len(set(k.tolist())) != len(k):
                raise InputError(self.source, "cells", "distinct corners", got=row.tolist())
            x, y = self.nodes[k, 0], self.nodes[k, 1]
            if 0.5 * np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y) <= 0:
                raise InputError(
                    self.source, "cells", "counter-clockwise corners (positive area)", row.tolist()
                )
        return cells

    @property
    def n_nodes(self) -> int:
        return len(self.nodes)

    @cached_property
    def rest_length(self) -> np.ndarray:
        """Rest length of each link, um."""
        return np.linalg.norm(self.nodes[self.edges[:, 0]] - self.nodes[self.edges[:, 1]], axis=1)

    @cached_property
    def degree(self) -> np.ndarray:
        """Number of links at each node."""
        return np.bincount(self.edges.ravel(), minlength=self.n_nodes)

    @cached_property
    def rim(self) -> np.ndarray:
        """Mask of rim nodes: fewer links than the most-linked node."""
        return self.degree < self.degree.max()

    @cached_property
    def cell_rest_area(self) -> np.ndarray:
        """Rest area of each cell, um^2 (empty without cells)."""
        if self.cells is None:
            return np.zeros(0)
        from nmsd.area import cell_areas

        return cell_areas(self.nodes, self.cells)

    @cached_property
    def triangulation(self) -> Delaunay:
        """Delaunay triangles of the reference nodes, for interpolating inside a cell."""
        return Delaunay(self.nodes)


def circular_lattice(
    diameter_um: float = 115.625, spacings_across: int = 17, shift: float = 0.25
) -> Lattice:
    """Square-grid disc with 8-neighbour (Moore) links; the defaults give 231 nodes.

    Nodes at ``((i + shift) h, j h)`` with ``h = diameter / spacings_across`` and
    ``x^2 + y^2 <= (diameter / 2)^2``, numbered row by row (small matrix bandwidth).
    ``shift`` is in units of ``h`` along the pipette axis. Cells (for the optional area
    term, :mod:`nmsd.area`): every grid square with all four corners inside, and the
    triangle of the three corners inside where one is missing (all their sides are links).
    """
    diameter_um = checks.number("circular_lattice", "diameter_um", diameter_um, ge=1e-3, le=1e6)
    spacings_across = int(
        checks.number(
            "circular_lattice", "spacings_across", spacings_across, ge=2, le=400, integer=True
        )
    )
    shift = checks.number("circular_lattice", "shift", shift, ge=-1, le=1)
    radius = 0.5 * diameter_um
    h = diameter_um / spacings_across
    m = spacings_across
    i, j = np.meshgrid(np.arange(-m, m + 1), np.arange(-m, m + 1))
    x, y = (i + shift) * h, j * h
    inside = x**2 + y**2 <= radius**2 * (1 + 1e-12)
    index = np.full(i.shape, -1)
    index[inside] = np.arange(inside.sum())
    nodes = np.column_stack([x[inside], y[inside]])
    pairs = []
    for di, dj in MOORE_OFFSETS:
        a = index[max(0, -dj) : 2 * m + 1 - max(0, dj), : 2 * m + 1 - di]
        b = index[max(0, dj) : 2 * m + 1 + min(0, dj), di:]
        linked = (a >= 0) & (b >= 0)
        pairs.append(np.column_stack([a[linked], b[linked]]))
    cells = []
    for r in range(2 * m):
        for c in range(2 * m):
            ring = [index[r, c], index[r, c + 1], index[r + 1, c + 1], index[r + 1, c]]
            present = [k for k in ring if k >= 0]
            if len(present) >= 3:
                cells.append(present + [-1] * (4 - len(present)))
    cells_array = np.array(cells, dtype=np.int64).reshape(-1, 4)
    return Lattice(nodes, np.vstack(pairs), radius, "circular_lattice", cells_array)
