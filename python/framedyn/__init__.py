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
differences in Rust (about 20 calls per coordinate), unless a gradient
``G(x, e) -> (dV/dx, dV/de)`` is supplied as ``user_gradient`` (partial
derivatives in the embedding components, ``dV/de`` of shape ``(N, E)`` like
``e``; one call of each function per evaluation, trusted as given). Every
evaluation takes the GIL: expect them to be orders of magnitude slower than
the built-in potentials of the scene files.
"""

from __future__ import annotations

import warnings
from typing import Any, Callable, Dict, Iterable, List, Mapping, Optional, Sequence, Tuple, Union

import numpy as np

from . import _framedyn
from ._errors import MAX_SAMPLES, MAX_THREADS, USIZE_MAX, FramedynError, IntegrationError, InternalError, InvalidInputError, OutputError, QualityWarning, check_int
from ._scene import INITIAL_FIELDS, Scene, as_scenes
from ._analysis import ChaosMap, GaliResult, LyapunovResult, MegnoResult, Section, chaos_map, gali, lyapunov, megno, sali, section
from ._ensemble import EnsembleSolution, table_columns
from ._solution import BatchSolution, EventRecords, Solution

__version__: str = _framedyn.__version__

__all__ = [
    "Scene",
    "Solution",
    "BatchSolution",
    "EnsembleSolution",
    "EventRecords",
    "Event",
    "Stepper",
    "solve",
    "solve_batch",
    "lyapunov",
    "sali",
    "gali",
    "megno",
    "chaos_map",
    "section",
    "ChaosMap",
    "GaliResult",
    "LyapunovResult",
    "MegnoResult",
    "Section",
    "FramedynError",
    "InvalidInputError",
    "IntegrationError",
    "OutputError",
    "InternalError",
    "QualityWarning",
    "INITIAL_FIELDS",
    "methods",
    "manifolds",
    "__version__",
]

UserPotential = Callable[[np.ndarray, np.ndarray], float]
UserGradient = Callable[[np.ndarray, np.ndarray], Tuple[Any, Any]]


def methods() -> List[Dict[str, Any]]:
    """The integration methods, from the core's registry (the same list as
    ``framedyn methods`` and the guide's table): one dict per method with
    ``name`` (the scene's ``method.name``), ``display``, ``family``
    (``"RKMK"``, ``"splitting"``, ``"implicit"``, ``"coordinate"``),
    ``order``, ``embedded_order`` (``None`` without an embedded pair),
    ``adaptive`` (accepts ``rtol``/``atol``), ``needs`` (``"nothing"``,
    ``"exact_free_flow"``, ``"chart"``) with ``needs_text``, ``params`` and
    ``summary``."""
    return [dict(m) for m in _framedyn.methods()]


def manifolds() -> Dict[str, Dict[str, List[str]]]:
    """The manifolds a scene can name, from the core: ``{kind: {"fields":
    [...], "coordinates": [...]}}`` — the ``[manifold]`` fields of the kind
    and its chart coordinates (the ``initial`` keywords, each also with its
    rate ``*_dot``)."""
    return {k: {"fields": list(v["fields"]), "coordinates": list(v["coordinates"])} for k, v in _framedyn.manifolds().items()}


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


EventFunction = Callable[[float, Dict[str, float]], float]


class Event:
    """A user event for :func:`solve`: the crossings of ``f(t, state) = 0``,
    ``state`` a dict of every record column at ``t`` (all quantities, e.g.
    ``state["x2"]``, ``state["r"]``, ``state["energy"]``), located by Brent's
    method on the method's own continuous extension (as the scene's built-in
    ``[[events]]`` kinds ``plane``, ``distance``, ``column``).

    ``direction``: ``"rising"``, ``"falling"`` or ``"either"``;
    ``terminal``: stop the run at the first crossing. Every evaluation takes
    the GIL: slower than the built-in kinds. An exception raised by ``f``
    stops the run and is re-raised by :func:`solve`.
    """

    __slots__ = {
        "f": "The event function ``f(t, state) -> float`` whose zeros are located.",
        "name": "The event's name (``None``: ``user<i>`` by position).",
        "direction": "Which crossings count: ``'rising'``, ``'falling'`` or ``'either'``.",
        "terminal": "Whether the first crossing stops the run.",
    }

    def __init__(self, f: EventFunction, name: Optional[str] = None, *, direction: str = "either", terminal: bool = False) -> None:
        if not callable(f):
            raise InvalidInputError(f"Event: `f` must be callable f(t, state) -> float, got {type(f).__name__}")
        if direction not in ("rising", "falling", "either"):
            raise InvalidInputError(f"invalid `direction` = {direction!r}: allowed: 'rising', 'falling', 'either'")
        if not isinstance(terminal, bool):
            raise InvalidInputError(f"invalid `terminal` = {terminal!r}: must be a bool")
        if name is not None and (not isinstance(name, str) or not name or any(c in name for c in ',"\n')):
            raise InvalidInputError(f"invalid `name` = {name!r}: a non-empty string without commas, quotes or newlines")
        self.f = f
        self.name = name
        self.direction = direction
        self.terminal = terminal

    def __repr__(self) -> str:
        return f"Event({self.name!r}, direction={self.direction!r}, terminal={self.terminal})"


def _events(events: Optional[Sequence[Union[Event, EventFunction]]]) -> Optional[List[Tuple[str, EventFunction, str, bool]]]:
    if events is None:
        return None
    if isinstance(events, (Event,)) or callable(events):
        events = [events]  # type: ignore[list-item]
    if isinstance(events, (str, bytes)) or not isinstance(events, Iterable):
        raise InvalidInputError(
            f"invalid `events`: a {type(events).__name__}; allowed: a framedyn.Event, a callable f(t, state) -> float, or a list of them"
        )
    out = []
    for i, e in enumerate(events):  # type: ignore[union-attr]
        if not isinstance(e, Event):
            if not callable(e):
                raise InvalidInputError(f"invalid `events[{i}]`: a {type(e).__name__}; allowed: a framedyn.Event or a callable f(t, state) -> float")
            e = Event(e)
        out.append((e.name or f"user{i}", e.f, e.direction, e.terminal))
    return out


def _warn_quality(found: Optional[Sequence[str]], where: str, stacklevel: int = 3) -> None:
    """Raises a :class:`QualityWarning` for a run's quality findings
    (``stacklevel``: as for :func:`warnings.warn`, counted from the caller)."""
    if found:
        warnings.warn(QualityWarning(f"{where}: " + "; ".join(found)), stacklevel=stacklevel)


def solve(
    scene: Union[Scene, Mapping[str, Any]],
    *,
    user_potential: Optional[UserPotential] = None,
    events: Optional[Sequence[Union[Event, EventFunction]]] = None,
    save: bool = False,
    user_gradient: Optional[UserGradient] = None,
) -> Solution:
    """Runs ``scene`` over its time span and returns its records.

    ``user_potential``: an optional Python callable ``V(x, e) -> float``
    added to the scene's potential (slow: see the module docs);
    ``user_gradient``: its gradient ``G(x, e) -> (dV/dx, dV/de)`` (shapes
    ``(E,)`` and ``(N, E)``), used instead of finite differences. ``events``:
    user events (:class:`Event` or bare callables ``f(t, state)``) after the
    scene's ``[[events]]``; the located ones are ``solution.events``. The run
    releases the GIL; Ctrl-C stops it within about 50 ms
    (``KeyboardInterrupt``).

    Files: ``solve`` keeps the records in memory and writes nothing unless
    ``save=True`` (a library call should not create files as a side effect
    of the scene's ``output.path``, which is the CLI's default). With
    ``save=True`` the records go to the scene's ``output.path`` (default
    ``trajectory.csv``) in its ``output.format`` (default from the
    extension), in the layout ``framedyn run`` writes (same header and columns;
    numbers in Python's shortest round-trip form); or call
    :meth:`Solution.save` with any path.

    Raises :class:`InvalidInputError` for an invalid scene and
    :class:`IntegrationError` (with ``.partial``, the records up to the last
    good state) when the integration fails; an exception raised by
    ``user_potential`` is re-raised as it is (also with ``.partial``). A
    run that finishes but fails the quality check (energy drift or defect
    over the scene's ``[quality]`` limits, or a non-finite energy) returns
    its records and warns with :class:`QualityWarning`
    (``solution.stats["warnings"]``).
    """
    s = _check_scene(scene)
    if not isinstance(save, bool):
        raise InvalidInputError(f"invalid `save` = {save!r}: must be a bool")
    evs = _events(events)
    try:
        raw = _framedyn.run(s._native, user_potential, evs, user_gradient)
    except BaseException as e:
        raise _with_partial(e)
    sol = Solution._from_raw(raw)
    _warn_quality(sol.stats.get("warnings"), "solve")
    if save:
        out = s.to_dict().get("output", {})
        fmt = out.get("format")
        path = out.get("path") or ("trajectory.npz" if fmt == "npz" else "trajectory.csv")
        sol.save(path, fmt)
    return sol


def solve_batch(
    scenes: Union[Scene, Iterable[Scene]],
    params: Optional[Any] = None,
    *,
    user_potential: Optional[UserPotential] = None,
    threads: Optional[int] = None,
    on_error: str = "raise",
    user_gradient: Optional[UserGradient] = None,
    keep: str = "all",
    samples: Optional[int] = None,
    oversubscribe: bool = False,
) -> Any:
    """Runs many scenes in parallel (Rust threads, GIL released).

    **Columnar** (the fast form): one base scene and a ``table``, a dict of
    dotted scene fields to 1-D arrays of equal length N (or a pandas /
    polars DataFrame with such columns)::

        out = fd.solve_batch(scene, {"initial.r": r, "initial.spin": s}, keep="final")
        out.final, out.status, out.stats["energy_drift"]

    Scalar fields are named as in the scene (``initial.r``,
    ``potential.beta_hat``, ``body.inertia``, ``time.t_end``, …), components
    of vector and matrix fields by index (``initial.position.2``,
    ``body.J.0.1``, ``potential.terms.1.kappa``). The table is validated and
    converted in Rust once; every member is run exactly as :func:`solve`
    would run that scene (the same records, bit for bit), and the result is
    an :class:`EnsembleSolution` of stacked arrays. ``keep``: ``"all"``
    records, ``"final"`` (the last record and the statistics only), or
    ``samples=k`` equally spaced records (replacing the scene's output
    times). A member that is invalid or whose run fails is reported in
    ``status``/``errors`` and never affects the others; ``on_error="raise"``
    raises an :class:`InvalidInputError` naming the column and member of the
    first invalid member (run failures are only reported). With a
    ``user_potential`` the members run one after another (each call holds
    the GIL), each with its own error state.

    **List of scenes** (the per-member form): a list of scenes, or one base
    scene with ``params``, a list of parameter sets, each a dict of dotted
    paths (``{"initial.r": 0.3, "potential.kappa": 2.0}``); returns a
    :class:`BatchSolution` of :class:`Solution` objects, each exactly the
    records of :func:`solve` on that scene. ``on_error``: ``"raise"`` raises
    the first failure (its ``index`` attribute names the member); ``"keep"``
    returns every member, failed ones holding their partial records and the
    exception in ``.error``.

    ``user_potential``, ``user_gradient``: as for :func:`solve`.
    ``threads``: worker threads (default: one per core; an int in
    [1, 1024]); never more than the members, nor more than the machine's
    cores unless ``oversubscribe=True`` (the work is CPU-bound).
    """
    if not isinstance(oversubscribe, bool):
        raise InvalidInputError(f"invalid `oversubscribe` = {oversubscribe!r}: must be a bool")
    if on_error not in ("raise", "keep"):
        raise InvalidInputError(f"invalid `on_error` = {on_error!r}: allowed: 'raise', 'keep'")
    threads = check_int(threads, "threads", 1, MAX_THREADS, optional=True)
    if isinstance(scenes, Scene) and params is not None and not isinstance(params, (list, tuple)):
        return _solve_table(scenes, params, user_potential, user_gradient, threads, on_error, keep, samples, oversubscribe)
    if keep != "all" or samples is not None:
        raise InvalidInputError("`keep` and `samples` apply to a columnar batch (one scene and a table of columns)")
    members = as_scenes(scenes, params)
    results = _framedyn.run_batch([m._native for m in members], user_potential, threads, user_gradient, oversubscribe)
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


def _solve_table(
    scene: Scene,
    table: Any,
    user_potential: Optional[UserPotential],
    user_gradient: Optional[UserGradient],
    threads: Optional[int],
    on_error: str,
    keep: str,
    samples: Optional[int],
    oversubscribe: bool = False,
) -> EnsembleSolution:
    if keep not in ("all", "final"):
        raise InvalidInputError(f"invalid `keep` = {keep!r}: allowed: 'all', 'final' (or samples=k)")
    mode = keep
    samples = check_int(samples, "samples", 2, MAX_SAMPLES, optional=True)
    if samples is not None:
        if keep == "final":
            raise InvalidInputError("give either keep='final' or samples=k, not both")
        mode = "samples"
    names, cols = table_columns(table)
    raw = _framedyn.run_table(scene._native, names, cols, mode, samples, threads, user_potential, user_gradient, oversubscribe)
    out = EnsembleSolution(raw)
    found = out.warnings.summary()
    if found:
        _warn_quality([found], "solve_batch", stacklevel=4)
    if on_error == "raise":
        bad = np.flatnonzero(out.status == "invalid")
        if bad.size:
            err = InvalidInputError(out.errors[int(bad[0])])
            err.index = int(bad[0])  # type: ignore[attr-defined]
            raise err
    return out


class Stepper:
    """A scene advanced step by step with its method (the stepping API).

    ``step(h)``, ``advance(h, n)``; ``t``, ``energy``, ``defect``;
    ``energy_drift``, ``max_defect`` and ``warnings`` (the quality check
    over the states between calls); ``row()``
    (the current record, the scene's output columns) and ``state()`` (the
    same as a dict); ``reset()`` goes back to the initial state. Steps run
    with the GIL released.
    """

    __slots__ = {"_native": "The native stepper.", "scene": "The :class:`Scene` being stepped (checked copy)."}

    def __init__(
        self,
        scene: Union[Scene, Mapping[str, Any]],
        *,
        user_potential: Optional[UserPotential] = None,
        user_gradient: Optional[UserGradient] = None,
    ) -> None:
        self.scene: Scene = _check_scene(scene)
        self._native = _framedyn.Stepper(self.scene._native, user_potential, user_gradient)

    @staticmethod
    def _check_h(h: Any) -> float:
        if isinstance(h, bool) or not isinstance(h, (int, float, np.integer, np.floating)):
            raise InvalidInputError(f"invalid `h` = {h!r}: must be a real number (finite, ≠ 0)")
        return float(h)

    def step(self, h: float) -> None:
        """One step of size ``h`` (finite, ≠ 0; negative goes backwards)."""
        self._native.step(self._check_h(h))

    def advance(self, h: float, n: int) -> None:
        """``n`` steps of size ``h`` (``n`` an int in [0, 2**64 - 1]); stops
        at the first failure."""
        count = check_int(n, "n", 0, USIZE_MAX)
        self._native.advance(self._check_h(h), count)

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
    def energy_drift(self) -> float:
        """``max |E − E0|`` over the states at the start and end of every
        ``step``/``advance`` call since construction or :meth:`reset` (not at
        every step inside one ``advance``); 0 before any call."""
        return float(self._native.energy_drift)

    @property
    def max_defect(self) -> float:
        """The largest constraint defect over the same states."""
        return float(self._native.max_defect)

    @property
    def warnings(self) -> List[str]:
        """The quality check of those states against the scene's
        ``[quality]`` limits (energy drift, defect, non-finite values):
        empty while sound."""
        return list(self._native.warnings)

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
