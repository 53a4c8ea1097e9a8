"""Planar (2-D) channel layouts built of rectangular blocks on one uniform grid, for blockMesh.

All lengths in um (the blockMeshDict scales to metres with ``scale 1e-6``). The mesh is one
cell thick in z (``front``/``back`` are ``empty``). Cells are numbered as blockMesh numbers
them: block by block, x fastest, then y; the face centres of a patch side follow y (x-sides)
or x (y-sides). Both orders are checked against OpenFOAM's ``writeCellCentres`` in the tests.

**The junction of seed 001, Fig. 6** (this model's reading; the paper gives only the channel
width 250 um, the cell diameters and the 500 um start): a T-junction. The main channel runs
along x from the cell inlet A (x = -upstream_length) through the junction (centred at x = 0)
to the outlet C (x = downstream_length); the medium inlet B is a side branch of the same width
entering from +y. The cell's centre starts ``cell_offset`` = 500 um upstream of the junction
centre on the channel axis (y = 0).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from oocyte_fe.errors import InputError

# hex vertex order (x0y0z0, x1y0z0, x1y1z0, x0y1z0, then z1); sides with outward normals
_SIDES = {
    "xmin": (0, 4, 7, 3),
    "xmax": (1, 2, 6, 5),
    "ymin": (0, 1, 5, 4),
    "ymax": (3, 7, 6, 2),
}


@dataclass(frozen=True)
class Block:
    """A rectangle ``[x0, x1] x [y0, y1]`` (um) meshed with ``nx`` x ``ny`` square cells."""

    x0: float
    x1: float
    y0: float
    y1: float
    nx: int
    ny: int

    def side_span(self, side: str) -> tuple[float, float, float]:
        """(fixed coordinate, start, end) of a side."""
        return {
            "xmin": (self.x0, self.y0, self.y1),
            "xmax": (self.x1, self.y0, self.y1),
            "ymin": (self.y0, self.x0, self.x1),
            "ymax": (self.y1, self.x0, self.x1),
        }[side]


@dataclass(frozen=True)
class Inlet:
    """A velocity inlet on one block side: plane-Poiseuille profile of mean ``velocity`` (um/s)
    pointing into the domain, carrying ``phase``."""

    block: int
    side: str
    velocity: float
    phase: str


@dataclass
class Layout:
    """Blocks on a uniform grid ``dx`` (um), inlets, one outlet; every other exterior side is a
    no-slip wall."""

    dx: float
    blocks: list[Block]
    inlets: dict[str, Inlet]
    outlet: tuple[int, str]
    outlet_name: str = "outlet"
    _centres: np.ndarray | None = field(default=None, repr=False)

    @property
    def n_cells(self) -> int:
        return sum(b.nx * b.ny for b in self.blocks)

    def cell_centres(self) -> np.ndarray:
        """(n_cells, 2) cell centres (um) in blockMesh order."""
        if self._centres is None:
            parts = []
            for b in self.blocks:
                x = b.x0 + (np.arange(b.nx) + 0.5) * self.dx
                y = b.y0 + (np.arange(b.ny) + 0.5) * self.dx
                xx, yy = np.meshgrid(x, y)  # rows: y, columns: x -> x fastest when raveled
                parts.append(np.column_stack([xx.ravel(), yy.ravel()]))
            self._centres = np.vstack(parts)
        return self._centres

    def side_face_centres(self, block: int, side: str) -> np.ndarray:
        """Coordinates along a side (um) of its face centres, in patch order."""
        b = self.blocks[block]
        n = b.ny if side.startswith("x") else b.nx
        _, start, _ = b.side_span(side)
        return start + (np.arange(n) + 0.5) * self.dx

    def exterior_sides(self) -> list[tuple[int, str]]:
        """Block sides not shared with another block."""
        opposite = {"xmin": "xmax", "xmax": "xmin", "ymin": "ymax", "ymax": "ymin"}
        spans = {(i, s): b.side_span(s) for i, b in enumerate(self.blocks) for s in _SIDES}
        exterior = []
        for (i, s), span in spans.items():
            shared = any(
                j != i and np.allclose(spans[(j, opposite[s])], span)
                for j in range(len(self.blocks))
            )
            if not shared:
                exterior.append((i, s))
        return exterior

    def vertices(self) -> tuple[list[tuple[float, float]], list[list[int]]]:
        """Unique (x, y) corner points and each block's 8 vertex labels (z0 then z1 layer)."""
        points: dict[tuple[float, float], int] = {}
        for b in self.blocks:
            for p in ((b.x0, b.y0), (b.x1, b.y0), (b.x1, b.y1), (b.x0, b.y1)):
                points.setdefault((round(p[0], 9), round(p[1], 9)), len(points))
        n = len(points)
        labels = []
        for b in self.blocks:
            base = [
                points[(round(x, 9), round(y, 9))]
                for x, y in ((b.x0, b.y0), (b.x1, b.y0), (b.x1, b.y1), (b.x0, b.y1))
            ]
            labels.append(base + [v + n for v in base])
        return list(points), labels

    def block_mesh_dict(self) -> dict:
        """The entries of ``system/blockMeshDict`` (lengths in um, scale 1e-6)."""
        points, labels = self.vertices()
        vertices = [f"({x:.9g} {y:.9g} 0)" for x, y in points]
        vertices += [f"({x:.9g} {y:.9g} {self.dx:.9g})" for x, y in points]
        blocks = [
            f"hex ({' '.join(map(str, lab))}) ({b.nx} {b.ny} 1) simpleGrading (1 1 1)"
            for b, lab in zip(self.blocks, labels, strict=True)
        ]

        def face(i: int, side: str) -> str:
            return "(" + " ".join(str(labels[i][k]) for k in _SIDES[side]) + ")"

        named = {(ib.block, ib.side): name for name, ib in self.inlets.items()}
        named[self.outlet] = self.outlet_name
        walls = [face(i, s) for i, s in self.exterior_sides() if (i, s) not in named]
        boundary = {
            name: {"type": "patch", "faces": [face(ib.block, ib.side)]}
            for name, ib in self.inlets.items()
        }
        boundary[self.outlet_name] = {"type": "patch", "faces": [face(*self.outlet)]}
        boundary["walls"] = {"type": "wall", "faces": walls}
        front = ["(" + " ".join(str(lab[k]) for k in (0, 3, 2, 1)) + ")" for lab in labels] + [
            "(" + " ".join(str(lab[k]) for k in (4, 5, 6, 7)) + ")" for lab in labels
        ]
        boundary["frontAndBack"] = {"type": "empty", "faces": front}
        return block_mesh_dict(vertices, blocks, boundary)

    def inlet_velocity(self, name: str) -> np.ndarray:
        """(n_faces, 3) plane-Poiseuille velocity (um/s) on inlet ``name``: 1.5 U (1 - s^2)."""
        inlet = self.inlets[name]
        b = self.blocks[inlet.block]
        _, start, end = b.side_span(inlet.side)
        s = (self.side_face_centres(inlet.block, inlet.side) - 0.5 * (start + end)) / (
            0.5 * (end - start)
        )
        speed = 1.5 * inlet.velocity * (1.0 - s**2)
        normal = {"xmin": (1, 0), "xmax": (-1, 0), "ymin": (0, 1), "ymax": (0, -1)}[inlet.side]
        return np.column_stack([speed * normal[0], speed * normal[1], 0.0 * speed])


def block_mesh_dict(vertices: list[str], blocks: list[str], boundary: dict[str, dict]) -> dict:
    """The entries of ``system/blockMeshDict`` (coordinates in um, ``scale`` to m) from the
    vertex and block lines and the patches (name -> type and face lines)."""
    return {
        "scale": 1e-6,
        "vertices": "(\n" + "\n".join(vertices) + "\n)",
        "blocks": "(\n" + "\n".join(blocks) + "\n)",
        "edges": "()",
        "boundary": "(\n" + "\n".join(_patch(k, v) for k, v in boundary.items()) + "\n)",
        "mergePatchPairs": "()",
    }


def _patch(name: str, spec: dict) -> str:
    faces = "\n            ".join(spec["faces"])
    return (
        f"    {name}\n    {{\n        type {spec['type']};\n"
        f"        faces\n        (\n            {faces}\n        );\n    }}"
    )


def _cells(length: float, dx: float, what: str) -> int:
    n = length / dx
    if abs(n - round(n)) > 1e-6 or round(n) < 1:
        raise InputError("geometry", what, f"a length that is a multiple of dx = {dx:g} um", length)
    return round(n)


@dataclass(frozen=True)
class JunctionGeometry:
    """Fig. 6 of seed 001 as read here (module docstring); all lengths um."""

    channel_width: float = 250.0
    branch_width: float = 250.0
    upstream_length: float = 875.0
    downstream_length: float = 1125.0
    branch_length: float = 500.0
    cell_diameter: float = 140.0
    cytoplasm_diameter: float = 110.0
    cell_offset: float = 500.0

    def layout(self, dx: float, velocity_a: float, velocity_b: float) -> Layout:
        """The T-junction: upstream arm, junction square, downstream arm, branch B on +y."""
        h, hb = 0.5 * self.channel_width, 0.5 * self.branch_width
        if self.cell_offset + 0.5 * self.cell_diameter + 2 * dx > self.upstream_length:
            raise InputError("geometry", "cell_offset", "the cell inside the upstream arm")
        arms = [
            (-self.upstream_length, -hb, -h, h),
            (-hb, hb, -h, h),
            (hb, self.downstream_length, -h, h),
            (-hb, hb, h, h + self.branch_length),
        ]
        blocks = [
            Block(x0, x1, y0, y1, _cells(x1 - x0, dx, "length"), _cells(y1 - y0, dx, "width"))
            for x0, x1, y0, y1 in arms
        ]
        inlets = {
            "inletA": Inlet(0, "xmin", velocity_a, "medium"),
            "inletB": Inlet(3, "ymax", velocity_b, "medium"),
        }
        return Layout(dx, blocks, inlets, (2, "xmax"), "outletC")

    @property
    def cell_centre(self) -> tuple[float, float]:
        return (-self.cell_offset, 0.0)


def slit_layout(length: float, half_height: float, dx: float, velocity: float) -> Layout:
    """A straight planar slit ``[0, length] x [-h, h]`` (um), inlet at x = 0, outlet at x = L."""
    block = Block(
        0.0,
        length,
        -half_height,
        half_height,
        _cells(length, dx, "length"),
        _cells(2 * half_height, dx, "height"),
    )
    return Layout(dx, [block], {"inlet": Inlet(0, "xmin", velocity, "medium")}, (0, "xmax"))


def disk_fraction(
    centres: np.ndarray, dx: float, centre: tuple[float, float], radius: float, samples: int = 8
) -> np.ndarray:
    """Fraction of each square cell (side dx, um) inside a disk, by ``samples``^2 sub-cell
    points (midpoint rule; error ~ the boundary cells' share / samples^2)."""
    out = np.zeros(len(centres))
    d = np.hypot(centres[:, 0] - centre[0], centres[:, 1] - centre[1])
    inside = d <= radius - dx
    out[inside] = 1.0
    edge = np.abs(d - radius) < dx
    offsets = (np.arange(samples) + 0.5) / samples - 0.5
    ox, oy = np.meshgrid(offsets * dx, offsets * dx)
    px = centres[edge, 0][:, None] + ox.ravel()[None, :]
    py = centres[edge, 1][:, None] + oy.ravel()[None, :]
    out[edge] = np.mean(np.hypot(px - centre[0], py - centre[1]) <= radius, axis=1)
    return out


def polygon_fraction(
    centres: np.ndarray, dx: float, polygon: np.ndarray, samples: int = 8
) -> np.ndarray:
    """Fraction of each square cell (side dx, um) inside a closed ``polygon`` ((k, 2), um;
    e.g. a deformed cell's outline), by ``samples``^2 sub-cell points (midpoint rule), like
    :func:`disk_fraction`; cells farther than one cell from the polygon's box are 0."""
    from matplotlib.path import Path as PolygonPath

    poly = np.asarray(polygon, dtype=float)
    if poly.ndim != 2 or poly.shape[1] != 2 or len(poly) < 3:
        raise InputError("polygon_fraction", "polygon", "(k >= 3, 2) points", poly.shape)
    out = np.zeros(len(centres))
    lo, hi = poly.min(axis=0) - dx, poly.max(axis=0) + dx
    near = np.all((centres >= lo) & (centres <= hi), axis=1)
    offsets = (np.arange(samples) + 0.5) / samples - 0.5
    ox, oy = np.meshgrid(offsets * dx, offsets * dx)
    px = centres[near, 0][:, None] + ox.ravel()[None, :]
    py = centres[near, 1][:, None] + oy.ravel()[None, :]
    inside = PolygonPath(poly).contains_points(np.column_stack([px.ravel(), py.ravel()]))
    out[near] = inside.reshape(px.shape).mean(axis=1)
    return out
