"""Lyapunov exponents and Poincaré sections from Python (issue 21): arrays
out, the numbers of the command line, typed errors for bad input."""

import math
from pathlib import Path

import numpy as np
import pytest

import framedyn as fd


def test_lyapunov_full_spectrum_arrays():
    scene = fd.Scene.example("s2-point-kepler")
    r = fd.lyapunov(scene, exponents="all")
    assert isinstance(r, fd.LyapunovResult)
    assert r.state_dimension == 5
    assert r.exponents.shape == (5,) and r.stderr.shape == (5,) and r.spread.shape == (5,)
    assert r.running.shape == (len(r.times), 5)
    assert np.array_equal(r.running[-1], r.exponents)
    # Exact tangent maps (RKMK4 on the tangent group): 1 + 1 step per vector.
    assert r.steps == 2000 and r.steps_per_step == 6 and r.exact_tangents
    assert r.two_trajectory is None
    # Integrable (Bertrand) orbit: the maximal exponent is small and the sum vanishes.
    assert abs(r.exponents.sum()) < 1e-6
    assert r.dimension == 5
    # The phase space's spectrum: 4 exponents, no gauge zero, the same steps.
    q = fd.lyapunov(scene, exponents="all", quotient=True)
    assert (q.dimension, q.state_dimension, q.exponents.shape, q.steps) == (4, 5, (4,), r.steps)
    assert q.steps_per_step == 5
    # Differenced on request: 2 steps per vector, the same spectrum to the
    # differences' error (about 1e-10 per step, relative).
    dif = fd.lyapunov(scene, exponents="all", differenced=True)
    assert dif.steps_per_step == 11 and not dif.exact_tangents
    assert np.max(np.abs(dif.exponents - r.exponents)) < 1e-6, (dif.exponents, r.exponents)
    with pytest.raises(TypeError, match="differenced"):
        fd.lyapunov(scene, differenced=1)
    with pytest.raises(fd.InvalidInputError, match="between 1 and 4"):
        fd.lyapunov(scene, exponents=5, quotient=True)
    with pytest.raises(TypeError, match="quotient"):
        fd.lyapunov(scene, quotient="yes")


def test_lyapunov_two_trajectory_agrees_on_a_chaotic_affine_body():
    # The elastic affine body of the scene with a general inertia J (the
    # paper: "no hope for integrability").
    scene = fd.Scene.example("s2-affine-elastic")
    d = scene.to_dict()
    del d["body"]["inertia"]
    d["body"]["J"] = [[0.1, 0.02], [0.02, 0.05]]
    d["time"]["t_end"] = 60.0
    r = fd.lyapunov(fd.Scene.from_dict(d), two_trajectory=True, transient=5.0)
    two = r.two_trajectory
    assert two is not None
    assert math.isfinite(r.exponents[0]) and math.isfinite(two["exponent"])
    assert abs(r.exponents[0] - two["exponent"]) <= 3 * two["stderr"] + 1e-6


def test_section_arrays_and_columns():
    scene = fd.Scene.example("s2-point-kepler")
    s = fd.section(scene, column="r", value=0.5, direction="falling")
    assert isinstance(s, fd.Section)
    assert len(s) >= 2 and s.data.shape == (len(s), len(s.columns))
    assert s.columns[0] == "t" and s.units[0] == "T"
    assert np.allclose(s.column("r"), 0.5, atol=1e-9)
    assert np.array_equal(s["r"], s.column("r")) and "r" in s and "nope" not in s  # indexed like a Solution
    with pytest.raises(KeyError, match="nope"):
        s["nope"]
    assert not s.rising.any()
    assert np.array_equal(s.t, s.data[:, 0])
    same = fd.section(scene, {"kind": "column", "column": "r", "value": 0.5, "direction": "falling"})
    assert np.array_equal(same.data, s.data)
    pole = fd.section(fd.Scene.example("s2-gyroscope-pole"), plane=[1.0, 0.0, 0.0])
    assert pole.column("x2")[0] > 0.9999


def test_bad_input_is_typed():
    scene = fd.Scene.example("s2-point-kepler")
    with pytest.raises(fd.InvalidInputError, match="exponents"):
        fd.lyapunov(scene, exponents=0)
    with pytest.raises(ValueError, match="between 1 and 5"):
        fd.lyapunov(scene, exponents=6)
    with pytest.raises(fd.InvalidInputError, match="eps"):
        fd.lyapunov(scene, eps=2.0)
    with pytest.raises(fd.InvalidInputError, match="every"):
        fd.lyapunov(scene, every=0)
    with pytest.raises(TypeError):
        fd.lyapunov(scene, transient="soon")
    with pytest.raises(TypeError):
        fd.lyapunov(42)
    d = scene.to_dict()
    d["method"] = {"name": "rk4", "rtol": 1e-8}
    with pytest.raises(fd.InvalidInputError, match="embedded pair"):
        fd.lyapunov(fd.Scene.from_dict(d))
    d["method"] = {"name": "dopri5", "rtol": 1e-6, "atol": 1e-6}
    d["time"]["t_end"] = 0.05
    with pytest.raises(fd.InvalidInputError, match="batches"):
        fd.lyapunov(fd.Scene.from_dict(d))
    with pytest.raises(fd.InvalidInputError, match="section.normal"):
        fd.section(scene, plane=[1.0, 0.0])
    with pytest.raises(fd.InvalidInputError, match="section.column"):
        fd.section(scene, column="nope", value=1.0)
    with pytest.raises(fd.InvalidInputError, match="no section"):
        fd.section(scene)
    with pytest.raises(fd.InvalidInputError, match="direction"):
        fd.section(scene, column="r", value=0.5, direction="up")
    s = fd.section(scene, column="r", value=0.5)
    with pytest.raises(fd.InvalidInputError, match="not a column"):
        s.column("nope")


def test_sali_regular_and_chaotic_scenes():
    kepler = fd.Scene.example("s2-point-kepler")
    d = kepler.to_dict()
    d["time"]["t_end"] = 100.0
    regular = fd.sali(fd.Scene.from_dict(d))
    assert regular["chaotic_at"] is None and regular["steps"] == 20000
    # The elastic affine body with general J at large deformation (docs/integrability.md).
    d = fd.Scene.example("s2-affine-elastic").to_dict()
    del d["body"]["inertia"]
    d["body"]["J"] = [[0.1, 0.02], [0.02, 0.05]]
    d["initial"].update(rho=[[1.8, 0.3], [0.0, 0.5]], rho_dot=[[0.0, 0.8], [-0.6, 0.0]], phi_dot=1.5)
    d["time"]["t_end"] = 1000.0
    chaotic = fd.sali(fd.Scene.from_dict(d))
    assert chaotic["chaotic_at"] is not None and chaotic["sali"] < 1e-8
    with pytest.raises(fd.InvalidInputError, match="threshold"):
        fd.sali(kepler, threshold=2.0)
    with pytest.raises(TypeError):
        fd.sali(kepler, threshold="small")


# The S² gyroscope of the atlas's tilted map (docs/integrability.md), a
# chaotic orbit; the CLI tests read the same file.
TILTED_GYROSCOPE = (Path(__file__).resolve().parents[2] / "tests" / "data" / "tilted_gyroscope.toml").read_text()


def test_megno_regular_and_chaotic_scenes():
    # Kepler (Bertrand, quasi-periodic): <Y> -> 2 (1.92 at T = 200, tests/suite/megno.rs).
    d = fd.Scene.example("s2-point-kepler").to_dict()
    d["time"]["t_end"] = 200.0
    regular = fd.megno(fd.Scene.from_dict(d))
    assert isinstance(regular, fd.MegnoResult)
    assert abs(regular.mean - 2.0) < 0.1 and abs(regular.slope) < 0.005
    assert regular.steps == 40000 and regular.steps_per_step == 2 and regular.exact_tangents
    assert regular.running_mean.shape == regular.times.shape == regular.running_megno.shape
    assert regular.times[-1] == 200.0 and regular.running_mean[-1] == regular.mean
    # Chaotic: <Y> = 16.9 at T = 300, twice its slope 0.083 (lambda_1 ~ 0.1).
    tilted = fd.Scene.from_toml(TILTED_GYROSCOPE)
    chaotic = fd.megno(tilted)
    assert chaotic.mean > 10.0 and 2.0 * chaotic.slope > 0.05, (chaotic.mean, chaotic.slope)
    # Differences of the step map (second and fourth order) against the
    # exact tangent maps: the same indicator to 1e-6 (the linearisation's
    # error, not the dynamics).
    second = fd.megno(tilted, differenced=True)
    fourth = fd.megno(tilted, fourth_order=True, differenced=True)
    assert (second.steps_per_step, fourth.steps_per_step) == (3, 5) and not fourth.exact_tangents
    for other in (second, fourth):
        assert abs(other.mean - chaotic.mean) < 1e-6 * chaotic.mean, (other.mean, chaotic.mean)
    kepler = fd.Scene.example("s2-point-kepler")
    with pytest.raises(ValueError, match="eps"):
        fd.megno(kepler, eps=0.5)
    with pytest.raises(ValueError, match="eps"):  # subnormal: no perturbation left
        fd.megno(kepler, eps=1e-320)
    with pytest.raises(fd.InvalidInputError, match="seed"):
        fd.megno(kepler, seed=-1)
    with pytest.raises(TypeError):
        fd.megno(kepler, fourth_order=1)
    with pytest.raises(TypeError):
        fd.megno(kepler, eps="small")
    # Error-controlled steps: the same indicator on the regular Kepler orbit,
    # in fewer steps than the fixed h = 0.005 (40 000 over T = 200).
    adaptive = kepler.to_dict()
    adaptive["method"].update(name="dop853", rtol=1e-10, atol=1e-10)
    del adaptive["method"]["h"]
    adaptive["time"]["t_end"] = 200.0
    a = fd.megno(fd.Scene.from_dict(adaptive))
    assert abs(a.mean - 2.0) < 0.1 and abs(a.slope) < 0.005, (a.mean, a.slope)
    assert a.steps < 10000 and a.times[-1] == 200.0 and np.all(np.diff(a.times) > 0)
    s = fd.sali(fd.Scene.from_dict(adaptive))
    assert s["chaotic_at"] is None and s["steps"] == a.steps
    exps = fd.lyapunov(fd.Scene.from_dict(adaptive), exponents="all")
    assert exps.steps == a.steps and abs(sum(exps.exponents)) < 1e-6
    # The same finite-time spectrum as RK4's fixed steps (h = 0.005), to 1e-5
    # (measured 1e-6): the tangent map of each accepted step at its size.
    fixed = kepler.to_dict()
    fixed["time"]["t_end"] = 200.0
    reference = fd.lyapunov(fd.Scene.from_dict(fixed), exponents="all")
    assert reference.steps == 40000
    assert np.max(np.abs(exps.exponents - reference.exponents)) < 1e-5, (exps.exponents, reference.exponents)


def _kepler_map_table():
    # Two regular orbits, an invalid member (negative step) in the middle, a
    # radial fall into the centre (SALI falls below the threshold, MEGNO's
    # run then fails), and a member at another step.
    return {
        "initial.r": np.array([0.8, 0.6, 0.7, 0.3, 0.9]),
        "initial.phi_dot": np.array([1.3, 1.5, 1.3, 0.0, 1.2]),
        "method.h": np.array([0.005, 0.005, -0.01, 0.005, 0.01]),
    }


def test_chaos_map_equals_single_calls_bit_for_bit():
    d = fd.Scene.example("s2-point-kepler").to_dict()
    d["time"]["t_end"] = 5.0
    base = fd.Scene.from_dict(d)
    table = _kepler_map_table()
    m = fd.chaos_map(base, table, threshold=1e-3, seed=7, threads=2)
    assert isinstance(m, fd.ChaosMap) and len(m) == 5
    for col in (m.sali, m.sali_min, m.chaotic_at, m.megno, m.megno_mean, m.megno_slope, m.lyapunov):
        assert isinstance(col, np.ndarray) and col.shape == (5,) and col.dtype == np.float64
    assert list(m.status) == ["finished", "finished", "invalid", "failed", "finished"]
    assert m.ok.tolist() == [True, True, False, False, True]
    for i in range(5):
        member = base.with_params({k: float(v[i]) for k, v in table.items()})
        if i == 2:
            with pytest.raises(fd.InvalidInputError, match="method.h") as e:
                fd.sali(member, threshold=1e-3, seed=7)
            assert m.errors[2] == f"member 2: sali: {e.value}"
            assert math.isnan(m.sali[2]) and math.isnan(m.megno_mean[2]) and m.sali_steps[2] == 0
            continue
        s = fd.sali(member, threshold=1e-3, seed=7)
        # Bit for bit: the same floats, not merely close ones.
        assert (m.sali[i], m.sali_min[i], int(m.sali_steps[i])) == (s["sali"], s["min"], s["steps"])
        assert m.chaotic_at[i] == s["chaotic_at"] if s["chaotic_at"] is not None else math.isnan(m.chaotic_at[i])
        if i == 3:
            with pytest.raises(fd.IntegrationError) as e:
                fd.megno(member, seed=7)
            assert m.errors[3] == f"member 3: megno: {e.value}"
            assert math.isnan(m.megno_mean[3]) and m.megno_steps[3] == 0
            continue
        y = fd.megno(member, seed=7)
        assert (m.megno[i], m.megno_mean[i], m.megno_slope[i], m.lyapunov[i], int(m.megno_steps[i])) == (y.megno, y.mean, y.slope, y.lyapunov, y.steps)
        assert m.errors[i] is None
    # GALI_3 in the same map: each member's single call, bit for bit.
    g = fd.chaos_map(base, table, sali=False, megno=False, gali=3, gali_threshold=1e-6, seed=7)
    stored = fd.chaos_map(base, table, sali=False, megno=False, gali=3, gali_threshold=1e-6, seed=7, gali_quotient=False)
    # The radial fall (member 3): GALI_3 falls below 1e-6 before the fall breaks the step.
    assert list(g.status) == ["finished", "finished", "invalid", "finished", "finished"]
    assert np.all(np.isnan(g.sali)) and np.all(np.isnan(g.megno_mean)) and g.gali_below_at[3] < 5.0
    for i in (0, 1, 3, 4):
        member = base.with_params({k: float(v[i]) for k, v in table.items()})
        r = fd.gali(member, k=3, threshold=1e-6, seed=7)
        assert (g.gali_log10[i], int(g.gali_steps[i])) == (r.log10, r.steps)
        assert g.gali_below_at[i] == r.below_at if r.below_at is not None else math.isnan(g.gali_below_at[i])
        r = fd.gali(member, k=3, threshold=1e-6, seed=7, quotient=False)
        assert (stored.gali_log10[i], int(stored.gali_steps[i])) == (r.log10, r.steps)
    # One thread gives the same bits; MEGNO alone leaves SALI's columns NaN.
    one = fd.chaos_map(base, table, threshold=1e-3, seed=7, threads=1)
    assert np.array_equal(one.megno_mean, m.megno_mean, equal_nan=True) and np.array_equal(one.sali, m.sali, equal_nan=True)
    only = fd.chaos_map(base, table, sali=False, seed=7)
    assert np.isnan(only.sali).all() and np.array_equal(only.megno_mean, m.megno_mean, equal_nan=True)


def test_chaos_map_bad_input_is_typed():
    base = fd.Scene.example("s2-point-kepler")
    table = _kepler_map_table()
    with pytest.raises(fd.InvalidInputError, match="indicators"):
        fd.chaos_map(base, table, sali=False, megno=False)
    with pytest.raises(fd.InvalidInputError, match="gali"):
        fd.chaos_map(base, table, gali=1)
    with pytest.raises(fd.InvalidInputError, match="gali_threshold"):
        fd.chaos_map(base, table, gali=2, gali_threshold=0.0)
    with pytest.raises(fd.InvalidInputError, match="threshold"):
        fd.chaos_map(base, table, threshold=2.0)
    with pytest.raises(fd.InvalidInputError, match="eps"):
        fd.chaos_map(base, table, eps=0.5)
    with pytest.raises(fd.InvalidInputError, match="threads"):
        fd.chaos_map(base, table, threads=0)
    with pytest.raises(fd.InvalidInputError, match="potential.nope"):
        fd.chaos_map(base, {"potential.nope": [1.0]})
    # A field the path grammar allows but this scene has not: the member is
    # invalid, as in solve_batch.
    bad = fd.chaos_map(base, {"initial.nope": [1.0]})
    assert list(bad.status) == ["invalid"] and "initial.nope" in bad.errors[0]
    with pytest.raises(fd.InvalidInputError, match="length"):
        fd.chaos_map(base, {"initial.r": [0.5, 0.6], "initial.phi_dot": [1.0]})
    with pytest.raises(TypeError, match="megno"):
        fd.chaos_map(base, table, megno=1)


def test_gali_chaotic_regular_and_bad_input():
    tilted = fd.Scene.from_toml(TILTED_GYROSCOPE)
    # GALI_2 and SALI of the same two vectors: GALI_2 = S sqrt(1 - S^2/4).
    g2 = fd.gali(tilted, k=2, threshold=1e-300, quotient=False)
    s = fd.sali(tilted, threshold=1e-300)
    assert isinstance(g2, fd.GaliResult) and g2.k == 2 and g2.steps == s["steps"]
    expected = s["sali"] * np.sqrt(1.0 - s["sali"] ** 2 / 4.0)
    assert abs(g2.gali / expected - 1.0) < 1e-6, (g2.gali, expected)
    assert g2.steps_per_step == 3 and g2.exact_tangents and s["exact_tangents"] and g2.times[-1] == 300.0 and g2.running_log10[-1] == g2.log10
    # Chaotic: GALI_3 falls below 1e-12 exponentially; the run stops there.
    g3 = fd.gali(tilted, k=3)
    assert g3.below_at is not None and g3.log10 < -12.0 and g3.times[-1] == g3.below_at
    # "all": the phase space's dimension (the state group's 7 less the
    # parallel frame's gauge direction), or the group's on the stored state.
    full = fd.gali(tilted, k="all", threshold=1e-300)
    assert (full.k, full.dimension, full.steps_per_step) == (6, 6, 7)
    stored = fd.gali(tilted, k="all", threshold=1e-300, quotient=False)
    assert (stored.k, stored.dimension, stored.steps_per_step) == (7, 7, 8)
    # Regular (Kepler, a Bertrand orbit): in the phase space GALI_2 falls
    # like 1/t (one drifting direction), not exponentially; on the stored
    # state the holonomy angle's drift keeps it of order 1.
    d = fd.Scene.example("s2-point-kepler").to_dict()
    d["time"]["t_end"] = 200.0
    regular = fd.gali(fd.Scene.from_dict(d))
    assert regular.below_at is None and -3.0 < regular.log10 < -1.5, regular.log10
    regular_stored = fd.gali(fd.Scene.from_dict(d), quotient=False)
    assert regular_stored.below_at is None and regular_stored.gali > 1e-2, regular_stored.gali
    kepler = fd.Scene.example("s2-point-kepler")
    with pytest.raises(fd.InvalidInputError, match="k"):
        fd.gali(kepler, k=1)
    with pytest.raises(fd.InvalidInputError, match="between 2 and 4"):
        fd.gali(kepler, k=5)
    with pytest.raises(fd.InvalidInputError, match="between 2 and 5"):
        fd.gali(kepler, k=6, quotient=False)
    with pytest.raises(TypeError, match="quotient"):
        fd.gali(kepler, quotient=1)
    with pytest.raises(fd.InvalidInputError, match="'all'"):
        fd.gali(kepler, k="some")
    with pytest.raises(fd.InvalidInputError, match="threshold"):
        fd.gali(kepler, threshold=0.0)
    with pytest.raises(fd.InvalidInputError, match="a float"):
        fd.gali(kepler, k=2.5)
    with pytest.raises(TypeError):
        fd.gali(kepler, threshold="small")
