"""Shared by the example scripts: print a measured number next to the
paper's value and exit with status 1 if any comparison fails."""

import sys

import numpy as np

_failed = []


def le(what, measured, bound):
    """Prints ``what: measured`` and records a failure if ``measured > bound`` (or NaN)."""
    ok = bool(measured <= bound)
    print(f"  {what:<62} {measured:>10.3e}  (≤ {bound:.0e}) {'ok' if ok else 'FAILED'}")
    if not ok:
        _failed.append(what)


def close(what, measured, expected, rel):
    """Prints a value next to its closed form and checks the relative difference."""
    print(f"  {what:<62} {measured:.12f}  closed form {expected:.12f}")
    le(f"  relative difference ({what})", abs((measured - expected) / expected), rel)


def drift(sol, name):
    """``max |q − q₀|`` of the column ``name``."""
    return float(np.max(sol.drift(name)))


def returned(sol):
    """``|x(t_end) − x(t0)|`` of the embedding position."""
    return float(np.linalg.norm(sol.position[-1] - sol.position[0]))


def finish():
    """Exits with status 1 if any check failed."""
    if _failed:
        print("FAILED: " + "; ".join(_failed), file=sys.stderr)
        sys.exit(1)
    print("all checks passed")
