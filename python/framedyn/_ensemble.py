"""Columnar ensembles: ``framedyn.solve_batch(scene, table)`` with a table of
dotted scene fields, and its result :class:`EnsembleSolution` (stacked
arrays with the member as the leading dimension)."""

from __future__ import annotations

import collections.abc
from typing import Any, Dict, Iterator, List, Mapping, Optional, Tuple, overload

import numpy as np

from ._errors import InvalidInputError
from ._solution import EventRecords, Solution

__all__ = ["EnsembleSolution", "MemberWarnings", "table_columns"]


def table_columns(table: Any) -> Tuple[List[str], List[np.ndarray]]:
    """The names and float64 columns of a table: a mapping of dotted field
    names to 1-D arrays (or sequences), or a pandas / polars DataFrame.
    Dtypes are checked here (numbers only; booleans, strings and objects are
    refused, naming the column); names, lengths and values are checked in
    Rust, once for the whole table."""
    if hasattr(table, "to_dict") and hasattr(table, "columns") and not isinstance(table, Mapping):
        # pandas or polars DataFrame: one numpy array per column.
        items = [(str(c), np.asarray(table[c])) for c in table.columns]
    elif isinstance(table, Mapping):
        items = list(table.items())
    else:
        raise InvalidInputError(
            f"table: expected a dict of dotted field names to 1-D arrays (or a pandas/polars DataFrame), got {type(table).__name__}"
        )
    if not items:
        raise InvalidInputError("table: no columns; give at least one dotted scene field, e.g. {'initial.r': array}")
    names: List[str] = []
    cols: List[np.ndarray] = []
    for name, values in items:
        if not isinstance(name, str) or not name:
            raise InvalidInputError(f"table: column name {name!r} must be a non-empty dotted path such as 'initial.r'")
        a = np.asarray(values)
        if a.ndim != 1:
            raise InvalidInputError(f"table column `{name}`: shape {a.shape}; allowed: a 1-D array (one value per member)")
        if a.dtype.kind not in "iuf":
            raise InvalidInputError(f"table column `{name}`: dtype {a.dtype}; allowed: integer or floating-point numbers")
        names.append(name)
        # Contiguous and aligned (arrays unpickled from a byte buffer, as on
        # Dask workers, may be unaligned).
        cols.append(np.require(a, dtype=np.float64, requirements=["C", "A"]))
    return names, cols


class MemberWarnings(collections.abc.Sequence):  # type: ignore[type-arg]
    """The quality warnings of every member of an ensemble, kept only for
    the members that have any: ``w[i]`` is member ``i``'s findings (a list
    of str, empty when its run is sound), as ``EnsembleSolution.warnings[i]``;
    ``flagged`` the indices of the members with warnings; ``list(w)`` the
    list of lists ``solve_batch`` gives."""

    __slots__ = {"flagged": "Indices of the members with warnings, ascending ``(k,)`` int64.", "_n": "Members.", "_texts": "Member index → findings."}

    def __init__(self, n: int, flagged: np.ndarray, texts: List[List[str]]) -> None:
        order = np.argsort(flagged, kind="stable")
        self.flagged: np.ndarray = np.asarray(flagged, dtype=np.int64)[order]
        self._n = int(n)
        self._texts: Dict[int, List[str]] = {int(self.flagged[k]): list(texts[int(j)]) for k, j in enumerate(order)}

    def __len__(self) -> int:
        return self._n

    @overload
    def __getitem__(self, i: int) -> List[str]: ...

    @overload
    def __getitem__(self, i: slice) -> List[List[str]]: ...

    def __getitem__(self, i: Any) -> Any:
        if isinstance(i, slice):
            return [self[k] for k in range(*i.indices(self._n))]
        if isinstance(i, bool) or not isinstance(i, (int, np.integer)) or not -self._n <= int(i) < self._n:
            raise IndexError(f"member index {i!r} out of range for {self._n} members")
        return list(self._texts.get(int(i) % self._n, []))

    def __iter__(self) -> Iterator[List[str]]:
        for i in range(self._n):
            yield list(self._texts.get(i, []))

    def __eq__(self, other: object) -> bool:
        if isinstance(other, MemberWarnings):
            return self._n == other._n and self._texts == other._texts
        if isinstance(other, collections.abc.Sequence) and not isinstance(other, (str, bytes)):
            return len(other) == self._n and all(list(a) == b for a, b in zip(other, self))
        return NotImplemented

    __hash__ = None  # type: ignore[assignment]

    def __repr__(self) -> str:
        return f"MemberWarnings({len(self.flagged)} of {self._n} members with warnings)"

    def summary(self) -> Optional[str]:
        """One line for a :class:`~framedyn.QualityWarning`: how many members
        failed the quality check and the findings of the first; None when
        none did."""
        if not len(self.flagged):
            return None
        first = int(self.flagged[0])
        return (
            f"{len(self.flagged)} of {self._n} members failed the quality check (out.warnings, out.warnings.flagged); "
            f"member {first}: " + "; ".join(self[first])
        )


class EnsembleSolution:
    """The records of every member of an ensemble, in one array.

    With the same number of records per member (fixed steps, ``samples=k``
    or ``keep="final"``), the arrays are stacked with the member first:

    - ``data``: ``(N, records, columns)``;
    - ``t``, ``energy``, ``defect``, ``solution["name"]``: ``(N, records)``;
    - ``position``, ``velocity``: ``(N, records, E)``; ``frame``,
      ``frame_rate``: ``(N, records, N_frame, E)``;
    - ``final``: ``(N, columns)``, each member's last record (NaN for a
      member without records).

    Otherwise (adaptive steps) the stacked views raise; ``flat``
    (``(total records, columns)``), ``offsets`` (member ``i`` is rows
    ``offsets[i]:offsets[i+1]``), ``member_index`` (the member of each row)
    and :meth:`member` give every record.

    Per member: ``status`` (``'finished'``, ``'event'``, ``'cancelled'``,
    ``'failed'``, ``'invalid'``), ``ok`` (finished or stopped by an event),
    ``errors`` (message or None), ``exceptions`` (the exception a member's
    user potential raised, or None), ``warnings`` (the quality check's
    findings, a list of str, empty when the run is sound: energy drift or
    defect over the scene's ``[quality]`` limits, non-finite energy),
    ``stats`` (a dict of ``(N,)`` arrays: steps, energy_drift, max_defect,
    t_reached, …; ``global_error`` and ``global_error_final``, NaN unless the
    scene sets ``[method] global_error = true``). Events: ``events`` (all
    members' located events, flat) with ``event_member`` (the member of each).
    """

    __slots__ = {
        "flat": "All records, ``(total records, columns)``.",
        "offsets": "Record offsets, ``(N + 1,)``: member ``i`` is ``flat[offsets[i]:offsets[i+1]]``.",
        "columns": "Column names (list of str).",
        "units": "Units of the columns.",
        "groups": "Quantity group of each column.",
        "frame_shape": "``(N_frame, E)``.",
        "status": "Per member: how it ended, ``(N,)`` array of str.",
        "status_names": "The statuses the core reports, in the order of their codes.",
        "status_codes": "Per member: the index of its status in ``status_names``, ``(N,)`` uint8.",
        "errors": "Per member: the error message, or None.",
        "exceptions": "Per member: the exception its user potential raised, or None.",
        "warnings": "Per member: the quality check's findings (:class:`MemberWarnings`: ``warnings[i]`` is a list of str, empty when the run is sound).",
        "stats": "Per-member run statistics, a dict of ``(N,)`` arrays.",
        "method": "The method's name.",
        "events": "The located events of all members (:class:`EventRecords`).",
        "event_member": "The member of each located event, ``(k,)``.",
        "_index": "Column name → index.",
    }

    def __init__(self, raw: Mapping[str, Any]) -> None:
        self.flat: np.ndarray = raw["data"]
        self.offsets: np.ndarray = raw["offsets"]
        self.columns: List[str] = list(raw["columns"])
        self.units: List[str] = list(raw["units"])
        self.groups: List[Optional[str]] = list(raw["groups"])
        self.frame_shape: Tuple[int, int] = tuple(raw["frame_shape"])  # type: ignore[assignment]
        self.status_names: List[str] = list(raw["status_names"])
        self.status_codes: np.ndarray = np.asarray(raw["status"], dtype=np.uint8)
        self.status: np.ndarray = np.array(self.status_names)[self.status_codes]
        self.errors: List[Optional[str]] = list(raw["errors"])
        self.exceptions: List[Optional[BaseException]] = list(raw["exceptions"])
        self.warnings = MemberWarnings(len(self.offsets) - 1, np.asarray(raw["warned"], dtype=np.int64), raw["warned_texts"])
        self.stats: Dict[str, np.ndarray] = dict(raw["summary"])
        self.method: Optional[str] = raw["method"]
        ev = raw["events"]
        self.events = EventRecords(ev, len(self.columns))
        self.event_member: np.ndarray = ev["member"]
        self._index = {c: i for i, c in enumerate(self.columns)}

    def __len__(self) -> int:
        return int(self.offsets.shape[0] - 1)

    @property
    def ok(self) -> np.ndarray:
        """Members that finished or were stopped by an event, ``(N,)`` bool."""
        return np.isin(self.status, ("finished", "event"))

    @property
    def records(self) -> np.ndarray:
        """Records per member, ``(N,)``."""
        return np.diff(self.offsets)

    @property
    def member_index(self) -> np.ndarray:
        """The member of each row of ``flat``."""
        return np.repeat(np.arange(len(self)), self.records)

    def _uniform(self) -> int:
        r = self.records
        if len(r) and np.all(r == r[0]):
            return int(r[0])
        raise InvalidInputError(
            "the members have different numbers of records (adaptive steps, failures or events); "
            "use `flat`, `offsets` and `member(i)`, or run with samples=k or keep='final'"
        )

    @property
    def data(self) -> np.ndarray:
        """All records, ``(N, records, columns)`` (a view of ``flat``)."""
        return self.flat.reshape(len(self), self._uniform(), len(self.columns))

    def __getitem__(self, name: str) -> np.ndarray:
        try:
            j = self._index[name]
        except KeyError:
            raise KeyError(f"no column {name!r}; columns: {', '.join(self.columns)}") from None
        return self.data[:, :, j]

    def _group(self, group: str) -> np.ndarray:
        idx = [i for i, g in enumerate(self.groups) if g == group]
        return self.data[:, :, idx]

    @property
    def t(self) -> np.ndarray:
        """Times, ``(N, records)``."""
        return self["t"]

    @property
    def position(self) -> np.ndarray:
        """Embedding positions, ``(N, records, E)``."""
        return self._group("position")

    @property
    def velocity(self) -> np.ndarray:
        """Embedding velocities, ``(N, records, E)``."""
        return self._group("velocity")

    def _vectors(self, group: str) -> np.ndarray:
        """A group of frame-shaped columns as ``(N, records, N_frame, E)``."""
        a = self._group(group)
        shape = self.frame_shape if a.shape[2] else (0, 0)
        return a.reshape(a.shape[0], a.shape[1], *shape)

    @property
    def frame(self) -> np.ndarray:
        """Body frame vectors, ``(N, records, N_frame, E)``."""
        return self._vectors("frame")

    @property
    def frame_rate(self) -> np.ndarray:
        """Affine bodies: ``De_A/Dt``, ``(N, records, N_frame, E)``."""
        return self._vectors("frame_rate")

    @property
    def energy(self) -> np.ndarray:
        """Energy, ``(N, records)``."""
        return self["energy"]

    @property
    def defect(self) -> np.ndarray:
        """Constraint defect, ``(N, records)``."""
        return self["defect"]

    @property
    def final(self) -> np.ndarray:
        """Each member's last record, ``(N, columns)`` (NaN rows for members
        without records)."""
        out = np.full((len(self), len(self.columns)), np.nan)
        has = self.records > 0
        out[has] = self.flat[self.offsets[1:][has] - 1]
        return out

    def member(self, i: int) -> Solution:
        """Member ``i`` as a :class:`Solution` (views, no copy)."""
        n = len(self)
        if not isinstance(i, (int, np.integer)) or isinstance(i, bool) or not -n <= int(i) < n:
            raise InvalidInputError(f"invalid member index {i!r}: allowed: an int in [{-n}, {n})")
        i = int(i) % n
        stats = {k: v[i].item() for k, v in self.stats.items()}
        stats["stop"] = str(self.status[i])
        stats["method"] = self.method
        sol = Solution(self.flat[self.offsets[i] : self.offsets[i + 1]], self.columns, self.units, stats, None, self.groups, self.frame_shape)
        exc = self.exceptions[i]
        if exc is None and self.errors[i] is not None:
            exc = RuntimeError(self.errors[i])
        sol.error = exc
        return sol

    def __repr__(self) -> str:
        counts = {s: int(np.sum(self.status == s)) for s in np.unique(self.status)}
        return f"EnsembleSolution({len(self)} members, {len(self.flat)} records, {counts})"
