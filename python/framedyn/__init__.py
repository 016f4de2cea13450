"""framedyn: structured particles (gyroscopes, affinely-rigid bodies) on S²,
H², T² and S³, integrated with geometric Lie-group methods in a global,
chart-free frame-bundle form (the Rust crate ``framedyn``; equation labels
refer to Sławianowski et al.).

Quick start::

    import framedyn as fd

    scene = fd.Scene.example("s2-gyroscope-pole")     # or fd.Scene(...), fd.Scene.load(path)
    sol = fd.solve(scene)
    sol.t, sol.position, sol.frame, sol.coordinates["r"], sol.energy, sol.stats

Computation happens in Rust with the GIL released. Errors arrive as
:class:`InvalidInputError` (a ``ValueError``), :class:`IntegrationError` (a
``RuntimeError`` carrying the partial :class:`Solution`), :class:`OutputError`
(an ``OSError``), all subclasses of :class:`FramedynError`.

User potentials are Python callables ``V(x, e) -> float`` of the embedding
position ``x`` (shape ``(E,)``) and the body frame ``e`` (shape ``(N, E)``,
the vectors as rows); their gradient is taken by extrapolated finite
differences in Rust, and every evaluation takes the GIL: expect them to be
orders of magnitude slower than the built-in potentials of the scene files.
"""

from __future__ import annotations

from typing import Any, Callable, Iterable, List, Mapping, Optional, Sequence, Tuple, Union

import numpy as np

from . import _framedyn
from ._errors import FramedynError, IntegrationError, InternalError, InvalidInputError, OutputError
from ._scene import INITIAL_FIELDS, Scene, as_scenes
from ._solution import BatchSolution, Solution

__version__: str = _framedyn.__version__

__all__ = [
    "Scene",
    "Solution",
    "BatchSolution",
    "Stepper",
    "solve",
    "solve_batch",
    "FramedynError",
    "InvalidInputError",
    "IntegrationError",
    "OutputError",
    "InternalError",
    "INITIAL_FIELDS",
    "__version__",
]

UserPotential = Callable[[np.ndarray, np.ndarray], float]


def _check_scene(scene: Any, what: str = "scene") -> Scene:
    if isinstance(scene, Scene):
        return scene
    if isinstance(scene, Mapping):
        return Scene.from_dict(scene)
    raise InvalidInputError(f"{what}: expected a framedyn.Scene or a dict, got {type(scene).__name__}")


def _with_partial(e: BaseException) -> BaseException:
    raw = getattr(e, "partial", None)
    if isinstance(raw, dict):
        try:
            e.partial = Solution._from_raw(raw)  # type: ignore[attr-defined]
        except Exception:  # pragma: no cover - the partial result is best effort
            pass
    return e


def solve(scene: Union[Scene, Mapping[str, Any]], *, user_potential: Optional[UserPotential] = None) -> Solution:
    """Runs ``scene`` over its time span and returns its records.

    ``user_potential``: an optional Python callable ``V(x, e) -> float``
    added to the scene's potential (slow: see the module docs). The run
    releases the GIL; Ctrl-C stops it within about 50 ms
    (``KeyboardInterrupt``).

    Raises :class:`InvalidInputError` for an invalid scene and
    :class:`IntegrationError` (with ``.partial``, the records up to the last
    good state) when the integration fails; an exception raised by
    ``user_potential`` is re-raised as it is (also with ``.partial``).
    """
    s = _check_scene(scene)
    try:
        raw = _framedyn.run(s._native, user_potential)
    except BaseException as e:
        raise _with_partial(e)
    return Solution._from_raw(raw)


def solve_batch(
    scenes: Union[Scene, Iterable[Scene]],
    params: Optional[Sequence[Mapping[str, Any]]] = None,
    *,
    user_potential: Optional[UserPotential] = None,
    threads: Optional[int] = None,
    on_error: str = "raise",
) -> BatchSolution:
    """Runs many scenes in parallel (Rust threads, GIL released).

    Either a list of scenes, or one base scene with ``params``: a list of
    parameter sets, each a dict of dotted paths (``{"initial.r": 0.3,
    "potential.kappa": 2.0}``). Every member gives exactly the records of
    :func:`solve` on that scene.

    ``threads``: worker threads (default: one per core). ``on_error``:
    ``"raise"`` raises the first failure (its ``index`` attribute names the
    member); ``"keep"`` returns every member, failed ones holding their
    partial records and the exception in ``.error``.
    """
    if on_error not in ("raise", "keep"):
        raise InvalidInputError(f"invalid `on_error` = {on_error!r}: allowed: 'raise', 'keep'")
    if threads is not None and (not isinstance(threads, int) or isinstance(threads, bool) or threads < 1):
        raise InvalidInputError(f"invalid `threads` = {threads!r}: must be an int ≥ 1 or None")
    members = as_scenes(scenes, params)
    results = _framedyn.run_batch([m._native for m in members], user_potential, threads)
    out: List[Solution] = []
    for i, r in enumerate(results):
        if isinstance(r, BaseException):
            _with_partial(r)
            try:
                r.index = i  # type: ignore[attr-defined]
            except AttributeError:  # pragma: no cover
                pass
            if on_error == "raise":
                raise r
            partial = getattr(r, "partial", None)
            sol = partial if isinstance(partial, Solution) else Solution(np.empty((0, 0)), [], [], {"stop": "failed"})
            sol.error = r
            out.append(sol)
        else:
            out.append(Solution._from_raw(r))
    return BatchSolution(out)


class Stepper:
    """A scene advanced step by step with its method (the stepping API).

    ``step(h)``, ``advance(h, n)``; ``t``, ``energy``, ``defect``; ``row()``
    (the current record, the scene's output columns) and ``state()`` (the
    same as a dict); ``reset()`` goes back to the initial state. Steps run
    with the GIL released.
    """

    __slots__ = ("_native", "scene")

    def __init__(self, scene: Union[Scene, Mapping[str, Any]], *, user_potential: Optional[UserPotential] = None) -> None:
        self.scene: Scene = _check_scene(scene)
        self._native = _framedyn.Stepper(self.scene._native, user_potential)

    @staticmethod
    def _check_h(h: Any) -> float:
        if isinstance(h, bool) or not isinstance(h, (int, float, np.integer, np.floating)):
            raise InvalidInputError(f"invalid `h` = {h!r}: must be a real number (finite, ≠ 0)")
        return float(h)

    def step(self, h: float) -> None:
        """One step of size ``h`` (finite, ≠ 0; negative goes backwards)."""
        self._native.step(self._check_h(h))

    def advance(self, h: float, n: int) -> None:
        """``n`` steps of size ``h``; stops at the first failure."""
        if isinstance(n, bool) or not isinstance(n, (int, np.integer)) or n < 0:
            raise InvalidInputError(f"invalid `n` = {n!r}: must be an int ≥ 0")
        self._native.advance(self._check_h(h), int(n))

    @property
    def t(self) -> float:
        """Current time."""
        return float(self._native.t)

    @property
    def energy(self) -> float:
        """Energy of the current state."""
        return float(self._native.energy)

    @property
    def defect(self) -> float:
        """Constraint defect of the current state."""
        return float(self._native.defect)

    @property
    def span(self) -> Tuple[float, float]:
        """The scene's time span ``(t0, t_end)``."""
        return tuple(self._native.span)  # type: ignore[return-value]

    @property
    def method(self) -> str:
        """The method's name."""
        return str(self._native.method)

    @property
    def columns(self) -> List[str]:
        """Names of the entries of :meth:`row`."""
        return [c for c, _ in self._native.columns]

    def row(self) -> np.ndarray:
        """The current state as one record."""
        return self._native.row()

    def state(self) -> dict:
        """The current record as ``{column: value}``."""
        return dict(zip(self.columns, self.row().tolist()))

    def reset(self) -> None:
        """Back to the initial state."""
        self._native.reset()

    def __repr__(self) -> str:
        return f"Stepper(t={self.t}, method={self.method!r})"
