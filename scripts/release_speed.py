#!/usr/bin/env python3
"""Run time of the `framedyn` CLI built two ways, on the same long scenes.

Used to choose the `release` profile (Cargo.toml, docs/development.md): the
CLI's hot loops live in the core's scene engine, so a change of profile or
of inlining in the core shows here as the run time of `framedyn run`.

    python3 scripts/release_speed.py BASELINE_BIN CANDIDATE_BIN [--rounds 5]

Each binary is a `framedyn` executable (for example built with
`CARGO_TARGET_DIR=/tmp/a cargo build --release -p framedyn-cli` at two
commits). The scenes are embedded examples (`framedyn scenes show NAME`) and
the default scene with other methods, lengthened so that one run takes
0.2-1.4 s, writing only the first and last record. Rounds alternate the two
binaries; the table gives the minimum wall time per scene and the ratio
candidate / baseline, and the script fails if the two binaries' outputs
differ in any byte (a profile change must not change the numbers).

    python3 scripts/release_speed.py BASELINE_BIN CANDIDATE_BIN --callgrind

counts instructions instead (valgrind's callgrind, one run per binary and
scene, each scene 1/32 as long): the same for the same binary and input
whatever else the machine does, so differences of a few percent that the
wall times' run-to-run spread hides show (about 20 s of valgrind per run).
"""
import argparse
import filecmp
import os
import re
import subprocess
import sys
import tempfile
import time

# (embedded scene, method table replacing the scene's or None, t_end)
SCENES = [
    ("s2-gyroscope-pole", 'name = "rk4"\nh = 0.0009765625', 4096.0),
    ("s2-gyroscope-pole", 'name = "strang"\nh = 0.0009765625', 4096.0),
    ("s2-gyroscope-pole", 'name = "blanes_moan_rkn6"\nh = 0.00390625', 4096.0),
    ("s2-gyroscope-pole", 'name = "dop853"\nrtol = 1e-12\natol = 1e-12', 102400.0),
    ("s2-gyroscope-pole", 'name = "dopri5"\nrtol = 1e-10\natol = 1e-10', 102400.0),
    ("s2-gyroscope-pole", 'name = "implicit_midpoint"\nh = 0.00390625', 1024.0),
    ("s2-affine-elastic", None, 2000.0),
    ("t2-gyroscope-separable", None, None),
    ("h2-gyroscope", None, None),
    ("s3-gyroscope", None, None),
    ("s3-affine-neo-hookean", None, None),
    ("h2-point-kepler", None, None),
    ("spheroid-gyroscope", None, None),
]
# t_end multiplier for the scenes above whose t_end is None.
STRETCH = {"t2-gyroscope-separable": 515, "h2-gyroscope": 865, "s3-gyroscope": 570,
           "s3-affine-neo-hookean": 535, "h2-point-kepler": 605, "spheroid-gyroscope": 370}


def scene_text(binary, name, method, t_end, shorten=1.0):
    text = subprocess.run([binary, "scenes", "show", name], check=True, capture_output=True, text=True).stdout
    if method is not None:
        text = re.sub(r"\[method\]\n(?:[^\[\n][^\n]*\n)*", "[method]\n" + method + "\n\n", text, count=1)
    old = float(re.search(r"^t_end = (\S+)", text, re.M).group(1))
    new = (t_end if t_end is not None else old * STRETCH[name]) / shorten
    text = re.sub(r"^t_end = \S+", f"t_end = {new!r}", text, count=1, flags=re.M)
    i = text.index("[output]")
    j = text.find("\n[", i + 1)
    rest = text[j:] if j >= 0 else ""
    return text[:i] + '[output]\nevery = 1000000000\nquantities = ["energy", "position"]\n' + rest


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("baseline")
    ap.add_argument("candidate")
    ap.add_argument("--rounds", type=int, default=5)
    ap.add_argument("--callgrind", action="store_true", help="count instructions (valgrind) instead of timing")
    a = ap.parse_args()
    bins = {"baseline": os.path.abspath(a.baseline), "candidate": os.path.abspath(a.candidate)}
    with tempfile.TemporaryDirectory() as d:
        labels = []
        for name, method, t_end in SCENES:
            label = name + ("" if method is None else "/" + method.split('"')[1])
            path = os.path.join(d, label.replace("/", "__") + ".toml")
            with open(path, "w") as f:
                f.write(scene_text(bins["baseline"], name, method, t_end, 32.0 if a.callgrind else 1.0))
            labels.append((label, path))
        if a.callgrind:
            same = count_instructions(bins, labels, d)
            if not same:
                sys.exit("the two binaries wrote different outputs")
            return
        best = {}
        for _ in range(a.rounds):
            for label, path in labels:
                for b, exe in bins.items():
                    out = f"{path}.{b}.csv"
                    t = time.perf_counter()
                    subprocess.run([exe, "run", "-q", path, "-o", out], check=True)
                    dt = time.perf_counter() - t
                    best[label, b] = min(best.get((label, b), float("inf")), dt)
        same = True
        print(f"| scene / method | baseline (s) | candidate (s) | candidate / baseline |")
        print("|---|---|---|---|")
        for label, path in labels:
            equal = filecmp.cmp(f"{path}.baseline.csv", f"{path}.candidate.csv", shallow=False)
            same &= equal
            r = best[label, "candidate"] / best[label, "baseline"]
            print(f"| {label} | {best[label, 'baseline']:.3f} | {best[label, 'candidate']:.3f} | {r:.3f}{'' if equal else ' (outputs differ)'} |")
    if not same:
        sys.exit("the two binaries wrote different outputs")


def count_instructions(bins, labels, d):
    """Instructions of each binary on each scene (callgrind); prints the
    table and returns whether the outputs agree byte for byte."""
    counts = {}
    for label, path in labels:
        for b, exe in bins.items():
            out = f"{path}.{b}.csv"
            cg = subprocess.run(
                ["valgrind", "--tool=callgrind", f"--callgrind-out-file={os.path.join(d, 'callgrind.out')}",
                 exe, "run", "-q", path, "-o", out],
                check=True, capture_output=True, text=True)
            m = re.search(r"Collected : (\d+)", cg.stderr)
            if m is None:
                sys.exit(f"no instruction count from valgrind for {label}: {cg.stderr[-500:]}")
            counts[label, b] = int(m.group(1))
    same = True
    print("| scene / method | baseline (instructions) | candidate (instructions) | candidate / baseline |")
    print("|---|---|---|---|")
    for label, path in labels:
        equal = filecmp.cmp(f"{path}.baseline.csv", f"{path}.candidate.csv", shallow=False)
        same &= equal
        base, cand = counts[label, "baseline"], counts[label, "candidate"]
        print(f"| {label} | {base:,} | {cand:,} | {cand / base:.3f}{'' if equal else ' (outputs differ)'} |")
    return same


if __name__ == "__main__":
    main()
