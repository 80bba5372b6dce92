"""The machine moving, drawn with matplotlib: one frame (:func:`plot_machine_frame`)
or a GIF over the cycle (:func:`animate_machine`), from the scenes of
:func:`cyclomech.machine._animation.machine_scenes` — the same data the report's
player draws. Part of :mod:`cyclomech.machine.plot`.
"""

from __future__ import annotations

import math
import os
from pathlib import Path
from typing import TYPE_CHECKING, Any, cast

import numpy as np

from .._arrays import finite_number, instance
from .._errors import InputError
from .._files import whole
from .._plotting import LINK_COLOR, PLATE_COLOR, pyplot
from .._scene import Scene
from ..cyclogram.plot import plot_cyclogram
from ._animation import FRAMES, frame_angles, scenes_at
from ._result import MachineResult

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

__all__ = ["animate_machine", "plot_machine_frame"]

#: Drawings per row of the figure.
_PER_ROW = 3


class _Painter:
    """A scene's artists on one axes [mm], made once and moved to each frame."""

    def __init__(self, ax: Axes, scene: Scene) -> None:
        from matplotlib.patches import Polygon

        self.scene = scene
        x0, x1, y0, y1 = (1e3 * v for v in scene.box())
        ax.set_xlim(x0, x1)
        ax.set_ylim(y0, y1)
        ax.set_aspect("equal")
        ax.set_title(scene.name, fontsize=10)
        ax.tick_params(labelsize=7)
        ax.set_xlabel("x [mm]", fontsize=8)
        for p in scene.traces:
            xy = 1e3 * scene.points[p]
            ax.plot(xy[:, 0], xy[:, 1], color="#6aa5d8", lw=0.9, gid=f"trace:{p}", zorder=1)
        self.bodies: list[tuple[Any, Any, Any]] = []  # (body, its patch or None, its line or None)
        for name, b in scene.bodies.items():
            if b.fill:
                patch = Polygon(
                    np.zeros((max(len(b.outline), 1), 2)),
                    closed=b.closed,
                    facecolor="#dfe5ec",
                    edgecolor="#4a4a4a",
                    lw=1.0,
                    gid=f"body:{name}",
                    zorder=2,
                )
                ax.add_patch(patch)
                self.bodies.append((b, patch, None))
            else:
                (line,) = ax.plot([], [], color="#4a4a4a", lw=1.0, gid=f"body:{name}", zorder=2)
                self.bodies.append((b, None, line))
        self.plates: list[Any] = [
            ax.add_patch(Polygon(np.zeros((len(ln), 2)), facecolor=PLATE_COLOR, zorder=2.5))
            for ln in scene.links
            if len(ln) > 2
        ]
        self.links = [
            ax.plot([], [], color=LINK_COLOR, lw=2.2, solid_capstyle="round", zorder=3)[0]
            for _ in scene.links
        ]
        (self.ground,) = ax.plot([], [], "^", color="white", mec="0.2", ms=9, zorder=3.5)
        (self.joints,) = ax.plot([], [], "o", color="white", mec=LINK_COLOR, ms=4.5, zorder=4)

    def artists(self) -> list[Any]:
        """The artists that move (the traces stand still)."""
        bodies = [patch if patch is not None else line for _, patch, line in self.bodies]
        return [*bodies, *self.plates, *self.links, self.ground, self.joints]

    def show(self, i: int) -> None:
        """Move every artist to frame ``i``."""
        s = self.scene
        for b, patch, line in self.bodies:
            xy = 1e3 * b.at(i)
            if b.closed and line is not None:
                xy = np.vstack([xy, xy[:1]])
            if patch is not None:
                patch.set_xy(xy)
            else:
                line.set_data(xy[:, 0], xy[:, 1])
        at = {p: 1e3 * v[i] for p, v in s.points.items()}
        plates = iter(self.plates)
        for ln, art in zip(s.links, self.links, strict=True):
            xy = np.array([at[p] for p in ln])
            if len(ln) > 2:
                next(plates).set_xy(xy)
                xy = np.vstack([xy, xy[:1]])
            art.set_data(xy[:, 0], xy[:, 1])
        g = np.array([at[p] for p in s.ground]).reshape(-1, 2)
        self.ground.set_data(g[:, 0], g[:, 1])
        j = np.array(list(at.values())).reshape(-1, 2)
        self.joints.set_data(j[:, 0], j[:, 1])


def _figure(result: MachineResult, theta: Any) -> tuple[Figure, list[_Painter], Any]:
    """The figure of the frames at the main shaft's angles ``theta`` [deg]: a
    drawing per mechanism, the cyclogram with its cursor below; (figure, painters,
    cursor line)."""
    plt = pyplot()
    scenes = scenes_at(result, theta)
    if not scenes:
        raise InputError(
            f"machine {result.machine.name!r}: none of its mechanisms can be drawn moving "
            + (
                "(the cyclogram does not fit at the nominal speed: no timing)"
                if result.optimum is None
                else "(no mechanism kind with a drawing)"
            )
        )
    cols = min(len(scenes), _PER_ROW)
    rows = math.ceil(len(scenes) / cols)
    timeline = result.optimum is not None
    fig = plt.figure(figsize=(max(3.6 * cols + 0.6, 8.0), 3.4 * rows + (2.4 if timeline else 0.3)))
    grid = fig.add_gridspec(
        rows + int(timeline), cols, height_ratios=[3.4] * rows + [2.0] * timeline
    )
    painters = [
        _Painter(fig.add_subplot(grid[k // cols, k % cols]), s)
        for k, s in enumerate(scenes.values())
    ]
    cursor = None
    if timeline:
        assert result.optimum is not None
        ax = fig.add_subplot(grid[rows, :])
        plot_cyclogram(result.optimum, ax, title="main shaft at θ = 0°")
        legend = ax.get_legend()
        if legend is not None:
            legend.remove()
        cursor = ax.axvline(0.0, color="#d62728", lw=2.0, gid="cursor")
    fig.set_layout_engine("constrained")
    return fig, painters, cursor


def _show(painters: list[_Painter], cursor: Any, theta: Any, i: int, fig: Any) -> None:
    for p in painters:
        p.show(i)
    if cursor is not None:
        cursor.set_xdata([theta[i], theta[i]])
    _label(fig, cursor).set_text(f"main shaft at θ = {theta[i]:.1f}°")


def _label(fig: Any, cursor: Any) -> Any:
    """The text that says the angle: the cyclogram's title, or the figure's without
    a cyclogram."""
    if cursor is not None:
        return cursor.axes.title
    return fig._suptitle if fig._suptitle is not None else fig.suptitle("", fontsize=11)


def plot_machine_frame(result: MachineResult, cycle_deg: float = 0.0) -> Figure:
    """The machine at one main-shaft angle: every drawable mechanism at its own phase
    (as the report's animation draws it) and the optimised cyclogram with a cursor.

    Parameters
    ----------
    result : MachineResult
        What :func:`~cyclomech.machine.analyze` computed.
    cycle_deg : float, default 0.0
        The main shaft's angle [deg], in [0, cycle).

    Returns
    -------
    matplotlib.figure.Figure
        A new figure; lengths in mm.

    Raises
    ------
    InputError
        If ``cycle_deg`` is outside the cycle, or no mechanism can be drawn.

    Examples
    --------
    >>> import matplotlib
    >>> matplotlib.use("Agg")
    >>> import matplotlib.pyplot as plt, cyclomech as cm
    >>> from cyclomech.machine.plot import plot_machine_frame
    >>> r = cm.machine.analyze(cm.Machine.from_toml("examples/knife_cutter.toml"), progress=False)
    >>> fig = plot_machine_frame(r, 90.0)
    >>> [ax.get_title() for ax in fig.axes]
    ['knife', 'main shaft at θ = 90.0°']
    >>> plt.close(fig)
    """
    instance("result", result, MachineResult)
    cycle = float(result.machine.cyclogram.cycle_deg)
    at = finite_number("cycle_deg", cycle_deg, "[deg]", low=0.0)
    if at >= cycle:
        raise InputError(f"cycle_deg = {cycle_deg!r} must be in [0, {cycle:g}) [deg]")
    # Solved on the report's frames and at θ: the drawing's extent and the traces
    # are the whole cycle's, the pose θ's.
    theta = np.append(frame_angles(result, FRAMES), at)
    fig, painters, cursor = _figure(result, theta)
    _show(painters, cursor, theta, theta.size - 1, fig)
    return cast("Figure", fig)


def animate_machine(
    result: MachineResult,
    path: str | os.PathLike[str],
    *,
    frames: int = 90,
    fps: float = 20,
    dpi: float = 72,
) -> Path:
    """Write the machine moving over one cycle as an animated GIF; return its path.

    The frames of :func:`plot_machine_frame` at ``frames`` main-shaft angles
    k·cycle/``frames``: drawn by matplotlib with blitting (the still parts once),
    written by Pillow.

    Parameters
    ----------
    result : MachineResult
        What :func:`~cyclomech.machine.analyze` computed.
    path : str or os.PathLike
        The file to write; it must end in ``.gif``.
    frames : int, default 90
        Frames over the cycle (≥ 2).
    fps : float, default 20
        Frames per second [1/s].
    dpi : float, default 72
        Resolution [dots per inch].

    Returns
    -------
    pathlib.Path
        The GIF written.

    Raises
    ------
    InputError
        If ``path`` does not end in ``.gif``, ``frames``, ``fps`` or ``dpi`` is not
        valid, or no mechanism can be drawn.

    Examples
    --------
    >>> import matplotlib
    >>> matplotlib.use("Agg")
    >>> import pathlib, tempfile, cyclomech as cm
    >>> from PIL import Image
    >>> from cyclomech.machine.plot import animate_machine
    >>> r = cm.machine.analyze(cm.Machine.from_toml("examples/knife_cutter.toml"), progress=False)
    >>> gif = animate_machine(r, pathlib.Path(tempfile.mkdtemp()) / "m.gif", frames=6, dpi=30)
    >>> with Image.open(gif) as im:
    ...     im.n_frames
    6
    """
    plt = pyplot()
    from PIL import Image

    instance("result", result, MachineResult)
    if not isinstance(path, str | os.PathLike):
        raise InputError(f"path must be a file name ending in .gif; got {path!r}")
    out = Path(path)
    if out.suffix.lower() != ".gif":
        raise InputError(f"path = {str(out)!r} must end in .gif (an animated GIF is written)")
    rate = finite_number("fps", fps, "[1/s]", low=0.0, strict=True)
    res = finite_number("dpi", dpi, "[dots per inch]", low=0.0, strict=True)
    theta = frame_angles(result, frames)
    fig, painters, cursor = _figure(result, theta)
    try:
        fig.set_dpi(res)
        _show(painters, cursor, theta, 0, fig)
        # The layout once; then matplotlib's blitting: the still parts (axes, ticks,
        # the cyclogram, the traces) drawn once, each frame only the moving artists.
        fig.canvas.draw()
        fig.set_layout_engine("none")
        moving = [a for p in painters for a in p.artists()]
        moving += [_label(fig, cursor)] + ([] if cursor is None else [cursor])
        for a in moving:
            a.set_animated(True)
        canvas: Any = fig.canvas  # the Agg canvas: copy_from_bbox, buffer_rgba
        canvas.draw()
        still = canvas.copy_from_bbox(fig.bbox)
        images = []
        for i in range(theta.size):
            canvas.restore_region(still)
            _show(painters, cursor, theta, i, fig)
            for a in moving:
                fig.draw_artist(a)
            w, h = canvas.get_width_height()
            rgba = Image.frombuffer(
                "RGBA", (w, h), bytes(canvas.buffer_rgba()), "raw", "RGBA", 0, 1
            )
            images.append(rgba.convert("RGB"))
        with whole(out) as tmp:
            images[0].save(
                tmp,
                format="GIF",
                save_all=True,
                append_images=images[1:],
                duration=round(1000.0 / rate),
                loop=0,
            )
    finally:
        plt.close(fig)
    return out
