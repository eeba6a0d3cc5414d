#!/usr/bin/env python3
"""make_fuzz_corpus.py: rewrites the fuzzers' seed corpora, tests/fuzz/corpus/.

usage: python3 tools/make_fuzz_corpus.py [--wiresketch build/wiresketch] [--out DIR] [--regressions]

Small real files of every kind the fuzz targets read (kept small: the
corpus is committed):
  scene/       the rose scene's transforms_train.json cut to 3 frames (and a
               few layouts of it), a synthetic scene's, a minimal one; the
               frames name train/r_0 .. train/r_2, which fuzz_scene.c
               provides as tiny PNGs
  png/         one tiny PNG of each kind the loader takes (gray, gray+alpha,
               RGB, RGBA at 8 and 16 bits, palette with and without tRNS,
               1- and 4-bit gray, Adam7-interlaced), and rose's r_0 photo
               box-filtered to 32 x 32
  weights/     a tiny CLIP (width 8, 1 layer, 2 heads, patch 4, resolution 8,
               output 4) as f32 and f16, written by convert_weights.py's
               own writer
  curves/      a fitted sketch, a synthetic scene's ground truth, edge cases
  checkpoint/  checkpoints of two short fits of a 32-pixel synthetic scene
  ply/         point clouds: ascii, binary of both byte orders, other types,
               extra properties, a list and a face element; rose's
               gt_points.ply cut to its first 40 points
The last two need a built wiresketch. Then the hand-made hostile inputs of
tests/fuzz/regressions/ (--regressions: only those). Python 3 standard
library only.
"""
import argparse
import json
import os
import random
import shutil
import struct
import subprocess
import sys
import tempfile
import zlib

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import convert_weights  # noqa: E402  (its writer and tensor table)

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
CORPUS = os.path.join(ROOT, "tests", "fuzz", "corpus")
ROSE = os.path.join(ROOT, "..", "shared", "scenes", "rose")


def write(kind, name, data):
    os.makedirs(os.path.join(CORPUS, kind), exist_ok=True)
    with open(os.path.join(CORPUS, kind, name), "wb") as f:
        f.write(data)


# --------------------------------------------------------------------------
# PNG: a minimal encoder (filter type 0, optional Adam7) and decoder

def chunk(kind, body):
    return struct.pack(">I", len(body)) + kind + body + struct.pack(">I", zlib.crc32(kind + body))


ADAM7 = [(0, 0, 8, 8), (4, 0, 8, 8), (0, 4, 4, 8), (2, 0, 4, 4), (0, 2, 2, 4), (1, 0, 2, 2),
         (0, 1, 1, 2)]  # x0, y0, dx, dy of each pass


def pack_row(samples, depth):
    """Samples of one row (already interleaved) at the given bit depth."""
    if depth == 16:
        return b"".join(struct.pack(">H", s) for s in samples)
    if depth == 8:
        return bytes(samples)
    out, acc, bits = bytearray(), 0, 0
    for s in samples:
        acc = acc << depth | s
        bits += depth
        if bits == 8:
            out.append(acc)
            acc, bits = 0, 0
    if bits:
        out.append(acc << (8 - bits))
    return bytes(out)


def png(width, height, depth, colour, pixel, interlace=False, extra=b""):
    """pixel(x, y) gives the tuple of samples of one pixel."""
    raw = bytearray()
    passes = ADAM7 if interlace else [(0, 0, 1, 1)]
    for x0, y0, dx, dy in passes:
        xs = range(x0, width, dx)
        if not xs:
            continue
        for y in range(y0, height, dy):
            raw.append(0)
            raw += pack_row([s for x in xs for s in pixel(x, y)], depth)
    ihdr = struct.pack(">IIBBBBB", width, height, depth, colour, 0, 0, 1 if interlace else 0)
    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", ihdr) + extra +
            chunk(b"IDAT", zlib.compress(bytes(raw), 9)) + chunk(b"IEND", b""))


def paeth(a, b, c):
    p = a + b - c
    pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
    return a if pa <= pb and pa <= pc else (b if pb <= pc else c)


def read_rgba8(path):
    """An 8-bit RGBA, non-interlaced PNG as rows of bytes."""
    data = open(path, "rb").read()
    pos, idat, head = 8, b"", None
    while pos < len(data):
        n, kind = struct.unpack(">I4s", data[pos:pos + 8])
        body = data[pos + 8:pos + 8 + n]
        if kind == b"IHDR":
            head = struct.unpack(">IIBBBBB", body)
        elif kind == b"IDAT":
            idat += body
        pos += 12 + n
    width, height, depth, colour, _, _, interlace = head
    if (depth, colour, interlace) != (8, 6, 0):
        raise SystemExit(f"{path}: expected 8-bit RGBA, not interlaced")
    raw, stride, rows, prev = zlib.decompress(idat), 4 * width, [], bytearray(4 * width)
    for y in range(height):
        kind, line = raw[y * (stride + 1)], bytearray(raw[y * (stride + 1) + 1:(y + 1) * (stride + 1)])
        for i in range(stride):
            a = line[i - 4] if i >= 4 else 0
            b, c = prev[i], prev[i - 4] if i >= 4 else 0
            line[i] = (line[i] + (0, a, b, (a + b) // 2, paeth(a, b, c))[kind]) & 255
        rows.append(line)
        prev = line
    return width, height, rows


def png_corpus():
    ramp = lambda x, y, top: (x * 7 + y * 13) % (top + 1)  # noqa: E731
    write("png", "gray8.png", png(3, 2, 8, 0, lambda x, y: (ramp(x, y, 255),)))
    write("png", "gray16.png", png(3, 2, 16, 0, lambda x, y: (ramp(x, y, 65535) * 251,)))
    write("png", "gray_alpha8.png", png(3, 2, 8, 4, lambda x, y: (ramp(x, y, 255), 40 * x)))
    write("png", "rgb8.png", png(4, 3, 8, 2, lambda x, y: (60 * x, 80 * y, 200)))
    write("png", "rgb16.png", png(2, 2, 16, 2, lambda x, y: (30000 * x, 65535, 9 * y)))
    write("png", "rgba8.png", png(3, 3, 8, 6, lambda x, y: (90 * x, 90 * y, 33, 120 * y)))
    write("png", "rgba16.png", png(2, 3, 16, 6, lambda x, y: (1000 * x, 2000 * y, 3, 30000 * x)))
    plte = chunk(b"PLTE", bytes([0, 0, 0, 255, 0, 0, 0, 255, 0, 10, 20, 30]))
    write("png", "palette8.png", png(4, 2, 8, 3, lambda x, y: ((x + y) % 4,), extra=plte))
    write("png", "palette2_trns.png",
          png(5, 2, 2, 3, lambda x, y: ((x + y) % 4,), extra=plte + chunk(b"tRNS", bytes([0, 128]))))
    write("png", "gray1.png", png(9, 2, 1, 0, lambda x, y: ((x + y) % 2,)))
    write("png", "gray4_trns.png",
          png(3, 3, 4, 0, lambda x, y: (ramp(x, y, 15),), extra=chunk(b"tRNS", struct.pack(">H", 7))))
    write("png", "rgb8_adam7.png", png(9, 9, 8, 2, lambda x, y: (28 * x, 28 * y, 99), interlace=True))
    # a real photo: rose's first training view, box-filtered to 32 x 32
    width, height, rows = read_rgba8(os.path.join(ROSE, "rgb", "train", "r_0.png"))
    fx, fy = width // 32, height // 32

    def box(x, y):
        return tuple(sum(rows[y * fy + i][4 * (x * fx + j) + c] for i in range(fy) for j in range(fx))
                     // (fx * fy) for c in range(4))
    write("png", "rose_r_0_32px.png", png(32, 32, 8, 6, box))


# --------------------------------------------------------------------------
# Scenes: transforms files whose frames name train/r_0 .. train/r_2

def scene_corpus(synthetic_dir):
    rose = json.load(open(os.path.join(ROSE, "transforms_train.json")))
    rose["frames"] = rose["frames"][:3]
    for k, frame in enumerate(rose["frames"]):
        frame["file_path"] = f"train/r_{k}"
    write("scene", "rose_3_frames.json", json.dumps(rose, indent=2).encode())
    compact = {"camera_angle_x": rose["camera_angle_x"],
               "frames": [{"file_path": f["file_path"] + ".png", "transform_matrix": f["transform_matrix"]}
                          for f in rose["frames"]]}
    write("scene", "rose_png_suffix.json", json.dumps(compact, separators=(",", ":")).encode())
    synthetic = json.load(open(os.path.join(synthetic_dir, "transforms_train.json")))
    synthetic["frames"] = synthetic["frames"][:3]
    for k, frame in enumerate(synthetic["frames"]):
        frame["file_path"] = f"./train/r_{k}"
    write("scene", "synthetic.json", json.dumps(synthetic, indent=1).encode())
    minimal = {"camera_angle_x": 0.8, "frames": [{"file_path": "train/r_0", "transform_matrix": [
        [1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 4], [0, 0, 0, 1]]}]}
    write("scene", "minimal.json", json.dumps(minimal).encode())


# --------------------------------------------------------------------------
# Weights: a tiny tower through convert_weights.py's writer

def weights_corpus():
    arch = {"width": 8, "layers": 1, "heads": 2, "patch": 4, "resolution": 8, "output_dim": 4}
    tokens = (arch["resolution"] // arch["patch"]) ** 2 + 1
    expected = convert_weights.expected_tensors(arch["width"], arch["layers"], arch["patch"], tokens,
                                                arch["output_dim"])
    rng = random.Random(1)
    tower = {}
    for name, shape in expected:
        n = 1
        for d in shape:
            n *= d
        values = struct.pack(f"<{n}f", *(rng.uniform(-0.5, 0.5) for _ in range(n)))
        tower[name] = convert_weights.Tensor("f32", shape, lambda v=values: iter((v,)))
    for dtype in ("f32", "f16"):
        path = os.path.join(CORPUS, "weights", f"tiny_{dtype}.bin")
        os.makedirs(os.path.dirname(path), exist_ok=True)
        convert_weights.write_weight_file(path, arch, tower, expected, dtype, lambda s: s)


# --------------------------------------------------------------------------
# PLY point clouds

def ply_corpus():
    points = [(0.5 * i, -0.25 * i, 1.0 + i) for i in range(5)]
    ascii_ = "ply\nformat ascii 1.0\ncomment seed\nelement vertex 5\nproperty float x\n" \
             "property float y\nproperty float z\nproperty uchar red\nelement face 1\n" \
             "property list uchar int vertex_indices\nend_header\n"
    ascii_ += "".join(f"{x} {y} {z} {i * 40}\n" for i, (x, y, z) in enumerate(points)) + "3 0 1 2\n"
    write("ply", "ascii_face.ply", ascii_.encode())
    head = ("ply\nformat binary_little_endian 1.0\nelement vertex 5\nproperty double x\n"
            "property double y\nproperty double z\nproperty float nx\nend_header\n").encode()
    write("ply", "binary_le_double.ply",
          head + b"".join(struct.pack("<dddf", x, y, z, 1.0) for x, y, z in points))
    head = ("ply\nformat binary_big_endian 1.0\nelement vertex 5\nproperty list uchar short idx\n"
            "property int16 x\nproperty int16 y\nproperty int16 z\nend_header\n").encode()
    write("ply", "binary_be_list_int16.ply",
          head + b"".join(struct.pack(">BhhBhhh", 2, 7, 8, i, -i, 2 * i, 3) for i in range(5)))
    rose = open(os.path.join(ROSE, "gt_points.ply"), "rb").read()
    end = rose.index(b"end_header\n") + len(b"end_header\n")
    header = rose[:end].replace(b"element vertex 136205", b"element vertex 40")
    write("ply", "rose_40_points.ply", header + rose[end:end + 40 * 12])


# --------------------------------------------------------------------------
# Curves and checkpoints: from short fits of a small synthetic scene

def run(cmd):
    done = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    if done.returncode != 0:
        raise SystemExit(f"{' '.join(cmd)}: exit {done.returncode}: {done.stderr.strip()}")


def fit_corpus(ws, scene, tmp):
    common = [ws, "fit", scene, "--loss", "edges", "--size", "32", "--threads", "1", "--quiet",
              "--length", "0.3"]
    run(common + ["--out", os.path.join(tmp, "a"), "--n-curves", "3", "--max-steps", "3",
                  "--inner-steps", "2"])
    run(common + ["--out", os.path.join(tmp, "b"), "--n-curves", "2", "--max-steps", "4",
                  "--inner-steps", "1", "--eval-every", "1", "--snapshot-every", "1", "--seed", "5"])
    for name in ("a", "b"):
        shutil.copy(os.path.join(tmp, name, "checkpoint.bin"),
                    os.path.join(CORPUS, "checkpoint", f"fit_{name}.bin"))
    shutil.copy(os.path.join(tmp, "a", "curves.json"), os.path.join(CORPUS, "curves", "fitted.json"))
    gt = json.load(open(os.path.join(scene, "gt_curves.json")))
    gt["curves"] = gt["curves"][:4]
    write("curves", "gt_trefoil_4.json", json.dumps(gt).encode())
    write("curves", "degenerate_and_long.json", json.dumps({
        "thickness": 0.02, "overlap": 0.6, "curves": [
            [[0.5, 0.5, 0.5]] * 4,
            [[0, 0, 0], [1000, 0, 0], [0, 1000, 0], [0, 0, 1000]],
            [[1e-3, 2e-3, 3e-3], [-1, 2, -3], [4, -5, 6], [0.25, 0.5, 0.75]]]}).encode())
    write("curves", "empty.json", b'{"thickness": 0.5, "overlap": 0, "curves": []}\n')


# --------------------------------------------------------------------------
# Regressions: hostile inputs of issue 15, each refused with the message
# tests/test_regressions.c expects (checksums right, so the check under
# test is the one that fires)

REGRESSIONS = os.path.join(ROOT, "tests", "fuzz", "regressions")


def write_regression(kind, name, data):
    os.makedirs(os.path.join(REGRESSIONS, kind), exist_ok=True)
    with open(os.path.join(REGRESSIONS, kind, name), "wb") as f:
        f.write(data)


def with_crc(body):
    return body + struct.pack("<I", zlib.crc32(body) & 0xffffffff)


def weight_regressions():
    tiny = open(os.path.join(CORPUS, "weights", "tiny_f32.bin"), "rb").read()
    count = struct.unpack_from("<I", tiny, 36)[0]
    # a table claiming 200 000 tensors (the header of a 1-layer tower)
    write_regression("weights", "tensors_200000.bin",
                     with_crc(tiny[:36] + struct.pack("<I", 200000) + tiny[40:-4]))
    # one tensor more than a 1-layer tower has: block 1's ln_1.bias; the
    # table grows by 120 bytes, so every data offset moves by 128 (aligned)
    table_end = 40 + count * 120
    data_start = (table_end + 63) // 64 * 64
    entries = []
    for i in range(count):
        e = bytearray(tiny[40 + 120 * i:160 + 120 * i])
        struct.pack_into("<Q", e, 104, struct.unpack_from("<Q", e, 104)[0] + 128)
        entries.append(bytes(e))
    data = tiny[data_start:-4]
    extra_at = (data_start + 128 + len(data) + 63) // 64 * 64
    entries.append(struct.pack("<64sII4QQQ", b"transformer.resblocks.1.ln_1.bias", 0, 1, 8, 0, 0, 0,
                               extra_at, 32))
    head = tiny[:36] + struct.pack("<I", count + 1) + b"".join(entries)
    body = head.ljust(data_start + 128, b"\0") + data
    body = body.ljust(extra_at, b"\0") + struct.pack("<8f", *([0.5] * 8))
    write_regression("weights", "tensor_beyond_layers.bin", with_crc(body))


def scene_regressions():
    def scene(angle, file_path, matrix):
        return json.dumps({"camera_angle_x": angle, "frames": [
            {"file_path": file_path, "transform_matrix": matrix}]}).encode()
    good = [[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 4], [0, 0, 0, 1]]
    write_regression("scene", "file_path_parent.json", scene(0.7, "train/../../r_0", good))
    write_regression("scene", "camera_angle_tiny.json", scene(1e-300, "train/r_0", good))
    write_regression("scene", "rotation_scaled.json", scene(0.7, "train/r_0", [
        [1e100, 0, 0, 0], [0, 1e100, 0, 0], [0, 0, 1e100, 4], [0, 0, 0, 1]]))
    write_regression("scene", "bottom_row.json", scene(0.7, "train/r_0", [
        [1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 4], [0, 0, 1, 1]]))


def regressions_corpus():
    weight_regressions()
    scene_regressions()
    write_regression("curves", "too_long_to_measure.json", json.dumps({
        "thickness": 0.02, "overlap": 0.6,
        "curves": [[[0, 0, 0], [1e300, 0, 0], [0, 1e300, 0], [0, 0, 1e300]]]}).encode())


def main():
    global CORPUS
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--wiresketch", default=os.path.join(ROOT, "build", "wiresketch"))
    ap.add_argument("--out", default=CORPUS, help="corpus directory [tests/fuzz/corpus]")
    ap.add_argument("--regressions", action="store_true",
                    help="only rewrite the hand-made regression inputs (no ../shared needed)")
    args = ap.parse_args()
    if args.regressions:
        regressions_corpus()
        return
    CORPUS = args.out
    for kind in ("scene", "png", "weights", "curves", "checkpoint", "ply"):
        shutil.rmtree(os.path.join(CORPUS, kind), ignore_errors=True)
        os.makedirs(os.path.join(CORPUS, kind))
    png_corpus()
    weights_corpus()
    ply_corpus()
    with tempfile.TemporaryDirectory() as tmp:
        scene = os.path.join(tmp, "scene")
        run([args.wiresketch, "scene", "trefoil", "--out", scene, "--size", "32", "--views-train", "3",
             "--views-val", "1", "--views-test", "1"])
        scene_corpus(scene)
        fit_corpus(args.wiresketch, scene, tmp)
    regressions_corpus()
    total = sum(os.path.getsize(os.path.join(d, f)) for d, _, fs in os.walk(CORPUS) for f in fs)
    print(f"make_fuzz_corpus.py: {CORPUS}: {total} bytes")


if __name__ == "__main__":
    main()
