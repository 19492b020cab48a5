"""Prints Mitsuba 3.9.1's `sunsky` radiance (scalar_rgb) along a few directions for the parameter
sets of the unit test `shading::emitter::sunsky::tests::matches_mitsuba`.

    python3 -m venv /tmp/mitsuba-venv && /tmp/mitsuba-venv/bin/pip install mitsuba==3.9.1
    /tmp/mitsuba-venv/bin/python crates/appel/tests/data/sunsky/mitsuba_values.py
"""
import math

import mitsuba as mi

mi.set_variant("scalar_rgb")
T = mi.ScalarTransform4f


def unit(v):
    n = math.sqrt(sum(x * x for x in v))
    return [x / n for x in v]


SETS = {
    "a": {"sun_direction": [0.3, 0.2, 0.6]},
    "b": {"sun_direction": [-0.2, 0.7, 0.25], "turbidity": 7.5,
          "albedo": {"type": "rgb", "value": [0.1, 0.5, 0.8]}, "sky_scale": 2.0,
          "sun_scale": 0.5, "sun_aperture": 2.0, "complex_sun": True},
    "c": {"sun_direction": [0.4, 0.8, -0.3], "turbidity": 1.5, "albedo": 0.0,
          "to_world": T().rotate([1, 0, 0], -90)},
    "d": {"latitude": 48.85, "longitude": 2.35, "timezone": 1, "year": 2024, "month": 6,
          "day": 21, "hour": 14.5, "turbidity": 2.0, "complex_sun": True},
}
DIRECTIONS = [[0, 0, 1], [0.9, 0, 0.1], [-0.5, 0.5, 0.3], [0.2, -0.9, 0.05],
              [0.1, 0.3, -0.5], [0, 1, 0.02], [0.3, 0.9, 0.4]]

for name, params in SETS.items():
    emitter = mi.load_dict(dict(params, type="sunsky"))
    sun = unit(list(mi.traverse(emitter)["sun_direction"]))
    # Toward the sun's centre, then 0.6 of the disk's angular radius away from it.
    h = 0.6 * math.radians(0.5 * params.get("sun_aperture", 0.5358))
    off = mi.Frame3f(mi.Vector3f(sun)).to_world(mi.Vector3f(math.sin(h), 0, math.cos(h)))
    print(name, "sun", ["%.9g" % x for x in sun], "disk", ["%.9g" % x for x in off])
    for d in [unit(x) for x in DIRECTIONS] + [sun, list(off)]:
        si = mi.SurfaceInteraction3f()
        si.wi = -mi.Vector3f(d)
        v = emitter.eval(si)
        print("   ", ["%.9g" % x for x in (v[0], v[1], v[2])])
