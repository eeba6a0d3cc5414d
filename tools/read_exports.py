#!/usr/bin/env python3
"""read_exports.py: reads wiresketch's exports back with Python's standard
library alone, independently of the C code (tests/test_export_read.c).

    python3 tools/read_exports.py svg FILE.svg CURVES.json SCENE SPLIT VIEW SIZE [--hidden]
    python3 tools/read_exports.py obj FILE.obj CURVES.json

svg: every <path> must be "M x y" followed by cubic segments "C x1 y1 x2 y2
x3 y3" (subpaths start with another M), one path per curve (id curve_K):
each segment's cubic is compared, at 9 points, with the curve's own
perspective image (the distance to its nearest point), computed here from the scene's camera (NeRF
transforms_SPLIT.json: camera_angle_x, the camera looking down -z); the
largest distance must be under 0.1 px. Without --hidden every curve in
front of the camera has its path, drawn whole (one subpath from t = 0 to
1); with it, paths may be cut or left out. obj: one `o` object per curve,
each with its `v` lines and one `l` line through them in order, the
vertices on the curve at t = k / (n - 1). Prints one summary line; exit
status 1 with the reason on anything else."""
import json
import math
import re
import sys
import xml.etree.ElementTree as ET


def bezier(P, t):
    s = 1 - t
    return [s**3 * P[0][i] + 3 * s * s * t * P[1][i] + 3 * s * t * t * P[2][i] + t**3 * P[3][i] for i in range(3)]


def distance_to_image(P, project, x):
    """The distance from pixel x to the curve's image: the nearest of 200
    samples, then a golden-section search between its neighbours."""
    def dist(t):
        u, v, _ = project(bezier(P, t))
        return math.hypot(u - x[0], v - x[1])
    n = 200
    k = min(range(n + 1), key=lambda j: dist(j / n))
    lo, hi = max(0, k - 1) / n, min(n, k + 1) / n
    g = (math.sqrt(5) - 1) / 2
    for _ in range(40):
        a, b = hi - g * (hi - lo), lo + g * (hi - lo)
        if dist(a) < dist(b):
            hi = b
        else:
            lo = a
    return min(dist(k / n), dist((lo + hi) / 2))


def fail(why):
    print("read_exports: " + why)
    sys.exit(1)


def camera(scene, split, view, size):
    with open(f"{scene}/transforms_{split}.json") as f:
        meta = json.load(f)
    m = meta["frames"][view]["transform_matrix"]
    R = [[m[i][j] for j in range(3)] for i in range(3)]
    t = [m[i][3] for i in range(3)]
    focal = size / 2 / math.tan(meta["camera_angle_x"] / 2)

    def project(p):
        d = [p[i] - t[i] for i in range(3)]
        c = [sum(R[j][i] * d[j] for j in range(3)) for i in range(3)]  # R^T (p - t)
        return size / 2 + focal * c[0] / -c[2], size / 2 - focal * c[1] / -c[2], -c[2]

    return project


def read_svg(path, curves, project, hidden):
    ns = "{http://www.w3.org/2000/svg}"
    paths = list(ET.parse(path).getroot().iter(ns + "path"))
    ids = set()
    worst, segments = 0.0, 0
    for p in paths:
        k = int(p.get("id").split("_")[1])
        ids.add(k)
        tokens = re.findall(r"[MC]|-?[0-9.]+(?:e-?[0-9]+)?", p.get("d"))
        subpaths, i = [], 0
        while i < len(tokens):
            if tokens[i] != "M":
                fail(f"{path}: curve_{k}: '{tokens[i]}' where M starts a subpath")
            start = (float(tokens[i + 1]), float(tokens[i + 2]))
            i += 3
            cubics = []
            while i < len(tokens) and tokens[i] == "C":
                xs = [float(v) for v in tokens[i + 1:i + 7]]
                cubics.append([start if not cubics else cubics[-1][3], (xs[0], xs[1]), (xs[2], xs[3]), (xs[4], xs[5])])
                i += 7
            if not cubics:
                fail(f"{path}: curve_{k}: a subpath without a C segment")
            subpaths.append(cubics)
        if not hidden and len(subpaths) != 1:
            fail(f"{path}: curve_{k}: {len(subpaths)} subpaths without hidden lines")
        P = curves[k]
        for cubics in subpaths:
            for q in cubics:
                segments += 1
                for j in range(9):
                    s = j / 8
                    r = 1 - s
                    x = [r**3 * q[0][a] + 3 * r * r * s * q[1][a] + 3 * r * s * s * q[2][a] + s**3 * q[3][a] for a in range(2)]
                    worst = max(worst, distance_to_image(P, project, x))
    in_front = {k for k, P in enumerate(curves) if all(project(c)[2] > 1e-3 for c in P)}
    if not hidden and ids != in_front:
        fail(f"{path}: paths for curves {sorted(ids)}, in front of the camera {sorted(in_front)}")
    if hidden and not ids <= in_front:
        fail(f"{path}: a path for a curve behind the camera")
    if worst >= 0.1:
        fail(f"{path}: a segment {worst:.3f} px off the curve's image")
    print(f"svg: {len(paths)} paths of {segments} cubic segments, within {worst:.3f} px of the curves' images")


def read_obj(path, curves):
    objects = []
    verts = []
    with open(path) as f:
        for line in f:
            w = line.split()
            if not w or w[0] == "#":
                continue
            if w[0] == "o":
                objects.append({"name": w[1], "first": len(verts), "lines": []})
            elif w[0] == "v":
                verts.append([float(x) for x in w[1:4]])
            elif w[0] == "l":
                if not objects:
                    fail(f"{path}: an l line before any object")
                objects[-1]["lines"].append([int(x) - 1 for x in w[1:]])
            else:
                fail(f"{path}: unknown line '{w[0]}'")
    if [o["name"] for o in objects] != [f"curve_{k}" for k in range(len(curves))]:
        fail(f"{path}: objects {[o['name'] for o in objects]}, curves {len(curves)}")
    worst = 0.0
    for k, o in enumerate(objects):
        last = objects[k + 1]["first"] if k + 1 < len(objects) else len(verts)
        own = list(range(o["first"], last))
        if len(o["lines"]) != 1 or o["lines"][0] != own:
            fail(f"{path}: {o['name']}: not one l line through its own vertices in order")
        for j, v in enumerate(own):
            p = bezier(curves[k], j / (len(own) - 1))
            worst = max(worst, max(abs(p[i] - verts[v][i]) for i in range(3)))
    if worst > 1e-6:
        fail(f"{path}: a vertex {worst:.2e} off its curve")
    print(f"obj: {len(objects)} objects of {len(verts) // max(1, len(objects))} vertices, on their curves")


def main():
    a = sys.argv[1:]
    with open(a[2]) as f:
        curves = json.load(f)["curves"]
    if a[0] == "svg":
        read_svg(a[1], curves, camera(a[3], a[4], int(a[5]), int(a[6])), "--hidden" in a)
    elif a[0] == "obj":
        read_obj(a[1], curves)
    else:
        fail(f"'{a[0]}' is not svg or obj")


if __name__ == "__main__":
    main()
