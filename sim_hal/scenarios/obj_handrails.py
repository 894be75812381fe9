#!/usr/bin/env python3
"""The ISS node and Cupola meshes (Wavefront .obj): makes the repository's
compact copies and finds the handrails they model, as mesh_handrails.py
does for Columbus's COLLADA mesh.

  obj_handrails.py compact SRC.obj DST.obj
      SRC is one of /work/shared/assets/iss_modules/*.obj (Y up, Blender's
      export). DST keeps only the geometry: its vertices turned to the
      station's Z-up frame, (x, y, z)_station = (x, -z, y)_obj, written to
      10 um (5 decimals), identical vertices merged, and triangles as
      vertex indices (no normals, texture coordinates, groups, materials).
      The station coordinates are kept (not re-centred): all four modules
      stay in one frame, and a scenario places the mesh with no position
      and no rotation.

  obj_handrails.py handrails MESH.obj [-o FILE] [-v]
      Finds the handrails MESH (a compact copy, station frame) models and
      writes them as JSON in mesh_handrails.py's format ({"mesh": ...,
      "handrails": [{"ends", "normal", "length_m", "bar_section_m"}, ...]}),
      in the mesh's frame (= the scenario's, the mesh placed with no
      rotation). -v prints every bar-like part and why it was taken or not.

How the handrails are found: triangles are grouped into connected parts
(shared vertices, rounded to 0.1 mm). A bar is a part 0.1 to 1.1 m long
along its principal axis, 1.5 to 2.2 cm across at its narrowest and 3.0 to
4.0 cm at its widest. Its normal is its section's principal axis (its deep
direction, along which its legs stand in the nodes), pointing away from the
nearer surface along it (rays from 1/4, 1/2 and 3/4 along the bar); when
sim_hal's loader would find nothing of the legs 2.5 cm behind the centre
line in its box (src/mesh_handrails.cpp: the Cupola's window-frame rails,
whose legs lean toward the sloping frame), the normal of the surface found
behind it instead, made perpendicular to the bar. The centre line runs
through the middle of the section, from the outer side of one leg (the
small parts, every size under 8.5 cm, within 6 mm of the bar and 8 cm of
an end) to the other's, or the bar's ends. The stand-off is the distance
from the centre line to the surface along -normal. Kept: 0.15 to 1.08 m
from end to end, 5 to 11 cm off the surface, and the loader's 2.5 cm.
-v prints what was taken and every bar-like part that was not, and why."""
import argparse
import json
import math
import os
import sys

# ---------------------------------------------------------------- geometry

def dot(a, b):
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]

def sub(a, b):
    return [a[0] - b[0], a[1] - b[1], a[2] - b[2]]

def cross(a, b):
    return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]

def unit(a):
    n = math.sqrt(dot(a, a))
    return [c / n for c in a]

def scale(a, k):
    return [c * k for c in a]

def add(a, b, k=1.0):
    return [a[i] + k * b[i] for i in range(3)]

def jacobi_eigen(A):
    """Eigenvalues and eigenvectors (rows) of a symmetric 3x3 matrix."""
    A = [r[:] for r in A]
    V = [[1.0 if i == j else 0.0 for j in range(3)] for i in range(3)]
    for _ in range(60):
        p, q = max(((0, 1), (0, 2), (1, 2)), key=lambda pq: abs(A[pq[0]][pq[1]]))
        if abs(A[p][q]) < 1e-18:
            break
        th = 0.5 * math.atan2(2 * A[p][q], A[q][q] - A[p][p])
        c, s = math.cos(th), math.sin(th)
        for k in range(3):
            akp, akq = A[k][p], A[k][q]
            A[k][p], A[k][q] = c * akp - s * akq, s * akp + c * akq
        for k in range(3):
            apk, aqk = A[p][k], A[q][k]
            A[p][k], A[q][k] = c * apk - s * aqk, s * apk + c * aqk
        for k in range(3):
            vkp, vkq = V[k][p], V[k][q]
            V[k][p], V[k][q] = c * vkp - s * vkq, s * vkp + c * vkq
    return [A[i][i] for i in range(3)], [[V[k][i] for k in range(3)] for i in range(3)]

def long_axis(points):
    n = len(points)
    m = [sum(p[i] for p in points) / n for i in range(3)]
    C = [[sum((p[i] - m[i]) * (p[j] - m[j]) for p in points) / n for j in range(3)] for i in range(3)]
    w, axes = jacobi_eigen(C)
    a = axes[max(range(3), key=lambda i: w[i])]
    # Snap to a coordinate axis when within 0.5 deg (the modules' rails mostly are).
    for i in range(3):
        if abs(a[i]) > math.cos(math.radians(0.5)):
            a = [0.0, 0.0, 0.0]
            a[i] = 1.0
    # A fixed sign: the first sizeable coordinate positive.
    for c in a:
        if abs(c) > 1e-6:
            return a if c > 0 else scale(a, -1)
    return a

def perpendicular_basis(a):
    t = [1.0, 0.0, 0.0] if abs(a[0]) < 0.9 else [0.0, 1.0, 0.0]
    u = unit(cross(a, t))
    return u, cross(a, u)

def extent(points, d):
    p = [dot(q, d) for q in points]
    return min(p), max(p)

def ray_triangle(o, d, a, b, c):
    e1, e2 = sub(b, a), sub(c, a)
    p = cross(d, e2)
    det = dot(e1, p)
    if abs(det) < 1e-14:
        return None
    inv = 1.0 / det
    s = sub(o, a)
    u = dot(s, p) * inv
    if u < 0 or u > 1:
        return None
    q = cross(s, e1)
    v = dot(d, q) * inv
    if v < 0 or u + v > 1:
        return None
    t = dot(e2, q) * inv
    return t if t > 1e-6 else None

# ---------------------------------------------------------------- files

def read_obj(path, to_station=False):
    """Vertices and triangles (vertex index triples) of an .obj; polygons
    fanned. to_station turns Y-up coordinates to the station's Z-up."""
    vertices, triangles = [], []
    with open(path) as f:
        for line in f:
            if line.startswith("v "):
                x, y, z = (float(c) for c in line.split()[1:4])
                vertices.append((x, -z, y) if to_station else (x, y, z))
            elif line.startswith("f "):
                idx = []
                for tok in line.split()[1:]:
                    k = int(tok.split("/")[0])
                    idx.append(k - 1 if k > 0 else len(vertices) + k)
                for j in range(1, len(idx) - 1):
                    triangles.append((idx[0], idx[j], idx[j + 1]))
    return vertices, triangles

def fmt(c):
    t = ("%.5f" % c).rstrip("0").rstrip(".")
    return "0" if t in ("-0", "") else t

def compact(src, dst):
    vertices, triangles = read_obj(src, to_station=True)
    index, out_v, remap = {}, [], []
    for v in vertices:
        text = " ".join(fmt(c) for c in v)
        if text not in index:
            index[text] = len(out_v)
            out_v.append(text)
        remap.append(index[text])
    faces = []
    for t in triangles:
        f = tuple(remap[k] for k in t)
        if len(set(f)) == 3:
            faces.append(f)
    with open(dst, "w") as f:
        f.write("# %s: geometry of %s, turned to the station's Z-up frame:\n"
                "# (x, y, z) = (x, -z, y) of the source. Metres. See README.md.\n"
                % (os.path.basename(dst), os.path.basename(src)))
        for text in out_v:
            f.write("v " + text + "\n")
        for a, b, c in faces:
            f.write("f %d %d %d\n" % (a + 1, b + 1, c + 1))
    print("obj_handrails: %s: %d vertices, %d triangles (source: %d, %d)"
          % (dst, len(out_v), len(faces), len(vertices), len(triangles)), file=sys.stderr)

# ---------------------------------------------------------------- handrails

def connected_parts(vertices, triangles):
    key = [tuple(round(c, 4) for c in v) for v in vertices]
    parent = {}

    def find(a):
        while parent.setdefault(a, a) != a:
            parent[a] = parent[parent[a]]
            a = parent[a]
        return a

    for t in triangles:
        for o in t[1:]:
            ra, rb = find(key[t[0]]), find(key[o])
            if ra != rb:
                parent[ra] = rb
    groups = {}
    for n, t in enumerate(triangles):
        groups.setdefault(find(key[t[0]]), []).append(n)
    parts = []
    for tris in groups.values():
        idx = sorted({k for n in tris for k in triangles[n]})
        parts.append({"triangles": tris, "points": [vertices[k] for k in idx]})
    return parts

class Caster:
    """Rays against the mesh's triangles, each ray tested only against the
    triangles whose box meets the ray's segment's box."""
    def __init__(self, vertices, triangles):
        self.tris = [(vertices[a], vertices[b], vertices[c]) for a, b, c in triangles]
        self.boxes = [([min(p[i] for p in t) for i in range(3)], [max(p[i] for p in t) for i in range(3)])
                      for t in self.tris]

    def cast(self, o, d, t_max, skip=()):
        e = add(o, d, t_max)
        lo = [min(o[i], e[i]) - 1e-4 for i in range(3)]
        hi = [max(o[i], e[i]) + 1e-4 for i in range(3)]
        best, normal = None, None
        for n, (blo, bhi) in enumerate(self.boxes):
            if any(blo[i] > hi[i] or bhi[i] < lo[i] for i in range(3)) or n in skip:
                continue
            a, b, c = self.tris[n]
            t = ray_triangle(o, d, a, b, c)
            if t is not None and t <= t_max and (best is None or t < best):
                best, normal = t, unit(cross(sub(b, a), sub(c, a)))
        return best, normal

def widths(points, a):
    """The narrowest and widest extent of the points across axis a (1 deg
    steps), with the directions."""
    u, v = perpendicular_basis(a)
    out = []
    for k in range(0, 180):
        t = math.radians(k)
        d = add(scale(u, math.cos(t)), v, math.sin(t))
        lo, hi = extent(points, d)
        out.append((hi - lo, d))
    return min(out), max(out)

def claimed_depth(rail, triangles_pts):
    """What sim_hal's loader does with an entry (src/mesh_handrails.cpp):
    the triangles wholly inside the handrail's box, and how deep behind the
    centre line they reach (it refuses under 2.5 cm)."""
    e0, e1, n = rail["ends"][0], rail["ends"][1], rail["normal"]
    a = unit(sub(e1, e0))
    w = cross(a, n)
    length = math.sqrt(dot(sub(e1, e0), sub(e1, e0)))
    deepest, count = 0.0, 0
    for tri in triangles_pts:
        inside = True
        for q in tri:
            r = sub(q, e0)
            if not (-0.02 <= dot(r, a) <= length + 0.02 and abs(dot(r, w)) <= 0.026 and -0.075 <= dot(r, n) <= 0.025):
                inside = False
                break
        if inside:
            count += 1
            deepest = max(deepest, max(-dot(sub(q, e0), n) for q in tri))
    return count, deepest

def find_handrails(vertices, triangles, verbose=False):
    parts = connected_parts(vertices, triangles)
    caster = Caster(vertices, triangles)
    for p in parts:
        pts = p["points"]
        p["lo"] = [min(q[i] for q in pts) for i in range(3)]
        p["hi"] = [max(q[i] for q in pts) for i in range(3)]
    small = [p for p in parts if max(p["hi"][i] - p["lo"][i] for i in range(3)) < 0.085]
    found, rejected = [], []
    for p in parts:
        pts = p["points"]
        if len(pts) < 6 or max(p["hi"][i] - p["lo"][i] for i in range(3)) < 0.1:
            continue
        a = long_axis(pts)
        lo_a, hi_a = extent(pts, a)
        bar_len = hi_a - lo_a
        if not 0.1 < bar_len < 1.3:
            continue
        (w_min, d_min), (w_max, d_max) = widths(pts, a)
        if w_max > 0.05 or w_min < 0.012:
            continue
        where = [round(c, 3) for c in scale(add(p["lo"], p["hi"]), 0.5)]
        label = "part at %s, %.3f m long, %.1f to %.1f cm across" % (where, bar_len, 100 * w_min, 100 * w_max)
        problems = []
        if not (0.015 <= w_min <= 0.022 and 0.030 <= w_max <= 0.040):
            problems.append("not a bar's section")
        if not 0.1 <= bar_len <= 1.1:
            problems.append("bar length")
        if problems:
            rejected.append(label + ": " + ", ".join(problems))
            continue
        # The centre line: the middle of the section's box (the widest
        # direction, the deep one, and across it).
        # (The section's principal axis: the mirror axis of a symmetric
        # section, where the widest extent may lean off it.)
        su, sv = perpendicular_basis(a)
        xs = [dot(q, su) for q in pts]
        ys = [dot(q, sv) for q in pts]
        mx, my = sum(xs) / len(xs), sum(ys) / len(ys)
        cxx = sum((x - mx) ** 2 for x in xs)
        cyy = sum((y - my) ** 2 for y in ys)
        cxy = sum((x - mx) * (y - my) for x, y in zip(xs, ys))
        th = 0.5 * math.atan2(2 * cxy, cxx - cyy)
        d_max = add(scale(su, math.cos(th)), sv, math.sin(th))
        d_min = cross(a, d_max)
        d_mid = [sum(extent(pts, d_min)) / 2, sum(extent(pts, d_max)) / 2]
        centre = add(scale(d_min, d_mid[0]), d_max, d_mid[1])
        centre = sub(centre, scale(a, dot(centre, a)))
        own = set(p["triangles"])
        # The normal: the bar's section's principal axis (its deep direction,
        # the legs' direction in the nodes), toward the room: away from the
        # nearer surface along it (rays from 1/4, 1/2 and 3/4 along the bar).
        side = []
        for sign in (1, -1):
            d = scale(d_max, sign)
            hits = []
            for f in (0.25, 0.5, 0.75):
                h, sn = caster.cast(add(centre, a, lo_a + f * bar_len), d, 0.2, own)
                if h is not None:
                    hits.append((h, sn))
            hits.sort(key=lambda x: x[0])
            side.append(hits[len(hits) // 2] if len(hits) >= 2 else None)
        if side[0] is None and side[1] is None:
            rejected.append(label + ": no surface within 20 cm along its deep direction")
            continue
        behind = 0 if side[1] is None or (side[0] is not None and side[0][0] < side[1][0]) else 1
        toward = scale(d_max, 1 if behind == 0 else -1)
        n = scale(toward, -1)
        # Unless sim_hal's loader would find nothing of its legs behind it
        # along that axis (the Cupola's rails on the window frames, whose
        # legs lean toward the sloping frame): then the normal of the
        # surface found behind it, made perpendicular to the bar.
        all_tris = [[vertices[k] for k in tri] for tri in triangles]

        def loader_depth(normal):
            probe = {"ends": [add(centre, a, lo_a), add(centre, a, hi_a)], "normal": normal}
            return claimed_depth(probe, all_tris)[1]

        lean = 0.0
        if loader_depth(n) < 0.03:
            sn = side[behind][1]
            n_s = unit(sub(sn, scale(a, dot(sn, a))))
            if dot(n_s, toward) > 0:
                n_s = scale(n_s, -1)
            lean = math.degrees(math.acos(min(1.0, dot(n, n_s))))
            n = n_s
        stand = []
        for f in (0.25, 0.5, 0.75):
            h, _ = caster.cast(add(centre, a, lo_a + f * bar_len), scale(n, -1), 0.2, own)
            if h is not None:
                stand.append(h)
        stand.sort()
        standoff = stand[len(stand) // 2] if stand else 1.0
        w = cross(a, n)
        section = [extent(pts, n)[1] - extent(pts, n)[0], extent(pts, w)[1] - extent(pts, w)[0]]
        # Its legs: small parts within 6 mm of the bar, near its ends; the
        # centre line runs to their outer sides (to the bar's ends if none).
        half = [(extent(pts, d)[1] - extent(pts, d)[0]) / 2 for d in (d_min, d_max)]

        def near_bar(q, tol=0.006):
            return (lo_a - tol <= dot(q, a) <= hi_a + tol and abs(dot(q, d_min) - d_mid[0]) <= half[0] + tol
                    and abs(dot(q, d_max) - d_mid[1]) <= half[1] + tol)

        box_lo = [c - 0.1 for c in p["lo"]]
        box_hi = [c + 0.1 for c in p["hi"]]
        legs = [s for s in small if s is not p
                and all(s["lo"][i] <= box_hi[i] and s["hi"][i] >= box_lo[i] for i in range(3))
                and any(near_bar(q) for q in s["points"])]
        at_ends = [[s for s in legs if abs(sum(extent(s["points"], a)) / 2 - e) < 0.08] for e in (lo_a, hi_a)]
        lo_all, hi_all = lo_a, hi_a
        for s in at_ends[0] + at_ends[1]:
            lo_all = min(lo_all, extent(s["points"], a)[0])
            hi_all = max(hi_all, extent(s["points"], a)[1])
        length = hi_all - lo_all
        rail = {"ends": [[round(c, 4) for c in add(centre, a, lo_all)], [round(c, 4) for c in add(centre, a, hi_all)]],
                "normal": [round(c, 6) for c in n], "length_m": round(length, 4),
                "bar_section_m": [round(x, 4) for x in section], "standoff_m": round(standoff, 4)}
        count, deepest = claimed_depth(rail, [[vertices[k] for k in tri] for tri in triangles])
        label = ("part at %s, %.3f m leg to leg (bar %.3f), %.1f x %.1f cm (along the normal x across), "
                 "%.1f cm off the surface (normal %.0f deg off the section's axis), legs at its ends %d + %d, "
                 "the loader's box %d triangles %.1f cm deep"
                 % (where, length, bar_len, 100 * section[0], 100 * section[1], 100 * standoff, lean,
                    len(at_ends[0]), len(at_ends[1]), count, 100 * deepest))
        if not 0.05 <= standoff <= 0.11:
            problems.append("stand-off")
        if not 0.15 <= length <= 1.08:
            problems.append("length")
        if deepest < 0.025:
            problems.append("nothing 2.5 cm behind it for the loader")
        if problems:
            rejected.append(label + ": " + ", ".join(problems))
            continue
        found.append(rail)
        if verbose:
            print("taken: " + label, file=sys.stderr)
    if verbose:
        for r in rejected:
            print("not taken: " + r, file=sys.stderr)
    found.sort(key=lambda h: (h["length_m"], h["ends"][0]))
    return found

def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter, epilog=__doc__)
    sub_p = ap.add_subparsers(dest="cmd", required=True)
    c = sub_p.add_parser("compact")
    c.add_argument("src")
    c.add_argument("dst")
    h = sub_p.add_parser("handrails")
    h.add_argument("mesh")
    h.add_argument("-o", "--out")
    h.add_argument("-v", "--verbose", action="store_true")
    args = ap.parse_args()
    if args.cmd == "compact":
        compact(args.src, args.dst)
        return
    vertices, triangles = read_obj(args.mesh)
    rails = find_handrails(vertices, triangles, args.verbose)
    # standoff_m is for the report only: the loader takes length_m and
    # bar_section_m along, nothing else.
    for r in rails:
        print("  %.3f m, %.1f x %.1f cm, %.1f cm off, normal %s" % (
            r["length_m"], 100 * r["bar_section_m"][0], 100 * r["bar_section_m"][1], 100 * r["standoff_m"],
            [round(c, 3) for c in r["normal"]]), file=sys.stderr)
        del r["standoff_m"]
    text = json.dumps({"mesh": os.path.basename(args.mesh), "handrails": rails}, indent=1) + "\n"
    if args.out:
        with open(args.out, "w") as f:
            f.write(text)
        print("obj_handrails: %d handrails -> %s" % (len(rails), args.out), file=sys.stderr)
    else:
        sys.stdout.write(text)

if __name__ == "__main__":
    main()
