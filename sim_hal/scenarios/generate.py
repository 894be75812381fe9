#!/usr/bin/env python3
"""Writes the shipped scenario files. The JSON files are committed; rerun
this after changing it (python3 generate.py) and commit both.

python3 generate.py --dev DIR [--dev-offset N] writes a development set instead: the rack-wall
scenarios with every layout drawn from other seeds (and other sensor noise),
approaches to four other rails in Columbus (other rack edges, other
lengths: COLUMBUS_DEV_RAILS), views along and across Columbus from other
places (columbus_views()), a flat wall with seeded clutter
(flat_clutter()) and seeded sweeps past handrails on a cluttered flat wall
(dev_sweep()), named dev-*, into DIR (not committed). Work on the
detector is tried there; the shipped scenarios stay the ones it is judged on, so that no threshold is
fitted to the scenes that score it.

World frame: the main wall is the plane x = 0, facing +x (toward the room),
z up. Cameras face -x unless a pose says otherwise."""
import json
import os
import sys

# --dev DIR [--dev-offset N]: the development set (see above); N (default
# 50000, a positive integer) is added to every seed, so another N draws
# another development set of the same kinds of scene.
DEV_DIR = None
DEV_SEED_OFFSET = 50000
USAGE = "usage: generate.py [--dev DIR [--dev-offset N]]"
if len(sys.argv) == 2 and sys.argv[1] in ("-h", "--help"):
    print(__doc__)
    print(USAGE)
    sys.exit(0)
if len(sys.argv) in (3, 5) and sys.argv[1] == "--dev":
    DEV_DIR = os.path.abspath(sys.argv[2])
    if len(sys.argv) == 5:
        if sys.argv[3] != "--dev-offset" or not sys.argv[4].isdigit() or int(sys.argv[4]) <= 0:
            sys.exit("generate.py: --dev-offset needs a positive integer, got %r\n%s" % (" ".join(sys.argv[3:]), USAGE))
        DEV_SEED_OFFSET = int(sys.argv[4])
elif len(sys.argv) != 1:
    sys.stderr.write("generate.py: unknown arguments %r\n%s (see --help)\n" % (" ".join(sys.argv[1:]), USAGE))
    sys.exit(2)

WALL = {"center": [0, 0, 0], "normal": [1, 0, 0], "up": [0, 0, 1], "size": [4.0, 2.5], "reflectivity": 0.6}

def clutter_around_horizontal_rail(y0=0.0):
    """Figure 14's setup: instruments above, below and beside a horizontal
    handrail, thin cables around it, one parallel to it."""
    return {
        "boxes": [
            {"center": [0.05, y0 + 0.05, 0.19], "size": [0.10, 0.22, 0.10]},
            {"center": [0.075, y0 - 0.08, -0.19], "size": [0.15, 0.18, 0.09]},
            {"center": [0.06, y0 + 0.43, 0.0], "size": [0.12, 0.10, 0.24]},
        ],
        "cables": [
            # Parallel to the rail, 9 cm below it, bridging 5 cm off the wall.
            {"points": [[0.0, y0 - 0.45, -0.09], [0.05, y0 - 0.30, -0.09], [0.05, y0 + 0.30, -0.09], [0.0, y0 + 0.45, -0.09]], "diameter": 0.012},
            # Lying on the wall, diagonal.
            {"points": [[0.008, y0 - 0.40, 0.08], [0.008, y0 + 0.35, 0.15]], "diameter": 0.016},
            # Crossing behind the rail, bridging 3 cm.
            {"points": [[0.0, y0 + 0.12, -0.30], [0.03, y0 + 0.12, -0.12], [0.03, y0 + 0.14, 0.12], [0.0, y0 + 0.16, 0.30]], "diameter": 0.008},
            # Thick bundle above, 2 cm across, 6 cm off the wall.
            {"points": [[0.0, y0 - 0.50, 0.11], [0.06, y0 - 0.35, 0.11], [0.06, y0 - 0.05, 0.12]], "diameter": 0.022},
        ],
        "pipes": [{"points": [[0.03, -2.0, -0.45], [0.03, 2.0, -0.45]], "diameter": 0.05}],
    }

TABLE2 = [  # id, y cm, z cm, roll, pitch, yaw (deg)
    (1, 0, 0, 0, 0, 0), (2, 0, 0, 30, 0, 0), (3, 15, 0, 0, 0, 30), (4, 15, 0, 30, 0, 30),
    (5, 0, 15, 0, 0, 30), (6, 0, 15, 30, 0, 30), (7, 15, 15, 0, 30, 30), (8, 15, 15, 30, 30, 30)]

MESH_55CM = "../assets/handrails/handrail_21_5.dae"  # the 21.5 in rail: the paper's 55 cm handrail

def rail(kind, foot, axis):
    """A 55 cm handrail of the given kind; the mesh kind takes its length
    from the model."""
    r = {"kind": kind, "foot": foot, "normal": [1, 0, 0], "axis": axis}
    if kind == "iss_mesh":
        r["mesh"] = MESH_55CM
    else:
        r["length"] = 0.55
    return r

def table2(kind):
    scene = {"walls": [WALL], "handrails": [rail(kind, [0, 0, 0], [0, 1, 0])]}
    scene.update(clutter_around_horizontal_rail())
    poses = []
    for tid, y, z, roll, pitch, yaw in TABLE2:
        # Turn toward the handrail: the camera sits at +y / +z of it.
        poses.append({"label": "table2-%d" % tid, "position": [0.60, y / 100.0, z / 100.0],
                      "rpy_deg": [roll, pitch, yaw], "frames": 50})
    return {"name": "table2-" + kind.replace("_", "-"),
            "description": "The paper's Table 2: camera 60 cm from the wall facing a horizontal %s handrail among instruments and cables, 8 poses x 50 frames." % kind,
            "seed": {"round": 2, "iss": 3, "iss_mesh": 4}[kind], "frame_rate_hz": 5, "gripper_angle_deg": 90, "scene": scene, "poses": poses}

def sweep():
    rails = [{"kind": "iss", "foot": [0, y, 0], "normal": [1, 0, 0], "axis": [0, 0, 1], "length": L}
             for y, L in ((-0.9, 0.55), (0.0, 1.055), (0.9, 0.55))]
    scene = {"walls": [WALL], "handrails": rails,
             "boxes": [{"center": [0.06, -0.45, 0.15], "size": [0.12, 0.2, 0.3]},
                       {"center": [0.04, 0.45, -0.2], "size": [0.08, 0.25, 0.2]},
                       {"center": [0.1, 1.35, 0.1], "size": [0.2, 0.3, 0.3]}],
             "cables": [{"points": [[0.0, -1.5, -0.3], [0.04, -1.2, -0.3], [0.04, 1.2, -0.28], [0.0, 1.5, -0.3]], "diameter": 0.012},
                        {"points": [[0.008, -0.6, -0.5], [0.008, -0.55, 0.5]], "diameter": 0.015},
                        {"points": [[0.0, 0.25, -0.5], [0.05, 0.25, -0.3], [0.05, 0.28, 0.3], [0.0, 0.3, 0.5]], "diameter": 0.01}]}
    return {"name": "sweep", "description": "The paper's simulation: a lateral sweep 75 cm from a cluttered wall past three vertical ISS handrails.",
            "seed": 11, "frame_rate_hz": 5, "scene": scene,
            "poses": [{"label": "sweep", "position": [0.75, -1.3, 0.0], "to": {"position": [0.75, 1.3, 0.0]}, "frames": 80}]}

def approach(kind):
    scene = {"walls": [WALL], "handrails": [rail(kind, [0, 0, 0], [0, 0, 1])],
             "boxes": [{"center": [0.05, 0.3, 0.1], "size": [0.1, 0.15, 0.2]}],
             "cables": [{"points": [[0.0, -0.15, -0.6], [0.04, -0.15, -0.4], [0.04, -0.16, 0.4], [0.0, -0.16, 0.6]], "diameter": 0.012}]}
    return {"name": "approach-" + kind.replace("_", "-"),
            "description": "A perching approach from 1.2 m to 0.25 m toward a vertical %s handrail, 12 cm above its centre: both ends in view, then one, then none." % kind,
            "seed": 21, "frame_rate_hz": 5, "scene": scene,
            "poses": [{"label": "approach", "position": [1.2, 0.0, 0.12], "to": {"position": [0.25, 0.0, 0.12]}, "frames": 60}]}

def clutter_only():
    scene = {"walls": [WALL]}
    scene.update(clutter_around_horizontal_rail())
    scene["cables"].append({"points": [[0.0, -0.3, -0.35], [0.06, -0.2, -0.3], [0.06, 0.25, -0.3], [0.0, 0.35, -0.35]], "diameter": 0.025})
    return {"name": "clutter-only", "description": "Instruments, cables and a pipe, no handrail: every detection is a false one.",
            "seed": 31, "frame_rate_hz": 5, "scene": scene,
            "poses": [{"label": "clutter", "position": [0.7, -0.3, 0.0], "to": {"position": [0.6, 0.3, 0.05], "rpy_deg": [20, 10, 15]}, "frames": 60}]}

def two_perpendicular():
    scene = {"walls": [WALL], "handrails": [
        {"kind": "iss", "foot": [0, -0.12, 0.0], "normal": [1, 0, 0], "axis": [0, 0, 1], "length": 0.55},
        {"kind": "iss", "foot": [0, 0.22, -0.05], "normal": [1, 0, 0], "axis": [0, 1, 0], "length": 0.55}],
        "cables": [{"points": [[0.008, -0.5, 0.2], [0.008, 0.5, 0.25]], "diameter": 0.015}]}
    return {"name": "two-perpendicular", "description": "A vertical and a horizontal ISS handrail in view; the gripper angle picks the vertical one.",
            "seed": 41, "frame_rate_hz": 5, "scene": scene,
            "poses": [{"label": "two", "position": [0.85, 0.05, 0.0], "to": {"position": [0.8, 0.1, 0.05], "rpy_deg": [5, 0, 5]}, "frames": 40}]}

def corner():
    scene = {"walls": [WALL, {"center": [0.6, 0.35, 0], "normal": [0, -1, 0], "up": [0, 0, 1], "size": [1.2, 2.5], "reflectivity": 0.5}],
             "handrails": [{"kind": "iss", "foot": [0, 0.17, 0], "normal": [1, 0, 0], "axis": [0, 0, 1], "length": 0.55}],
             "boxes": [{"center": [0.05, -0.25, -0.2], "size": [0.1, 0.15, 0.15]}]}
    return {"name": "corner", "description": "A vertical ISS handrail 18 cm from a concave module corner (multipath, a second wall in view).",
            "seed": 51, "frame_rate_hz": 5, "scene": scene,
            "poses": [{"label": "corner", "position": [0.8, -0.1, 0.0], "rpy_deg": [0, 0, -10], "to": {"position": [0.65, 0.0, 0.0], "rpy_deg": [0, 0, -20]}, "frames": 40}]}

ASSETS = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "assets")

def write(s):
    if DEV_DIR is not None:
        # Only the rack walls, whose layouts come from the seeds, the
        # Columbus approaches and views around the development rails (other
        # rack edges of the module, surveyed below; the views from other
        # places) and the seeded flat-wall clutter. Mesh
        # paths made absolute, the files living elsewhere.
        dev_scene = s["name"].startswith("rack-") and "control" not in s["name"]
        if not (dev_scene or s["name"] in ("columbus-approaches", "columbus-module-views", "flat-clutter", "flat-sweep")):
            return
        text = json.dumps(s).replace('"../assets/', '"' + os.path.normpath(ASSETS) + '/')
        s = json.loads(text)
        s["name"] = "dev-" + s["name"]
        s["seed"] += DEV_SEED_OFFSET
        os.makedirs(DEV_DIR, exist_ok=True)
        path = os.path.join(DEV_DIR, s["name"] + ".json")
    else:
        # Beside this script, wherever it is run from.
        path = os.path.join(os.path.dirname(os.path.abspath(__file__)), s["name"] + ".json")
    with open(path, "w") as f:
        json.dump(s, f, indent=1)
        f.write("\n")
    print("wrote", path)

for s in (table2("round"), table2("iss"), table2("iss_mesh"), sweep(), approach("iss"), approach("round"),
          approach("iss_mesh"), clutter_only(), two_perpendicular(), corner()):
    write(s)

# ---------------------------------------------------------------------------
# ISS rack walls: scenes built from the station's facts, not from
# what the detector finds easy.
#
# - Handrails stand on seat tracks: strips 2.6 cm wide, 1.3 cm proud of the
#   rack face, along rack edges; the bar's centre line is 6.1 cm above the
#   track, 7.4 cm above the face.
# - Neighbouring rack faces differ in depth by 1 to 5 cm; about 2 cm beside a
#   track there is often a gap between racks about 12 cm deep, or an opening
#   that returns nothing; some handrails stand beside an empty bay 35 cm
#   deep. A view shows two or three surfaces at different depths, none of
#   them the track the handrail stands on.
# - Lengths: 8.5 in (bar 0.20 m), 21.5 in (0.53 m), 30 in (0.76 m), 41.5 in
#   (1.04 m) and the 1 m module rails (a box bar on legs).
# - Clutter: cables 0.6 to 2.5 cm thick lying on the surface, bridging 2 to
#   8 cm above it or running 6 to 16 cm beside a handrail, some handrail-like
#   (1.5 to 2.5 cm thick, 2 to 8 cm off); boxes 5 to 20 cm proud and 10 to
#   40 cm across.
# Every layout is drawn from a seeded random.Random, so the files are the
# same on every run.
import random

if DEV_DIR is not None:
    # Every layout drawn from other seeds: random.Random(seed) shifted.
    class _ShiftedRandom(random.Random):
        def __init__(self, seed=None):
            super().__init__(seed + DEV_SEED_OFFSET if isinstance(seed, int) else seed)
    random.Random = _ShiftedRandom

TRACK_W, TRACK_H, RAIL_OFFSET = 0.026, 0.013, 0.061
MESHES = {  # file, bar length (measured from the mesh by sim_hal's measure_bar)
    "8-5": ("../assets/handrails/handrail_8_5.dae", 0.202),
    "21-5": ("../assets/handrails/handrail_21_5.dae", 0.531),
    "30": ("../assets/handrails/handrail_30.dae", 0.762),
    "41-5": ("../assets/handrails/handrail_41_5.dae", 1.040),
}

def r4(x):
    return round(x, 4)

def vec(v):
    return [r4(c) for c in v]

def add(a, b, k=1.0):
    return [a[i] + k * b[i] for i in range(3)]

def cross(a, b):
    return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]

class Wall:
    """A rack wall's frame as sim_hal builds it: v = up, u = v x normal."""
    def __init__(self, center, normal, up):
        self.c, self.n, self.v = center, normal, up
        self.u = cross(up, normal)

    def point(self, u, v, depth):
        return add(add(add(self.c, self.u, u), self.v, v), self.n, depth)

class RackLayout:
    """A rack wall around one seat track, in the rail's own coordinates: a
    along the track (the track's centre at a = 0), c across it (the track
    from c = -0.013 to 0.013, the neighbouring rack at c > 0). `vertical`
    runs the track along the wall's v (up), else along u; `side` mirrors c."""
    def __init__(self, rng, rail_len, wall, vertical=False, bay=False, gap=None, extent=1.4):
        self.rng, self.wall, self.vertical = rng, wall, vertical
        self.side = rng.choice((-1, 1))
        self.faces, self.tracks, self.gaps, self.bays, self.strips = [], [], [], [], []
        u = rng.uniform
        d_a = u(-0.02, 0.02)                        # rack A's frame, the track's base
        self.base = d_a
        edge = TRACK_W / 2 + u(0.015, 0.025)        # the track ~2 cm from rack A's edge
        c_panel = -u(0.05, 0.15)                    # rack A's frame, then its inner panel
        d_panel = d_a + rng.choice((-1, 1)) * u(0.01, 0.04)
        gap_kind = gap or rng.choice(("recess", "recess", "opening", "opening", "none"))
        g = 0.0 if gap_kind == "none" else u(0.02, 0.05)
        d_b = d_a + rng.choice((-1, 1)) * u(0.01, 0.05)
        # Along the track: rack A, then (past a narrow opening) racks C at
        # their own depths, each with its own seat track.
        a_lo, a_hi = -(rail_len / 2 + u(0.06, 0.35)), rail_len / 2 + u(0.06, 0.35)
        refl = lambda: r4(u(0.45, 0.7))
        self.face((a_lo, a_hi), (c_panel, edge), d_a, refl())
        self.face((a_lo, a_hi), (-extent, c_panel), d_panel, refl())
        self.track((a_lo + 0.01, a_hi - 0.01), d_a)
        for lo, hi in ((-extent, a_lo - u(0.01, 0.03)), (a_hi + u(0.01, 0.03), extent)):
            d_c = d_a + rng.choice((-1, 1)) * u(0.01, 0.05)
            self.face((lo, hi), (-extent, edge), d_c, refl())
            self.track((lo + 0.01, hi - 0.01), d_c)
        if gap_kind == "recess":
            self.gap((-extent, extent), (edge, edge + g), r4(-u(0.10, 0.14)))
        elif gap_kind == "opening":
            self.gap((-extent, extent), (edge, edge + g), None)
        c_b = edge + g
        if bay:
            # An empty bay beside the handrail: a rack's worth of wall
            # missing, 35 cm deep, racks B around it.
            b_lo, b_hi, c_hi = -u(0.45, 0.6), u(0.45, 0.6), c_b + u(0.8, 1.0)
            self.bay((b_lo, b_hi), (c_b, c_hi), d_a - 0.35, min(d_a, d_b))
            self.face((-extent, b_lo), (c_b, extent), d_b, refl())
            self.face((b_hi, extent), (c_b, extent), d_b, refl())
            if c_hi < extent:
                self.face((b_lo, b_hi), (c_hi, extent), d_b, refl())
        else:
            self.face((-extent, extent), (c_b, extent), d_b, refl())
            # An edge strip along rack B's edge and a light on its face.
            self.strip((-extent, extent), (c_b + 0.004, c_b + u(0.012, 0.02)), d_b, 0.004, 0.85)
            a0 = u(-0.3, 0.2)
            self.strip((a0, a0 + u(0.08, 0.16)), (c_b + u(0.06, 0.1), c_b + u(0.12, 0.16)), d_b, 0.002, 0.95)
        # A label on rack A's panel.
        a0 = u(-0.4, 0.3)
        self.strip((a0, a0 + 0.07), (c_panel - 0.09, c_panel - 0.04), d_panel, 0.001, 0.9)
        self.gap_kind, self.d = gap_kind, {"a": d_a, "panel": d_panel, "b": d_b}
        self.edge, self.c_panel, self.c_b = edge, c_panel, c_b

    # Rail coordinates to the wall's (u, v) rectangle.
    def rect(self, a, c):
        cs = sorted((self.side * c[0], self.side * c[1]))
        if self.vertical:
            return {"u": vec(cs), "v": vec(a)}
        return {"u": vec(a), "v": vec(cs)}

    def uv(self, a, c):
        return (self.side * c, a) if self.vertical else (a, self.side * c)

    def face(self, a, c, depth, refl):
        f = self.rect(a, c)
        f.update({"depth": r4(depth), "reflectivity": refl})
        self.faces.append(f)

    def track(self, a, depth):
        self.tracks.append({"from": vec(self.uv(a[0], 0.0)), "to": vec(self.uv(a[1], 0.0)), "depth": r4(depth)})

    def gap(self, a, c, depth):
        g = self.rect(a, c)
        if depth is not None:
            g["depth"] = depth
        self.gaps.append(g)

    def bay(self, a, c, depth, rim):
        b = self.rect(a, c)
        b.update({"depth": r4(depth), "rim": r4(rim)})
        self.bays.append(b)

    def strip(self, a, c, depth, height, refl):
        st = self.rect(a, c)
        st.update({"depth": r4(depth), "height": height, "reflectivity": refl})
        self.strips.append(st)

    def surface_depth(self, a, c):
        """The rack surface's depth at rail point (a, c), for clutter."""
        if c < self.c_panel:
            return self.d["panel"]
        if c < self.edge:
            return self.base + (TRACK_H if abs(c) < TRACK_W / 2 else 0.0)
        return self.d["b"]

    def json(self):
        w = {"center": vec(self.wall.c), "normal": self.wall.n, "up": self.wall.v, "faces": self.faces,
             "seat_tracks": self.tracks}
        if self.gaps:
            w["gaps"] = self.gaps
        if self.bays:
            w["bays"] = self.bays
        w["strips"] = self.strips
        return w

    def world(self, a, c, height):
        """World point at rail coordinates (a, c), `height` above the rack
        surface there."""
        u, v = self.uv(a, c)
        return self.wall.point(u, v, self.surface_depth(a, c) + height)

    def rail_axis(self):
        return self.wall.v if self.vertical else self.wall.u

    def foot(self):
        """The handrail's footprint centre: on the track's top at a = 0."""
        return vec(self.wall.point(0.0, 0.0, self.base + TRACK_H))

def rack_rail(layout, kind, length=None, mesh=None):
    r = {"kind": kind, "foot": layout.foot(), "normal": layout.wall.n, "axis": layout.rail_axis()}
    if kind == "iss_mesh":
        r["mesh"] = mesh
    else:
        r["length"] = length
    return r

WALL_X = Wall([0, 0, 0], [1, 0, 0], [0, 0, 1])  # u = +y, v = +z: cameras face -x

RACK_RAILS = [  # name, kind, length or mesh, bar length
    ("iss-mesh-8-5", "iss_mesh", MESHES["8-5"][0], MESHES["8-5"][1]),
    ("iss-mesh-21-5", "iss_mesh", MESHES["21-5"][0], MESHES["21-5"][1]),
    ("iss-mesh-30", "iss_mesh", MESHES["30"][0], MESHES["30"][1]),
    ("iss-mesh-41-5", "iss_mesh", MESHES["41-5"][0], MESHES["41-5"][1]),
    ("iss-0-20", "iss", 0.20, 0.20), ("iss-0-53", "iss", 0.53, 0.53), ("iss-0-76", "iss", 0.76, 0.76),
    ("iss-1-04", "iss", 1.04, 1.04), ("module-rail", "module_rail", 1.0, 1.0)]

def rail_for(layout, kind, what):
    return rack_rail(layout, kind, mesh=what) if kind == "iss_mesh" else rack_rail(layout, kind, length=what)

def rack_table2(index, name, kind, what, bar):
    rng = random.Random(1700 + index)
    lay = RackLayout(rng, bar + 0.02, WALL_X, bay=(index % 3 == 2))
    scene = {"rack_walls": [lay.json()], "handrails": [rail_for(lay, kind, what)]}
    x0 = lay.base + TRACK_H
    poses = [{"label": "table2-%d" % tid, "position": [r4(x0 + 0.60), y / 100.0, z / 100.0],
              "rpy_deg": [roll, pitch, yaw], "frames": 50} for tid, y, z, roll, pitch, yaw in TABLE2]
    gaps = {"recess": "a gap %.0f cm deep" % (100 * -lay.gaps[0].get("depth", 0)) if lay.gaps else "",
            "opening": "an opening that returns nothing", "none": "no gap"}[lay.gap_kind]
    return {"name": "rack-table2-" + name,
            "description": ("The paper's Table 2 (8 poses x 50 frames, camera 60 cm from the mount surface) on an ISS "
                            "rack wall: a horizontal %s handrail (bar %.2f m) on a seat track along rack A's edge "
                            "(frame %+.1f cm, panel %+.1f cm), %s beside it, then %s at %+.1f cm.") %
                           (kind, bar, 100 * lay.d["a"], 100 * lay.d["panel"], gaps,
                            "an empty bay 35 cm deep among racks" if lay.bays else "rack B", 100 * lay.d["b"]),
            "seed": 1700 + index, "frame_rate_hz": 5, "gripper_angle_deg": 90, "scene": scene, "poses": poses}

def pose_on(wall, point, distance, offset_u=0.0, offset_v=0.0, rpy=(0, 0, 0), up=None):
    """A camera `distance` off the wall in front of `point` (moved along the
    wall's u and v), facing the wall."""
    p = add(add(add(point, wall.n, distance), wall.u, offset_u), wall.v, offset_v)
    pose = {"position": vec(p), "facing": [-x for x in wall.n], "rpy_deg": list(rpy)}
    pose["up"] = up or wall.v
    return pose

def approach_segments(wall, foot, along, vertical_in_image, label_prefix="approach"):
    """Three approaches from 1.2 m to 0.3 m off the mount surface, 12 cm
    along the rail from its centre: straight, tilted (pitch and yaw), and
    rolled; 40 frames each."""
    up = wall.v if (vertical_in_image == (along == wall.v)) else wall.u
    off = [0.12 * x for x in along]
    start = add(foot, off)
    segs = []
    for label, rpy0, rpy1 in (("straight", (0, 0, 0), (0, 0, 0)), ("tilt", (0, -15, 20), (0, 10, -10)),
                              ("roll", (30, 5, 0), (-20, 0, 10))):
        a = pose_on(wall, start, 1.2, rpy=rpy0, up=up)
        b = pose_on(wall, start, 0.3, rpy=rpy1, up=up)
        a["label"] = label_prefix + "-" + label
        a["frames"] = 40
        a["to"] = {"position": b["position"], "rpy_deg": b["rpy_deg"]}
        segs.append(a)
    return segs

def rack_approach(index, name, kind, what, bar, wall, vertical_track, vertical_in_image, where):
    rng = random.Random(1800 + index)
    lay = RackLayout(rng, bar + 0.02, wall, vertical=vertical_track, bay=(index == 2))
    scene = {"rack_walls": [lay.json()], "handrails": [rail_for(lay, kind, what)]}
    along = lay.rail_axis()
    poses = approach_segments(wall, lay.foot(), along, vertical_in_image)
    return {"name": "rack-approach-" + name,
            "description": ("Perching approaches on an ISS rack %s from 1.2 m to 0.3 m off the mount surface toward a "
                            "%s handrail (bar %.2f m, %s in the image) on a seat track, 12 cm along it from its "
                            "centre: straight, tilted, rolled (40 frames each); gap beside the track: %s%s.") %
                           (where, kind, bar, "vertical" if vertical_in_image else "horizontal", lay.gap_kind,
                            ", an empty bay beyond" if lay.bays else ""),
            "seed": 1800 + index, "frame_rate_hz": 5, "gripper_angle_deg": 0 if vertical_in_image else 90,
            "scene": scene, "poses": poses}

def clutter_on(lay, rng, rail_len, with_rail_like=True):
    """Clutter per the station's facts around the rail (rail coordinates)."""
    u = rng.uniform
    cables, boxes = [], []
    side_c = rng.choice((-1, 1))
    # Beside the handrail, 6 to 16 cm away, bridging 2 to 8 cm above the surface.
    c = side_c * u(0.06, 0.16)
    h = u(0.02, 0.08)
    d = r4(u(0.006, 0.025))
    cables.append({"points": [vec(lay.world(-0.7, c, d / 2)), vec(lay.world(-0.45, c, h)),
                              vec(lay.world(0.45, c, h)), vec(lay.world(0.7, c, d / 2))], "diameter": d})
    # Lying on the surface, across the view.
    for _ in range(2):
        c0, c1 = u(-0.35, -0.12), u(0.15, 0.4)
        a0, a1 = u(-0.5, 0.5), u(-0.5, 0.5)
        d = r4(u(0.006, 0.025))
        cables.append({"points": [vec(lay.world(a0, c0, d / 2)), vec(lay.world(a1, c1, d / 2))], "diameter": d})
    # Bridging 2 to 8 cm over the surface.
    a0 = u(-0.4, 0.4)
    h = u(0.02, 0.08)
    d = r4(u(0.006, 0.02))
    cables.append({"points": [vec(lay.world(a0, -0.4, d / 2)), vec(lay.world(a0 + 0.05, -0.2, h)),
                              vec(lay.world(a0 + 0.1, 0.2, h)), vec(lay.world(a0 + 0.15, 0.4, d / 2))], "diameter": d})
    if with_rail_like:
        # Handrail-like: 1.5 to 2.5 cm thick, straight, 2 to 8 cm off the surface.
        c = -side_c * u(0.18, 0.3)
        h = u(0.02, 0.08)
        a0 = u(-0.3, 0.0)
        d = r4(u(0.015, 0.025))
        cables.append({"points": [vec(lay.world(a0 - 0.08, c, d / 2)), vec(lay.world(a0, c, h)),
                                  vec(lay.world(a0 + u(0.3, 0.5), c, h)), vec(lay.world(a0 + 0.6, c, d / 2))],
                       "diameter": d})
    # Boxes 5 to 20 cm proud, 10 to 40 cm across, clear of the rail.
    for k in range(3):
        w_a, w_c, proud = u(0.1, 0.4), u(0.1, 0.3), u(0.05, 0.2)
        a = rng.choice((-1, 1)) * u(rail_len / 2 + 0.05 + w_a / 2, rail_len / 2 + 0.3 + w_a / 2) if k == 0 else u(-0.5, 0.5)
        c = (rng.choice((-1, 1)) * u(0.12 + w_c / 2, 0.35 + w_c / 2)) if k else u(-0.1, 0.1)
        base = lay.surface_depth(a, c)
        uu, vv = lay.uv(a, c)
        center = lay.wall.point(uu, vv, base + proud / 2)
        size_uv = (w_c, w_a) if lay.vertical else (w_a, w_c)
        # WALL_X: box axes = world x (normal), y (u), z (v).
        boxes.append({"center": vec(center), "size": vec([proud, size_uv[0], size_uv[1]]),
                      "reflectivity": r4(u(0.3, 0.7))})
    return cables, boxes

def rack_clutter(index, name, kind, what, bar, vertical):
    rng = random.Random(1900 + index)
    lay = RackLayout(rng, bar + 0.02, WALL_X, vertical=vertical)
    cables, boxes = clutter_on(lay, rng, bar)
    scene = {"rack_walls": [lay.json()], "handrails": [rail_for(lay, kind, what)], "cables": cables, "boxes": boxes}
    foot = lay.foot()
    along, across = lay.rail_axis(), (WALL_X.u if vertical else WALL_X.v)
    start = add(add(foot, along, -0.25), across, 0.05)
    end = add(add(foot, along, 0.25), across, -0.08)
    poses = []
    for label, dist0, dist1, rpy0, rpy1 in (("clutter-pass", 0.8, 0.6, (0, 0, 10), (10, 10, -15)),
                                           ("clutter-close", 0.55, 0.45, (-15, -10, -10), (20, 5, 15))):
        a = pose_on(WALL_X, start, dist0, rpy=rpy0)
        b = pose_on(WALL_X, end, dist1, rpy=rpy1)
        a.update({"label": label, "frames": 50, "to": {"position": b["position"], "rpy_deg": b["rpy_deg"]}})
        poses.append(a)
        start, end = end, start
    return {"name": "rack-clutter-" + name,
            "description": ("A %s %s handrail (bar %.2f m) on a seat track among ISS rack clutter: a cable 6-16 cm "
                            "beside it, cables lying and bridging, a handrail-like cable (1.5-2.5 cm, 2-8 cm off), "
                            "three boxes 5-20 cm proud; two passes of 50 frames.") %
                           ("vertical" if vertical else "horizontal", kind, bar),
            "seed": 1900 + index, "frame_rate_hz": 5, "gripper_angle_deg": 0 if vertical else 90,
            "scene": scene, "poses": poses}

def rack_no_handrail_wall():
    rng = random.Random(2001)
    lay = RackLayout(rng, 0.6, WALL_X, gap="opening")
    lay2 = RackLayout(random.Random(2002), 0.6, Wall([0, 1.6, 0], [1, 0, 0], [0, 0, 1]), vertical=True, bay=True)
    cables, boxes = clutter_on(lay, rng, 0.6)
    # Two more handrail-like cables: straight, 2 cm thick, 4 and 7 cm off.
    for c, h, a0 in ((0.1, 0.04, -0.3), (-0.2, 0.07, 0.1)):
        cables.append({"points": [vec(lay.world(a0 - 0.1, c, 0.01)), vec(lay.world(a0, c, h)),
                                  vec(lay.world(a0 + 0.45, c, h)), vec(lay.world(a0 + 0.55, c, 0.01))],
                       "diameter": 0.02})
    scene = {"rack_walls": [lay.json(), lay2.json()], "cables": cables, "boxes": boxes}
    poses = [{"label": "no-rail-sweep", "position": [0.75, -0.6, 0.05], "rpy_deg": [0, 0, 0], "frames": 60,
              "to": {"position": [0.7, 1.4, -0.05], "rpy_deg": [10, 5, 15]}},
             {"label": "no-rail-close", "position": [0.45, 0.3, 0.2], "rpy_deg": [-20, 15, -10], "frames": 40,
              "to": {"position": [0.5, -0.3, -0.2], "rpy_deg": [25, -10, 20]}}]
    return {"name": "rack-no-handrail-wall",
            "description": "ISS rack walls with seat tracks, gaps, an opening, an empty bay, edge strips, lights, "
                           "boxes and three handrail-like cables, and no handrail: every detection is false. 100 frames.",
            "seed": 2001, "frame_rate_hz": 5, "gripper_angle_deg": 90, "scene": scene, "poses": poses}

def rack_no_handrail_corner():
    # A wall of racks (x = 0) meeting a deck of racks (z = -0.9) in a
    # concave corner, and an overhead (z = 1.1) in the second pass.
    wall = RackLayout(random.Random(2101), 0.6, WALL_X, gap="recess")
    deck = RackLayout(random.Random(2102), 0.6, Wall([0.75, 0, -0.9], [0, 0, 1], [1, 0, 0]), vertical=True)
    over = RackLayout(random.Random(2103), 0.6, Wall([0.75, 0, 1.1], [0, 0, -1], [1, 0, 0]), vertical=False)
    # Keep the deck and overhead in front of the wall: their racks start at x = 0.
    for lay in (deck, over):
        for item in lay.faces + lay.gaps + lay.bays + lay.strips:
            lo, hi = item["v"]
            item["v"] = [max(lo, -0.73), max(hi, -0.72)]
        lay.tracks = [t for t in lay.tracks if min(t["from"][1], t["to"][1]) > -0.7]
    scene = {"rack_walls": [wall.json(), deck.json(), over.json()],
             "cables": [{"points": [[0.01, -0.6, -0.88], [0.25, -0.4, -0.86], [0.6, -0.45, -0.87]], "diameter": 0.02}]}
    poses = [{"label": "corner-deck", "position": [0.8, -0.3, -0.3], "rpy_deg": [0, 30, 0], "frames": 40,
              "to": {"position": [0.6, 0.4, -0.4], "rpy_deg": [15, 40, 20]}},
             {"label": "corner-overhead", "position": [0.8, 0.4, 0.5], "rpy_deg": [0, -30, 10], "frames": 40,
              "to": {"position": [0.6, -0.4, 0.6], "rpy_deg": [-15, -40, -20]}}]
    return {"name": "rack-no-handrail-corner",
            "description": "Concave corners of ISS rack walls with the deck and the overhead: rack edges, seat tracks, "
                           "gaps and a cable, no handrail: every detection is false. 80 frames.",
            "seed": 2101, "frame_rate_hz": 5, "gripper_angle_deg": 90, "scene": scene, "poses": poses}

rack_scenarios = []
for i, (name, kind, what, bar) in enumerate(RACK_RAILS):
    rack_scenarios.append(rack_table2(i, name, kind, what, bar))
WALL_DECK = Wall([0, 0, -0.9], [0, 0, 1], [1, 0, 0])      # u = -y, v = +x: cameras face -z
WALL_OVER = Wall([0, 0, 1.1], [0, 0, -1], [1, 0, 0])      # u = +y, v = +x: cameras face +z
rack_scenarios += [
    rack_approach(0, "vertical-21-5", "iss_mesh", MESHES["21-5"][0], MESHES["21-5"][1], WALL_X, True, True, "wall"),
    rack_approach(1, "horizontal-30", "iss_mesh", MESHES["30"][0], MESHES["30"][1], WALL_X, False, False, "wall"),
    rack_approach(2, "vertical-8-5", "iss_mesh", MESHES["8-5"][0], MESHES["8-5"][1], WALL_X, True, True, "wall"),
    rack_approach(3, "deck-41-5", "iss_mesh", MESHES["41-5"][0], MESHES["41-5"][1], WALL_DECK, True, True, "deck"),
    rack_approach(4, "overhead-module-rail", "module_rail", 1.0, 1.0, WALL_OVER, False, False, "overhead"),
    rack_clutter(0, "horizontal-21-5", "iss_mesh", MESHES["21-5"][0], MESHES["21-5"][1], False),
    rack_clutter(1, "vertical-30", "iss_mesh", MESHES["30"][0], MESHES["30"][1], True),
    rack_no_handrail_wall(), rack_no_handrail_corner()]

# Controls for reading the rack-wall results: the rack-table2-iss-mesh-21-5
# layout with its racks made flat and the handrail on the face (the
# simulator should then score like a flat wall), and flat racks with the
# seat track kept (what the 1.3 cm track alone does).
def rack_control(track):
    s = json.loads(json.dumps(rack_scenarios[1]))
    w = s["scene"]["rack_walls"][0]
    base = w["seat_tracks"][0]["depth"]
    for f in w["faces"]:
        f["depth"] = base
    w.pop("gaps", None)
    w.pop("bays", None)
    w["strips"] = []
    if track:
        for t in w["seat_tracks"]:
            t["depth"] = base
    else:
        w["seat_tracks"] = []
        s["scene"]["handrails"][0]["foot"][0] = base
        for p in s["poses"]:
            p["position"][0] = r4(base + 0.60)
    s["name"] = "rack-control-" + ("track-only" if track else "flat")
    s["description"] = ("Control for rack-table2-iss-mesh-21-5: its rack faces all at one depth, no gaps or strips, "
                        + ("the handrail on its 1.3 cm seat track." if track else "no seat track: the handrail on the face."))
    return s

rack_scenarios += [rack_control(False), rack_control(True)]

# The Columbus laboratory (sim_hal/assets/iss_modules: metres, Z up, the long
# axis y, the aisle's centre line near x = 0, z = -0.44). Its rack faces, as
# ray casting finds them: starboard x = 1.0532, port x = -1.0709, deck
# z = -1.0834, overhead z = 1.0447; rack edges (grooves, strips, openings)
# every ~1.05 m along y. The model has no seat tracks: they are added as
# boxes (2.6 cm x 1.3 cm) beside rack edges, and the handrails stand on them;
# sim_hal's test_every_shipped_handrail_stands_on_a_surface checks their feet.
COLUMBUS = "../assets/iss_modules/columbus_eu_lab.dae"

# Where the rails stand in Columbus: on a seat track 4 cm beside a rack
# edge, found by ray casting the module (sim_hal/scenarios/columbus_survey.py
# prints each wall's faces and edges). Each: kind, mesh or length, the point
# on the rack face under the rail's middle, the face's normal, the rail's
# axis, the track's length.
COLUMBUS_RAILS = (
    # Starboard: a vertical 21.5 in rail 4 cm beside the rack edge at y = 3.38.
    ("iss_mesh", "21-5", [1.0532, 3.42, -0.15], [-1, 0, 0], [0, 0, 1], 1.3),
    # Port: a vertical 30 in rail beside the edge strip at y = 2.31.
    ("iss_mesh", "30", [-1.0709, 2.36, -0.15], [1, 0, 0], [0, 0, 1], 1.3),
    # Deck: a 41.5 in rail across the module beside the edge at y = 3.37.
    ("iss_mesh", "41-5", [0.05, 3.42, -1.0834], [0, 0, 1], [1, 0, 0], 1.3),
    # Overhead: a 1 m module rail across the module beside the edge at y = 3.4.
    ("module_rail", 1.0, [0.0, 3.56, 1.0447], [0, 0, -1], [1, 0, 0], 1.2),
)
# The development set's rails (generate.py --dev): other rack edges of the
# same module, other lengths. Each face was checked flat (within 3 mm) past
# both ends of its track by the survey's line scans.
COLUMBUS_DEV_RAILS = (
    # Starboard: a vertical 30 in rail 4 cm beside the edge (a groove) at
    # y = 4.42; the face is flat over z -0.81 .. 0.53.
    ("iss_mesh", "30", [1.0532, 4.465, -0.15], [-1, 0, 0], [0, 0, 1], 1.2),
    # Port: a vertical 8.5 in rail beside the edge strip at y = 3.39, a gap
    # 7 cm further; flat over z -0.82 .. 0.54.
    ("iss_mesh", "8-5", [-1.0727, 3.435, -0.15], [1, 0, 0], [0, 0, 1], 1.2),
    # Deck: a 21.5 in rail across the module beside the edge at y = 1.26,
    # an opening that returns nothing before it; flat over x -0.53 .. 0.65.
    ("iss_mesh", "21-5", [0.05, 1.30, -1.0701], [0, 0, 1], [1, 0, 0], 1.1),
    # Overhead: a 1 m module rail beside the edge at y = 2.335, a gap before
    # it; flat over x -0.57 .. 0.73.
    ("module_rail", 1.0, [0.08, 2.375, 1.0446], [0, 0, -1], [1, 0, 0], 1.2),
)

def columbus_scene():
    rails, tracks = [], []
    def on_track(kind, what, face_point, normal, axis, track_len, along_offset=0.0):
        # The track: from 2 mm inside the face to 1.3 cm proud of it.
        n, a = normal, axis
        center = add(add(face_point, n, (TRACK_H - 0.002) / 2), a, along_offset)
        size = [0.0, 0.0, 0.0]
        for i in range(3):
            size[i] = abs(n[i]) * (TRACK_H + 0.002) + abs(a[i]) * track_len
        across = [1 - abs(n[i]) - abs(a[i]) for i in range(3)]
        size = [size[i] + across[i] * TRACK_W for i in range(3)]
        tracks.append({"center": vec(center), "size": vec(size), "reflectivity": 0.5})
        r = {"kind": kind, "foot": vec(add(face_point, n, TRACK_H)), "normal": n, "axis": a}
        if kind == "iss_mesh":
            r["mesh"] = what
        else:
            r["length"] = what
        rails.append(r)
    for kind, what, face_point, normal, axis, track_len in (
            COLUMBUS_DEV_RAILS if DEV_DIR is not None else COLUMBUS_RAILS):
        on_track(kind, MESHES[what][0] if kind == "iss_mesh" else what, face_point, normal, axis,
                 track_len)
    # The handrails the module's mesh models itself (mesh_handrails.py found
    # them; assets/iss_modules/columbus_eu_lab.handrails.json): ground truth
    # knows them, so that finding one is a handrail found, not a false
    # detection.
    with open(os.path.join(ASSETS, "iss_modules", "columbus_eu_lab.handrails.json")) as f:
        modelled = json.load(f)["handrails"]
    return {"meshes": [{"path": COLUMBUS, "reflectivity": 0.55, "handrails": modelled}],
            "handrails": rails, "boxes": tracks}

def columbus_approaches():
    poses = []
    # Toward each rail from the aisle, 12 cm along it from its centre, the
    # rail vertical in the image (gripper angle 0). The development set's
    # approaches: other start points, 4 to 10 cm along their rails either
    # way, other tilts.
    approaches = (
        ("columbus-starboard", [0.0, 3.42, -0.03], [0.74, 3.42, -0.03], [1, 0, 0], [0, 0, 1], (0, 0, 10), (5, -5, -5)),
        ("columbus-port", [0.0, 2.36, -0.03], [-0.758, 2.36, -0.03], [-1, 0, 0], [0, 0, 1], (0, 10, -15), (-10, 0, 5)),
        ("columbus-deck", [0.17, 3.42, -0.1], [0.17, 3.42, -0.77], [0, 0, -1], [1, 0, 0], (0, 0, 0), (15, 5, -10)),
        ("columbus-overhead", [0.12, 3.56, 0.3], [0.12, 3.56, 0.73], [0, 0, 1], [1, 0, 0], (0, -10, 10), (0, 5, 0)))
    if DEV_DIR is not None:
        approaches = (
            ("columbus-starboard", [-0.1, 4.465, -0.25], [0.72, 4.465, -0.25], [1, 0, 0], [0, 0, 1], (0, 5, -10), (-5, 0, 5)),
            ("columbus-port", [0.1, 3.435, -0.11], [-0.76, 3.435, -0.11], [-1, 0, 0], [0, 0, 1], (0, -5, 10), (5, 5, 0)),
            ("columbus-deck", [0.15, 1.30, 0.0], [0.15, 1.30, -0.76], [0, 0, -1], [1, 0, 0], (0, 0, 10), (-10, 5, 0)),
            ("columbus-overhead", [-0.02, 2.375, 0.2], [-0.02, 2.375, 0.73], [0, 0, 1], [1, 0, 0], (0, 10, -5), (5, -5, 0)))
    for label, start, end, facing, up, rpy0, rpy1 in approaches:
        poses.append({"label": label, "position": start, "facing": facing, "up": up, "rpy_deg": list(rpy0),
                      "frames": 40, "to": {"position": end, "rpy_deg": list(rpy1)}})
    return {"name": "columbus-approaches",
            "description": "Whole-module views inside the Columbus laboratory: approaches from the aisle to 0.3 m "
                           "toward four handrails standing on seat tracks beside rack edges (starboard 21.5 in, port "
                           "30 in, deck 41.5 in, overhead 1 m module rail), 40 frames each, rail vertical in the image.",
            "seed": 2201, "frame_rate_hz": 5, "gripper_angle_deg": 0, "scene": columbus_scene(), "poses": poses}

def columbus_views():
    # Looking along and across the module from the aisle: racks, edges, the
    # end cone, the handrails among them at 0.6 to 2.5 m.
    poses = [{"label": "columbus-look-starboard", "position": [-0.3, 1.6, -0.2], "facing": [0.8, 1, 0],
              "rpy_deg": [0, 0, 10], "frames": 30, "to": {"position": [-0.4, 3.0, -0.3], "rpy_deg": [0, 5, -25]}},
             {"label": "columbus-look-port", "position": [0.4, 4.6, -0.3], "facing": [-0.8, -1, 0],
              "rpy_deg": [0, 0, -10], "frames": 30, "to": {"position": [0.5, 3.2, -0.2], "rpy_deg": [0, 5, 20]}},
             {"label": "columbus-look-deck", "position": [0.0, 2.0, 0.2], "facing": [0, 1, -1], "up": [0, 1, 1],
              "frames": 30, "to": {"position": [0.1, 4.5, 0.1], "rpy_deg": [0, 0, 0]}},
             {"label": "columbus-look-overhead", "position": [0.0, 4.8, -0.6], "facing": [0, -1, 1.2], "up": [0, -1.2, -1],
              "rpy_deg": [0, 0, 90], "frames": 30, "to": {"position": [0.1, 2.5, -0.7], "rpy_deg": [0, 0, 90]}}]
    if DEV_DIR is not None:
        # The development set's views: from the other ends of the module,
        # the other way along it, other tilts.
        poses = [{"label": "columbus-look-starboard", "position": [-0.2, 4.4, 0.1], "facing": [0.8, -1, 0],
                  "rpy_deg": [0, 0, -10], "frames": 30, "to": {"position": [-0.3, 3.0, 0.0], "rpy_deg": [0, -5, 20]}},
                 {"label": "columbus-look-port", "position": [0.3, 1.5, -0.1], "facing": [-0.8, 1, 0],
                  "rpy_deg": [0, 0, 10], "frames": 30, "to": {"position": [0.4, 2.8, -0.2], "rpy_deg": [0, 5, -20]}},
                 {"label": "columbus-look-deck", "position": [0.1, 4.2, 0.3], "facing": [0, -1, -1], "up": [0, -1, 1],
                  "frames": 30, "to": {"position": [0.0, 1.8, 0.2], "rpy_deg": [0, 0, 15]}},
                 {"label": "columbus-look-overhead", "position": [-0.1, 1.6, -0.5], "facing": [0, 1, 1.2],
                  "up": [0, 1.2, -1], "rpy_deg": [0, 0, 90], "frames": 30,
                  "to": {"position": [0.0, 3.8, -0.6], "rpy_deg": [0, 5, 80]}}]
    return {"name": "columbus-module-views",
            "description": "Inside the Columbus laboratory, the camera looking along and across the module at its rack "
                           "walls, deck and overhead with four handrails on seat tracks among them (30 frames a "
                           "view, the gripper taking rails vertical in the image).",
            "seed": 2202, "frame_rate_hz": 5, "gripper_angle_deg": 0, "scene": columbus_scene(), "poses": poses}

class FlatLayout:
    """A plain wall in the rail coordinates clutter_on() uses: a along v,
    c along u, every surface at the wall."""
    def __init__(self, wall):
        self.wall, self.vertical = wall, True

    def uv(self, a, c):
        return (c, a)

    def surface_depth(self, a, c):
        return 0.0

    def world(self, a, c, height):
        return self.wall.point(c, a, height)

def flat_clutter():
    """The development set's flat wall: clutter_only()'s kind of scene (a
    flat wall, the station's clutter, no handrail) drawn from a seed, so
    that a change's false detections on a flat wall are seen before the
    scored flat walls are. Written only with --dev."""
    rng = random.Random(2301)
    flat = FlatLayout(WALL_X)
    cables, boxes = [], []
    for a_off in (-0.35, 0.35):
        more_cables, more_boxes = clutter_on(flat, rng, 0.55)
        for cab in more_cables:
            cab["points"] = [[p[0], p[1] + a_off, p[2]] for p in cab["points"]]
        for box in more_boxes:
            box["center"][1] += a_off
        cables += more_cables
        boxes += more_boxes
    scene = {"walls": [WALL], "cables": cables, "boxes": boxes,
             "pipes": [{"points": [[0.03, -2.0, -0.45], [0.03, 2.0, -0.45]], "diameter": 0.05}]}
    return {"name": "flat-clutter",
            "description": "A flat wall with the station's clutter (cables lying, bridging and handrail-like, boxes, "
                           "a pipe) drawn from a seed, no handrail: every detection is false. 100 frames.",
            "seed": 2301, "frame_rate_hz": 5, "gripper_angle_deg": 90, "scene": scene,
            "poses": [{"label": "flat-clutter-sweep", "position": [0.75, -0.7, 0.0], "rpy_deg": [0, 0, -10],
                       "frames": 60, "to": {"position": [0.65, 0.7, 0.05], "rpy_deg": [15, 10, 15]}},
                      {"label": "flat-clutter-close", "position": [0.45, 0.4, 0.15], "rpy_deg": [-20, 10, 10],
                       "frames": 40, "to": {"position": [0.5, -0.4, -0.15], "rpy_deg": [20, -10, -20]}}]}

def dev_sweep():
    """The development set's sweep: sweep()'s kind of scene (lateral passes
    along a flat wall past vertical ISS handrails, each rail crossing the
    whole image, its first and last frames at the image's edges) with the
    rails' places and lengths, the station's clutter around each and the
    passes' distances, heights and attitudes drawn from a seed, so that a
    rail at the edge of the view is studied on other frames than the scored
    sweep's. Written only with --dev."""
    rng = random.Random(2401)
    u = rng.uniform
    flat = FlatLayout(WALL_X)
    rails, cables, boxes = [], [], []
    y = -0.9
    for _ in range(3):
        length = rng.choice((0.202, 0.531, 0.762, 1.040))
        foot_z = u(-0.15, 0.15)
        rails.append({"kind": "iss", "foot": [0, r4(y), r4(foot_z)], "normal": [1, 0, 0], "axis": [0, 0, 1],
                      "length": length})
        more_cables, more_boxes = clutter_on(flat, rng, length)
        for cab in more_cables:
            cab["points"] = [[p[0], p[1] + y, p[2] + foot_z] for p in cab["points"]]
        for box in more_boxes:
            box["center"][1] += y
            box["center"][2] += foot_z
        cables += more_cables
        boxes += more_boxes
        y += u(0.8, 1.0)
    scene = {"walls": [WALL], "handrails": rails, "cables": cables, "boxes": boxes}
    first, last = rails[0]["foot"][1], rails[-1]["foot"][1]
    poses = []
    for k, distance in enumerate((u(0.5, 0.6), u(0.7, 0.8), u(0.9, 1.0))):
        z0, z1 = u(-0.1, 0.1), u(-0.1, 0.1)
        rpy0 = [r4(u(-5, 5)), r4(u(-5, 5)), r4(u(-8, 8))]
        rpy1 = [r4(u(-5, 5)), r4(u(-5, 5)), r4(u(-8, 8))]
        ends = (first - 0.7 * distance, last + 0.7 * distance)
        if k % 2:
            ends = ends[::-1]
        poses.append({"label": "dev-sweep-%d" % k, "position": [r4(distance), r4(ends[0]), r4(z0)], "rpy_deg": rpy0,
                      "frames": 60, "to": {"position": [r4(distance), r4(ends[1]), r4(z1)], "rpy_deg": rpy1}})
    return {"name": "flat-sweep",
            "description": "Three lateral passes along a flat wall with the station's clutter past three vertical ISS "
                           "handrails, each rail crossing the whole image (rails, clutter and passes drawn from a "
                           "seed; development set only).",
            "seed": 2401, "frame_rate_hz": 5, "gripper_angle_deg": 0, "scene": scene, "poses": poses}


# ---------------------------------------------------------------------------
# The nodes and the Cupola (sim_hal/assets/iss_modules/*.obj: compact copies
# of the shared meshes, already turned to the station's Z-up frame and kept
# in station coordinates, so placed with no position and no rotation). Only
# the handrails each mesh models are in view: obj_handrails.py found them
# (assets/iss_modules/<module>.handrails.json) and the mesh's "handrails"
# make them ground truth. Per module: several rails seen head-on and oblique
# (up to 45 deg), vertical and horizontal in the image, with one end out of
# view, from 0.3 to 1.2 m, some among clutter; and 12 views of walls, corners
# and hatches with no handrail in view (the views were surveyed with hrsim:
# no labelled rail, nor the Cupola's four unlabelled bracket-held bars, in
# view). The gripper angle is 0 as in columbus_views(): rails vertical in
# the image are the gripper's; a rail horizontal in the image is still the
# frame's target when it is the only one in view (tools/doc/hreval.md).
# These are held-out scenes: nothing in the detector is tuned on them.
import math

def unit(v):
    n = math.sqrt(sum(c * c for c in v))
    return [c / n for c in v]

def module_rails(module):
    with open(os.path.join(ASSETS, "iss_modules", module + ".handrails.json")) as f:
        return json.load(f)["handrails"]

def rail_frame(h):
    """A labelled rail's centre, axis, normal (toward the room), across."""
    e0, e1 = h["ends"]
    c = [(e0[i] + e1[i]) / 2 for i in range(3)]
    a = unit([e1[i] - e0[i] for i in range(3)])
    n = unit(h["normal"])
    return c, a, n, cross(a, n), h["length_m"]

def box_rpy(n, u, v):
    """rpy_deg turning a box's x, y, z to n, u, v (scenario.cpp: Rz Ry Rx)."""
    R = [[n[i], u[i], v[i]] for i in range(3)]
    pitch = math.asin(max(-1.0, min(1.0, -R[2][0])))
    roll = math.atan2(R[2][1], R[2][2])
    yaw = math.atan2(R[1][0], R[0][0])
    return [r4(math.degrees(roll)), r4(math.degrees(pitch)), r4(math.degrees(yaw))]

class RailLayout(FlatLayout):
    """clutter_on()'s rail coordinates around a module's rail: a along it,
    c across it, height off the surface it stands on (its centre line's
    stand-off behind it). Across the rail, past 17 cm, distances are halved:
    the nodes' corner panels are narrow."""
    def __init__(self, h, standoff):
        c, a, n, w, _ = rail_frame(h)
        FlatLayout.__init__(self, Wall(add(c, n, -standoff), n, a))

    def world(self, a, c, height):
        if abs(c) > 0.17:
            c = math.copysign(0.17 + 0.5 * (abs(c) - 0.17), c)
        return self.wall.point(c, a, height)

def module_clutter(h, rng, standoff):
    lay = RailLayout(h, standoff)
    cables, boxes = clutter_on(lay, rng, h["length_m"])
    # clutter_on() sizes boxes along the world's axes (its walls face x):
    # turn them to the rail's surface (x = normal, y = across, z = along).
    rpy = box_rpy(lay.wall.n, lay.wall.u, lay.wall.v)
    for b in boxes:
        b["rpy_deg"] = rpy
    return cables, boxes

def look(label, position, target, up, frames, to=None, rpy0=(0, 0, 0), rpy1=None):
    facing = unit([target[i] - position[i] for i in range(3)])
    pose = {"label": label, "position": vec(position), "facing": vec(facing), "up": vec(up),
            "rpy_deg": list(rpy0), "frames": frames}
    if to is not None:
        pose["to"] = {"position": vec(to), "rpy_deg": list(rpy1 if rpy1 is not None else rpy0)}
    return pose

def rail_views(tag, h, rng, far=1.2, flip=False):
    """24 frames around one labelled rail (rail-vertical views have up =
    the rail's axis; horizontal ones up = across it)."""
    u = rng.uniform
    c, a, n, w, L = rail_frame(h)
    j = lambda k: [r4(u(-k, k)), r4(u(-k, k)), r4(u(-k, k))]
    poses = []
    # Head-on, from `far` to 0.35 m, the rail vertical in the image, the
    # view 5 to 10 cm along it from its middle.
    off = rng.choice((-1, 1)) * u(0.05, 0.10)
    t = add(c, a, off)
    near = 0.35 if L < 0.8 else 0.4  # a long rail still 30 % in view
    poses.append(look(tag + "-head-on", add(t, n, far), t, a, 8, to=add(t, n, near), rpy0=j(3), rpy1=j(3)))
    # Oblique, 30 to 45 deg across the rail, 0.8 to 0.5 m, rail vertical.
    th = math.radians(u(30, 45)) * rng.choice((-1, 1)) * (-1 if flip else 1)
    d = add(scale_(n, math.cos(th)), w, math.sin(th))
    poses.append(look(tag + "-oblique", add(c, d, min(0.8, far)), c, a, 6, to=add(c, d, 0.5), rpy0=j(2), rpy1=j(4)))
    # Horizontal in the image, seen 15 to 35 deg along it, 0.9 to 0.45 m.
    ph = math.radians(u(15, 35)) * rng.choice((-1, 1))
    d = add(scale_(n, math.cos(ph)), a, math.sin(ph))
    poses.append(look(tag + "-horizontal", add(c, d, min(0.9, far)), c, w, 6, to=add(c, d, 0.45), rpy0=j(3), rpy1=j(3)))
    # One end out of view: looking 12 to 18 cm inside one end from 0.35 to
    # 0.5 m (0.55 to 0.65 m for a long rail, still 30 % in view), the far
    # end past the image's edge, up to 20 deg oblique.
    sgn = rng.choice((-1, 1))
    t = add(c, a, sgn * (L / 2 - u(0.12, 0.18)))
    th = math.radians(u(-20, 20))
    d = add(scale_(n, math.cos(th)), w, math.sin(th))
    d0, d1 = (u(0.45, 0.5), u(0.35, 0.4)) if L < 0.8 else (u(0.6, 0.65), u(0.55, 0.6))
    if L < 0.35:
        # A 0.2 m rail: looking 3 cm past one end from 0.3 m, its other end
        # just out of view.
        t = add(c, a, sgn * (L / 2 + 0.03))
        d0, d1 = 0.32, 0.3
    poses.append(look(tag + "-partial", add(t, d, d0), t, a, 4, to=add(t, d, d1), rpy0=j(3), rpy1=j(3)))
    return poses

def scale_(v, k):
    return [k * x for x in v]

# Per module: the mesh, the seed, the rails viewed (indices into its
# handrails.json, sorted by length) with the clutter placed near some of
# them (their stand-offs, obj_handrails.py -v), the farthest head-on view,
# (the Cupola: rails 1, 4 and 5 stand behind equipment seen from the room,
# so rail 3 is seen twice, with other draws),
# and the no-handrail views (position, looked-at point, up), surveyed.
ISS_OBJ_MODULES = {
    "node1": {"mesh": "node_1", "seed": 2501, "far": 1.2,
              "rails": [(3, None), (5, 0.083), (8, None), (13, 0.070)],
              "bare": [
                 ([-0.007, -16.694, 0.017], [1.049, -16.327, 0.083], [-0.131, 0.199, 0.971]),  # 1.12 m
                 ([-0.435, -14.894, 0.413], [-0.191, -15.151, 1.701], [0.916, 0.389, -0.095]),  # 1.34 m
                 ([-0.317, -16.45, 0.449], [-0.366, -17.003, 1.057], [0.473, 0.632, 0.614]),  # 0.82 m
                 ([0.084, -14.616, 0.44], [0.962, -14.115, 1.163], [-0.488, -0.318, 0.813]),  # 1.24 m
                 ([-0.005, -17.038, -0.274], [0.246, -17.696, 0.087], [-0.76, 0.064, 0.647]),  # 0.79 m
                 ([0.065, -15.768, 0.379], [0.371, -15.578, 1.065], [-0.757, -0.458, 0.466]),  # 0.78 m
                 ([-0.124, -16.069, -0.058], [1.049, -16.498, 0.141], [-0.014, 0.391, 0.92]),  # 1.26 m
                 ([0.436, -16.321, 0.078], [0.562, -15.667, 1.065], [0.44, -0.773, 0.456]),  # 1.19 m
                 ([-0.043, -14.354, 0.45], [-0.091, -13.101, 0.688], [-0.421, -0.185, 0.888]),  # 1.28 m
                 ([0.005, -16.411, 0.2], [-1.033, -16.517, 0.507], [0.283, 0.008, 0.959]),  # 1.09 m
                 ([0.289, -17.202, 0.465], [0.574, -17.589, 1.039], [-0.846, 0.142, 0.515]),  # 0.75 m
                 ([-0.08, -14.103, 0.309], [0.148, -13.756, 1.065], [-0.599, -0.643, 0.477]),  # 0.86 m
             ]},
    "node2": {"mesh": "node_2", "seed": 2502, "far": 1.2,
              "rails": [(6, 0.089), (7, None), (8, None), (9, 0.077)],
              "bare": [
                 ([-0.413, -3.202, -0.417], [-1.067, -3.644, -0.553], [-0.05, -0.225, 0.973]),  # 0.80 m
                 ([0.006, -3.579, 0.072], [-0.252, -3.899, -0.71], [-0.355, -0.819, 0.452]),  # 0.88 m
                 ([0.283, 0.956, -0.466], [0.323, 1.226, -1.067], [0.979, 0.155, 0.135]),  # 0.66 m
                 ([-0.491, -3.321, -0.194], [-0.389, -3.202, -0.778], [0.728, 0.636, 0.257]),  # 0.60 m
                 ([-0.046, 0.286, 0.443], [-0.131, 0.686, 1.584], [0.881, 0.462, -0.097]),  # 1.21 m
                 ([-0.363, -3.033, -0.211], [0.794, -2.927, -0.299], [0.051, 0.245, 0.968]),  # 1.16 m
                 ([-0.211, -2.946, 0.021], [-0.775, -3.178, 0.351], [0.481, 0.076, 0.873]),  # 0.69 m
                 ([-0.266, -2.983, -0.015], [-0.794, -3.728, 0.398], [-0.36, 0.634, 0.684]),  # 1.00 m
                 ([-0.379, -1.726, 0.484], [-0.279, -1.617, 1.101], [0.759, -0.65, -0.007]),  # 0.63 m
                 ([-0.093, -2.129, -0.47], [-0.926, -2.522, -0.361], [0.378, -0.608, 0.698]),  # 0.93 m
                 ([0.195, -2.257, 0.435], [0.786, -2.761, 0.102], [0.514, 0.036, 0.857]),  # 0.85 m
                 ([0.329, -2.553, -0.094], [0.758, -2.88, 0.355], [-0.73, -0.02, 0.683]),  # 0.70 m
             ]},
    "node3": {"mesh": "node_3", "seed": 2503, "far": 1.2,
              "rails": [(6, None), (9, 0.065), (10, 0.063), (0, None)], "flip": (6,),
              "bare": [
                 ([7.099, -14.519, 0.102], [7.944, -15.441, 0.199], [0.25, 0.325, 0.912]),  # 1.25 m
                 ([7.22, -14.359, 0.184], [7.628, -15.105, 1.016], [-0.814, 0.173, 0.555]),  # 1.19 m
                 ([4.614, -14.347, 0.312], [4.344, -13.735, 1.003], [0.801, -0.258, 0.541]),  # 0.96 m
                 ([6.929, -14.479, -0.178], [7.047, -13.524, -0.854], [0.529, 0.446, 0.722]),  # 1.18 m
                 ([7.667, -15.053, 0.099], [7.523, -15.815, 0.907], [0.563, 0.549, 0.618]),  # 1.12 m
                 ([6.849, -14.912, 0.32], [8.062, -15.35, 0.159], [0.294, 0.519, 0.802]),  # 1.30 m
                 ([7.381, -14.648, -0.109], [8.014, -14.699, -0.249], [0.222, 0.092, 0.971]),  # 0.65 m
                 ([7.543, -14.975, 0.344], [8.022, -14.958, -0.327], [0.784, -0.286, 0.552]),  # 0.82 m
                 ([4.929, -14.408, 0.147], [4.232, -13.326, -0.263], [-0.487, 0.017, 0.873]),  # 1.35 m
                 ([6.75, -15.037, -0.245], [7.822, -15.451, -0.216], [-0.165, -0.365, 0.916]),  # 1.15 m
                 ([4.596, -15.275, -0.436], [5.195, -15.815, 0.107], [-0.43, 0.355, 0.83]),  # 0.97 m
                 ([5.301, -15.124, 0.173], [5.377, -13.785, -0.022], [-0.007, 0.145, 0.989]),  # 1.36 m
             ]},
    "cupola": {"mesh": "cupola", "seed": 2504, "far": 0.9,
               "rails": [(0, 0.055), (2, None), (3, 0.055), (3, None)],
               "bare": [
                 ([6.005, -14.427, 2.429], [6.105, -14.324, 3.041], [0.982, 0.071, -0.173]),  # 0.63 m
                 ([6.252, -14.81, 2.429], [6.159, -15.122, 3.207], [0.988, -0.14, 0.062]),  # 0.84 m
                 ([6.397, -14.576, 2.672], [6.761, -14.688, 3.211], [-0.443, 0.77, 0.46]),  # 0.66 m
                 ([6.493, -14.596, 2.857], [6.728, -14.949, 3.217], [-0.361, 0.537, 0.763]),  # 0.56 m
                 ([6.643, -14.673, 2.416], [6.652, -14.497, 3.211], [0.998, -0.059, 0.002]),  # 0.81 m
                 ([6.517, -14.712, 2.738], [6.597, -14.275, 3.074], [-0.479, -0.478, 0.736]),  # 0.56 m
                 ([6.67, -14.562, 2.824], [6.571, -14.289, 3.121], [0.248, -0.671, 0.699]),  # 0.41 m
                 ([6.085, -14.675, 2.823], [6.793, -14.958, 3.21], [-0.026, 0.783, 0.622]),  # 0.85 m
                 ([6.61, -14.993, 2.303], [6.419, -15.066, 3.253], [0.81, -0.574, 0.119]),  # 0.97 m
                 ([6.665, -15.11, 2.59], [6.804, -15.136, 3.205], [0.975, 0.03, -0.22]),  # 0.63 m
                 ([6.583, -15.121, 2.881], [6.826, -14.954, 3.21], [-0.83, 0.163, 0.533]),  # 0.44 m
                 ([6.163, -14.768, 2.67], [6.216, -14.557, 3.255], [0.99, 0.078, -0.118]),  # 0.62 m
             ]},
}

def module_views(name):
    m = ISS_OBJ_MODULES[name]
    rng = random.Random(m["seed"])
    rails = module_rails(m["mesh"])
    cables, boxes, poses = [], [], []
    seen = []
    for k, (index, standoff) in enumerate(m["rails"]):
        h = rails[index]
        tag = "%s-rail%d%s" % (name, index, "b" if index in seen else "")
        seen.append(index)
        poses += rail_views(tag, h, rng, m["far"], index in m.get("flip", ()))
        if standoff is not None:
            more_cables, more_boxes = module_clutter(h, rng, standoff)
            cables += more_cables
            boxes += more_boxes
    for k, (position, target, up) in enumerate(m["bare"]):
        poses.append(look("%s-no-handrail-%d" % (name, k), position, target, up, 1))
    scene = {"meshes": [{"path": "../assets/iss_modules/%s.obj" % m["mesh"], "reflectivity": 0.55,
                         "handrails": rails}]}
    if cables:
        scene["cables"] = cables
    if boxes:
        scene["boxes"] = boxes
    frames = sum(p["frames"] for p in poses)
    return {"name": "%s-views" % name,
            "description": ("Inside %s (assets/iss_modules/%s.obj, its %d modelled handrails labelled): %d rails "
                            "seen head-on, oblique, horizontal in the image and with one end out of view, 0.3 to "
                            "%.1f m, clutter near %d of them, and %d views with no handrail; %d frames. Held out: "
                            "nothing is tuned on it.")
                           % ({"node1": "Node 1 (Unity)", "node2": "Node 2 (Harmony)", "node3": "Node 3 (Tranquility)",
                               "cupola": "the Cupola"}[name], m["mesh"], len(rails), len(m["rails"]), m["far"],
                              sum(1 for _, s_ in m["rails"] if s_ is not None), len(m["bare"]), frames),
            "seed": m["seed"], "frame_rate_hz": 5, "gripper_angle_deg": 0, "scene": scene, "poses": poses}

if DEV_DIR is None:
    rack_scenarios += [module_views(n) for n in ("node1", "node2", "node3", "cupola")]

rack_scenarios += [columbus_approaches(), columbus_views()]
if DEV_DIR is not None:
    rack_scenarios += [flat_clutter(), dev_sweep()]
for s in rack_scenarios:
    write(s)
