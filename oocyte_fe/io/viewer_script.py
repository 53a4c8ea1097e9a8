"""A pyvista script written next to a field series that opens it as the report's figures
show it: the section in its current configuration (reference points + ``displacement_um``),
coloured by the displacement magnitude (um), element edges grey, the rigid obstacles as black
polylines, mirrored about the axis r = 0 for an axisymmetric half-section, cut to the same
window as the report's figure where that shows only a part (the Hertz contact zone).

The script needs only pyvista (``python view_<name>.py`` opens a window at the last step;
``--time T`` picks the step nearest to T s; ``--screenshot out.png`` renders off-screen to a
file instead). It reads the ``.pvd`` files beside it, so the folder can be moved.
"""

from __future__ import annotations

from pathlib import Path

TEMPLATE = '''"""Open the {name} series as the report shows it (written by oocyte-fe).

python {script}                       # a window at the last step
python {script} --time 0.5            # the step nearest to 0.5 s
python {script} --screenshot out.png  # off-screen, to a PNG
"""

import argparse
from pathlib import Path

import numpy as np
import pyvista as pv

HERE = Path(__file__).resolve().parent
FIELDS = "{name}.pvd"
OBSTACLES = {obstacles!r}
MIRROR = {mirror!r}  # axisymmetric half-section: draw its reflection about r = 0 too
WINDOW = {window!r}  # (x_min, x_max, y_min, y_max) um shown, as in the report; None: all


def at_time(pvd, time_s):
    """The dataset of ``pvd`` at the step nearest to ``time_s`` (the last if None)."""
    reader = pv.get_reader(str(HERE / pvd))
    times = reader.time_values
    pick = times[-1] if time_s is None else min(times, key=lambda t: abs(t - time_s))
    reader.set_active_time_value(pick)
    return reader.read()[0], pick


def pieces(mesh):
    """``mesh`` and, for a half-section, its mirror image about x = 0; cut to WINDOW."""
    found = [mesh] + ([mesh.reflect((1.0, 0.0, 0.0), point=(0.0, 0.0, 0.0))] if MIRROR else [])
    if WINDOW is not None:
        found = [p.clip_box((*WINDOW, -1.0, 1.0), invert=False) for p in found]
    return [p for p in found if p.n_cells]


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--time", type=float, default=None, help="time in s (default: last)")
    parser.add_argument("--screenshot", default=None, help="write this PNG off-screen")
    args = parser.parse_args()

    grid, t = at_time(FIELDS, args.time)
    grid = grid.cast_to_unstructured_grid()
    grid.point_data["|u| (um)"] = np.linalg.norm(grid.point_data["displacement_um"], axis=1)
    current = grid.warp_by_vector("displacement_um", factor=1.0)
    plotter = pv.Plotter(off_screen=args.screenshot is not None, window_size=(1200, 900))
    plotter.set_background("white")
    shown = pieces(current)
    top = max(float(p.point_data["|u| (um)"].max()) for p in shown)
    for piece in shown:
        plotter.add_mesh(
            piece,
            scalars="|u| (um)",
            clim=(0.0, max(top, 1e-12)),
            cmap="viridis",
            show_edges=True,
            edge_color="gray",
            scalar_bar_args={{
                "title": "displacement (um)",
                "color": "black",
                "vertical": True,
                "position_x": 0.8,
                "fmt": "%.3g",
                "title_font_size": 14,
                "label_font_size": 12,
            }},
        )
    for pvd in OBSTACLES:
        wall, _ = at_time(pvd, t)
        for piece in pieces(wall):
            plotter.add_mesh(piece, color="black", line_width=3)
    plotter.add_text(f"{name}, t = {{t:.3g}} s", position="upper_left", font_size=12, color="black")
    plotter.view_xy()
    plotter.enable_parallel_projection()
    if WINDOW is not None:
        plotter.reset_camera(bounds=(*WINDOW, 0.0, 0.0))
    plotter.camera.zoom(0.8)  # room for the colour bar
    if args.screenshot:
        plotter.screenshot(args.screenshot)
        plotter.close()
    else:
        plotter.show()


if __name__ == "__main__":
    main()
'''


def write_viewer_script(
    folder: Path,
    name: str,
    obstacles: list[str],
    mirror: bool,
    window: tuple[float, float, float, float] | None = None,
) -> Path:
    """Write ``folder/view_<name>.py`` for the series ``<name>.pvd`` and the obstacle series
    ``obstacles`` (``.pvd`` file names in ``folder``), showing only ``window`` (um, in the
    drawn plane) when given; return its path."""
    script = f"view_{name}.py"
    path = Path(folder) / script
    box = None if window is None else tuple(float(v) for v in window)
    text = TEMPLATE.format(name=name, script=script, obstacles=obstacles, mirror=mirror, window=box)
    path.write_text(text)
    return path
