"""``framedyn.Solution``: the records of a run as numpy arrays."""

from __future__ import annotations

import os
from typing import Any, Dict, List, Mapping, Optional, Sequence, Tuple, Union

import numpy as np

from . import _framedyn
from ._errors import InvalidInputError, OutputError

__all__ = ["Solution", "BatchSolution", "EventRecords"]


class EventRecords:
    """The events located during a run, in time order.

    ``name`` (list), ``index`` (the event's position: scene ``[[events]]``
    first, then the ``events=`` of :func:`framedyn.solve`), ``t`` (located
    times), ``rising``, ``terminal`` (bool arrays) and ``data`` (the record at
    each event, the solution's columns, shape ``(k, columns)``).
    ``times(name)`` gives the times of one event.
    """

    __slots__ = {
        "name": "Event names, one per located event (list of str).",
        "index": "Position of each event's definition: scene ``[[events]]`` first, then ``events=``.",
        "t": "Located times, shape ``(k,)``.",
        "rising": "Whether each crossing was rising (bool array).",
        "terminal": "Whether each event stopped the run (bool array).",
        "data": "The record at each event, the solution's columns, shape ``(k, columns)``.",
    }

    def __init__(self, raw: Optional[Mapping[str, Any]], ncols: int) -> None:
        raw = raw or {}
        self.name: List[str] = list(raw.get("name", []))
        self.index: np.ndarray = np.asarray(raw.get("index", []), dtype=np.int64)
        self.t: np.ndarray = np.asarray(raw.get("t", []), dtype=np.float64)
        self.rising: np.ndarray = np.asarray(raw.get("rising", []), dtype=bool)
        self.terminal: np.ndarray = np.asarray(raw.get("terminal", []), dtype=bool)
        data = raw.get("data")
        self.data: np.ndarray = np.asarray(data, dtype=np.float64) if data is not None else np.empty((0, ncols))

    def times(self, name: str) -> np.ndarray:
        """The located times of the event ``name``."""
        return self.t[[i for i, n in enumerate(self.name) if n == name]]

    def __len__(self) -> int:
        return len(self.name)

    def __repr__(self) -> str:
        return f"EventRecords({len(self)} events)"


class Solution:
    """The records of one run.

    ``data`` is the ``(records, columns)`` array the core produced (no copy);
    every other array is a view into it:

    - ``t``: times, shape ``(n,)``;
    - ``position``, ``velocity``: embedding coordinates, ``(n, E)`` (E = 3;
      4 on S³; H² in Minkowski space ℝ^{2,1});
    - ``frame``: the body frame vectors ``e_A`` in embedding components,
      ``(n, N, E)`` (N = 2 on surfaces, 3 on S³; absent for points):
      ``frame[:, a]`` is the vector ``e_{a+1}`` (the vectors as rows; Rust's
      ``body_frame`` returns them as the columns of an ``E × N`` matrix);
    - ``frame_rate``: affine bodies, the covariant rates ``De_A/Dt``, same shape;
    - ``coordinates``: the paper's chart coordinates and rates by name
      (``r, phi, r_dot, phi_dot`` on S²/H², ``theta, phi, …`` on T²,
      ``r1, r2, r3, …`` on S³; NaN where the chart is singular), plus
      ``alpha`` (gyroscope angle) or ``stretch_*`` (affine bodies);
    - ``momenta``: ``spin`` / ``spin_1..3`` or the hypermomentum ``k_AB``;
    - ``energy``, ``defect``: shape ``(n,)``;
    - ``momentum_maps``: ``p_phi`` (S², H², T²) or ``J_ab`` (S³);
    - ``stats``: steps, rejected steps, vector-field evaluations, wall time,
      energy drift, maximal defect, why the run stopped.

    ``solution["name"]`` gives any column by name; ``columns`` and
    ``units`` describe them.
    """

    __slots__ = {
        "data": "The ``(records, columns)`` array the core produced (no copy); every other array is a view into it.",
        "columns": "Column names of ``data`` (list of str).",
        "units": "Units of the columns: ``L``, ``T``, ``M`` products (list of str).",
        "stats": "Run statistics: steps, rejected steps, vector-field evaluations, wall time, drifts, maximal defect, stop reason.",
        "_index": "Column name → column index.",
        "error": "For a failed member of a batch run with ``on_error=\"keep\"``: the exception, else None.",
        "events": "The located events (:class:`EventRecords`).",
        "groups": "The quantity group of each column (``'position'``, ``'frame'``, …; ``None`` for ``t``), as the core reports it.",
        "frame_shape": "``(N, E)``: body frame vectors and embedding dimension (``(0, E)`` for points).",
    }

    def __init__(
        self,
        data: np.ndarray,
        columns: Sequence[str],
        units: Sequence[str],
        stats: Mapping[str, Any],
        events: Optional[EventRecords] = None,
        groups: Optional[Sequence[Optional[str]]] = None,
        frame_shape: Tuple[int, int] = (0, 0),
    ) -> None:
        self.data: np.ndarray = data
        self.columns: List[str] = list(columns)
        self.units: List[str] = list(units)
        self.groups: List[Optional[str]] = list(groups) if groups is not None else [None] * len(self.columns)
        self.frame_shape: Tuple[int, int] = (int(frame_shape[0]), int(frame_shape[1]))
        self.stats: Dict[str, Any] = dict(stats)
        self._index = {c: i for i, c in enumerate(self.columns)}
        #: For a failed member of a batch run with ``on_error="keep"``: the exception.
        self.error: Optional[BaseException] = None
        #: The located events (:class:`EventRecords`).
        self.events: EventRecords = events if events is not None else EventRecords(None, len(self.columns))

    @classmethod
    def _from_raw(cls, raw: Mapping[str, Any]) -> "Solution":
        return cls(
            raw["data"],
            raw["columns"],
            raw["units"],
            raw["summary"],
            EventRecords(raw.get("events"), len(raw["columns"])),
            raw.get("groups"),
            tuple(raw.get("frame_shape", (0, 0))),
        )

    # -- columns ----------------------------------------------------------------

    def __getitem__(self, name: str) -> np.ndarray:
        try:
            return self.data[:, self._index[name]]
        except KeyError:
            raise KeyError(f"no column {name!r}; columns: {', '.join(self.columns)}") from None

    def __contains__(self, name: object) -> bool:
        return name in self._index

    def __len__(self) -> int:
        return int(self.data.shape[0])

    def unit(self, name: str) -> str:
        """The unit of column ``name`` (in L, T, M)."""
        return self.units[self._index[name]]

    def _in(self, group: str) -> List[int]:
        return [i for i, g in enumerate(self.groups) if g == group]

    def _cols(self, idx: List[int]) -> np.ndarray:
        if not idx:
            return np.empty((len(self), 0))
        if idx == list(range(idx[0], idx[-1] + 1)):
            return self.data[:, idx[0] : idx[-1] + 1]
        return self.data[:, idx]

    @property
    def t(self) -> np.ndarray:
        """Times, shape ``(n,)``."""
        return self["t"]

    @property
    def position(self) -> np.ndarray:
        """Embedding positions, shape ``(n, E)``."""
        return self._cols(self._in("position"))

    @property
    def velocity(self) -> np.ndarray:
        """Embedding velocities, shape ``(n, E)``."""
        return self._cols(self._in("velocity"))

    @property
    def frame(self) -> np.ndarray:
        """Body frame vectors ``e_A`` (embedding components), shape ``(n, N, E)``."""
        idx = self._in("frame")
        if not idx:
            return np.empty((len(self), 0, 0))
        n_vec, n_emb = self.frame_shape
        return self._cols(idx).reshape(len(self), n_vec, n_emb)

    @property
    def frame_rate(self) -> np.ndarray:
        """Affine bodies: the covariant rates ``De_A/Dt`` of the body frame
        vectors (embedding components), shape ``(n, N, E)`` like
        :attr:`frame`; empty for other bodies."""
        idx = self._in("frame_rate")
        if not idx:
            return np.empty((len(self), 0, 0))
        n_vec, n_emb = self.frame_shape
        return self._cols(idx).reshape(len(self), n_vec, n_emb)

    @property
    def coordinates(self) -> Dict[str, np.ndarray]:
        """The paper's coordinates and rates (and ``alpha`` / ``stretch_*``) by name."""
        return {self.columns[i]: self.data[:, i] for i in self._in("coordinates")}

    @property
    def momenta(self) -> Dict[str, np.ndarray]:
        """Momenta of the internal motion (spin, hypermomentum) by name."""
        return {self.columns[i]: self.data[:, i] for i in self._in("momenta")}

    @property
    def momentum_maps(self) -> Dict[str, np.ndarray]:
        """Momentum maps (``p_phi``; ``J_ab`` on S³) by name."""
        return {self.columns[i]: self.data[:, i] for i in self._in("momentum_map")}

    @property
    def energy(self) -> np.ndarray:
        """Total energy ``T + V``, shape ``(n,)``."""
        return self["energy"]

    @property
    def defect(self) -> np.ndarray:
        """Constraint defect, shape ``(n,)``."""
        return self["defect"]

    def drift(self, name: str = "energy") -> np.ndarray:
        """``|q(t) − q(t₀)|`` of the column ``name`` (an invariant)."""
        q = self[name]
        return np.abs(q - q[0])

    def __repr__(self) -> str:
        return f"Solution({len(self)} records, {len(self.columns)} columns, stop={self.stats.get('stop')!r})"

    def __reduce__(self) -> Any:
        return (_rebuild, (self.data, self.columns, self.units, self.stats, self.error, self.events, self.groups, self.frame_shape))

    def save(self, path: Union[str, "os.PathLike[str]"], format: Optional[str] = None) -> None:
        """Writes the records exactly as ``framedyn run`` does (the same
        writer, in Rust): CSV with a header line (``format="csv"``) or a
        numpy ``.npz`` archive with ``data``, ``columns``, ``units``
        (``format="npz"``); by default from the extension of ``path``
        (``.npz``, else CSV). Atomic: a temporary file renamed onto ``path``
        when complete, so a failure leaves any previous file untouched."""
        p = os.fspath(path)
        fmt = format if format is not None else ("npz" if p.lower().endswith(".npz") else "csv")
        if fmt not in ("csv", "npz"):
            raise InvalidInputError(f"invalid `format` = {format!r}: allowed: 'csv', 'npz'")
        data = np.ascontiguousarray(self.data, dtype=np.float64).reshape(len(self), len(self.columns))
        _framedyn.write_records(p, fmt, self.columns, self.units, data)


def _rebuild(
    data: np.ndarray,
    columns: List[str],
    units: List[str],
    stats: Dict[str, Any],
    error: Optional[BaseException],
    events: Optional[EventRecords] = None,
    groups: Optional[List[Optional[str]]] = None,
    frame_shape: Tuple[int, int] = (0, 0),
) -> Solution:
    s = Solution(data, columns, units, stats, events, groups, frame_shape)
    s.error = error
    return s


class BatchSolution(Sequence[Solution]):
    """The solutions of a batch, in order, with stacked arrays.

    Indexing gives the single :class:`Solution`; ``stack(name)`` and the
    properties ``t``, ``position``, ``energy``, … stack the members along a
    new first axis (all members must have the same number of records, as
    with ``output.samples`` or ``output.times``).
    """

    def __init__(self, solutions: Sequence[Solution]) -> None:
        self.solutions: List[Solution] = list(solutions)

    def __getitem__(self, i: Any) -> Any:
        return self.solutions[i]

    def __len__(self) -> int:
        return len(self.solutions)

    def stack(self, attr: str) -> np.ndarray:
        """The attribute or column ``attr`` of every member, stacked:
        shape ``(batch, n, …)``."""
        arrays = [getattr(s, attr) if hasattr(Solution, attr) else s[attr] for s in self.solutions]
        lengths = {a.shape[0] for a in arrays}
        if len(lengths) > 1:
            raise ValueError(
                f"cannot stack `{attr}`: the members have different numbers of records {sorted(lengths)}; "
                "use output.samples or output.times for equal records"
            )
        return np.stack(arrays)

    @property
    def data(self) -> np.ndarray:
        """All records, shape ``(batch, n, columns)``."""
        return self.stack("data")

    @property
    def t(self) -> np.ndarray:
        """Times, shape ``(batch, n)``."""
        return self.stack("t")

    @property
    def position(self) -> np.ndarray:
        """Embedding positions, shape ``(batch, n, E)``."""
        return self.stack("position")

    @property
    def frame(self) -> np.ndarray:
        """Body frames, shape ``(batch, n, N, E)``."""
        return self.stack("frame")

    @property
    def energy(self) -> np.ndarray:
        """Energies, shape ``(batch, n)``."""
        return self.stack("energy")

    @property
    def defect(self) -> np.ndarray:
        """Constraint defects, shape ``(batch, n)``."""
        return self.stack("defect")

    @property
    def errors(self) -> List[Optional[BaseException]]:
        """The exception of each member (``None`` where it succeeded)."""
        return [s.error for s in self.solutions]

    def __repr__(self) -> str:
        return f"BatchSolution({len(self)} runs)"
