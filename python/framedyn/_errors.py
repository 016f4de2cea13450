"""Exception classes raised by framedyn.

Every error raised by the Rust core arrives as one of these, carrying the
Rust message (which names the offending field, its value and the allowed
range). They subclass the built-in exception a Python user would expect, so
``except ValueError`` keeps working.
"""

from __future__ import annotations

from typing import Any, Optional

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
