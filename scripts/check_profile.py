#!/usr/bin/env python3
"""Checks the dev profile's opt-level-0 exceptions (Cargo.toml).

A dependency compiled at opt-level 0 exports its copies of generic
functions, `#[inline]` ones included (rustc's share-generics), and a crate
of ours that links it calls those unoptimised copies instead of compiling
its own: with regex-syntax, which proptest links into the integration
suite, at opt-level 0 the suite ran twice as long. (At opt-level 1 a crate
still shares generics but compiles `#[inline]` ones into each caller
instead of exporting them; the crates named at 1 measured no slower,
docs/development.md, "Profiles". "s" and "z" would behave like 1 but are
unmeasured, so they count as 0 here.) So a crate may be named with
`opt-level = 0` under `[profile.dev.package.NAME]` only if none of these
link it:

- the published crates and the extension (framedyn, framedyn-cli,
  framedyn-py), through their normal dependencies;
- the suite and the examples, through framedyn-tests' dependencies and
  dev-dependencies other than criterion, which only the bench uses
  (checked here too: no test or example file refers to the crate).

Proc macros and their dependencies are never linked (they run inside the
compiler), so they never count. Exit status 1, naming the crate and who
links it, if the rule is broken. Run by scripts/test.sh; needs only cargo
and Python 3.11 (tomllib).
"""

import json
import re
import pathlib
import subprocess
import sys
import tomllib

ROOT = pathlib.Path(__file__).resolve().parent.parent
BENCH_ONLY = {"criterion"}


def main() -> int:
    profile = tomllib.loads((ROOT / "Cargo.toml").read_text())["profile"]["dev"]["package"]
    low = {name for name, p in profile.items() if name != "*" and p.get("opt-level", 3) in (0, "s", "z")}
    meta = json.loads(
        subprocess.run(
            ["cargo", "metadata", "--format-version", "1", "--locked", "--filter-platform", "x86_64-unknown-linux-gnu"],
            cwd=ROOT,
            check=True,
            capture_output=True,
            text=True,
        ).stdout
    )
    packages = {p["id"]: p for p in meta["packages"]}
    nodes = {n["id"]: n for n in meta["resolve"]["nodes"]}
    by_name = {packages[i]["name"]: i for i in meta["workspace_members"]}

    def is_proc_macro(pid: str) -> bool:
        return any("proc-macro" in t["kind"] for t in packages[pid]["targets"])

    def linked(root: str, dev: bool) -> dict[str, str]:
        """Crates linked into `root`'s targets: name -> the crate that pulls it in."""
        seen: dict[str, str] = {}
        stack = []
        for d in nodes[by_name[root]]["deps"]:
            kinds = {k["kind"] for k in d["dep_kinds"]}
            if None in kinds or (dev and "dev" in kinds):
                if dev and packages[d["pkg"]]["name"] in BENCH_ONLY:
                    continue
                stack.append((d["pkg"], root))
        while stack:
            pid, parent = stack.pop()
            name = packages[pid]["name"]
            if name in seen or is_proc_macro(pid):
                continue
            seen[name] = parent
            for d in nodes[pid]["deps"]:
                if any(k["kind"] is None for k in d["dep_kinds"]):
                    stack.append((d["pkg"], name))
        return seen

    problems = []
    for root, dev in (("framedyn", False), ("framedyn-cli", False), ("framedyn-py", False), ("framedyn-tests", True)):
        for name, parent in linked(root, dev).items():
            if name in low:
                problems.append(f"{name} is at opt-level 0 in [profile.dev.package.{name}] but {root} links it (through {parent})")

    for path in list((ROOT / "tests").rglob("*.rs")) + list((ROOT / "examples").rglob("*.rs")):
        if re.search(r"\bcriterion::|\buse criterion\b|extern crate criterion", path.read_text(encoding="utf-8")):
            problems.append(f"{path.relative_to(ROOT)} names criterion, which the dev profile treats as used by the bench only")

    for p in problems:
        print(f"check_profile: {p}", file=sys.stderr)
    if problems:
        print("check_profile: see the comment above these entries in Cargo.toml", file=sys.stderr)
        return 1
    print(f"check_profile: {len(low)} crates at opt-level 0, none linked by our binaries")
    return 0


if __name__ == "__main__":
    sys.exit(main())
