#!/usr/bin/env python3
"""Figures of docs/validation.md from the CSV files of the example
`validation_figures`:

    cargo run --example validation_figures
    python3 scripts/validation_figures.py

Reads out/validation/*.csv, writes docs/figures/*.png (needs matplotlib).
"""
import csv
import math
import os
from collections import defaultdict

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
DATA = os.path.join(ROOT, "out", "validation")
FIGS = os.path.join(ROOT, "docs", "figures")
R = 1.2


def rows(name):
    with open(os.path.join(DATA, name + ".csv")) as f:
        return list(csv.DictReader(f))


def groups(data, key):
    out = defaultdict(list)
    for r in data:
        out[r[key]].append(r)
    return out


def disk(x, y, z, radius):
    """Poincaré disk coordinates of a point of the hyperboloid."""
    return x / (radius + z), y / (radius + z)


def orbits():
    g = groups(rows("orbits"), "case")
    fig, axes = plt.subplots(2, 3, figsize=(12, 8))
    for ax, (case, rs) in zip(axes.flat, g.items()):
        x = [float(r["x"]) for r in rs]
        y = [float(r["y"]) for r in rs]
        z = [float(r["z"]) for r in rs]
        if case.startswith("H2"):
            x, y = zip(*[disk(a, b, c, R) for a, b, c in zip(x, y, z)])
            ax.set_title(case + "\n(Poincaré disk, t ≤ 40)")
        else:
            ax.set_title(case + "\n(projection on the xy plane, t ≤ 40)")
        ax.plot(x, y, lw=0.6)
        ax.plot([0], [0], "k+")
        ax.set_aspect("equal")
    fig.suptitle("Bertrand (closed) and non-Bertrand (precessing) orbits of a point, m = 1.3, R = 1.2")
    fig.tight_layout()
    fig.savefig(os.path.join(FIGS, "bertrand_orbits.png"), dpi=110)


def h2_threshold():
    g = groups(rows("h2_threshold"), "ratio")
    fig, ax = plt.subplots(figsize=(7, 4.5))
    for ratio, rs in g.items():
        ax.plot([float(r["t"]) for r in rs], [float(r["r"]) / R for r in rs], label=f"E = {float(ratio):.4g} · κR²/2")
    ax.set_xlabel("t")
    ax.set_ylabel("r / R")
    ax.set_title("H² oscillator (a133): bounded below E = κR²/2, unbounded above")
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(os.path.join(FIGS, "h2_oscillator_threshold.png"), dpi=110)


def precession():
    g = groups(rows("precession"), "potential")
    fig, ax = plt.subplots(figsize=(7, 4.5))
    for pot, rs in g.items():
        ax.plot([float(r["spin"]) for r in rs], [float(r["precession"]) for r in rs], "o-", ms=3, label=pot)
    ax.axhline(0, color="k", lw=0.5)
    ax.set_xlabel("spin s")
    ax.set_ylabel("periapsis precession per radial period (rad)")
    ax.set_title("Spin coupling removes closure (S², m = 1.3, R = 1.2, I = 0.3)")
    ax.legend()
    fig.tight_layout()
    fig.savefig(os.path.join(FIGS, "precession_vs_spin.png"), dpi=110)


def gyro_paths():
    g = groups(rows("gyro_paths"), "manifold")
    fig, axes = plt.subplots(1, 2, figsize=(11, 5))
    for ax, (man, rs) in zip(axes, g.items()):
        for spin, ss in groups(rs, "spin").items():
            x = [float(r["x"]) for r in ss]
            y = [float(r["y"]) for r in ss]
            z = [float(r["z"]) for r in ss]
            if man == "H2":
                x, y = zip(*[disk(a, b, c, 1.0) for a, b, c in zip(x, y, z)])
            label = "geodesic (s = 0)" if float(spin) == 0 else f"s = {spin}"
            ax.plot(x, y, lw=1.5 if float(spin) == 0 else 0.9, label=label)
        ax.set_aspect("equal")
        ax.legend(fontsize=8)
        ax.set_title(
            "S² (R = 1): xy projection, t ≤ 10" if man == "S2" else "H² (R = 1): Poincaré disk, t ≤ 4"
        )
    fig.suptitle("Free gyroscope (m = 1, I = 0.3) vs the geodesic from the same initial data: (a59) bends the path")
    fig.tight_layout()
    fig.savefig(os.path.join(FIGS, "gyroscope_vs_geodesic.png"), dpi=110)


def rotation_numbers():
    g = groups(rows("rotation_numbers"), "moment")
    fig, ax = plt.subplots(figsize=(7, 4.5))
    mr2 = 1.3 * R * R
    for moment, rs in g.items():
        m = float(moment)
        name = "I = mR²" if abs(m - mr2) < 1e-12 else f"I = {m:g}"
        s = [float(r["spin"]) for r in rs]
        ax.plot(s, [float(r["omega_psi_over_omega_r"]) for r in rs], "o", ms=4, label=name + " (measured)")
        ax.plot(s, [float(r["predicted"]) for r in rs], "-", lw=0.8, label=name + " (2π∂E/∂J)")
    ax.set_xlabel("spin s = J_ψ/2π")
    ax.set_ylabel("rotation number ω_ψ / ω_r")
    ax.set_title("Free S² gyroscope: total degeneracy only for I = mR²")
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(os.path.join(FIGS, "rotation_numbers.png"), dpi=110)


def main():
    os.makedirs(FIGS, exist_ok=True)
    orbits()
    h2_threshold()
    precession()
    gyro_paths()
    rotation_numbers()
    print("figures written to", FIGS)


if __name__ == "__main__":
    main()
