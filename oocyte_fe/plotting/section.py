"""PNG of a deformed 2D section coloured by the displacement magnitude (pyvista, off-screen).

The section is drawn in the current configuration ``x + scale * u`` (um). An axisymmetric
half-section (x = r >= 0) can be mirrored about the axis x = 0 for display. Rigid obstacles
(pipette walls, plates, indenter profiles) are drawn as polylines given by their points in
the same plane, in um. Quadratic triangles are split into four linear ones for drawing.
``window`` = (x_min, x_max, y_min, y_max) um, in the drawn (mirrored) plane, cuts the
drawing to that rectangle and fits the view to it (a contact zone that is a
small part of a large mesh). Titles and the colour-bar label print the unit as "µm" (VTK's
text renderer has no mathtext; "|u|" would draw its bars as a raised "u", so the title
should say "displacement magnitude"). No display is needed: rendering is off-screen.
"""

from __future__ import annotations

import re
from collections.abc import Sequence
from pathlib import Path

import numpy as np
import pyvista as pv
import skfem

from oocyte_fe.mesh.nodal import nodal_values

pv.OFF_SCREEN = True

# corner/mid-edge node indices of the four linear triangles in one 6-node triangle
_P2_SPLIT = np.array([[0, 3, 5], [3, 1, 4], [5, 4, 2], [3, 4, 5]])


def _triangles(mesh: skfem.Mesh) -> np.ndarray:
    """Linear triangles (node indices into ``mesh.doflocs``), shape (n, 3)."""
    nodes = mesh.dofs.element_dofs.T  # (n_elements, 3 or 6), VTK node order
    if nodes.shape[1] == 3:
        return nodes
    return nodes[:, _P2_SPLIT].reshape(-1, 3)


SCALARS = "displacement (µm)"

Window = tuple[float, float, float, float]


def _clip(item: pv.DataSet, window: Window | None) -> pv.DataSet:
    """``item`` cut to the rectangle ``window`` (um), or unchanged if None."""
    if window is None:
        return item
    return item.clip_box((*window, -1.0, 1.0), invert=False)


def _surface(points_xy: np.ndarray, triangles: np.ndarray, scalars: np.ndarray) -> pv.PolyData:
    points = np.column_stack([points_xy, np.zeros(len(points_xy))])
    faces = np.column_stack([np.full(len(triangles), 3), triangles]).ravel()
    surface = pv.PolyData(points, faces)
    surface.point_data[SCALARS] = scalars
    return surface


def _edges(points_xy: np.ndarray, mesh: skfem.Mesh) -> pv.PolyData:
    """The element edges as line segments (through the mid-edge node of quadratic meshes)."""
    ends = mesh.facets.T
    if mesh.doflocs.shape[1] > mesh.nvertices:
        mids = mesh.dofs.facet_dofs[0]
        ends = np.vstack([np.column_stack([ends[:, 0], mids]), np.column_stack([mids, ends[:, 1]])])
    points = np.column_stack([points_xy, np.zeros(len(points_xy))])
    return pv.PolyData(points, lines=np.column_stack([np.full(len(ends), 2), ends]).ravel())


def _polyline(points_xy: np.ndarray) -> pv.PolyData:
    pts = np.asarray(points_xy, dtype=float)
    if pts.ndim != 2 or pts.shape[1] != 2 or len(pts) < 2:
        raise ValueError(f"plot_section: obstacle: expected an (m >= 2, 2) array, got {pts.shape}")
    return pv.lines_from_points(np.column_stack([pts, np.zeros(len(pts))]))


def _bounds(items: Sequence[pv.PolyData]) -> tuple[float, float, float, float]:
    """x and y limits (um) of everything drawn."""
    b = np.array([item.bounds[:4] for item in items])
    return b[:, 0].min(), b[:, 1].max(), b[:, 2].min(), b[:, 3].max()


def plot_section(
    path: str | Path,
    mesh: skfem.Mesh,
    displacement: np.ndarray | None = None,
    *,
    scale: float = 1.0,
    mirror: bool = False,
    obstacles: Sequence[np.ndarray] = (),
    show_edges: bool = True,
    title: str | None = None,
    window: Window | None = None,
    window_size: tuple[int, int] = (1200, 900),
) -> Path:
    """Write a PNG of ``mesh`` deformed by ``scale * displacement`` (um, nodal, 2
    components), coloured by ``|u|``; ``mirror`` adds the reflection about x = 0 (for an
    axisymmetric half-section, also applied to the obstacles); ``window`` (um) draws only
    that part of the section. Returns ``path``."""
    path = Path(path)
    xy = mesh.doflocs.T
    u = (
        np.zeros_like(xy)
        if displacement is None
        else nodal_values(mesh, displacement, 2, "plot_section: displacement")
    )
    magnitude = np.linalg.norm(u, axis=1)
    current = xy + scale * u
    tri = _triangles(mesh)
    flips = [np.array([1.0, 1.0])] + ([np.array([-1.0, 1.0])] if mirror else [])
    pieces = [_clip(_surface(current * flip, tri, magnitude), window) for flip in flips]
    if any(p.n_cells == 0 for p in pieces):
        raise ValueError(f"plot_section: no element inside the window {window} um")
    edges = [_clip(_edges(current * flip, mesh), window) for flip in flips] if show_edges else []
    lines = [
        _clip(_polyline(np.asarray(o, dtype=float) * flip), window)
        for flip in flips
        for o in obstacles
    ]
    lines = [line for line in lines if line.n_cells]

    plotter = pv.Plotter(off_screen=True, window_size=list(window_size))
    try:
        plotter.set_background("white")
        bar = {
            "title": SCALARS,
            "color": "black",
            "vertical": True,
            "fmt": "%.3g",
            "position_x": 0.8,
            "title_font_size": 14,
            "label_font_size": 12,
        }
        shown = max(float(np.max(p.point_data[SCALARS])) for p in pieces)
        limits = [0.0, max(shown, 1e-12)]
        for piece in pieces:
            plotter.add_mesh(
                piece,
                scalars=SCALARS,
                cmap="viridis",
                clim=limits,
                scalar_bar_args=bar,
            )
        for edge in edges:
            plotter.add_mesh(edge, color="gray", line_width=0.5)
        for line in lines:
            plotter.add_mesh(line, color="black", line_width=3)
        if title:
            text = re.sub(r"\bum\b", "µm", title)
            plotter.add_text(text, position="upper_edge", font_size=12, color="black")
        plotter.view_xy()
        plotter.enable_parallel_projection()
        plotter.reset_camera()
        # fit the drawing into the left 75 % of the window, the colour bar on the right
        xmin, xmax, ymin, ymax = window if window is not None else _bounds(pieces + lines)
        aspect = window_size[0] / window_size[1]
        half_height = 0.55 * max(ymax - ymin, (xmax - xmin) / (0.75 * aspect))
        shift = 0.2 * half_height * aspect  # drawing centred at 40 % of the width
        focus = np.array([0.5 * (xmin + xmax) + shift, 0.5 * (ymin + ymax), 0.0])
        camera = plotter.camera
        camera.position = tuple(focus + np.array([0.0, 0.0, 10.0 * half_height]))
        camera.focal_point = tuple(focus)
        camera.parallel_scale = half_height
        path.parent.mkdir(parents=True, exist_ok=True)
        plotter.screenshot(str(path))
    finally:
        plotter.close()
    return path
