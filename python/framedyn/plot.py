"""Plotting helpers (matplotlib, imported only when a function is called).

- :func:`path3d`: the path on the embedded surface in 3-D, with the body
  frame drawn as small arrows;
- :func:`invariant_drift`: ``|q(t) − q(t₀)|`` of the energy and the momentum
  maps against time.
"""

from __future__ import annotations

from typing import Any, Optional, Sequence

import numpy as np

from ._errors import InvalidInputError
from ._solution import Solution

__all__ = ["path3d", "invariant_drift", "surface_mesh"]


def _pyplot() -> Any:
    try:
        import matplotlib.pyplot as plt
    except ImportError as e:  # pragma: no cover - depends on the environment
        raise ImportError("framedyn.plot needs matplotlib: pip install 'framedyn[plot]'") from e
    return plt


def surface_mesh(manifold: dict, n: int = 40, r_max: Optional[float] = None) -> Optional[tuple]:
    """``(X, Y, Z)`` of a wireframe of the embedded surface of a scene's
    ``manifold`` table (``None`` for S³, which has no surface in ℝ³)."""
    kind = manifold.get("kind")
    u = np.linspace(0.0, 2.0 * np.pi, n)
    if kind == "S2":
        R = manifold.get("radius", 1.0)
        th = np.linspace(0.0, np.pi, n)
        T, P = np.meshgrid(th, u)
        return R * np.sin(T) * np.cos(P), R * np.sin(T) * np.sin(P), R * np.cos(T)
    if kind == "H2":
        R = manifold.get("radius", 1.0)
        chi = np.linspace(0.0, (r_max if r_max is not None else 1.5 * R) / R, n)
        C, P = np.meshgrid(chi, u)
        return R * np.sinh(C) * np.cos(P), R * np.sinh(C) * np.sin(P), R * np.cosh(C)
    if kind == "T2":
        # Scenes serialise the radii as major/minor; L and R are their aliases.
        L = manifold.get("major", manifold.get("L", 2.0))
        R = manifold.get("minor", manifold.get("R", 1.0))
        T, P = np.meshgrid(u, u)
        return (L + R * np.cos(T)) * np.cos(P), (L + R * np.cos(T)) * np.sin(P), R * np.sin(T)
    return None


def _stereographic(x: np.ndarray, R: float) -> np.ndarray:
    """S³(R) ⊂ ℝ⁴ → ℝ³ from the point (−R, 0, 0, 0) (the chart pole maps to 0)."""
    return R * x[..., 1:] / (R + x[..., :1])


def path3d(
    solution: Solution,
    scene: Any = None,
    *,
    ax: Any = None,
    frame_every: int = 10,
    arrow_length: float = 0.15,
    surface: bool = True,
    color: str = "C0",
) -> Any:
    """Draws the path of ``solution`` on the embedded surface in 3-D, with the
    body frame vectors as arrows every ``frame_every`` records.

    ``scene`` (a :class:`framedyn.Scene`) supplies the surface to draw; S³
    paths are shown in the stereographic projection to ℝ³ (frames projected
    by the differential). Returns the matplotlib ``Axes3D``.
    """
    if not isinstance(solution, Solution):
        raise InvalidInputError(f"path3d: `solution` must be a framedyn.Solution, got {type(solution).__name__}")
    if isinstance(frame_every, bool) or not isinstance(frame_every, int) or frame_every < 1:
        raise InvalidInputError(f"path3d: invalid `frame_every` = {frame_every!r}: must be an int ≥ 1")
    if not (np.isfinite(arrow_length) and arrow_length > 0):
        raise InvalidInputError(f"path3d: invalid `arrow_length` = {arrow_length!r}: must be finite and > 0")
    x = solution.position
    if x.shape[1] == 0:
        raise InvalidInputError("path3d: the solution has no position columns (add \"position\" to output.quantities)")
    plt = _pyplot()
    if ax is None:
        fig = plt.figure()
        ax = fig.add_subplot(projection="3d")
    manifold = scene.to_dict()["manifold"] if scene is not None else {}
    frame = solution.frame
    if x.shape[1] == 4:
        R = float(manifold.get("radius", np.linalg.norm(x[0])))
        p = _stereographic(x, R)
        if frame.shape[1] > 0:
            # Push the frame forward: d(stereo)(x)[v] = R v_s/(R + x0) − R x_s v0/(R + x0)².
            d = R + x[:, None, :1]
            frame = R * frame[..., 1:] / d - R * x[:, None, 1:] * frame[..., :1] / d**2
        ax.set_title("S³, stereographic projection")
    else:
        p = x
        if surface and manifold:
            r_max = float(np.nanmax(solution.coordinates.get("r", np.array([1.5])))) * 1.2 if manifold.get("kind") == "H2" else None
            mesh = surface_mesh(manifold, r_max=r_max)
            if mesh is not None:
                ax.plot_wireframe(*mesh, color="0.8", linewidth=0.4)
    ax.plot(p[:, 0], p[:, 1], p[:, 2], color=color, linewidth=1.2)
    if frame.shape[1] > 0:
        idx = np.arange(0, len(p), frame_every)
        for a, c in zip(range(frame.shape[1]), ("C3", "C2", "C1")):
            v = frame[idx, a, :3]
            ax.quiver(p[idx, 0], p[idx, 1], p[idx, 2], v[:, 0], v[:, 1], v[:, 2], length=arrow_length, normalize=True, color=c)
    ax.set_xlabel("x")
    ax.set_ylabel("y")
    ax.set_zlabel("z")
    return ax


def invariant_drift(
    solution: Solution,
    quantities: Optional[Sequence[str]] = None,
    *,
    ax: Any = None,
    log: bool = True,
) -> Any:
    """Plots ``|q(t) − q(t₀)|`` against ``t`` for the energy and the momentum
    maps (or the columns named in ``quantities``). Returns the ``Axes``."""
    if not isinstance(solution, Solution):
        raise InvalidInputError(f"invariant_drift: `solution` must be a framedyn.Solution, got {type(solution).__name__}")
    if quantities is None:
        quantities = [q for q in ["energy", *solution.momentum_maps] if q in solution]
    else:
        quantities = list(quantities)
        for q in quantities:
            if q not in solution:
                raise InvalidInputError(f"invariant_drift: no column {q!r} in `quantities`; columns: {', '.join(solution.columns)}")
    if not quantities:
        raise InvalidInputError("invariant_drift: nothing to plot (no energy or momentum-map columns)")
    plt = _pyplot()
    if ax is None:
        _, ax = plt.subplots()
    t = solution.t
    for q in quantities:
        d = solution.drift(q)
        if log:
            # Exact zeros (the first record) cannot be shown on a log axis.
            d = np.where(d > 0, d, np.nan)
        ax.plot(t, d, label=q)
    if log:
        ax.set_yscale("log")
    ax.set_xlabel("t")
    ax.set_ylabel("|q(t) − q(t₀)|")
    ax.legend()
    return ax
