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
"""

from __future__ import annotations

from typing import Any, Iterable, List, Mapping, Optional, Sequence, Union

from ._errors import InvalidInputError
from ._scene import Scene, as_scenes
from ._solution import BatchSolution, Solution

__all__ = ["solve_ensemble"]


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
