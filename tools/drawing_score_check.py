#!/usr/bin/env python3
"""An independent computation of the drawing score (src/metrics/drawing_score.h),
to check `wiresketch eval`'s "drawing" against.

usage: python3 tools/drawing_score_check.py FIT_OUT SCENE [VIEW ...]

Reads the sketch renders a fit wrote (FIT_OUT/test/r_K.png, black strokes on
white) and the scene's reference lines (SCENE/lines/test/r_K_parts.png), and
prints per view and their mean: precision, recall, F, contour recall and
interior scribble at 1% and 0.5% of the image diagonal, and overdraw.
Written apart from the C code on purpose: its own PNG decoder (zlib),
thinning by the textbook Zhang-Suen sub-passes, and distances by scanning
every pixel offset within tau (no distance transform). Standard library only.
"""
import math
import os
import struct
import sys
import zlib

PART = {(0, 0, 0): 0, (48, 48, 48): 1, (255, 60, 60): 2, (60, 255, 60): 3, (60, 160, 255): 4}


def read_png(path):
    """8-bit gray / RGB / RGBA / gray+alpha, non-interlaced: (w, h, channels, rows)."""
    data = open(path, "rb").read()
    assert data[:8] == b"\x89PNG\r\n\x1a\n", path + ": not a PNG file"
    pos, idat = 8, b""
    while pos < len(data):
        n, = struct.unpack(">I", data[pos:pos + 4])
        kind, body = data[pos + 4:pos + 8], data[pos + 8:pos + 8 + n]
        pos += 12 + n
        if kind == b"IHDR":
            w, h, depth, ctype, _, _, interlace = struct.unpack(">IIBBBBB", body)
            assert depth == 8 and interlace == 0, path + ": only 8-bit non-interlaced"
        elif kind == b"IDAT":
            idat += body
    ch = {0: 1, 2: 3, 4: 2, 6: 4}[ctype]
    raw, stride, rows, prev, p = zlib.decompress(idat), w * ch, [], bytearray(w * ch), 0
    for _ in range(h):
        ftype, line = raw[p], bytearray(raw[p + 1:p + 1 + stride])
        p += 1 + stride
        for x in range(stride):
            a = line[x - ch] if x >= ch else 0
            b, c = prev[x], (prev[x - ch] if x >= ch else 0)
            if ftype == 1:
                line[x] = (line[x] + a) & 255
            elif ftype == 2:
                line[x] = (line[x] + b) & 255
            elif ftype == 3:
                line[x] = (line[x] + (a + b) // 2) & 255
            elif ftype == 4:
                q = a + b - c
                pa, pb, pc = abs(q - a), abs(q - b), abs(q - c)
                line[x] = (line[x] + (a if pa <= pb and pa <= pc else b if pb <= pc else c)) & 255
        rows.append(line)
        prev = line
    return w, h, ch, rows


def zhang_suen(img, w, h):
    img = [row[:] for row in img]

    def at(y, x):
        return img[y][x] if 0 <= y < h and 0 <= x < w else 0

    changed = True
    while changed:
        changed = False
        for step in (0, 1):
            remove = []
            for y in range(h):
                for x in range(w):
                    if not img[y][x]:
                        continue
                    P = [at(y - 1, x), at(y - 1, x + 1), at(y, x + 1), at(y + 1, x + 1),
                         at(y + 1, x), at(y + 1, x - 1), at(y, x - 1), at(y - 1, x - 1)]
                    B = sum(P)
                    A = sum(1 for k in range(8) if P[k] == 0 and P[(k + 1) % 8] == 1)
                    p2, p4, p6, p8 = P[0], P[2], P[4], P[6]
                    if step == 0:
                        ok = p2 * p4 * p6 == 0 and p4 * p6 * p8 == 0
                    else:
                        ok = p2 * p4 * p8 == 0 and p2 * p6 * p8 == 0
                    if 2 <= B <= 6 and A == 1 and ok:
                        remove.append((y, x))
            for y, x in remove:
                img[y][x] = 0
            changed = changed or bool(remove)
    return img


def near(points, target, tau):
    """How many of points lie within tau (Euclidean, pixel centres) of a pixel of target."""
    r = int(math.floor(tau))
    offsets = [(dy, dx) for dy in range(-r, r + 1) for dx in range(-r, r + 1) if dy * dy + dx * dx <= tau * tau]
    return sum(1 for (y, x) in points if any((y + dy, x + dx) in target for dy, dx in offsets))


def score(sketch_png, parts_png):
    w, h, ch, rows = read_png(sketch_png)
    sketch = [[1 if rows[y][x * ch] < 128 else 0 for x in range(w)] for y in range(h)]
    sketch = zhang_suen(sketch, w, h)
    pw, ph, pch, prow = read_png(parts_png)
    assert (pw, ph) == (w, h)
    part = [[PART[tuple(prow[y][x * pch:x * pch + 3])] for x in range(w)] for y in range(h)]
    S = [(y, x) for y in range(h) for x in range(w) if sketch[y][x]]
    R = [(y, x) for y in range(h) for x in range(w) if part[y][x] >= 2]
    C = [(y, x) for y in range(h) for x in range(w) if part[y][x] in (2, 3)]
    Sset, Rset = set(S), set(R)
    out = {"overdraw": len(S) / len(R)}
    for name, frac in (("1", 0.01), ("0.5", 0.005)):
        tau = frac * math.hypot(w, h)
        far = [(y, x) for (y, x) in S if not near([(y, x)], Rset, tau)]
        P = 1 - len(far) / len(S) if S else 0
        Rc = near(R, Sset, tau) / len(R)
        out["precision_" + name] = P
        out["recall_" + name] = Rc
        out["fscore_" + name] = 2 * P * Rc / (P + Rc) if P + Rc else 0
        out["contour_recall_" + name] = near(C, Sset, tau) / len(C) if C else float("nan")
        out["scribble_" + name] = sum(1 for (y, x) in far if part[y][x] != 0) / len(S) if S else 0
    return out


def main():
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    fit, scene = sys.argv[1], sys.argv[2]
    views = sys.argv[3:] or sorted((f[:-4] for f in os.listdir(os.path.join(fit, "test"))
                                    if f.endswith(".png") and not f.endswith("_photo.png")),
                                   key=lambda s: int(s.split("_")[1]))
    rows = []
    for v in views:
        s = score(os.path.join(fit, "test", v + ".png"), os.path.join(scene, "lines", "test", v + "_parts.png"))
        rows.append(s)
        print(v, " ".join("%s %.4f" % kv for kv in sorted(s.items())))
    keys = sorted(rows[0])
    print("mean", " ".join("%s %.4f" % (k, sum(r[k] for r in rows if r[k] == r[k]) /
                                       max(1, sum(1 for r in rows if r[k] == r[k]))) for k in keys))


if __name__ == "__main__":
    main()
