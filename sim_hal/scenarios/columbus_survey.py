#!/usr/bin/env python3
"""Surveys the Columbus module's rack faces by ray casting, to place
handrails on them (generate.py's COLUMBUS_RAILS and COLUMBUS_DEV_RAILS).

It renders the module alone (no handrails, every sensor effect off, so each
pixel is the exact ray-cast range) with hrsim, turns every pixel into world
coordinates with the frame's true camera pose, and prints runs of equal
depth:

  columbus_survey.py walls [--build DIR]
      per wall (starboard, port, deck, overhead), along the module (y) on
      the line where the shipped rails stand: the faces (y from .. to, the
      face's x or z), so that the edges and gaps between them show;
  columbus_survey.py line WALL Y AXIS_CENTRE [--build DIR]
      along a rail's axis at y = Y on one wall (z for the side walls, x for
      deck and overhead), seen from across the aisle: where the face under
      a rail's track is flat.

Needs a built hrsim (default build/release/tools/hrsim). Writes its
scratch scenario and frames under a temporary folder."""
import argparse
import json
import math
import os
import struct
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.normpath(os.path.join(HERE, "..", ".."))
MODULE = os.path.join(ROOT, "sim_hal", "assets", "iss_modules", "columbus_eu_lab.dae")

# Per wall: how the camera looks at it, which world axis runs along the
# module (y), which is the face's depth, and the line the walls scan uses.
WALLS = {
    "starboard": {"facing": [1, 0, 0], "up": [0, 0, 1], "depth": 0, "across": 2, "at": -0.15,
                  "camera": lambda y: [0.1, y, -0.15], "far": lambda y, c: [-0.5, y, c]},
    "port": {"facing": [-1, 0, 0], "up": [0, 0, 1], "depth": 0, "across": 2, "at": -0.15,
             "camera": lambda y: [-0.1, y, -0.15], "far": lambda y, c: [0.5, y, c]},
    "deck": {"facing": [0, 0, -1], "up": [1, 0, 0], "depth": 2, "across": 0, "at": 0.05,
             "camera": lambda y: [0.05, y, -0.3], "far": lambda y, c: [c, y, 0.3]},
    "overhead": {"facing": [0, 0, 1], "up": [1, 0, 0], "depth": 2, "across": 0, "at": 0.0,
                 "camera": lambda y: [0.0, y, 0.3], "far": lambda y, c: [c, y, -0.7]},
}


def rotate(q_wxyz, v):
    w, x, y, z = q_wxyz
    r = [[1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
         [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
         [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]]
    return [sum(r[i][j] * v[j] for j in range(3)) for i in range(3)]


def read_points(path):
    """The valid points of a binary PCD frame as hrsim writes it (x y z
    intensity noise as floats, confidence as a byte)."""
    data = open(path, "rb").read()
    marker = b"DATA binary\n"
    start = data.index(marker) + len(marker)
    record = struct.Struct("<fffffB")
    count = (len(data) - start) // record.size
    for k in range(count):
        x, y, z, _, _, confidence = record.unpack_from(data, start + k * record.size)
        if confidence > 0 and math.isfinite(z):
            yield x, y, z


def render_world_points(hrsim, poses, work):
    scenario = {"name": "columbus-survey", "description": "ray-cast survey of the module",
                "seed": 1, "frame_rate_hz": 5, "gripper_angle_deg": 0,
                "sensor": {"noise": False, "flying_pixels": False, "flying_filter": False,
                           "invalid_pixels": False, "multipath": False},
                "scene": {"meshes": [{"path": MODULE, "reflectivity": 0.55}]}, "poses": poses}
    path = os.path.join(work, "survey.json")
    with open(path, "w") as f:
        json.dump(scenario, f)
    out = os.path.join(work, "frames")
    subprocess.run([hrsim, path, "-o", out], check=True, stdout=subprocess.DEVNULL)
    with open(os.path.join(out, "truth.jsonl")) as f:
        for line in f:
            t = json.loads(line)
            p, q = t["camera_position"], t["camera_quaternion_wxyz"]
            for point in read_points(os.path.join(out, t["file"])):
                w = rotate(q, point)
                yield w[0] + p[0], w[1] + p[1], w[2] + p[2]


def runs_of_equal_depth(samples, bin_m, join_m, min_len_m):
    """Median depth per bin along the line, then bins of equal depth (within
    3 mm) joined into runs; runs shorter than min_len_m left out."""
    bins = {}
    for along, depth in samples:
        bins.setdefault(round(along / bin_m), []).append(depth)
    runs = []
    for k in sorted(bins):
        values = sorted(bins[k])
        along, depth = k * bin_m, values[len(values) // 2]
        if runs and abs(depth - runs[-1][2]) < 0.003 and along - runs[-1][1] <= join_m:
            runs[-1][1] = along
        else:
            runs.append([along, along, depth])
    return [r for r in runs if r[1] - r[0] >= min_len_m]


def survey_walls(hrsim, work):
    ys = [0.6 + 0.3 * k for k in range(17)]
    for name, w in WALLS.items():
        poses = [{"label": "%s-%d" % (name, k), "position": w["camera"](y), "facing": w["facing"],
                  "up": w["up"], "frames": 1} for k, y in enumerate(ys)]
        samples = [(p[1], p[w["depth"]]) for p in render_world_points(hrsim, poses, work)
                   if abs(p[w["across"]] - w["at"]) < 0.006]
        for a, b, depth in runs_of_equal_depth(samples, 0.005, 0.011, 0.015):
            print("%-9s y %.3f .. %.3f  face at %.4f" % (name, a, b, depth))


def survey_line(hrsim, work, wall, y, centre):
    w = WALLS[wall]
    poses = [{"label": "line", "position": w["far"](y, centre), "facing": w["facing"],
              "up": w["up"], "frames": 1}]
    samples = [(p[w["across"]], p[w["depth"]]) for p in render_world_points(hrsim, poses, work)
               if abs(p[1] - y) < 0.004]
    for a, b, depth in runs_of_equal_depth(samples, 0.01, 0.021, 0.02):
        print("%s y = %.3f: along %.2f .. %.2f  face at %.4f" % (wall, y, a, b, depth))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("what", choices=["walls", "line"], help="walls, or line WALL Y AXIS_CENTRE")
    ap.add_argument("args", nargs="*", help="for line: WALL (starboard, port, deck, overhead), "
                                            "Y (m), the rail's centre along its axis (m)")
    ap.add_argument("--build", default=os.path.join(ROOT, "build", "release"),
                    help="build folder holding tools/hrsim (default build/release)")
    a = ap.parse_args()
    hrsim = os.path.join(a.build, "tools", "hrsim")
    if not os.access(hrsim, os.X_OK):
        sys.exit("columbus_survey: no hrsim at %s: build it first (cmake --build --preset "
                 "release --target hrsim) or pass --build DIR" % hrsim)
    with tempfile.TemporaryDirectory() as work:
        if a.what == "walls":
            if a.args:
                sys.exit("columbus_survey: 'walls' takes no arguments")
            survey_walls(hrsim, work)
        else:
            if len(a.args) != 3 or a.args[0] not in WALLS:
                sys.exit("columbus_survey: line WALL Y AXIS_CENTRE, WALL one of %s"
                         % ", ".join(WALLS))
            try:
                y, centre = float(a.args[1]), float(a.args[2])
            except ValueError:
                sys.exit("columbus_survey: Y and AXIS_CENTRE are metres, not '%s' '%s'"
                         % (a.args[1], a.args[2]))
            survey_line(hrsim, work, a.args[0], y, centre)


if __name__ == "__main__":
    main()
