"""The spheroid from Python: force-free motion follows the geodesic of
GeographicLib (Karney's algorithm, the optional package ``geographiclib``)
over several circuits, and the scene's coordinate names are the spheroid's."""

from __future__ import annotations

import math

import numpy as np
import pytest

import framedyn as fd


def test_the_spheroid_is_a_scene_manifold():
    ms = fd.manifolds()
    assert ms["spheroid"]["coordinates"] == ["lat", "lon"]
    assert ms["spheroid"]["fields"] == ["equatorial_radius", "polar_radius"]
    sol = fd.solve(fd.Scene.example("spheroid-gyroscope"))
    assert sol.stats["stop"] == "finished"
    assert set(sol.coordinates) >= {"lat", "lon", "lat_dot", "lon_dot", "alpha"}
    assert np.max(sol.drift("energy")) < 1e-8 and np.max(np.abs(sol.momentum_maps["p_phi"] - sol.momentum_maps["p_phi"][0])) < 1e-8


@pytest.mark.parametrize("polar", [0.99, 1.01])
def test_free_point_follows_the_geographiclib_geodesic(polar):
    geodesic = pytest.importorskip("geographiclib.geodesic")
    a, c = 1.0, polar
    lat0, lon0, lat_dot, lon_dot = 0.4, 0.1, 0.7, 0.5
    times = np.linspace(0.0, 20.0, 41)  # about three circuits at unit speed
    scene = fd.Scene(
        manifold={"kind": "spheroid", "equatorial_radius": a, "polar_radius": c},
        body="point",
        lat=lat0, lon=lon0, lat_dot=lat_dot, lon_dot=lon_dot,
        method="butcher6", h=0.005, t_end=float(times[-1]), times=times,
    )
    sol = fd.solve(scene)
    # The initial azimuth (clockwise from north) and speed, from the radii of
    # curvature M (meridian) and N (prime vertical).
    w = math.sqrt(math.cos(lat0) ** 2 + (c / a) ** 2 * math.sin(lat0) ** 2)
    m_r, n_r = c * c / (a * w ** 3), a / w
    north, east = m_r * lat_dot, n_r * math.cos(lat0) * lon_dot
    speed = math.hypot(north, east)
    azi = math.degrees(math.atan2(east, north))
    g = geodesic.Geodesic(a, (a - c) / a)
    worst = 0.0
    for t, x in zip(sol.t, sol.position):
        d = g.Direct(math.degrees(lat0), math.degrees(lon0), azi, speed * t)
        phi, lam = math.radians(d["lat2"]), math.radians(d["lon2"])
        wn = math.sqrt(math.cos(phi) ** 2 + (c / a) ** 2 * math.sin(phi) ** 2)
        n2 = a / wn
        ref = np.array([n2 * math.cos(phi) * math.cos(lam), n2 * math.cos(phi) * math.sin(lam), (c / a) ** 2 * n2 * math.sin(phi)])
        worst = max(worst, float(np.linalg.norm(x - ref)) / a)
    assert worst <= 1e-10, f"largest distance from the GeographicLib geodesic: {worst:e}"
