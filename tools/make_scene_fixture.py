#!/usr/bin/env python3
"""Makes tests/fixtures/scene_small: the small scene `make test` reads in
place of ../shared/scenes (a trefoil knot of tubes seen by 8 / 2 / 4
cameras at 64 x 64, about 60 KB), and prints the values the tests assert,
taken from an independent decode (zlib + PNG unfiltering, here, not libpng).

    python3 tools/make_scene_fixture.py [--bin build/wiresketch] [--out tests/fixtures/scene_small]

Steps: `wiresketch scene trefoil` writes the views and gt_curves.json; this
script adds gt_points.ply (points on the curves, binary little-endian float
x y z, like the shared scenes' ground truth) and rewrites val/r_1.png as
16-bit RGBA whose alpha is 0 where the 8-bit photo is black (background)
and 65535 elsewhere, so the loader's 16-bit and alpha paths are exercised
on a real scene file. Only the Python standard library is used."""
import argparse
import json
import os
import shutil
import struct
import subprocess
import zlib


def png_chunks(data):
    assert data[:8] == b"\x89PNG\r\n\x1a\n"
    pos = 8
    while pos < len(data):
        (n,) = struct.unpack(">I", data[pos:pos + 4])
        kind = data[pos + 4:pos + 8]
        yield kind, data[pos + 8:pos + 8 + n]
        pos += 12 + n


def png_decode(path):
    """Returns (width, height, channels, depth, rows of samples)."""
    data = open(path, "rb").read()
    idat = b""
    for kind, body in png_chunks(data):
        if kind == b"IHDR":
            w, h, depth, ctype, _, _, interlace = struct.unpack(">IIBBBBB", body)
            assert interlace == 0 and ctype in (0, 2, 4, 6)
        elif kind == b"IDAT":
            idat += body
    nc = {0: 1, 2: 3, 4: 2, 6: 4}[ctype]
    bpp = nc * depth // 8
    stride = w * bpp
    raw = zlib.decompress(idat)
    rows, prev = [], bytearray(stride)
    for i in range(h):
        f = raw[i * (stride + 1)]
        line = bytearray(raw[i * (stride + 1) + 1:(i + 1) * (stride + 1)])
        for x in range(stride):
            a = line[x - bpp] if x >= bpp else 0
            b = prev[x]
            c = prev[x - bpp] if x >= bpp else 0
            if f == 1:
                line[x] = (line[x] + a) & 255
            elif f == 2:
                line[x] = (line[x] + b) & 255
            elif f == 3:
                line[x] = (line[x] + (a + b) // 2) & 255
            elif f == 4:
                p = a + b - c
                pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                pred = a if pa <= pb and pa <= pc else (b if pb <= pc else c)
                line[x] = (line[x] + pred) & 255
        prev = line
        if depth == 16:
            rows.append([line[k] << 8 | line[k + 1] for k in range(0, stride, 2)])
        else:
            rows.append(list(line))
    return w, h, nc, depth, rows


def png_write_rgba16(path, w, h, rows):
    def chunk(kind, body):
        return struct.pack(">I", len(body)) + kind + body + struct.pack(">I", zlib.crc32(kind + body))
    raw = b"".join(b"\x00" + b"".join(struct.pack(">H", s) for s in row) for row in rows)
    with open(path, "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n")
        f.write(chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 16, 6, 0, 0, 0)))
        f.write(chunk(b"IDAT", zlib.compress(raw, 9)))
        f.write(chunk(b"IEND", b""))


def bezier(P, t):
    s = 1 - t
    return [s * s * s * P[0][x] + 3 * s * s * t * P[1][x] + 3 * s * t * t * P[2][x] + t * t * t * P[3][x]
            for x in range(3)]


def axes_center(scene):
    """The point nearest every camera's optical axis (-z of c2w) in the least-squares
    sense: solve sum (I - d d^T) x = sum (I - d d^T) p by Cramer's rule."""
    A = [[0.0] * 3 for _ in range(3)]
    b = [0.0] * 3
    for split in ("train", "val", "test"):
        for f in json.load(open(os.path.join(scene, "transforms_%s.json" % split)))["frames"]:
            m = f["transform_matrix"]
            p = [m[i][3] for i in range(3)]
            d = [-m[i][2] for i in range(3)]
            n = sum(v * v for v in d) ** 0.5
            d = [v / n for v in d]
            for i in range(3):
                for j in range(3):
                    e = (i == j) - d[i] * d[j]
                    A[i][j] += e
                    b[i] += e * p[j]

    def det(M):
        return (M[0][0] * (M[1][1] * M[2][2] - M[1][2] * M[2][1]) - M[0][1] * (M[1][0] * M[2][2] - M[1][2] * M[2][0])
                + M[0][2] * (M[1][0] * M[2][1] - M[1][1] * M[2][0]))
    D = det(A)
    return [det([[b[r] if c == k else A[r][c] for c in range(3)] for r in range(3)]) / D for k in range(3)]


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--bin", default="build/wiresketch")
    ap.add_argument("--out", default="tests/fixtures/scene_small")
    a = ap.parse_args()
    shutil.rmtree(a.out, ignore_errors=True)
    subprocess.run([a.bin, "scene", "trefoil", "--out", a.out, "--size", "64", "--views-train", "8",
                    "--views-val", "2", "--views-test", "4", "--seed", "11"], check=True)
    curves = json.load(open(os.path.join(a.out, "gt_curves.json")))["curves"]
    pts = [bezier(P, k / 100.0) for P in curves for k in range(100)]
    with open(os.path.join(a.out, "gt_points.ply"), "wb") as f:
        f.write(("ply\nformat binary_little_endian 1.0\ncomment points on the curves of gt_curves.json\n"
                 "element vertex %d\nproperty float x\nproperty float y\nproperty float z\nend_header\n"
                 % len(pts)).encode())
        for p in pts:
            f.write(struct.pack("<3f", *p))
    val1 = os.path.join(a.out, "rgb", "val", "r_1.png")
    w, h, nc, depth, rows = png_decode(val1)
    assert nc == 3 and depth == 8
    out = []
    for row in rows:
        r16 = []
        for j in range(w):
            rgb = row[3 * j:3 * j + 3]
            r16 += [v * 257 for v in rgb] + [65535 if any(rgb) else 0]
        out.append(r16)
    png_write_rgba16(val1, w, h, out)

    # the values the tests assert, from this decoder
    pts32 = [struct.unpack("<3f", struct.pack("<3f", *p)) for p in pts]
    angle = json.load(open(os.path.join(a.out, "transforms_train.json")))["camera_angle_x"]
    print("points %d, first %r, last %r" % (len(pts), struct.unpack("<3f", struct.pack("<3f", *pts[0])),
                                             struct.unpack("<3f", struct.pack("<3f", *pts[-1]))))
    _, _, _, _, t0 = png_decode(os.path.join(a.out, "rgb", "train", "r_0.png"))
    _, _, _, _, v1 = png_decode(val1)
    def brightest(rows, nc):
        return max(((i, j) for i in range(h) for j in range(w)), key=lambda ij: sum(rows[ij[0]][nc * ij[1]:nc * ij[1] + 3]))
    for (i, j) in [brightest(t0, 3), brightest(v1, 4), (0, 0)]:
        print("train r_0 (%d,%d): %r" % (i, j, t0[i][3 * j:3 * j + 3]))
        print("val r_1 (%d,%d): %r" % (i, j, v1[i][4 * j:4 * j + 4]))
    lo = [min(p[x] for p in pts32) for x in range(3)]
    hi = [max(p[x] for p in pts32) for x in range(3)]
    print("bbox %r - %r, diagonal %.9g" % (lo, hi, sum((hi[x] - lo[x]) ** 2 for x in range(3)) ** 0.5))
    print("camera_angle_x %.17g, centre %s" % (angle, ", ".join("%.17g" % c for c in axes_center(a.out))))
    print("val r_1 opaque pixels: %d of %d" % (sum(1 for r in v1 for j in range(w) if r[4 * j + 3]), w * h))


if __name__ == "__main__":
    main()
