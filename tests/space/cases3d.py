"""3D structures the search was not tuned on, as 3D JSON specs, for the result-folder checks:
an extruded seed wall loaded in plane and out of plane, a small dome, a small box building,
other friction coefficients, the same turned 30 degrees about z."""
import copy
import math

import numpy as np


def turned(spec, degrees=30.0):
    """The spec turned about z (its vertices, live load, loads and their points)."""
    c, s = math.cos(math.radians(degrees)), math.sin(math.radians(degrees))
    R = np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])
    out = copy.deepcopy(spec)
    for b in out["blocks"]:
        b["vertices"] = (np.asarray(b["vertices"], float) @ R.T).tolist()
        for key in ("dead", "live"):
            if key in b:
                b[key] = (R @ np.asarray(b[key], float)).tolist()
    if "live_load" in out:
        out["live_load"] = (R @ np.asarray(out["live_load"], float)).tolist()
    for ld in out.get("loads", []):
        ld["at"] = (R @ np.asarray(ld["at"], float)).tolist()
        ld["force"] = (R @ np.asarray(ld["force"], float)).tolist()
    out["name"] = out["name"] + "_turned"
    return out


def with_mu(spec, mu):
    out = copy.deepcopy(spec)
    out["mu"] = mu
    for b in out["blocks"]:
        b.pop("mu", None)
    out["name"] = f"{out['name']}_mu{mu:g}"
    return out


def case_specs() -> dict:
    """name -> 3D spec."""
    from lamodel.geometry import box_building, dome, extrude, seed_wall
    wall = extrude(seed_wall(4), depth=0.6, name="seedwall")
    wall_oop = dict(copy.deepcopy(wall), name="seedwall_oop", live_load=[0.0, 1.0, 0.0])
    for b in wall_oop["blocks"]:
        b.pop("live", None)
    specs = {
        "seedwall": wall,
        "seedwall_oop": wall_oop,
        "dome": dome(n_rings=4, n_per_ring=8, name="dome"),
        "building": box_building(length=2.0, width=1.6, courses=4, door=(0.8, 1.2, 3), windows=(), name="building"),
    }
    specs["seedwall_mu0.4"] = with_mu(wall, 0.4)
    specs["building_mu0.9"] = with_mu(specs["building"], 0.9)
    specs["seedwall_oop_turned"] = turned(wall_oop)
    specs["building_turned"] = turned(specs["building"])
    return specs
