#!/usr/bin/python3
"""Makes tests/fixtures/augment_torchvision.txt: one augmentation computed by
torchvision itself, for tests/test_augment.c to compare src/augment.c with.

The transform objects of METHOD.md section 5 are run as they are,
  RandomPerspective(distortion_scale=0.5, p=1, fill=0, bilinear) and
  RandomResizedCrop((H, W), scale=(0.8, 0.8), ratio=(1, 1), bilinear),
with their get_params replaced by fixed corner points and a fixed crop box,
on a non-square 3-channel image (so a swap of x and y cannot pass), in
float64. torch solves the homography in float32 least squares, which alone
moves the result by ~1e-5; so the file holds the output twice: as
torchvision computes it, and with the homography solved in float64 (torch's
_get_perspective_coeffs replaced, everything else unchanged), which
src/augment.c (float64 homography) must match to float rounding.

Needs torch and torchvision (Debian: python3-torchvision); run from the
repository root:  /usr/bin/python3 tools/make_augment_fixture.py
File format (text): a comment line, then
  size W H C / corners x y (4 pairs) / crop top left height width /
  input: C*H*W integers n (the value is n / 255) / output: C*H*W floats /
  output_exact_homography: C*H*W floats.
"""
import math
import sys

import numpy as np
import torch
import torchvision
from torchvision import transforms as T
from torchvision.transforms import functional as F

W, H, C = 40, 36, 3
CORNERS = [[7, 3], [31, 1], [37, 28], [2, 33]]  # where TL, TR, BR, BL go
CROP = (1, 5, 34, 34)  # top, left, height, width: side round(sqrt(0.8*W*H)) = 34
OUT = "tests/fixtures/augment_torchvision.txt"


def test_image():
    """Smooth pattern plus a few sharp edges, quantised to 8 bits (exact in C)."""
    img = torch.zeros(C, H, W, dtype=torch.float64)
    for c in range(C):
        for i in range(H):
            for j in range(W):
                v = 0.5 + 0.3 * math.sin(0.21 * j + 0.9 * c) * math.cos(0.17 * i - 0.4 * c)
                if (i - 18) ** 2 + (j - 20 + 3 * c) ** 2 < 64:
                    v += 0.15
                img[c, i, j] = round(max(0.0, min(1.0, v)) * 255)
    return img


def augment(img):
    start = [[0, 0], [W - 1, 0], [W - 1, H - 1], [0, H - 1]]
    persp = T.RandomPerspective(distortion_scale=0.5, p=1.0, fill=0,
                                interpolation=T.InterpolationMode.BILINEAR)
    crop = T.RandomResizedCrop((H, W), scale=(0.8, 0.8), ratio=(1.0, 1.0),
                               interpolation=T.InterpolationMode.BILINEAR)
    persp.get_params = lambda width, height, d: (start, CORNERS)
    crop.get_params = lambda im, scale, ratio: CROP
    return crop(persp(img))


def coeffs_float64(startpoints, endpoints):
    """torchvision's _get_perspective_coeffs, solved in float64."""
    a, b = [], []
    for (ex, ey), (sx, sy) in zip(endpoints, startpoints):
        a.append([ex, ey, 1, 0, 0, 0, -sx * ex, -sx * ey])
        a.append([0, 0, 0, ex, ey, 1, -sy * ex, -sy * ey])
        b += [sx, sy]
    return np.linalg.solve(np.array(a, dtype=np.float64), np.array(b, dtype=np.float64)).tolist()


def write_image(f, name, img):
    f.write(name + "\n")
    for row in img.reshape(-1, W).tolist():
        f.write(" ".join("%.8g" % v for v in row) + "\n")


def main():
    counts = test_image()
    out = augment(counts / 255.0)
    out32 = augment((counts / 255.0).float()).double()
    F._get_perspective_coeffs = coeffs_float64
    exact = augment(counts / 255.0)
    print("torchvision", torchvision.__version__, "max |diff| float32 vs float64 image:",
          float((out - out32).abs().max()), "float32 vs float64 homography:",
          float((out - exact).abs().max()), file=sys.stderr)
    with open(OUT, "w") as f:
        f.write("# made by tools/make_augment_fixture.py with torch %s torchvision %s\n"
                % (torch.__version__, torchvision.__version__))
        f.write("size %d %d %d\n" % (W, H, C))
        f.write("corners %s\n" % " ".join("%d %d" % (x, y) for x, y in CORNERS))
        f.write("crop %d %d %d %d\n" % CROP)
        f.write("input\n")
        for row in counts.reshape(-1, W).tolist():
            f.write(" ".join("%d" % v for v in row) + "\n")
        write_image(f, "output", out)
        write_image(f, "output_exact_homography", exact)


if __name__ == "__main__":
    main()
