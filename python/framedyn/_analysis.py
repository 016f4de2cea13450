"""Integrability, measured (issue 21): Lyapunov exponents, the chaos
indicators SALI and MEGNO (of one scene, or mapped over a table of
initial conditions), and Poincaré sections of a scene, computed in the Rust
core (``framedyn::analysis``) with the GIL released; results as numpy
arrays."""

from __future__ import annotations

import json
import math
from dataclasses import dataclass
from typing import Any, Dict, Mapping, Optional, Sequence, Tuple, Union

import numpy as np

from . import _framedyn
from ._ensemble import table_columns
from ._errors import MAX_THREADS, InvalidInputError, check_int
from ._scene import Scene

_U64_MAX = 2**64 - 1


@dataclass(frozen=True)
class LyapunovResult:
    """Lyapunov exponents of a scene's trajectory (:func:`lyapunov`).

    ``exponents``: the ``k`` largest, largest first (1/time); ``stderr``:
    their batch-means standard errors; ``spread``: max − min of each running
    estimate over the second half of the run (how far from converged);
    ``times`` and ``running`` (shape ``(len(times), k)``): the running
    estimates at every re-orthonormalisation; ``steps``: steps taken (fixed,
    or accepted error-controlled ones);
    ``steps_per_step``: steps of the method per step (1 + 1 per tangent
    vector with exact tangent maps, where a step of the tangent lift costs
    about two plain steps; 1 + 2 per vector with differences, 4 with
    fourth-order ones); ``exact_tangents``: whether the tangent maps were
    exact (see :func:`lyapunov`); ``state_dimension``: the
    state group's dimension; ``dimension``: the number of exponents of the
    full spectrum (``state_dimension``, less the gauge directions with
    ``quotient=True``); ``two_trajectory``: with
    ``two_trajectory=True``, the maximal exponent from two nearby
    trajectories (``exponent``, ``stderr``, ``spread``, ``times``,
    ``running``), else ``None``."""

    exponents: np.ndarray
    stderr: np.ndarray
    spread: np.ndarray
    times: np.ndarray
    running: np.ndarray
    steps: int
    steps_per_step: int
    exact_tangents: bool
    state_dimension: int
    dimension: int
    two_trajectory: Optional[Dict[str, Any]]


@dataclass(frozen=True)
class MegnoResult:
    """MEGNO of a scene's trajectory (:func:`megno`).

    ``megno``: ``Y`` at the end of the run; ``mean``: its time average
    ``⟨Y⟩`` there (→ 2 on a quasi-periodic orbit, → 0 on a stable
    isochronous periodic one, ≈ λ₁t/2 on a chaotic one); ``slope``: the
    least-squares slope of ``⟨Y⟩`` over the second half of the run (≈ λ₁/2
    if chaotic, → 0 if regular); ``lyapunov``: the finite-time exponent
    ``log(|δ(T)|/|δ(0)|)/T`` of the same tangent vector; ``times``,
    ``running_megno``, ``running_mean``: ``Y`` and ``⟨Y⟩`` along the run
    (every step, thinned to at most 10 000 and the last); ``steps``: steps
    taken (fixed, or accepted error-controlled ones); ``steps_per_step``:
    steps of the method per step; ``exact_tangents``: whether the tangent
    maps were exact (see :func:`lyapunov`)."""

    megno: float
    mean: float
    slope: float
    lyapunov: float
    times: np.ndarray
    running_megno: np.ndarray
    running_mean: np.ndarray
    steps: int
    steps_per_step: int
    exact_tangents: bool


@dataclass(frozen=True)
class ChaosMap:
    """SALI and MEGNO of every member of a table (:func:`chaos_map`): one
    ``(N,)`` array per quantity, index ``i`` the table's member ``i``.

    SALI (with ``sali=True``): ``sali`` at the end of the run, ``sali_min``
    its smallest value, ``chaotic_at`` the time it fell below the threshold
    (the run stops there; NaN if it did not), ``sali_steps``. MEGNO (with
    ``megno=True``): ``megno`` (``Y`` at the end), ``megno_mean`` (``⟨Y⟩``:
    → 2 regular, ≈ λ₁t/2 chaotic), ``megno_slope`` (of ``⟨Y⟩`` over the
    second half, ≈ λ₁/2 chaotic), ``lyapunov`` (the finite-time maximal
    exponent of MEGNO's tangent vector), ``megno_steps``. GALI_k (with
    ``gali=k``): ``gali_log10`` (``log₁₀ GALI_k`` at the end),
    ``gali_below_at`` (the time it fell below ``gali_threshold``: the run
    stops there; NaN if it did not), ``gali_steps``. Columns of an
    indicator not asked for, or that failed on a member, hold NaN (steps 0).

    ``status``: per member ``'finished'``, ``'invalid'`` (its scene cannot
    be analysed: not run), ``'failed'`` (an indicator's run failed: the
    other's values are kept) or ``'cancelled'``; ``status_codes`` the
    index in ``status_names`` (the codes of :class:`EnsembleSolution`);
    ``errors``: per member the message (``None`` if finished)."""

    sali: np.ndarray
    sali_min: np.ndarray
    chaotic_at: np.ndarray
    sali_steps: np.ndarray
    megno: np.ndarray
    megno_mean: np.ndarray
    megno_slope: np.ndarray
    lyapunov: np.ndarray
    megno_steps: np.ndarray
    gali_log10: np.ndarray
    gali_below_at: np.ndarray
    gali_steps: np.ndarray
    status: np.ndarray
    status_codes: np.ndarray
    status_names: Tuple[str, ...]
    errors: Tuple[Optional[str], ...]

    def __len__(self) -> int:
        return int(self.status.shape[0])

    @property
    def ok(self) -> np.ndarray:
        """Per member: finished (every indicator asked for computed)."""
        return self.status == "finished"


@dataclass(frozen=True)
class Section:
    """The crossings of a Poincaré section (:func:`section`): ``data`` has one
    row per crossing and one column per name in ``columns`` (``t`` first,
    then every record column of the scene, units in ``units``); ``rising``
    says whether each crossing went from − to + through the section."""

    name: str
    columns: Tuple[str, ...]
    units: Tuple[str, ...]
    data: np.ndarray
    rising: np.ndarray

    def __len__(self) -> int:
        return int(self.data.shape[0])

    def column(self, name: str) -> np.ndarray:
        """The values of column ``name`` at the crossings."""
        try:
            j = self.columns.index(name)
        except ValueError:
            raise InvalidInputError(f"invalid column {name!r}: not a column of this section; columns: {', '.join(self.columns)}") from None
        return self.data[:, j]

    def __getitem__(self, name: str) -> np.ndarray:
        """``section["r"]``: :meth:`column`, indexed like a :class:`Solution`
        (a missing name is a ``KeyError``, as there)."""
        if name not in self.columns:
            raise KeyError(f"no column {name!r}; columns: {', '.join(self.columns)}")
        return self.column(name)

    def __contains__(self, name: object) -> bool:
        return name in self.columns

    @property
    def t(self) -> np.ndarray:
        """The crossing times."""
        return self.data[:, 0]


def _scene(scene: Any) -> Scene:
    if isinstance(scene, Scene):
        return scene
    if isinstance(scene, Mapping):
        return Scene.from_dict(scene)
    raise TypeError(f"scene: expected a framedyn.Scene or a dict, got {type(scene).__name__}")


def _bools(**flags: Any) -> None:
    """``TypeError`` naming the first of ``flags`` that is not a bool."""
    for name, flag in flags.items():
        if not isinstance(flag, bool):
            raise TypeError(f"invalid `{name}` = {flag!r}: must be a bool")


def _real(value: Any, name: str) -> float:
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, (int, float, np.integer, np.floating)):
        raise TypeError(f"invalid `{name}` = {value!r}: must be a real number, not {type(value).__name__}")
    v = float(value)
    if not math.isfinite(v):
        raise InvalidInputError(f"invalid `{name}` = {value!r}: must be finite")
    return v


def _count_or_all(value: Union[int, str], name: str, lo: int, allowed: str) -> Optional[int]:
    """A count option that also takes ``"all"`` (``None``): an int in
    ``[lo, 10 000]`` (the analysis checks it against the state's dimension)."""
    if isinstance(value, str):
        if value != "all":
            raise InvalidInputError(f"invalid `{name}` = {value!r}: must be {allowed} or 'all'")
        return None
    return check_int(value, name, lo, 10_000)


def lyapunov(
    scene: Union[Scene, Mapping[str, Any]],
    *,
    exponents: Union[int, str] = 1,
    every: int = 10,
    transient: float = 0.0,
    batches: int = 10,
    seed: int = 1,
    eps: Optional[float] = None,
    fourth_order: bool = False,
    two_trajectory: bool = False,
    quotient: bool = False,
    differenced: bool = False,
) -> LyapunovResult:
    """The Lyapunov exponents of ``scene``'s trajectory: its method with its
    steps over its time span (a fixed step ``method.h``, or ``rtol``/``atol``:
    the steps a run would take, chosen by the trajectory's error alone),
    carrying tangent vectors ``δy = y·ξ`` (Lie-algebra coordinates) by the
    tangent map of each step at its size, re-orthonormalised every
    ``every`` steps (Benettin's discrete QR).

    ``exponents``: how many (largest first), or ``"all"`` (the dimension of
    the state group: the phase space plus the parallel frame's gauge
    direction, which contributes a 0; with ``quotient=True`` the phase
    space's). ``quotient``: the spectrum of the phase space — the tangent
    vectors taken modulo the gauge directions after every step, as
    :func:`gali` does by default — whose ``2n`` exponents pair
    (``λᵢ + λ₂ₙ₊₁₋ᵢ = 0``) with no gauge zero among them; default ``False``
    (the stored state's spectrum). ``transient``: time at the start left
    out of the averages; ``batches``: batches of the standard error;
    ``seed``: of the random initial tangent frame;
    ``two_trajectory``: also the two-nearby-trajectory estimate.

    The tangent map of a step is exact where it exists: every model in a
    potential of the scene format (not a Python closure), stepped by a
    Runge–Kutta–Munthe-Kaas method or the implicit midpoint rule — the
    method steps the linearised system on the tangent group (dual numbers
    over the state group) and so differentiates its own step to round-off
    (``exact_tangents`` in the result). Elsewhere (the splittings, closure
    potentials), or with ``differenced=True``, it is a central difference of
    the step map: ``eps`` and ``fourth_order`` choose it (default second
    order, ``eps = 1e-5``, about 1e-10 relative per step; fourth order
    ``eps = 1e-3``, 1e-12).

    Raises :class:`InvalidInputError` (a ``ValueError``) for a bad option, a
    scene with a coordinate method, or an error-controlled run too short for
    ``batches`` (its steps are not known before it), ``TypeError`` for an
    argument of the wrong type, :class:`IntegrationError` when a step fails;
    Ctrl-C raises ``KeyboardInterrupt``."""
    s = _scene(scene)
    k = _count_or_all(exponents, "exponents", 1, "a positive int")
    _bools(fourth_order=fourth_order, two_trajectory=two_trajectory, quotient=quotient, differenced=differenced)
    raw = _framedyn.lyapunov(
        s._native,
        k,
        check_int(every, "every", 1, 2**32),
        _real(transient, "transient"),
        check_int(batches, "batches", 2, 2**32),
        check_int(seed, "seed", 0, _U64_MAX),
        None if eps is None else _real(eps, "eps"),
        fourth_order,
        two_trajectory,
        quotient,
        differenced,
    )
    return LyapunovResult(**raw)


def section(
    scene: Union[Scene, Mapping[str, Any]],
    spec: Optional[Mapping[str, Any]] = None,
    *,
    plane: Optional[Sequence[float]] = None,
    offset: float = 0.0,
    column: Optional[str] = None,
    value: Optional[float] = None,
    event: Optional[str] = None,
    direction: Optional[str] = None,
) -> Section:
    """The Poincaré section of ``scene``'s trajectory: every crossing, located
    on the method's continuous extension, with the whole record there.

    The section is one of: ``spec``, an ``[[events]]`` entry as a dict
    (``{"kind": "plane", "normal": [0, 0, 1]}``, ``{"kind": "column",
    "column": "r", "value": 1.0}``, …); ``plane`` (the normal, embedding
    components) with ``offset``; ``column`` with ``value``; ``event``, the
    name of an ``[[events]]`` entry of the scene; or, with none of these,
    the scene's only ``[[events]]`` entry. ``direction``: ``"rising"``,
    ``"falling"`` or ``"either"`` (default: the entry's, else either).

    Raises :class:`InvalidInputError` for an invalid section (naming the
    field) and :class:`IntegrationError` when the run fails."""
    s = _scene(scene)
    given = [x is not None for x in (spec, plane, column, event)]
    if sum(given) > 1:
        raise InvalidInputError("give one section: spec, plane, column or event")
    if spec is not None:
        if not isinstance(spec, Mapping):
            raise TypeError(f"spec: expected a dict (an [[events]] entry), got {type(spec).__name__}")
        entry: Dict[str, Any] = dict(spec)
    elif plane is not None:
        normal = [_real(x, "plane") for x in plane]
        entry = {"kind": "plane", "name": "section", "normal": normal, "offset": _real(offset, "offset")}
    elif column is not None:
        if not isinstance(column, str):
            raise TypeError(f"column: expected a str, got {type(column).__name__}")
        if value is None:
            raise InvalidInputError("column needs value (the value crossed)")
        entry = {"kind": "column", "name": "section", "column": column, "value": _real(value, "value")}
    else:
        events = s.to_dict().get("events", [])
        if event is not None:
            found = [e for e in events if e.get("name") == event]
            if not found:
                names = [e["name"] for e in events if "name" in e]
                raise InvalidInputError(f"invalid `event` = {event!r}: must name an [[events]] entry of the scene; named entries: {', '.join(names) or 'none'}")
            entry = dict(found[0])
        elif len(events) == 1:
            entry = dict(events[0])
        else:
            raise InvalidInputError(f"no section given and the scene has {len(events)} [[events]] entries: give spec, plane, column or event")
    if direction is not None:
        if direction not in ("rising", "falling", "either"):
            raise InvalidInputError(f"invalid `direction` = {direction!r}: must be 'rising', 'falling' or 'either'")
        entry["direction"] = direction
    raw = _framedyn.section(s._native, json.dumps(entry))
    return Section(name=raw["name"], columns=tuple(raw["columns"]), units=tuple(raw["units"]), data=raw["data"], rising=raw["rising"])


def sali(
    scene: Union[Scene, Mapping[str, Any]], *, threshold: float = 1e-8, seed: int = 1, eps: Optional[float] = None, fourth_order: bool = False, differenced: bool = False
) -> Dict[str, Any]:
    """The Smaller Alignment Index (Skokos 2001) of ``scene``'s trajectory: a
    fast chaos indicator for maps over initial conditions. Two tangent
    vectors are carried by the tangent map of each step (the scene's method
    and steps, fixed or error-controlled, as for :func:`lyapunov`) and
    normalised; ``SALI = min(|u₁ + u₂|,
    |u₁ − u₂|)`` falls like ``exp(−(λ₁ − λ₂)t)`` on a chaotic orbit and stays
    away from 0 on a regular one. The run stops when SALI falls below
    ``threshold``. ``eps``, ``fourth_order``, ``differenced``: the tangent
    maps, as for :func:`lyapunov` (SALI has no floor set by differences:
    the difference ``u₁ − u₂`` is carried as a tangent vector of its own).

    Returns ``{"sali": final value, "chaotic_at": the time it fell below the
    threshold or None, "min": smallest value, "steps": steps taken,
    "exact_tangents": whether the tangent maps were exact}``.
    Raises :class:`InvalidInputError` for a bad threshold or ``eps`` or an
    unsuitable scene, ``TypeError`` for arguments of the wrong type."""
    s = _scene(scene)
    _bools(fourth_order=fourth_order, differenced=differenced)
    value, at, low, steps, exact = _framedyn.sali(
        s._native, _real(threshold, "threshold"), check_int(seed, "seed", 0, _U64_MAX), None if eps is None else _real(eps, "eps"), fourth_order, differenced
    )
    return {"sali": value, "chaotic_at": at, "min": low, "steps": steps, "exact_tangents": exact}


@dataclass(frozen=True)
class GaliResult:
    """The Generalised Alignment Index of a scene's trajectory (:func:`gali`).

    ``gali``: ``GALI_k`` at the end of the run (0.0 below the smallest
    float; see ``log10``); ``log10``: its base-10 logarithm there;
    ``below_at``: the time it fell below ``threshold`` (the run stops
    there) or ``None``; ``times``, ``running_log10``: ``log₁₀ GALI_k`` along
    the run (every step, thinned to at most 10 000 and the last); ``k``:
    the number of deviation vectors; ``steps``: steps taken;
    ``steps_per_step``: steps of the method per step; ``dimension``: the
    dimension of the space the vectors live in (the phase space's with
    ``quotient=True``, the state group's without); ``exact_tangents``:
    whether the tangent maps were exact (see :func:`lyapunov`)."""

    gali: float
    log10: float
    below_at: Optional[float]
    times: np.ndarray
    running_log10: np.ndarray
    k: int
    steps: int
    steps_per_step: int
    dimension: int
    exact_tangents: bool


def gali(
    scene: Union[Scene, Mapping[str, Any]],
    *,
    k: Union[int, str] = 2,
    threshold: float = 1e-12,
    seed: int = 1,
    eps: Optional[float] = None,
    fourth_order: bool = False,
    quotient: bool = True,
    differenced: bool = False,
) -> GaliResult:
    """The Generalised Alignment Index ``GALI_k`` (Skokos, Bountis &
    Antonopoulos 2007) of ``scene``'s trajectory: the volume spanned by ``k``
    unit deviation vectors carried by the tangent map of each step (the
    scene's method and steps, fixed or error-controlled, as for
    :func:`lyapunov`). On a chaotic orbit it falls like
    ``exp(−Σ_{j=2..k}(λ₁ − λ_j) t)``; on a regular orbit on an ``N``-torus it
    stays away from 0 for ``k ≤ N`` and falls like a power of ``t`` for
    ``k > N`` — so it tells the dimension of the torus (a maximally
    degenerate, superintegrable motion has tori of low dimension).
    ``GALI_2 = S·√(1 − S²/4)`` for ``S`` = :func:`sali` with the same seed.
    The vectors are carried as an orthonormal frame and a small triangular
    matrix, so the index has no floor and is accumulated as a logarithm.

    ``quotient`` (default ``True``): the index of the physical phase space —
    the deviation vectors are taken modulo the gauge directions of the
    parallel frame the state carries (turning it in place, with the
    components stored in it turned back, changes nothing physical; its
    holonomy angle drifts like an angle of the torus). ``False`` gives the
    index of the stored state. On a Bertrand orbit, the paper's maximally
    degenerate case, ``GALI_2`` falls like ``1/t`` in the phase space and
    stays on a non-degenerate regular orbit; on the stored state it stays
    on both.

    ``k``: 2 … the phase space's dimension (with ``quotient=False`` the
    state group's), or ``"all"``; ``threshold``: the
    run stops when the index falls below it (1e-300 ≤ threshold < 1; that
    means chaos only for small ``k``: compare ``running_log10`` with a power
    law);
    ``seed``, ``eps``, ``fourth_order``, ``differenced``: as for :func:`lyapunov` (with
    ``quotient=False`` the initial vectors are the first ``k`` of its frame;
    with it, their parts outside the gauge directions, orthonormalised).

    Raises :class:`InvalidInputError` (a ``ValueError``) for a bad option or
    a scene with a coordinate method, ``TypeError`` for an argument of the
    wrong type, :class:`IntegrationError` when a step fails; Ctrl-C raises
    ``KeyboardInterrupt``."""
    s = _scene(scene)
    kk = _count_or_all(k, "k", 2, "an int ≥ 2")
    _bools(fourth_order=fourth_order, quotient=quotient, differenced=differenced)
    raw = _framedyn.gali(s._native, kk, _real(threshold, "threshold"), check_int(seed, "seed", 0, _U64_MAX), None if eps is None else _real(eps, "eps"), fourth_order, quotient, differenced)
    return GaliResult(**raw)


def megno(scene: Union[Scene, Mapping[str, Any]], *, seed: int = 1, eps: Optional[float] = None, fourth_order: bool = False, differenced: bool = False) -> MegnoResult:
    """MEGNO, the Mean Exponential Growth factor of Nearby Orbits (Cincotta &
    Simó 2000), of ``scene``'s trajectory: a fast chaos indicator from one
    tangent vector carried by the tangent map of each step (the scene's
    method and steps, fixed or error-controlled, as for :func:`lyapunov`,
    over its time span). Discrete form (Cincotta, Giordano & Simó 2003):
    ``Y(t_N) = (2/t_N) Σ t_k log(|δ_k| / |δ_{k−1}|)``, ``⟨Y⟩(t_N) = (1/t_N)
    Σ h Y(t_k)`` (``t_k`` from the start, ``h`` the ``k``-th step's size).

    ``seed``: of the random initial tangent vector; ``eps``,
    ``fourth_order``, ``differenced``: the tangent maps, as for
    :func:`lyapunov`.

    Raises :class:`InvalidInputError` (a ``ValueError``) for a bad option or
    a scene with a coordinate method, ``TypeError`` for an argument of the
    wrong type, :class:`IntegrationError` when a step fails; Ctrl-C raises
    ``KeyboardInterrupt``."""
    s = _scene(scene)
    _bools(fourth_order=fourth_order, differenced=differenced)
    raw = _framedyn.megno(s._native, check_int(seed, "seed", 0, _U64_MAX), None if eps is None else _real(eps, "eps"), fourth_order, differenced)
    return MegnoResult(**raw)


def chaos_map(
    scene: Union[Scene, Mapping[str, Any]],
    table: Any,
    *,
    sali: bool = True,
    megno: bool = True,
    gali: Optional[int] = None,
    threshold: float = 1e-8,
    gali_threshold: float = 1e-12,
    gali_quotient: bool = True,
    seed: int = 1,
    eps: Optional[float] = None,
    fourth_order: bool = False,
    threads: Optional[int] = None,
    oversubscribe: bool = False,
    differenced: bool = False,
) -> ChaosMap:
    """SALI, MEGNO and/or GALI_k over initial conditions: every member of ``table``
    on ``scene``, in parallel (Rust threads, GIL released), returned as
    columns (:class:`ChaosMap`) — no Python object per member::

        m = fd.chaos_map(scene, {"initial.r": r, "initial.phi_dot": w}, threshold=1e-8)
        m.chaotic_at, m.megno_mean, m.lyapunov, m.status

    ``table``: the member table of :func:`solve_batch` — a dict of dotted
    scene fields (``initial.position.0``, ``body.J.0.1``, ``method.h``, …)
    to 1-D arrays of equal length N, or a pandas / polars DataFrame. Each
    member is the scene with its row applied, and its values are exactly
    (bit for bit) those of :func:`sali`, :func:`megno` and :func:`gali` on
    that scene alone with the same ``threshold`` (``gali_threshold``,
    ``gali_quotient`` as its ``quotient``), ``seed``, ``eps``,
    ``fourth_order`` and ``differenced``: its method, steps (fixed ``method.h`` or
    ``rtol``/``atol``) and time span.
    ``sali``, ``megno``, ``gali`` (its ``k``, or ``None``): which indicators
    (at least one). ``threads``:
    worker threads (default one per core; never more than the members, nor
    than the cores unless ``oversubscribe=True``).

    A member whose scene is invalid or whose run fails is reported in
    ``status``/``errors`` with NaN in the failed indicator's columns; the
    others are not affected. Raises :class:`InvalidInputError` for a bad
    option or table (naming the field or column), ``TypeError`` for an
    argument of the wrong type; Ctrl-C stops the running members and raises
    ``KeyboardInterrupt``."""
    s = _scene(scene)
    _bools(sali=sali, megno=megno, fourth_order=fourth_order, oversubscribe=oversubscribe, gali_quotient=gali_quotient, differenced=differenced)
    names, cols = table_columns(table)
    raw = _framedyn.chaos_map(
        s._native,
        names,
        cols,
        sali,
        megno,
        check_int(gali, "gali", 2, 10_000, optional=True),
        _real(threshold, "threshold"),
        _real(gali_threshold, "gali_threshold"),
        gali_quotient,
        check_int(seed, "seed", 0, _U64_MAX),
        None if eps is None else _real(eps, "eps"),
        fourth_order,
        check_int(threads, "threads", 1, MAX_THREADS, optional=True),
        oversubscribe,
        differenced,
    )
    status_names = tuple(raw["status_names"])
    codes = np.asarray(raw["status"], dtype=np.uint8)
    return ChaosMap(
        sali=raw["sali"],
        sali_min=raw["sali_min"],
        chaotic_at=raw["chaotic_at"],
        sali_steps=raw["sali_steps"],
        megno=raw["megno"],
        megno_mean=raw["megno_mean"],
        megno_slope=raw["megno_slope"],
        lyapunov=raw["lyapunov"],
        megno_steps=raw["megno_steps"],
        gali_log10=raw["gali_log10"],
        gali_below_at=raw["gali_below_at"],
        gali_steps=raw["gali_steps"],
        status=np.array(status_names)[codes],
        status_codes=codes,
        status_names=status_names,
        errors=tuple(raw["errors"]),
    )
