"""Pictures with matplotlib (Agg canvas, no display needed).

- :func:`plot_world` draws rods as shaded 3-D tubes (the generalised-
  cylinder mesh of the core) and saves a PNG of exactly ``size`` pixels.
- :func:`plot_curves` plots recorded quantities against time (or any column).
"""
from __future__ import annotations

import os
from typing import Dict, Iterable, Sequence

import numpy as np

from . import _native
from ._files import file_error, temporary_for

__all__ = ["plot_world", "plot_curves"]

_VIEWS = {"xy": (90.0, -90.0), "xz": (0.0, -90.0), "yz": (0.0, 0.0), "iso": (25.0, -60.0)}


def _figure(size, dpi):
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    fig = Figure(figsize=(size[0] / dpi, size[1] / dpi), dpi=dpi)
    FigureCanvasAgg(fig)
    return fig


def _rods(scene) -> list:
    if isinstance(scene, _native.World):
        return scene.rods()
    if isinstance(scene, _native.Rod):
        return [scene]
    return list(scene)


def _save(fig, path):
    """Saves atomically (see ``_files.temporary_for``): no temporary is left on an error."""
    if path is not None:
        try:
            os.makedirs(os.path.dirname(os.path.abspath(path)), exist_ok=True)
        except OSError as e:
            raise file_error(path, e) from e
        fmt = os.path.splitext(path)[1][1:].lower() or "png"
        with temporary_for(path) as tmp:
            fig.savefig(tmp, dpi=fig.dpi, format=fmt)


def _shade(n, base, eye, up):
    """Lambert + a little Blinn–Phong on face normals ``n``; light from the viewer's upper left."""
    left = np.cross(up, eye)
    light = eye + 0.6 * up + 0.4 * left
    light /= np.linalg.norm(light)
    half = (light + eye) / np.linalg.norm(light + eye)
    n = n / np.maximum(np.linalg.norm(n, axis=1, keepdims=True), 1e-300)
    diffuse = np.clip(n @ light, 0.0, 1.0)
    spec = np.clip(n @ half, 0.0, 1.0) ** 24
    return np.clip(base[None, :] * (0.3 + 0.7 * diffuse)[:, None] + 0.35 * spec[:, None], 0.0, 1.0)


# Planar views: (in-plane axes, eye direction, screen-up direction).
_PLANES = {
    "xy": ((0, 1), (0.0, 0.0, 1.0), (0.0, 1.0, 0.0)),
    "xz": ((0, 2), (0.0, -1.0, 0.0), (0.0, 0.0, 1.0)),
    "yz": ((1, 2), (1.0, 0.0, 0.0), (0.0, 0.0, 1.0)),
}


def plot_world(scene, path: str | None = None, *, size: Sequence[int] = (800, 600), dpi: int = 100,
               view: str | None = None, elev: float | None = None, azim: float | None = None,
               colors: Iterable | None = None, rings_per_segment: int = 4, points_per_ring: int = 16,
               radius_scale: float = 1.0, min_radius: float = 0.006, title: str | None = None,
               show_axes: bool = True, overlay: Sequence | None = None, vertical_axis: str = "z"):
    """Draws a World, a Rod or a list of rods as shaded tubes; saves a PNG
    of ``size`` = (width, height) pixels to ``path`` if given; returns the
    matplotlib Figure.

    ``view``: "xy", "xz", "yz" (flat, orthographic, equal axes: for planar
    problems) or "iso" (3-D; or give ``elev``/``azim`` in degrees). Tubes
    have the section's bounding radius × ``radius_scale``, thickened to at
    least ``min_radius`` × the scene size so thin ropes stay visible.
    ``overlay``: list of (points (n, 3), matplotlib style dict) drawn as
    lines or markers, e.g. a reference curve. ``vertical_axis``: the data
    axis drawn upwards in 3-D views, "z" or "y" (scenes with y up).
    """
    if vertical_axis not in ("x", "y", "z"):
        raise ValueError(f"vertical_axis must be 'x', 'y' or 'z', got {vertical_axis!r}")
    from matplotlib import colormaps

    rods = _rods(scene)
    fig = _figure(size, dpi)
    plane = _PLANES.get(view or "")
    if plane is None:
        e0, a0 = _VIEWS.get(view or "iso", _VIEWS["iso"])
        elev = e0 if elev is None else elev
        azim = a0 if azim is None else azim
        el, az = np.radians(elev), np.radians(azim)
        eye = np.array([np.cos(el) * np.cos(az), np.cos(el) * np.sin(az), np.sin(el)])
        # Matplotlib rolls the data axes so that `vertical_axis` is up.
        shift = {"z": 0, "y": 2, "x": 1}[vertical_axis]
        eye = np.roll(eye, -shift)
        vert = np.roll(np.array([0.0, 0.0, 1.0]), -shift)
        up = vert if abs(eye @ vert) < 0.99 else np.roll(np.array([0.0, 1.0, 0.0]), -shift)
        up = up - eye * eye.dot(up)
        up /= np.linalg.norm(up)
    else:
        eye, up = np.array(plane[1]), np.array(plane[2])
    overlay = list(overlay or [])
    faces_all, colors_all, normals_all = [], [], []
    if rods:
        pts = np.concatenate([r.sample_points() for r in rods] + [np.asarray(o[0], float) for o in overlay])
        extent = float(np.linalg.norm(pts.max(axis=0) - pts.min(axis=0))) or 1.0
        palette = list(colors) if colors is not None else [colormaps["tab10"](i % 10) for i in range(len(rods))]
        for i, rod in enumerate(rods):
            r = max(s.bounding_radius for s in rod.sections)
            scale = max(radius_scale, min_radius * extent / r)
            v, vn, tri, _ = _native.tube_mesh(rod, rings_per_segment=rings_per_segment,
                                              points_per_ring=points_per_ring, radius_scale=scale, caps=True)
            # Averaged vertex normals (exact radial directions) shade smoothly.
            n = vn[tri].mean(axis=1)
            faces_all.append(v[tri])
            normals_all.append(n)
            colors_all.append(_shade(n, np.array(palette[i % len(palette)][:3], float), eye, up))
    faces = np.concatenate(faces_all) if faces_all else np.zeros((0, 3, 3))
    fcol = np.concatenate(colors_all) if colors_all else np.zeros((0, 3))
    if plane is not None:
        # Back faces are hidden in a flat view anyway: cull them.
        front = (np.concatenate(normals_all) @ eye > -1e-9) if normals_all else np.zeros(0, bool)
        _draw_planar(fig, faces[front], fcol[front], plane, overlay, show_axes, title)
    else:
        _draw_3d(fig, faces, fcol, elev, azim, overlay, show_axes, vertical_axis)
        if title:
            fig.suptitle(title)
    _save(fig, path)
    return fig


def _draw_planar(fig, faces, fcol, plane, overlay, show_axes, title):
    from matplotlib.collections import PolyCollection

    (i, j), eye, _ = plane
    ax = fig.add_subplot()
    # Painter's algorithm: far faces first (depth along the eye direction).
    depth = faces.mean(axis=1) @ np.array(eye)
    order = np.argsort(depth)
    ax.add_collection(PolyCollection(faces[order][:, :, [i, j]], facecolors=fcol[order], edgecolors="none",
                                     antialiased=False))
    for o in overlay:
        p = np.asarray(o[0], float)
        ax.plot(p[:, i], p[:, j], zorder=10, **(dict(o[1]) if len(o) > 1 else {}))
    ax.set_aspect("equal")
    ax.autoscale_view()
    ax.margins(0.04)
    if show_axes:
        ax.set_xlabel("xyz"[i])
        ax.set_ylabel("xyz"[j])
        ax.grid(True, alpha=0.3)
    else:
        ax.set_axis_off()
    if title:
        ax.set_title(title)
    fig.tight_layout()


def _draw_3d(fig, faces, fcol, elev, azim, overlay, show_axes, vertical_axis="z"):
    from mpl_toolkits.mplot3d.art3d import Poly3DCollection

    ax = fig.add_subplot(projection="3d", computed_zorder=False)
    ax.view_init(elev=elev, azim=azim, vertical_axis=vertical_axis)
    if len(faces):
        ax.add_collection3d(Poly3DCollection(faces, facecolors=fcol, edgecolors="none", linewidths=0.0,
                                             antialiased=False))
    for o in overlay:
        p = np.asarray(o[0], float)
        ax.plot(p[:, 0], p[:, 1], p[:, 2], zorder=10, **(dict(o[1]) if len(o) > 1 else {}))
    pts = np.concatenate([faces.reshape(-1, 3)] + [np.asarray(o[0], float) for o in overlay]) if len(faces) else None
    if pts is not None and len(pts):
        lo, hi = pts.min(axis=0), pts.max(axis=0)
        # Equal scales on the three axes (with a floor for flat scenes).
        centre, half = 0.5 * (lo + hi), 0.5 * (hi - lo)
        half = np.maximum(half, 0.02 * half.max() + 1e-12) * 1.05
        ax.set_xlim(centre[0] - half[0], centre[0] + half[0])
        ax.set_ylim(centre[1] - half[1], centre[1] + half[1])
        ax.set_zlim(centre[2] - half[2], centre[2] + half[2])
        ax.set_box_aspect(tuple(half))
    if show_axes:
        ax.set_xlabel("x")
        ax.set_ylabel("y")
        ax.set_zlabel("z")
    else:
        ax.set_axis_off()
    fig.subplots_adjust(left=0, right=1, bottom=0, top=0.93)


def _columns(data) -> Dict[str, np.ndarray]:
    if hasattr(data, "columns") and callable(data.columns):
        return data.columns()
    return {k: np.asarray(v) for k, v in dict(data).items()}


def plot_curves(data, y, x: str = "time", path: str | None = None, *, labels: Sequence[str] | None = None,
                references: Dict | None = None, xlabel: str | None = None, ylabel: str | None = None,
                title: str | None = None, size: Sequence[int] = (800, 500), dpi: int = 100, logy: bool = False):
    """Plots columns ``y`` (a name or list of names; vector channels are
    split as name_x, name_fy, …) of a Recorder (or dict of arrays) against
    ``x``. ``references``: {label: value} horizontal lines or {label: (xs, ys)}
    curves. Saves a PNG to ``path`` if given; returns the Figure."""
    cols = _columns(data)
    ys = [y] if isinstance(y, str) else list(y)
    fig = _figure(size, dpi)
    ax = fig.add_subplot()
    xs = cols[x]
    for i, name in enumerate(ys):
        if name not in cols:
            raise KeyError(f"no column {name!r}; columns: {sorted(cols)}")
        ax.plot(xs, cols[name], label=labels[i] if labels else name)
    for label, ref in (references or {}).items():
        if np.ndim(ref) == 0:
            ax.axhline(float(ref), ls="--", color="k", lw=1, label=label)
        else:
            ax.plot(np.asarray(ref[0]), np.asarray(ref[1]), ls="--", lw=1, label=label)
    if logy:
        ax.set_yscale("log")
    ax.set_xlabel(xlabel or x)
    if ylabel:
        ax.set_ylabel(ylabel)
    if title:
        ax.set_title(title)
    ax.grid(True, alpha=0.3)
    ax.legend()
    fig.tight_layout()
    _save(fig, path)
    return fig
