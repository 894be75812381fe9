#!/usr/bin/env python3
"""Writes the shipped scenario files. The JSON files are committed; rerun
this after changing it (python3 generate.py) and commit both.

World frame: the main wall is the plane x = 0, facing +x (toward the room),
z up. Cameras face -x unless a pose says otherwise."""
import json

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

for s in (table2("round"), table2("iss"), table2("iss_mesh"), sweep(), approach("iss"), approach("round"),
          approach("iss_mesh"), clutter_only(), two_perpendicular(), corner()):
    with open(s["name"] + ".json", "w") as f:
        json.dump(s, f, indent=1)
        f.write("\n")
    print("wrote", s["name"] + ".json")
