"""framedyn.Scene: construction from TOML, JSON, dicts and paper-named
keywords; validation errors that name the field; pickling; parameter sets."""

import json
import math
import pickle

import numpy as np
import pytest
from hypothesis import assume, given, settings, strategies as st

import framedyn as fd

from conftest import gyro_s2

TOML = """
name = "demo"
[manifold]
kind = "S2"
radius = 1.0
[body]
kind = "gyroscope"
inertia = 0.2
[initial]
r = 0.5
phi = 0.0
r_dot = -1.0
spin = 0.05
[method]
name = "rk4"
h = 0.01
[time]
t_end = 1.0
"""


def test_from_toml_json_dict_keywords_agree():
    a = fd.Scene.from_toml(TOML)
    b = fd.Scene.from_json(a.to_json())
    c = fd.Scene.from_dict(a.to_dict())
    d = fd.Scene(
        manifold={"kind": "S2", "radius": 1.0}, body={"kind": "gyroscope", "inertia": 0.2},
        r=0.5, phi=0.0, r_dot=-1.0, spin=0.05, method="rk4", h=0.01, t_end=1.0, name="demo",
    )
    e = fd.Scene.from_toml(a.to_toml())
    assert a == b == c == d == e
    assert a.name == "demo"
    assert a.validate() is a


def test_keyword_strings_and_t_span():
    s = fd.Scene("S2", "point", r=0.5, phi=0.2, t_span=(0.0, 1.0))
    d = s.to_dict()
    assert d["manifold"]["kind"] == "S2" and d["body"]["kind"] == "point"
    assert d["time"] == {"t0": 0.0, "t_end": 1.0}
    assert d["initial"]["r"] == 0.5


def test_load_files(tmp_path):
    p = tmp_path / "s.toml"
    p.write_text(TOML)
    q = tmp_path / "s.json"
    q.write_text(fd.Scene.from_toml(TOML).to_json())
    assert fd.Scene.load(p) == fd.Scene.load(str(q))


def test_examples_all_validate():
    names = fd.Scene.examples()
    assert "s2-gyroscope-pole" in names
    for n in names:
        fd.Scene.example(n).validate()


def test_unknown_example():
    with pytest.raises(fd.InvalidInputError, match="no embedded scene `nope`"):
        fd.Scene.example("nope")


def test_pickle_roundtrip():
    s = gyro_s2()
    assert pickle.loads(pickle.dumps(s)) == s
    assert hash(s) == hash(pickle.loads(pickle.dumps(s)))


def test_with_params_and_replace():
    s = gyro_s2()
    t = s.with_params({"initial.r": 0.3, "potential.beta_hat": -0.1})
    assert t.to_dict()["initial"]["r"] == 0.3
    assert t.to_dict()["potential"]["beta_hat"] == -0.1
    assert s.to_dict()["initial"]["r"] == 0.6  # unchanged
    assert s.replace(initial__r=0.3, potential__beta_hat=-0.1) == t


def test_columns_describe_output():
    cols = dict(gyro_s2().columns())
    assert cols["t"] == "T" and cols["x0"] == "L" and cols["energy"] == "M L^2/T^2"


# -- errors name the field, the value and what is allowed -----------------------------


def test_toml_error_has_line_and_column():
    bad = TOML.replace("inertia = 0.2", "inertia = 0.2\nmas = 3.0")
    with pytest.raises(fd.InvalidInputError, match=r"body.*mas.*line \d+, column \d+"):
        fd.Scene.from_toml(bad)


def test_json_wrong_type():
    d = fd.Scene.from_toml(TOML).to_dict()
    d["body"]["mass"] = "heavy"
    with pytest.raises(fd.InvalidInputError, match="body.mass"):
        fd.Scene.from_json(json.dumps(d))


@pytest.mark.parametrize(
    "change, field",
    [
        ({"body.mass": -1.0}, "body.mass"),
        ({"manifold.radius": 0.0}, "manifold.radius"),
        ({"method.h": -0.1}, "method.h"),
        ({"method.name": "euler"}, "method.name"),
        ({"time.t_end": 0.0}, "time.t_end"),
        ({"output.every": 0}, "output.every"),
    ],
)
def test_bad_parameters_name_the_field(change, field):
    # The path is written `body.mass` or `body (mass)` by the core.
    table, key = field.split(".")
    with pytest.raises(fd.InvalidInputError, match=rf"`{table}(\.| \(){key}"):
        gyro_s2().with_params(change).validate()


@pytest.mark.parametrize("field", ["r", "phi", "r_dot", "spin"])
@pytest.mark.parametrize("value", [math.nan, math.inf, -math.inf, np.float32("nan")])
def test_nan_names_the_field(field, value):
    with pytest.raises(fd.InvalidInputError, match=rf"initial\.{field}.*finite"):
        gyro_s2(**{field: value})


def test_nan_inside_an_array_names_the_entry():
    with pytest.raises(fd.InvalidInputError, match=r"initial\.position\[1\].*finite"):
        fd.Scene("S2", "point", position=np.array([1.0, np.nan, 0.0]), t_end=1.0)


def test_wrong_shapes_name_the_argument():
    with pytest.raises(fd.InvalidInputError, match=r"initial\.position.*shape \(3, 1\)"):
        fd.Scene("S2", "point", position=np.ones((3, 1)), t_end=1.0)
    with pytest.raises(fd.InvalidInputError, match=r"initial\.position"):
        # Four numbers on S²: rejected by the core with the field named.
        fd.Scene("S2", "point", position=[1.0, 0.0, 0.0, 0.0], t_end=1.0).validate()
    with pytest.raises(fd.InvalidInputError, match=r"initial\.rho.*matrix"):
        fd.Scene("S2", "affine", r=0.5, phi=0.0, rho=[1.0, 0.0], t_end=1.0)


def test_wrong_dtypes_name_the_argument():
    with pytest.raises(fd.InvalidInputError, match=r"initial\.position.*dtype"):
        fd.Scene("S2", "point", position=np.array(["a", "b", "c"]), t_end=1.0)
    with pytest.raises(fd.InvalidInputError, match=r"initial\.velocity\[1\].*expected f64"):
        fd.Scene("S2", "point", r=0.5, phi=0.0, velocity=[1.0, "x", 0.0], t_end=1.0)
    with pytest.raises(fd.InvalidInputError, match=r"initial\.r.*object"):
        fd.Scene("S2", "point", r=object(), t_end=1.0)


def test_off_manifold_position_is_rejected():
    with pytest.raises(fd.InvalidInputError, match=r"initial"):
        fd.Scene("S2", "point", position=[2.0, 0.0, 0.0], t_end=1.0).validate()


def test_keyword_errors():
    with pytest.raises(fd.InvalidInputError, match="unknown keyword `radius`"):
        fd.Scene("S2", "point", radius=1.0, r=0.5, t_end=1.0)
    with pytest.raises(fd.InvalidInputError, match="manifold"):
        fd.Scene(body="point")
    with pytest.raises(fd.InvalidInputError, match="t_span"):
        fd.Scene("S2", "point", r=0.5, t_span=(0, 1), t_end=2.0)
    with pytest.raises(fd.InvalidInputError, match="t_span"):
        fd.Scene("S2", "point", r=0.5, t_span=3.0)
    with pytest.raises(fd.InvalidInputError, match="body"):
        fd.Scene("S2", 3, r=0.5, t_end=1.0)
    with pytest.raises(fd.InvalidInputError, match="from_toml"):
        fd.Scene.from_toml(b"x")
    with pytest.raises(fd.InvalidInputError, match="from_dict"):
        fd.Scene.from_dict([1, 2])
    with pytest.raises(fd.InvalidInputError, match="params"):
        gyro_s2().with_params([("initial.r", 1.0)])


def test_unknown_manifold_kind_lists_the_allowed():
    with pytest.raises(fd.InvalidInputError, match=r"manifold\.kind.*S2"):
        fd.Scene("S4", "point", r=0.5, t_end=1.0)


@settings(max_examples=25, deadline=None)
@given(
    r=st.floats(0.05, math.pi - 0.05),
    phi=st.floats(-math.pi, math.pi),
    r_dot=st.floats(-2, 2),
    phi_dot=st.floats(-2, 2),
    spin=st.floats(-1, 1),
)
def test_random_paper_states_run_and_conserve(r, phi, r_dot, phi_dot, spin):
    """Random initial states in the paper's coordinates: the run starts at
    those coordinates, and the energy is conserved to the RK4 accuracy."""
    s = gyro_s2(r=r, phi=phi, r_dot=r_dot, phi_dot=phi_dot, spin=spin, h=0.002, t_end=0.5)
    sol = fd.solve(s)
    c = sol.coordinates
    assert c["r"][0] == pytest.approx(r, abs=1e-12)
    assert math.remainder(c["phi"][0] - phi, 2 * math.pi) == pytest.approx(0.0, abs=1e-12)
    assert c["r_dot"][0] == pytest.approx(r_dot, abs=1e-12)
    assert sol.momenta["spin"][0] == pytest.approx(spin, abs=1e-12)
    scale = max(1.0, abs(sol.energy[0]))
    assert sol.stats["energy_drift"] < 1e-7 * scale


unit3 = st.tuples(st.floats(-1, 1), st.floats(-1, 1), st.floats(-1, 1)).filter(lambda v: 0.1 < np.linalg.norm(v))


@settings(max_examples=25, deadline=None)
@given(p=unit3, v=unit3, R=st.floats(0.5, 3.0), speed=st.one_of(st.just(0.0), st.floats(1e-6, 2.0)))
def test_random_embedding_states(p, v, R, speed):
    """Initial states given as numpy arrays in the embedding: the first
    record reproduces them, and the point stays on the sphere."""
    x = R * np.asarray(p) / np.linalg.norm(p)
    u = np.asarray(v) - np.dot(v, x) * x / R**2  # tangent part
    assume(np.linalg.norm(u) > 1e-3)
    u *= speed / np.linalg.norm(u)
    s = fd.Scene({"kind": "S2", "radius": R}, "point", position=x, velocity=u, method="rk4", h=0.01, t_end=0.3)
    sol = fd.solve(s)
    np.testing.assert_allclose(sol.position[0], x, atol=1e-12 * R)
    np.testing.assert_allclose(sol.velocity[0], u, atol=1e-12 * max(1.0, speed))
    np.testing.assert_allclose(np.linalg.norm(sol.position, axis=1), R, rtol=1e-12)
    # A free point moves on a great circle at constant speed.
    np.testing.assert_allclose(np.linalg.norm(sol.velocity, axis=1), speed, atol=1e-9)


def test_numbers_cross_json_exactly():
    # serde_json's default float parser can be one ulp off; scenes parse
    # every number to the nearest f64 (as Python and TOML do).
    for v in (0.9186334105401731, 0.1 + 0.2, 2.0**-1074 * 3, 1.7976931348623157e308 / 3):
        s = fd.Scene.example("s2-gyroscope-pole").with_params({"initial.r": v})
        assert s.to_dict()["initial"]["r"] == v
