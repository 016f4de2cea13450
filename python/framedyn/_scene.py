"""``framedyn.Scene``: a whole simulation described by data.

A scene is the same description the command-line tool reads from TOML or
JSON (see ``framedyn scenes show NAME`` and the crate docs of
``framedyn::scenes``): ``manifold``, ``body``, ``potential``, ``initial``,
``method``, ``time`` and ``output`` tables. Every table rejects unknown
fields and every bad value is reported with the field's path, the value and
what is allowed.
"""

from __future__ import annotations

import copy
import json
import math
import os
from typing import Any, Dict, Iterable, List, Mapping, Optional, Sequence, Tuple, Union

import numpy as np

from . import _framedyn
from ._errors import InvalidInputError, OutputError

__all__ = ["Scene", "INITIAL_FIELDS"]

#: The names of the initial-state fields, read from the core: every
#: manifold's chart coordinates as it names them (``r, phi`` on S², H²;
#: ``theta, phi`` on T²; ``r1, r2, r3`` on S³; …) with their rates ``*_dot``,
#: then the fixed fields ``position``, ``velocity``, ``frame``, ``alpha``,
#: ``orientation``, ``spin``, ``omega``, ``rho``, ``rho_dot``.
def _initial_fields() -> Tuple[str, ...]:
    coords: List[str] = []
    for spec in _framedyn.manifolds().values():
        for c in spec["coordinates"]:
            if c not in coords:
                coords.append(c)
    return tuple(coords) + tuple(f"{c}_dot" for c in coords) + tuple(_framedyn.initial_fields())


INITIAL_FIELDS: Tuple[str, ...] = _initial_fields()

# Expected array ranks of the array-valued fields (None: a number or a vector).
_ARRAY_RANK = {
    "position": 1, "velocity": 1, "centre": 1, "frame": 2, "rho": 2, "rho_dot": 2,
    "J": 2, "orientation": 1, "times": 1, "spin": None, "omega": None,
}

PathLike = Union[str, "os.PathLike[str]"]


def _plain(value: Any, path: str) -> Any:
    """``value`` as JSON-ready Python data; numpy arrays and scalars become
    lists and floats. Non-finite numbers, wrong dtypes and wrong ranks raise
    :class:`InvalidInputError` naming ``path``."""
    if isinstance(value, Mapping):
        out = {}
        for k, v in value.items():
            if not isinstance(k, str):
                raise InvalidInputError(f"{path}: key {k!r} is not a string")
            out[k] = _plain(v, f"{path}.{k}" if path else k)
        return out
    if isinstance(value, (str, bool)) or value is None:
        return value
    if isinstance(value, (int, np.integer)):
        return int(value)
    if isinstance(value, (float, np.floating)):
        x = float(value)
        if not math.isfinite(x):
            raise InvalidInputError(f"invalid `{path}` = {x}: must be finite")
        return x
    if isinstance(value, (list, tuple, np.ndarray)):
        name = path.rsplit(".", 1)[-1]
        if name in ("terms",) or (isinstance(value, (list, tuple)) and any(isinstance(v, (Mapping, str)) for v in value)):
            return [_plain(v, f"{path}[{i}]") for i, v in enumerate(value)]
        if isinstance(value, np.ndarray) and value.dtype.kind not in "fiu":
            raise InvalidInputError(f"invalid `{path}`: dtype {value.dtype} is not a real number type (float or int)")
        try:
            arr = np.asarray(value, dtype=np.float64)
        except (TypeError, ValueError) as e:
            raise InvalidInputError(f"invalid `{path}`: expected numbers (float64) ({e})") from None
        rank = _ARRAY_RANK.get(name, "any")
        if rank is not None and rank != "any" and arr.ndim != rank:
            raise InvalidInputError(f"invalid `{path}`: shape {arr.shape} must be {'a vector (1-D)' if rank == 1 else 'a matrix (2-D, rows)'}")
        if rank is None and arr.ndim > 1:
            raise InvalidInputError(f"invalid `{path}`: shape {arr.shape} must be a number or a vector")
        bad = ~np.isfinite(arr)
        if bad.any():
            idx = tuple(int(i) for i in np.argwhere(bad)[0])
            raise InvalidInputError(f"invalid `{path}{''.join(f'[{i}]' for i in idx)}` = {arr[idx]}: must be finite")
        return arr.tolist()
    raise InvalidInputError(f"invalid `{path}`: a {type(value).__name__} is not allowed here (numbers, strings, arrays or tables)")


def _table(value: Any, key: str, path: str) -> Dict[str, Any]:
    """A table given as a dict, or a bare string meaning ``{key: value}``."""
    if isinstance(value, str):
        return {key: value}
    if isinstance(value, Mapping):
        return dict(value)
    raise InvalidInputError(f"invalid `{path}`: a {type(value).__name__}; allowed: a string ({key}) or a dict")


def _set_path(d: Dict[str, Any], dotted: str, value: Any) -> None:
    parts = dotted.split(".")
    for p in parts[:-1]:
        nxt = d.get(p)
        if nxt is None:
            nxt = d[p] = {}
        if not isinstance(nxt, dict):
            raise InvalidInputError(f"invalid parameter path `{dotted}`: `{p}` is not a table")
        d = nxt
    d[parts[-1]] = value


class Scene:
    """A scene (immutable): manifold, body, potential, initial state, method,
    time span and output.

    Build it from a file or text (:meth:`from_toml`, :meth:`from_json`,
    :meth:`load`), from a dict (:meth:`from_dict`), from an embedded example
    (:meth:`example`), or with keywords named as in the paper::

        scene = framedyn.Scene(
            manifold={"kind": "S2", "radius": 1.0},
            body={"kind": "gyroscope", "inertia": 0.2},
            potential={"kind": "cosine", "beta_hat": -0.3},
            r=0.6, phi=0.0, r_dot=-1.0, spin=0.02,   # the paper's (r, φ), ṙ, spin
            method="rk4", h=0.005, t_end=4.0,
        )

    ``manifold``, ``body``, ``potential`` and ``method`` take a dict or just
    the kind / method name. Initial-state keywords (:data:`INITIAL_FIELDS`)
    go to ``initial``; ``h``, ``rtol``, ``atol``, ``max_steps``, ``global_error``, ``project`` to ``method``;
    ``t0``, ``t_end`` (or ``t_span=(t0, t_end)``) to ``time``; ``every``,
    ``times``, ``samples``, ``quantities`` to ``output``. Arrays may be numpy
    arrays; their shapes, dtypes and finiteness are checked, and every error
    names the field.
    """

    __slots__ = ("_native",)
    _native: "_framedyn.Scene"

    def __init__(
        self,
        manifold: Union[str, Mapping[str, Any], None] = None,
        body: Union[str, Mapping[str, Any], None] = None,
        *,
        potential: Union[str, Mapping[str, Any], None] = None,
        initial: Optional[Mapping[str, Any]] = None,
        method: Union[str, Mapping[str, Any], None] = None,
        t_span: Optional[Tuple[float, float]] = None,
        output: Optional[Mapping[str, Any]] = None,
        name: Optional[str] = None,
        description: Optional[str] = None,
        **fields: Any,
    ) -> None:
        if manifold is None or body is None:
            raise InvalidInputError("Scene: `manifold` and `body` are required (or use Scene.from_toml / from_dict / example)")
        d: Dict[str, Any] = {
            "manifold": _table(manifold, "kind", "manifold"),
            "body": _table(body, "kind", "body"),
        }
        if potential is not None:
            d["potential"] = _table(potential, "kind", "potential")
        d["initial"] = dict(initial) if initial is not None else {}
        d["method"] = _table(method, "name", "method") if method is not None else {}
        d["time"] = {}
        d["output"] = dict(output) if output is not None else {}
        if t_span is not None:
            try:
                t0, t1 = t_span
            except (TypeError, ValueError):
                raise InvalidInputError(f"invalid `t_span` = {t_span!r}: must be a pair (t0, t_end)") from None
            d["time"].update(t0=t0, t_end=t1)
        for k, v in fields.items():
            if k in INITIAL_FIELDS:
                d["initial"][k] = v
            elif k in ("h", "rtol", "atol", "max_steps", "global_error", "project"):
                d["method"][k] = v
            elif k in ("t0", "t_end"):
                if t_span is not None:
                    raise InvalidInputError(f"`{k}`: give either t_span or t0/t_end, not both")
                d["time"][k] = v
            elif k in ("every", "times", "samples", "quantities", "format", "path"):
                d["output"][k] = v
            else:
                raise InvalidInputError(
                    f"Scene: unknown keyword `{k}`; allowed: the initial-state fields {', '.join(INITIAL_FIELDS)}, "
                    "h, rtol, atol, max_steps, global_error, project, t0, t_end, every, times, samples, quantities, format, path"
                )
        for k in ("method", "output"):
            if not d[k]:
                del d[k]
        if name is not None:
            d["name"] = name
        if description is not None:
            d["description"] = description
        self._native = Scene.from_dict(d)._native

    # -- constructors ---------------------------------------------------------

    @classmethod
    def _wrap(cls, native: "_framedyn.Scene") -> "Scene":
        obj = cls.__new__(cls)
        obj._native = native
        return obj

    @classmethod
    def from_toml(cls, text: str) -> "Scene":
        """Parses a TOML scene (errors give the field, value, allowed range,
        line and column)."""
        if not isinstance(text, str):
            raise InvalidInputError(f"from_toml: `text` must be a str, got {type(text).__name__}")
        return cls._wrap(_framedyn.Scene.from_toml(text))

    @classmethod
    def from_json(cls, text: str) -> "Scene":
        """Parses a JSON scene (same fields as TOML)."""
        if not isinstance(text, str):
            raise InvalidInputError(f"from_json: `text` must be a str, got {type(text).__name__}")
        return cls._wrap(_framedyn.Scene.from_json(text))

    @classmethod
    def from_dict(cls, d: Mapping[str, Any]) -> "Scene":
        """A scene from a dict with the tables of a scene file (numpy arrays
        allowed; checked for shape, dtype and finiteness)."""
        if not isinstance(d, Mapping):
            raise InvalidInputError(f"from_dict: expected a dict, got {type(d).__name__}")
        return cls._wrap(_framedyn.Scene.from_json(json.dumps(_plain(d, ""), indent=1)))

    @classmethod
    def load(cls, path: PathLike) -> "Scene":
        """Reads a scene file: JSON if it ends in ``.json``, else TOML."""
        try:
            p = os.fspath(path)
        except TypeError:
            raise InvalidInputError(f"Scene.load: invalid `path` = {path!r}: a {type(path).__name__}; allowed: a str or os.PathLike") from None
        try:
            with open(p, "rb") as f:
                data = f.read()
        except OSError as e:
            raise OutputError(e.errno, f"Scene.load: cannot read the scene file `path` = {p!r}: {e.strerror or e}", p) from e
        try:
            text = data.decode("utf-8")
        except UnicodeDecodeError as e:
            raise InvalidInputError(f"Scene.load: the scene file {p!r} is not UTF-8 text (invalid byte at offset {e.start})") from None
        return cls.from_json(text) if p.lower().endswith(".json") else cls.from_toml(text)

    @classmethod
    def example(cls, name: str) -> "Scene":
        """The embedded example scene ``name`` (see :meth:`examples`)."""
        return cls._wrap(_framedyn.Scene.example(name))

    @staticmethod
    def examples() -> List[str]:
        """The names of the embedded example scenes."""
        return list(_framedyn.Scene.example_names())

    # -- views ----------------------------------------------------------------

    def to_dict(self) -> Dict[str, Any]:
        """The scene as a dict (a fresh copy)."""
        return json.loads(self._native.to_json())

    def to_json(self) -> str:
        """The scene as JSON."""
        return self._native.to_json()

    def to_toml(self) -> str:
        """The scene as TOML."""
        return self._native.to_toml()

    def validate(self) -> "Scene":
        """Checks everything a run checks, without running; returns ``self``."""
        self._native.validate()
        return self

    def columns(self) -> List[Tuple[str, str]]:
        """``(name, unit)`` of each output column of a run."""
        return [(c[0], c[1]) for c in self._native.columns()]

    def replace(self, **changes: Any) -> "Scene":
        """A copy with fields changed; keys are dotted paths with ``.``
        written as ``__`` (``initial__r=0.3``) or passed through
        :meth:`with_params`."""
        return self.with_params({k.replace("__", "."): v for k, v in changes.items()})

    def with_params(self, params: Mapping[str, Any]) -> "Scene":
        """A copy with the dotted paths in ``params`` set, e.g.
        ``{"initial.r": 0.3, "potential.kappa": 2.0}``."""
        if not isinstance(params, Mapping):
            raise InvalidInputError(f"params: expected a dict of dotted paths, got {type(params).__name__}")
        d = self.to_dict()
        for k, v in params.items():
            if not isinstance(k, str) or not k:
                raise InvalidInputError(f"params: key {k!r} must be a non-empty dotted path such as 'initial.r'")
            _set_path(d, k, copy.deepcopy(v))
        return Scene.from_dict(d)

    @property
    def name(self) -> Optional[str]:
        """The scene's name, if any."""
        return self.to_dict().get("name")

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, Scene):
            return NotImplemented
        return bool(self._native == other._native)

    def __hash__(self) -> int:
        return hash(self.to_json())

    def __repr__(self) -> str:
        d = self.to_dict()
        return f"Scene(name={d.get('name')!r}, manifold={d['manifold']}, body={d['body']})"

    def __reduce__(self) -> Tuple[Any, Tuple[str]]:
        # Pickled as JSON (for multiprocessing and Dask).
        return (Scene.from_json, (self.to_json(),))


def as_scenes(scenes: Union[Scene, Iterable[Scene]], params: Optional[Sequence[Mapping[str, Any]]], what: str = "scenes") -> List[Scene]:
    """The list of scenes of a batch: a list of scenes, or one scene and a
    list of parameter sets (dotted paths)."""
    if isinstance(scenes, Scene):
        if params is None:
            return [scenes]
        if isinstance(params, Mapping):
            raise InvalidInputError("params: expected a list of dicts (one per run), got one dict")
        return [scenes.with_params(p) for p in params]
    if params is not None:
        raise InvalidInputError("params: give a single base scene together with params, not a list of scenes")
    if isinstance(scenes, (str, bytes, Mapping)) or not isinstance(scenes, Iterable):
        raise InvalidInputError(f"invalid `{what}`: a {type(scenes).__name__}; allowed: a framedyn.Scene or a list of them")
    out = list(scenes)
    for i, s in enumerate(out):
        if not isinstance(s, Scene):
            raise InvalidInputError(f"{what}[{i}]: expected a framedyn.Scene, got {type(s).__name__}")
    return out
