#!/usr/bin/env python3
"""Summed compile times of groups of crates in cargo timing reports.

    python3 scripts/timing_units.py BEFORE.html [AFTER.html]

Each file is a report of `cargo … --timings` (`target/cargo-timings/
cargo-timing-*.html`). Prints, per report, the summed unit times of all
units, of our crates, of faer's stack and of the CLI's parsing and output
crates, and when the core started compiling; with two reports, also the
summed time of the units found in only one of them (crates a change
removed or added) and the units whose time changed most. Unit times overlap
on two cores, so their sums are CPU-like totals, not wall time
(docs/development.md, "Profiles").
"""

import json
import pathlib
import re
import sys
from typing import Any, Callable

OURS = {"framedyn", "framedyn-cli", "framedyn-py", "framedyn-tests"}
GROUPS: dict[str, Callable[[str], bool]] = {
    "our crates": lambda n: n in OURS,
    "faer's stack (faer, gemm, nano-gemm, private-gemm-x86, pulp)": lambda n: n.startswith(("faer", "gemm", "nano-gemm", "private-gemm", "pulp")),
    "the CLI's parsing and output crates": lambda n: n in {"clap_builder", "clap_lex", "toml", "toml_edit", "toml_datetime", "winnow", "indicatif", "zip"},
}


def units(path: str) -> list[dict[str, Any]]:
    text = pathlib.Path(path).read_text(encoding="utf-8")
    match = re.search(r"const UNIT_DATA = (\[.*?\]);\n", text, re.S)
    if match is None:
        sys.exit(f"timing_units: {path} is not a cargo timing report (no UNIT_DATA)")
    data: list[dict[str, Any]] = json.loads(match.group(1))
    return data


def by_unit(data: list[dict[str, Any]]) -> dict[tuple[str, str, str], float]:
    """Summed time per (crate, version, target): a crate built twice (for the compiler and for the target) counts both builds."""
    out: dict[tuple[str, str, str], float] = {}
    for u in data:
        key = (u["name"], u["version"], u["target"])
        out[key] = out.get(key, 0.0) + u["duration"]
    return out


def main() -> int:
    paths = sys.argv[1:]
    if not 1 <= len(paths) <= 2:
        print(__doc__, file=sys.stderr)
        return 2
    reports = [units(p) for p in paths]
    for path, data in zip(paths, reports):
        print(path)
        print(f"  all units: {sum(u['duration'] for u in data):.0f} s")
        for label, member in GROUPS.items():
            print(f"  {label}: {sum(u['duration'] for u in data if member(u['name'])):.0f} s")
        core = [u["start"] for u in data if u["name"] == "framedyn" and u["target"].strip() == ""]
        if core:
            print(f"  the core starts at {min(core):.0f} s")
    if len(reports) == 2:
        a, b = by_unit(reports[0]), by_unit(reports[1])
        print(f"units only in the first report: {sum(v for k, v in a.items() if k not in b):.0f} s")
        print(f"units only in the second report: {sum(v for k, v in b.items() if k not in a):.0f} s")
        print("largest changes (first, second):")
        for key in sorted(set(a) | set(b), key=lambda k: -abs(a.get(k, 0.0) - b.get(k, 0.0)))[:15]:
            name, _, target = key
            print(f"  {name:24s} {target.strip()[:24]:24s} {a.get(key, 0.0):7.1f} {b.get(key, 0.0):7.1f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
