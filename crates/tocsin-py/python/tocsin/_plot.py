"""Pictures: the two meshes at a pose pair (a time of contact), witness points and normal."""

from typing import Any, Optional, Union

import numpy as np
import numpy.typing as npt

from ._core import ContactResult, DistanceResult, Mesh
from ._errors import TocsinError


def plot_contact(
    mesh1: Mesh,
    pose1: npt.ArrayLike,
    mesh2: Mesh,
    pose2: npt.ArrayLike,
    result: Optional[Union[ContactResult, DistanceResult]] = None,
    path: Optional[str] = None,
    ax: Optional[Any] = None,
) -> Any:
    """Draws mesh1 at pose1 (blue) and mesh2 at pose2 (orange), world frame, with the witness
    points of `result` (a ContactResult or DistanceResult; computed with tocsin.distance when
    omitted) and the normal from body 1 to body 2 as an arrow. Writes a PNG to `path` when given
    and returns the matplotlib figure. With `path` and no `ax`, the figure is drawn off screen
    without pyplot (the process's matplotlib backend is left alone); without `path`, it is a
    pyplot figure. Needs matplotlib (pip install "tocsin[plot]")."""
    try:
        from matplotlib.figure import Figure
        from mpl_toolkits.mplot3d.art3d import Poly3DCollection
    except ImportError as e:  # pragma: no cover - exercised only without matplotlib
        raise TocsinError('plot_contact needs matplotlib: pip install "tocsin[plot]"') from e
    from ._core import distance

    p1, p2 = np.asarray(pose1, dtype=float), np.asarray(pose2, dtype=float)
    if result is None:
        result = distance(mesh1, p1, mesh2, p2)
    q1, q2 = np.asarray(result.point1), np.asarray(result.point2)
    if isinstance(result, ContactResult):
        normal = np.asarray(result.normal)
    else:
        gap = q2 - q1
        normal = gap / np.linalg.norm(gap) if np.linalg.norm(gap) > 0 else np.array([0.0, 0.0, 1.0])
    if ax is None:
        if path is not None:
            fig = Figure(figsize=(8, 6))
        else:
            import matplotlib.pyplot as plt

            fig = plt.figure(figsize=(8, 6))
        ax = fig.add_subplot(projection="3d")
    fig = ax.figure
    points = []
    for mesh, pose, color in ((mesh1, p1, "tab:blue"), (mesh2, p2, "tab:orange")):
        v = mesh.vertices @ pose[:3, :3].T + pose[:3, 3]
        ax.add_collection3d(Poly3DCollection(v[mesh.triangles], facecolor=color, edgecolor="none", alpha=0.55))
        points.append(v)
    allv = np.vstack(points)
    lo, hi = allv.min(0), allv.max(0)
    centre, half = 0.5 * (lo + hi), 0.5 * (hi - lo).max()
    for setter, c in zip((ax.set_xlim, ax.set_ylim, ax.set_zlim), centre):
        setter(c - half, c + half)
    ax.scatter(*q1, color="black", s=30, label="point1")
    ax.scatter(*q2, color="red", s=30, label="point2")
    ax.quiver(*q1, *(normal * 0.3 * half), color="red", label="normal (1 to 2)")
    title = f"distance {result.distance:.3g}"
    if isinstance(result, ContactResult):
        title = f"time of contact {result.time:.6f}, " + title
    ax.set_title(title)
    ax.legend(loc="upper left")
    if path is not None:
        fig.savefig(path, dpi=100)
    return fig
