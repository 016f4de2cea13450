"""Exception classes raised by framedyn.

Every error raised by the Rust core arrives as one of these, carrying the
Rust message (which names the offending field, its value and the allowed
range). They subclass the built-in exception a Python user would expect, so
``except ValueError`` keeps working.
"""

from __future__ import annotations

import struct
from typing import Any, Optional, overload

__all__ = [
    "FramedynError",
    "InvalidInputError",
    "IntegrationError",
    "OutputError",
    "InternalError",
]


class FramedynError(Exception):
    """Base class of every framedyn error."""


class InvalidInputError(FramedynError, ValueError):
    """Invalid input: a scene field, parameter, array shape or dtype, or a NaN."""


class IntegrationError(FramedynError, RuntimeError):
    """The integration failed (step-size underflow, non-finite state, ...).

    ``partial`` holds the :class:`framedyn.Solution` computed up to the last
    good state (``None`` if the failure happened before the first step).
    """

    partial: Optional[Any]

    def __init__(self, *args: object) -> None:
        super().__init__(*args)
        self.partial = None


class OutputError(FramedynError, OSError):
    """Reading a scene file or writing an output file failed."""


class QualityWarning(UserWarning):
    """A run finished, but its summary failed the quality check: the energy
    drift or constraint defect exceeds the scene's ``[quality]`` limits
    (default 1e-3 relative, 1e-9), or the energy or defect is not finite.
    The records are complete; ``solution.stats["warnings"]`` lists the
    findings. Turn it into an error with
    ``warnings.simplefilter("error", framedyn.QualityWarning)``."""


class InternalError(FramedynError, RuntimeError):
    """A bug in framedyn (a Rust panic caught at the boundary): please report it."""


#: The largest value of Rust's ``usize`` on this machine (a count handed to
#: the core, such as ``Stepper.advance``'s ``n``).
USIZE_MAX = 2 ** (8 * struct.calcsize("P")) - 1

#: The largest thread count (``EnsembleOptions::MAX_THREADS`` in Rust).
MAX_THREADS = 1024

#: The largest ``samples`` (the core's limit on ``output.samples``).
MAX_SAMPLES = 10**8


def _bound(n: int) -> str:
    return "2**64 - 1" if n == 2**64 - 1 else "2**32 - 1" if n == 2**32 - 1 else f"{n:_}" if n >= 10**5 else str(n)


@overload
def check_int(value: Any, name: str, lo: int, hi: int) -> int: ...


@overload
def check_int(value: Any, name: str, lo: int, hi: int, *, optional: bool) -> Optional[int]: ...


def check_int(value: Any, name: str, lo: int, hi: int, *, optional: bool = False) -> Optional[int]:
    """``value`` as an int if it is one (Python or numpy, not a bool) in
    ``[lo, hi]``; else an :class:`InvalidInputError` naming the argument and
    the range. Every integer argument that reaches the Rust core goes through
    here, so that none raises ``OverflowError`` there."""
    import numpy as np

    if optional and value is None:
        return None
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, (int, np.integer)) or not lo <= int(value) <= hi:
        kind = "" if isinstance(value, (int, np.integer)) and not isinstance(value, (bool, np.bool_)) else f" (a {type(value).__name__})"
        raise InvalidInputError(
            f"invalid `{name}` = {value!r}{kind}: must be an int in [{_bound(lo)}, {_bound(hi)}]" + (" or None" if optional else "")
        )
    return int(value)
