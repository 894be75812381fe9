#!/usr/bin/env python3
"""Finds the handrails modelled in an ISS module mesh and writes them as
JSON, for the scenarios that render the module (generate.py puts them in
the mesh's "handrails" list, so that ground truth knows them).

The Columbus mesh (assets/iss_modules/) says it has no handrails, but it
models some three dozen: a bar about 3.0 x 2.2 cm in section, 0.19 to
1.07 m long, on two legs 4.4 cm long, on feet and mounting plates that
stand on a rack face or a seat track, the bar's centre line about 6.3 cm
off the face: the ISS handrail's dimensions. The detector finds them,
and a detection of one is a handrail found, not a false detection.

How they are found: the mesh's triangles are grouped into connected parts
(shared vertices); a bar is a part longer than 10 cm and at most 1.2 m
(the longer thin parts, 1.69 m, are rack-edge posts) whose other two
sizes are 1.5 to 3.5 cm, with exactly two leg-sized parts (every size
under 5 cm, the longest over 3.5 cm) touching it. The centre line runs
through the middle of the bar's section, from the outer side of one leg
to the outer side of the other (the ends a handrail's truth uses); the
normal is the leg's long direction, toward the module's centre line.

  mesh_handrails.py [MESH.dae] [-o FILE]

Default mesh: sim_hal/assets/iss_modules/columbus_eu_lab.dae; default
output: stdout. Coordinates are the mesh's own after its node transform
(what sim_hal's loader gives), metres."""
import argparse
import json
import os
import sys
import xml.etree.ElementTree as ET

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.normpath(os.path.join(HERE, "..", ".."))
DEFAULT_MESH = os.path.join(ROOT, "sim_hal", "assets", "iss_modules", "columbus_eu_lab.dae")
NS = "{http://www.collada.org/2005/11/COLLADASchema}"

# Columbus's centre line (its README): y runs along the module.
MODULE_AXIS_XZ = (0.0, -0.44)
MODULE_MIDDLE_Y = 3.0


def matrix_apply(m, v):
    return [m[4 * i] * v[0] + m[4 * i + 1] * v[1] + m[4 * i + 2] * v[2] + m[4 * i + 3]
            for i in range(3)]


def read_triangles(path):
    """Every triangle of the file as three world points (each geometry's
    node matrix applied; nested nodes are not composed, which the module's
    single node does not need)."""
    root = ET.parse(path).getroot()
    placed = {}
    for node in root.iter(NS + "node"):
        m = node.find(NS + "matrix")
        for g in node.findall(NS + "instance_geometry"):
            matrix = [float(x) for x in m.text.split()] if m is not None else \
                [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1]
            placed[g.get("url")[1:]] = matrix
    for geom in root.iter(NS + "geometry"):
        matrix = placed.get(geom.get("id"))
        if matrix is None:
            continue
        mesh = geom.find(NS + "mesh")
        sources = {s.get("id"): [float(x) for x in s.find(NS + "float_array").text.split()]
                   for s in mesh.findall(NS + "source")}
        position = mesh.find(NS + "vertices").find(NS + "input").get("source")[1:]
        flat = sources[position]
        points = [matrix_apply(matrix, flat[i:i + 3]) for i in range(0, len(flat), 3)]
        for tris in mesh.findall(NS + "triangles"):
            inputs = tris.findall(NS + "input")
            stride = max(int(i.get("offset")) for i in inputs) + 1
            vertex = [int(i.get("offset")) for i in inputs if i.get("semantic") == "VERTEX"][0]
            idx = [int(x) for x in tris.find(NS + "p").text.split()]
            for k in range(0, len(idx), 3 * stride):
                yield [points[idx[k + j * stride + vertex]] for j in range(3)]


def connected_parts(triangles):
    """Bounding boxes (lo, hi) of the groups of triangles sharing vertices."""
    parent = {}

    def find(a):
        while parent.setdefault(a, a) != a:
            parent[a] = parent[parent[a]]
            a = parent[a]
        return a

    def key(v):
        return tuple(round(c, 4) for c in v)

    for t in triangles:
        k = [key(v) for v in t]
        for other in k[1:]:
            ra, rb = find(k[0]), find(other)
            if ra != rb:
                parent[ra] = rb
    boxes = {}
    for t in triangles:
        root = find(key(t[0]))
        lo, hi = boxes.setdefault(root, ([1e9] * 3, [-1e9] * 3))
        for v in t:
            for i in range(3):
                lo[i] = min(lo[i], v[i])
                hi[i] = max(hi[i], v[i])
    return list(boxes.values())


def size(box):
    return [box[1][i] - box[0][i] for i in range(3)]


def touching(a, b, tol=0.006):
    return all(a[0][i] - tol <= b[1][i] and b[0][i] - tol <= a[1][i] for i in range(3))


def find_handrails(triangles):
    parts = connected_parts(triangles)
    bars = [p for p in parts
            if 0.10 < max(size(p)) <= 1.2 and 0.015 <= sorted(size(p))[0]
            and sorted(size(p))[1] <= 0.035]
    legs = [p for p in parts if max(size(p)) < 0.05 and max(size(p)) > 0.035
            and min(size(p)) > 0.015]
    found = []
    for bar in bars:
        s = size(bar)
        along = max(range(3), key=lambda i: s[i])
        touching_legs = [leg for leg in legs if touching(bar, leg)]
        if len(touching_legs) != 2:
            continue
        leg = size(touching_legs[0])
        out = max((i for i in range(3) if i != along), key=lambda i: leg[i])
        middle = [0.5 * (bar[0][i] + bar[1][i]) for i in range(3)]
        if out == 1:
            toward = MODULE_MIDDLE_Y - middle[1]
        else:
            toward = MODULE_AXIS_XZ[0 if out == 0 else 1] - middle[out]
        normal = [0, 0, 0]
        normal[out] = 1 if toward > 0 else -1
        lo = min([bar[0][along]] + [p[0][along] for p in touching_legs])
        hi = max([bar[1][along]] + [p[1][along] for p in touching_legs])
        ends = [list(middle), list(middle)]
        ends[0][along], ends[1][along] = lo, hi
        across = 3 - along - out
        found.append({"ends": [[round(c, 4) for c in e] for e in ends], "normal": normal,
                      "length_m": round(hi - lo, 4),
                      "bar_section_m": [round(s[out], 4), round(s[across], 4)]})
    found.sort(key=lambda h: (h["length_m"], h["ends"][0]))
    return found


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("mesh", nargs="?", default=DEFAULT_MESH, help="COLLADA file")
    ap.add_argument("-o", "--out", help="write the JSON here (default stdout)")
    a = ap.parse_args()
    if not os.path.isfile(a.mesh):
        sys.exit("mesh_handrails: no file %s" % a.mesh)
    try:
        rails = find_handrails(list(read_triangles(a.mesh)))
    except (ET.ParseError, AttributeError, ValueError, IndexError) as e:
        sys.exit("mesh_handrails: %s is not a COLLADA mesh this script reads: %s" % (a.mesh, e))
    text = json.dumps({"mesh": os.path.basename(a.mesh), "handrails": rails}, indent=1) + "\n"
    if a.out:
        with open(a.out, "w") as f:
            f.write(text)
        print("mesh_handrails: %d handrails -> %s" % (len(rails), a.out), file=sys.stderr)
    else:
        sys.stdout.write(text)


if __name__ == "__main__":
    main()
