"""The ``framedyn`` command installed by the wheel: the command-line tool of
the Rust crate ``framedyn-cli`` (``framedyn run``, ``framedyn scenes``,
``framedyn validate``), running inside the extension module."""

from __future__ import annotations

import sys
from typing import List, Optional

from . import _framedyn

__all__ = ["main"]


def main(argv: Optional[List[str]] = None) -> int:
    """Runs the command line ``argv`` (default ``sys.argv``); returns the exit code."""
    args = list(sys.argv if argv is None else ["framedyn", *argv])
    cli_main = getattr(_framedyn, "cli_main", None)
    if cli_main is None:
        print(
            "framedyn: the command-line tool is not bound into this build of the Python module "
            "(it needs the library entry point framedyn_cli::main_with_args); "
            "run it from the source tree with `cargo run -p framedyn-cli -- ...`",
            file=sys.stderr,
        )
        return 2
    try:
        return int(cli_main(args))
    except KeyboardInterrupt:
        # The run already stopped on the signal and wrote its partial result
        # (exit code 130); Python's own handler, chained after the tool's,
        # raises the interrupt once control is back here.
        return 130


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
