"""A 3-D version of a planar layout: the blocks extruded over a channel depth, for timing runs.

Each block of :class:`.geometry.Layout` becomes ``nx x ny x nz`` cubic cells over
``-depth/2 < z < depth/2`` (``nz = depth/dx``); the front and back faces become no-slip walls, so
the planar channel of width w becomes a rectangular duct w x depth. Cells are numbered as
blockMesh numbers them (block by block, x fastest, then y, then z). The cell and its cytoplasm
are spheres (:func:`sphere_fraction`), the inlets carry the product-parabola duct profile
``u = (9/4) U (1 - s^2)(1 - t^2)`` (mean U; s, t across the width and the depth; an
approximation of the exact duct series, good enough for timing), set on the face centres that
OpenFOAM's ``writeCellCentres`` reports, so no face order is assumed. The medium and the cell
start at rest (the first pressure solve starts the flow).
"""

from __future__ import annotations

import re
from dataclasses import replace
from pathlib import Path

import numpy as np

from oocyte_fe.microchannel.vof.casewriter import UM, VofSetup, write_case
from oocyte_fe.microchannel.vof.foamfile import field_values, read_internal_field, write_dictionary
from oocyte_fe.microchannel.vof.geometry import _SIDES, Layout, _cells, block_mesh_dict
from oocyte_fe.microchannel.vof.runner import OpenFoam, run_utility

_Z_SIDES = {"zmin": (0, 3, 2, 1), "zmax": (4, 5, 6, 7)}


def extruded_mesh_dict(layout: Layout, depth: float) -> dict:
    """``blockMeshDict`` entries of the layout extruded over ``depth`` (um)."""
    nz = _cells(depth, layout.dx, "depth")
    points, labels = layout.vertices()
    vertices = [f"({x:.9g} {y:.9g} {-0.5 * depth:.9g})" for x, y in points]
    vertices += [f"({x:.9g} {y:.9g} {0.5 * depth:.9g})" for x, y in points]
    blocks = [
        f"hex ({' '.join(map(str, lab))}) ({b.nx} {b.ny} {nz}) simpleGrading (1 1 1)"
        for b, lab in zip(layout.blocks, labels, strict=True)
    ]

    def face(i: int, corners: tuple[int, ...]) -> str:
        return "(" + " ".join(str(labels[i][k]) for k in corners) + ")"

    named = {(ib.block, ib.side): name for name, ib in layout.inlets.items()}
    named[layout.outlet] = layout.outlet_name
    boundary = {
        name: {"type": "patch", "faces": [face(ib.block, _SIDES[ib.side])]}
        for name, ib in layout.inlets.items()
    }
    boundary[layout.outlet_name] = {"type": "patch", "faces": [face(*_outlet(layout))]}
    walls = [face(i, _SIDES[s]) for i, s in layout.exterior_sides() if (i, s) not in named]
    walls += [face(i, c) for i in range(len(layout.blocks)) for c in _Z_SIDES.values()]
    boundary["walls"] = {"type": "wall", "faces": walls}
    return block_mesh_dict(vertices, blocks, boundary)


def _outlet(layout: Layout) -> tuple[int, tuple[int, ...]]:
    block, side = layout.outlet
    return block, _SIDES[side]


def extruded_centres(layout: Layout, depth: float) -> np.ndarray:
    """(n, 3) cell centres (um) in blockMesh order."""
    nz = _cells(depth, layout.dx, "depth")
    z = -0.5 * depth + (np.arange(nz) + 0.5) * layout.dx
    planar = layout.cell_centres()
    parts, start = [], 0
    for b in layout.blocks:
        stop = start + b.nx * b.ny
        xy = planar[start:stop]
        parts.append(np.column_stack([np.tile(xy, (nz, 1)), np.repeat(z, len(xy))]))
        start = stop
    return np.vstack(parts)


def sphere_fraction(
    centres: np.ndarray, dx: float, centre: tuple[float, float, float], radius: float
) -> np.ndarray:
    """Fraction of each cube (side dx, um) inside a sphere, 4^3 sub-points per edge cell."""
    d = np.linalg.norm(centres - np.asarray(centre), axis=1)
    out = (d <= radius - dx).astype(float)
    edge = np.abs(d - radius) < dx
    o = (np.arange(4) + 0.5) / 4 - 0.5
    offsets = np.stack(np.meshgrid(o, o, o), axis=-1).reshape(-1, 3) * dx
    pts = centres[edge][:, None, :] + offsets[None, :, :]
    out[edge] = np.mean(np.linalg.norm(pts - np.asarray(centre), axis=2) <= radius, axis=1)
    return out


def write_extruded_case(setup: VofSetup, directory: Path, depth: float, ranks: int = 1) -> Path:
    """The planar case of ``setup`` written, then its mesh and fields replaced by the 3-D ones
    (spheres for the disks, the fluid at rest); :func:`set_inlet_profiles` after blockMesh."""
    planar = replace(setup, numerics=replace(setup.numerics, moments=()))  # 2-D moments only
    d = write_case(planar, directory, ranks)
    layout = setup.layout
    write_dictionary(d / "system" / "blockMeshDict", extruded_mesh_dict(layout, depth))
    centres = extruded_centres(layout, depth)
    names = [p.name for p in setup.phases]
    alpha = {n: np.zeros(len(centres)) for n in names}
    alpha[names[0]][:] = 1.0
    for disk in setup.disks:
        f = sphere_fraction(centres, layout.dx, (*disk.centre, 0.0), disk.radius)
        for n in alpha:
            alpha[n] *= 1.0 - f
        alpha[disk.phase] += f
    for name, values in alpha.items():
        _replace_field(d / "0" / f"alpha.{name}", values)
    _replace_field(d / "0" / "U", np.zeros((len(centres), 3)))
    for name in ("p_rgh", "alphas"):
        _replace_field(d / "0" / name, None)
    return d


def _replace_field(path: Path, values: np.ndarray | None) -> None:
    """Swap the internal field (when given) and remove the planar ``empty`` patch."""
    text = path.read_text()
    text = re.sub(r"\n\s*frontAndBack\s*\{[^}]*\}", "", text)
    if values is not None:
        start = text.index("internalField")
        end = text.index("\n);", start) + 3 if "nonuniform" in text[start : start + 40] else None
        end = end if end is not None else text.index(";", start) + 1
        text = text[:start] + f"internalField {field_values(values)};" + text[end:]
    path.write_text(text)


def set_inlet_profiles(foam: OpenFoam, case: Path, layout: Layout, depth: float) -> np.ndarray:
    """Write each inlet's duct profile on the face centres that ``writeCellCentres`` gives;
    return OpenFOAM's cell centres (um), to check against :func:`extruded_centres`."""
    run_utility(foam, case, ["postProcess", "-func", "writeCellCentres", "-time", "0"])
    c_text = (case / "0" / "C").read_text()
    centres = read_internal_field(case / "0" / "C") * 1e6
    u_path = case / "0" / "U"
    u_text = u_path.read_text()
    for name, inlet in layout.inlets.items():
        faces = _patch_values(c_text, name) * 1e6  # m -> um
        b = layout.blocks[inlet.block]
        _, lo, hi = b.side_span(inlet.side)
        across = faces[:, 1] if inlet.side.startswith("x") else faces[:, 0]
        s = (across - 0.5 * (lo + hi)) / (0.5 * (hi - lo))
        t = faces[:, 2] / (0.5 * depth)
        speed = 2.25 * inlet.velocity * (1 - s**2) * (1 - t**2) * UM
        normal = {"xmin": (1, 0), "xmax": (-1, 0), "ymin": (0, 1), "ymax": (0, -1)}[inlet.side]
        u = np.column_stack([speed * normal[0], speed * normal[1], 0 * speed])
        start = u_text.index(name, u_text.index("boundaryField"))
        v0 = u_text.index("value", start)
        v1 = u_text.index("\n);", v0) + 3
        u_text = u_text[:v0] + f"value {field_values(u)};" + u_text[v1:]
    u_path.write_text(u_text)
    for name in ("C", "Cx", "Cy", "Cz", "V"):
        (case / "0" / name).unlink(missing_ok=True)
    return centres


def _patch_values(text: str, patch: str) -> np.ndarray:
    start = text.index(patch, text.index("boundaryField"))
    m = re.compile(r"nonuniform\s+List<vector>\s*(\d+)\s*\(", re.S).search(text, start)
    if m is None:
        raise ValueError(f"no face centres for patch {patch}")
    body = text[m.end() : text.index("\n)", m.end())].replace("(", " ").replace(")", " ")
    return np.array(body.split(), dtype=float).reshape(int(m.group(1)), 3)
