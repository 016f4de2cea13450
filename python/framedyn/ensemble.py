"""Ensembles on a Dask cluster: the same batch as :func:`framedyn.solve_batch`,
split into chunks that run on the workers (each chunk in parallel Rust
threads there). Needs the optional dependency ``dask[distributed]``
(``pip install 'framedyn[dask]'``); framedyn must be installed on the workers.

Example::

    from dask.distributed import Client, LocalCluster
    import framedyn as fd
    from framedyn.ensemble import solve_ensemble

    with LocalCluster(n_workers=2, threads_per_worker=1) as cluster, Client(cluster) as client:
        base = fd.Scene.example("s2-gyroscope-pole")
        batch = solve_ensemble(base, [{"initial.r": r} for r in (0.2, 0.4, 0.6, 0.8)], client=client)
        print(batch.energy.shape)

Results are identical to :func:`framedyn.solve_batch` on one machine.

**Columnar ensembles at scale** (:func:`solve_table`): one base scene and a
table of dotted fields (as for ``solve_batch(scene, table)``). The table is
cut into chunks of arrays (no per-member JSON or objects); each task runs
its chunk in Rust and, with ``store=`` a Zarr path (optional dependency
``zarr``), writes its records into the chunked store itself and returns only
the statuses and summaries, so the client's memory does not grow with the
ensemble::

    out = solve_table(base, {"initial.r": r}, client=client, keep="final", store="runs.zarr")
    out.status, out.stats["energy_drift"]        # (N,) arrays on the client
    out.warnings[i], out.warnings.flagged         # quality findings of member i; members with any
    zarr.open_group("runs.zarr")["data"]          # (N, records, columns) on disk

The same code runs on a multi-machine cluster (``Client("tcp://scheduler:8786")``)
when ``store`` is on storage every worker can reach (a shared file system,
or an ``s3://`` / ``gs://`` URL with the matching fsspec package).
"""

from __future__ import annotations

from typing import Any, Dict, Iterable, List, Mapping, Optional, Sequence, Union

import numpy as np

from ._ensemble import EnsembleSolution, MemberWarnings, table_columns
from ._errors import MAX_SAMPLES, MAX_THREADS, InvalidInputError, check_int
from ._scene import Scene, as_scenes
from ._solution import BatchSolution, Solution

__all__ = ["solve_ensemble", "solve_table", "StoredEnsemble", "MemberWarnings"]


def _run_chunk(jsons: List[str], user_potential: Any, threads: Optional[int], user_gradient: Any = None) -> List[Solution]:
    """Runs on a worker: one chunk of the ensemble (failures kept per member)."""
    import framedyn

    scenes = [Scene.from_json(j) for j in jsons]
    return list(
        framedyn.solve_batch(scenes, user_potential=user_potential, user_gradient=user_gradient, threads=threads, on_error="keep")
    )


def solve_ensemble(
    scenes: Union[Scene, Iterable[Scene]],
    params: Optional[Sequence[Mapping[str, Any]]] = None,
    *,
    client: Any = None,
    chunk_size: Optional[int] = None,
    threads_per_task: Optional[int] = 1,
    user_potential: Any = None,
    on_error: str = "raise",
    user_gradient: Any = None,
) -> BatchSolution:
    """Runs the batch (a list of scenes, or one scene and ``params``, as in
    :func:`framedyn.solve_batch`) on the Dask cluster of ``client`` (default:
    the current client).

    ``chunk_size``: members per task (default: spread over twice the
    cluster's worker threads). ``threads_per_task``: Rust threads per task
    (default 1: Dask's worker threads provide the parallelism).
    ``user_potential``, ``user_gradient`` (picklable callables): as for
    :func:`framedyn.solve`. Errors as :func:`framedyn.solve_batch`.
    """
    try:
        from dask.distributed import get_client
    except ImportError as e:  # pragma: no cover - depends on the environment
        raise ImportError("framedyn.ensemble needs dask: pip install 'framedyn[dask]'") from e
    if on_error not in ("raise", "keep"):
        raise InvalidInputError(f"invalid `on_error` = {on_error!r}: allowed: 'raise', 'keep'")
    if chunk_size is not None and (isinstance(chunk_size, bool) or not isinstance(chunk_size, int) or chunk_size < 1):
        raise InvalidInputError(f"invalid `chunk_size` = {chunk_size!r}: must be an int ≥ 1 or None")
    threads_per_task = check_int(threads_per_task, "threads_per_task", 1, MAX_THREADS, optional=True)
    members = as_scenes(scenes, params)
    if client is None:
        client = get_client()
    if chunk_size is None:
        slots = max(1, sum(client.nthreads().values()))
        chunk_size = max(1, -(-len(members) // (2 * slots)))
    jsons = [m.to_json() for m in members]
    chunks = [jsons[i : i + chunk_size] for i in range(0, len(jsons), chunk_size)]
    futures = [client.submit(_run_chunk, c, user_potential, threads_per_task, user_gradient, pure=False) for c in chunks]
    solutions: List[Solution] = [s for part in client.gather(futures) for s in part]
    if on_error == "raise":
        for i, s in enumerate(solutions):
            if s.error is not None:
                try:
                    s.error.index = i  # type: ignore[attr-defined]
                except AttributeError:  # pragma: no cover
                    pass
                raise s.error
    return BatchSolution(solutions)


def _zarr() -> Any:
    """The optional ``zarr`` module, or an ImportError saying how to get it."""
    import importlib

    try:
        return importlib.import_module("zarr")
    except ImportError as e:  # pragma: no cover - depends on the environment
        raise ImportError("a Zarr store needs the optional dependency zarr: pip install zarr") from e


def _table_chunk(base: Any, names: List[str], cols: List[Any], keep: str, samples: Optional[int], threads: Optional[int],
                 store: Optional[str], start: int, user_potential: Any, user_gradient: Any) -> Dict[str, Any]:
    """Runs on a worker: one chunk of a columnar ensemble. With a store, its
    records go into the store's rows ``start:start + n`` and only statuses
    and summaries come back."""
    import warnings

    import framedyn

    # The findings travel back in the result; the client warns once.
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", framedyn.QualityWarning)
        out = framedyn.solve_batch(
            base, dict(zip(names, cols)), keep=keep, samples=samples, threads=threads, on_error="keep",
            user_potential=user_potential, user_gradient=user_gradient,
        )
    part: Dict[str, Any] = {
        # Statuses as codes and errors only where there are any: a chunk of
        # 65,536 members ships arrays, not a Python object per member.
        "status": out.status_codes, "status_names": out.status_names,
        "errored": np.array([i for i, e in enumerate(out.errors) if e is not None], dtype=np.int64),
        "error_texts": [e for e in out.errors if e is not None],
        "stats": out.stats, "columns": out.columns, "units": out.units,
        "groups": out.groups, "frame_shape": out.frame_shape, "method": out.method,
        "exceptions": [None if e is None else repr(e) for e in out.exceptions],
    }
    # The quality warnings of the members that have any (most have none):
    # their indices in the chunk and their findings.
    part["warned"] = out.warnings.flagged
    part["warned_texts"] = [out.warnings[int(i)] for i in out.warnings.flagged]
    if store is None:
        part.update(flat=out.flat, offsets=out.offsets, events=out.events, event_member=out.event_member)
        return part
    zarr = _zarr()
    g = zarr.open_group(store, mode="r+")
    n, records = len(out), g["data"].shape[1]
    if len(out.columns):
        block = np.full((n, records, len(out.columns)), np.nan)
        for i in range(n):
            rows = out.flat[out.offsets[i] : out.offsets[i + 1]][:records]
            block[i, : len(rows)] = rows
        g["data"][start : start + n] = block
    return part


class StoredEnsemble:
    """A columnar ensemble whose records are in a Zarr store: per member
    ``status``, ``errors``, ``stats`` and ``warnings`` (on the client) and
    the store's path; :meth:`open` gives the Zarr group with ``data``
    (``(N, records, columns)``, NaN for members without records),
    ``status``, the summaries, ``warnings`` (strings, each member's findings
    joined by ``"; "``, empty when none) and the ``columns``/``units``
    attributes."""

    __slots__ = {"path": "The Zarr store.", "status": "Per member: how it ended.", "errors": "Per member: message or None.",
                 "stats": "Per-member summaries, a dict of ``(N,)`` arrays.", "columns": "Record columns.",
                 "warnings": "Per member: the quality check's findings (:class:`MemberWarnings`; ``warnings[i]`` is a list of str, "
                             "empty when the run is sound), as ``EnsembleSolution.warnings``."}

    def __init__(self, path: str, status: np.ndarray, errors: List[Optional[str]], stats: Dict[str, np.ndarray], columns: List[str],
                 warnings: Optional[MemberWarnings] = None) -> None:
        self.path, self.status, self.errors, self.stats, self.columns = path, status, errors, stats, columns
        self.warnings: MemberWarnings = warnings if warnings is not None else MemberWarnings(len(status), np.empty(0, np.int64), [])

    def __len__(self) -> int:
        return int(self.status.shape[0])

    @property
    def ok(self) -> np.ndarray:
        """Members that finished or were stopped by an event."""
        return np.isin(self.status, ("finished", "event"))

    def open(self) -> Any:
        """The Zarr group (read-only)."""
        return _zarr().open_group(self.path, mode="r")

    def __repr__(self) -> str:
        return f"StoredEnsemble({len(self)} members in {self.path!r})"


def solve_table(
    scene: Scene,
    table: Any,
    *,
    client: Any = None,
    chunk_size: Optional[int] = None,
    keep: str = "final",
    samples: Optional[int] = None,
    store: Optional[str] = None,
    threads_per_task: Optional[int] = 1,
    user_potential: Any = None,
    user_gradient: Any = None,
) -> Union[EnsembleSolution, "StoredEnsemble"]:
    """The columnar ensemble ``solve_batch(scene, table)`` on a Dask cluster.

    ``chunk_size``: members per task (default: spread over four tasks per
    worker thread, at most 65,536). Without ``store`` the chunks are
    gathered into one :class:`~framedyn.EnsembleSolution`, equal to
    ``solve_batch(scene, table, keep=..., samples=...)`` bit for bit. With
    ``store`` (a Zarr path or URL; needs ``keep="final"`` or ``samples=k``,
    so that every member has the same number of records) each task writes
    its rows into the store and returns only statuses and summaries: a
    :class:`StoredEnsemble`. Failures are per member (as ``on_error="keep"``).
    """
    try:
        from dask.distributed import get_client
    except ImportError as e:  # pragma: no cover - depends on the environment
        raise ImportError("framedyn.ensemble needs dask: pip install 'framedyn[dask]'") from e
    if not isinstance(scene, Scene):
        raise InvalidInputError(f"scene: expected a framedyn.Scene, got {type(scene).__name__}")
    if chunk_size is not None and (isinstance(chunk_size, bool) or not isinstance(chunk_size, int) or chunk_size < 1):
        raise InvalidInputError(f"invalid `chunk_size` = {chunk_size!r}: must be an int ≥ 1 or None")
    if keep not in ("all", "final"):
        raise InvalidInputError(f"invalid `keep` = {keep!r}: allowed: 'all', 'final' (or samples=k)")
    threads_per_task = check_int(threads_per_task, "threads_per_task", 1, MAX_THREADS, optional=True)
    samples = check_int(samples, "samples", 2, MAX_SAMPLES, optional=True)
    if samples is not None:
        keep = "all"
    if store is not None and keep == "all" and samples is None:
        raise InvalidInputError("a Zarr `store` needs keep='final' or samples=k (the same number of records per member)")
    names, cols = table_columns(table)
    n = len(cols[0])
    if any(len(c) != n for c in cols):
        bad = next(nm for nm, c in zip(names, cols) if len(c) != n)
        raise InvalidInputError(f"table column `{bad}`: length differs from `{names[0]}` ({n} members)")
    if client is None:
        client = get_client()
    if chunk_size is None:
        slots = max(1, sum(client.nthreads().values()))
        chunk_size = min(65536, max(1, -(-n // (4 * slots))))
    if store is not None:
        # The column layout of the base scene (a table sets values only, so
        # every member has the same columns).
        zarr = _zarr()
        layout = scene.columns()
        records = 1 if samples is None else int(samples)
        g = zarr.open_group(store, mode="w")
        g.create_array("data", shape=(n, records, len(layout)), chunks=(chunk_size, records, len(layout)), dtype="f8", fill_value=np.nan)
        g.attrs["columns"] = [c for c, _ in layout]
        g.attrs["units"] = [u for _, u in layout]
        g.attrs["table"] = names
    # A key of its own per call (hash=False): with the default content hash,
    # every call on an equal scene scatters to the same key, and when the
    # previous call's future is released while this call replicates it, the
    # scheduler forgets the key and the chunks fail with "lost dependencies"
    # (dask/distributed#8576, #4612).
    base = client.scatter(scene, broadcast=True, hash=False)
    futures = []
    for start in range(0, n, chunk_size):
        part = [c[start : start + chunk_size] for c in cols]
        futures.append(client.submit(_table_chunk, base, names, part, keep, samples, threads_per_task, store, start,
                                     user_potential, user_gradient, pure=False))
    parts = client.gather(futures)
    status_codes = np.concatenate([p["status"] for p in parts]).astype(np.uint8)
    starts = np.cumsum([0] + [len(p["status"]) for p in parts[:-1]])
    errors: List[Optional[str]] = [None] * n
    for p, k in zip(parts, starts):
        for i, text in zip(p["errored"], p["error_texts"]):
            errors[int(k + i)] = text
    warned = MemberWarnings(
        n,
        np.concatenate([p["warned"] + k for p, k in zip(parts, starts)]) if parts else np.empty(0, np.int64),
        [w for p in parts for w in p["warned_texts"]],
    )
    stats = {k: np.concatenate([p["stats"][k] for p in parts]) for k in parts[0]["stats"]}
    columns: List[str] = next((p["columns"] for p in parts if p["columns"]), [])
    names_of_status: List[str] = parts[0]["status_names"]
    status = np.array(names_of_status)[status_codes]
    found = warned.summary()
    if found:
        import warnings

        from ._errors import QualityWarning

        warnings.warn(QualityWarning(f"solve_table: {found}"), stacklevel=2)
    if store is not None:
        g = _zarr().open_group(store, mode="r+")
        st = g.create_array("status", shape=(n,), chunks=(chunk_size,), dtype="i1")
        st[:] = status_codes.astype(np.int8)
        g.attrs["status_names"] = names_of_status
        for k, v in stats.items():
            g.create_array(k, shape=(n,), chunks=(chunk_size,), dtype="f8")[:] = v
        texts = g.create_array("warnings", shape=(n,), chunks=(chunk_size,), dtype=str, fill_value="")
        if len(warned.flagged):
            texts.set_coordinate_selection(warned.flagged, np.array(["; ".join(warned[int(i)]) for i in warned.flagged], dtype=object))
        return StoredEnsemble(store, status, errors, stats, columns, warned)
    flat = np.concatenate([p["flat"] for p in parts]) if parts else np.empty((0, 0))
    offsets = [0]
    for p in parts:
        base_row = offsets[-1]
        offsets.extend(base_row + int(o) for o in p["offsets"][1:])
    ev_rows = [p["events"] for p in parts]
    raw = {
        "data": flat if flat.size else flat.reshape(0, len(columns)), "offsets": np.asarray(offsets, dtype=np.int64),
        "columns": columns, "units": next((p["units"] for p in parts if p["columns"]), []),
        "groups": next((p["groups"] for p in parts if p["columns"]), []),
        "frame_shape": next((p["frame_shape"] for p in parts if p["columns"]), (0, 0)),
        "status_names": names_of_status,
        "status": status_codes,
        "errors": errors, "exceptions": [None] * n, "warned": warned.flagged, "warned_texts": [warned[int(i)] for i in warned.flagged], "summary": stats, "method": parts[0]["method"] if parts else None,
        "events": {
            "member": np.concatenate([p["event_member"] + k for p, k in zip(parts, starts)]) if parts else np.empty(0, np.int64),
            "index": np.concatenate([e.index for e in ev_rows]) if parts else np.empty(0, np.int64),
            "name": [nm for e in ev_rows for nm in e.name],
            "t": np.concatenate([e.t for e in ev_rows]) if parts else np.empty(0),
            "rising": np.concatenate([e.rising for e in ev_rows]) if parts else np.empty(0, bool),
            "terminal": np.concatenate([e.terminal for e in ev_rows]) if parts else np.empty(0, bool),
            "data": np.concatenate([e.data for e in ev_rows]) if parts else None,
        },
    }
    return EnsembleSolution(raw)
