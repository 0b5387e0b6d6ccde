"""Pictures of a knit (matplotlib, imported by the caller)."""
from __future__ import annotations

from .geometry import yarn_points

__all__ = ["draw_front"]


def draw_front(ax, world, fabric, *, title=None, depth: float = 0.6e-3, point_size: float = 1.5):
    """Front view of the yarn now (mm): its centreline, coloured by depth z
    (red towards the technical face, blue away; the colour scale spans
    ±``depth`` m), on a matplotlib ``ax``."""
    for p in yarn_points(world, fabric):
        ax.scatter(p[:, 0] * 1e3, p[:, 1] * 1e3, c=p[:, 2] * 1e3, s=point_size, cmap="coolwarm",
                   vmin=-depth * 1e3, vmax=depth * 1e3)
        ax.plot(p[:, 0] * 1e3, p[:, 1] * 1e3, color="0.3", lw=0.3)
    ax.set_aspect("equal")
    ax.set_xlabel("x along the course [mm]")
    ax.set_ylabel("y along the wale [mm]")
    if title:
        ax.set_title(title)
    return ax
