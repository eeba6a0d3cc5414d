#!/usr/bin/env python3
"""The reference points of tests/test_lens.c (tests/fixtures/lens_points.txt).

usage: python3 tools/lens_reference.py > tests/fixtures/lens_points.txt

For lenses of every COLMAP camera model, pixels of the undistorted
(pinhole) image on a grid over the frame are pushed through OpenCV's
published distortion formulas (cv::projectPoints for the perspective
models, with the rational model for FULL_OPENCV; cv::fisheye for
OPENCV_FISHEYE), written here from the documentation, independently of
src/render/lens.c and in another form (explicit powers, no Horner).
Each line: MODEL W H nparams params... u v u_distorted v_distorted, pixels
with centres at integer + 1/2. test_lens checks that lens.c's inverse
takes (u_distorted, v_distorted) back to (u, v) within 0.01 px.
Standard library only, no numpy.
"""
import math

LENSES = [
    ("SIMPLE_RADIAL", 640, 480, [500.0, 320.0, 240.0, -0.12]),
    ("RADIAL", 640, 480, [520.0, 330.0, 236.0, -0.2, 0.05]),
    ("OPENCV", 800, 600, [610.0, 605.0, 404.0, 297.0, -0.28, 0.08, 0.0012, -0.0008]),
    ("OPENCV", 640, 480, [500.0, 500.0, 320.0, 240.0, 0.1, 0.02, -0.002, 0.001]),
    ("FULL_OPENCV", 800, 600,
     [600.0, 598.0, 401.0, 302.0, -0.3, 0.1, 0.001, -0.0005, -0.01, 0.05, 0.01, 0.002]),
    ("OPENCV_FISHEYE", 800, 800, [300.0, 301.0, 400.0, 399.0, 0.05, -0.01, 0.003, -0.0005]),
]


def distort(model, p, x, y):
    """Normalised undistorted (x, y) -> distorted pixel (u, v)."""
    if model in ("SIMPLE_RADIAL", "RADIAL"):
        f, cx, cy = p[0], p[1], p[2]
        k1 = p[3]
        k2 = p[4] if model == "RADIAL" else 0.0
        r2 = x * x + y * y
        s = 1 + k1 * r2 + k2 * r2 ** 2
        return f * x * s + cx, f * y * s + cy
    fx, fy, cx, cy = p[0], p[1], p[2], p[3]
    if model == "OPENCV_FISHEYE":
        k1, k2, k3, k4 = p[4:8]
        r = math.sqrt(x * x + y * y)
        th = math.atan(r)
        thd = th * (1 + k1 * th ** 2 + k2 * th ** 4 + k3 * th ** 6 + k4 * th ** 8)
        s = thd / r if r > 0 else 1.0
        return fx * x * s + cx, fy * y * s + cy
    k1, k2, p1, p2 = p[4:8]
    k3 = k4 = k5 = k6 = 0.0
    if model == "FULL_OPENCV":
        k3, k4, k5, k6 = p[8:12]
    r2 = x * x + y * y
    radial = (1 + k1 * r2 + k2 * r2 ** 2 + k3 * r2 ** 3) / (1 + k4 * r2 + k5 * r2 ** 2 + k6 * r2 ** 3)
    xd = x * radial + 2 * p1 * x * y + p2 * (r2 + 2 * x * x)
    yd = y * radial + p1 * (r2 + 2 * y * y) + 2 * p2 * x * y
    return fx * xd + cx, fy * yd + cy


def main():
    for model, w, h, p in LENSES:
        fx, fy = (p[0], p[0]) if model in ("SIMPLE_RADIAL", "RADIAL") else (p[0], p[1])
        cx, cy = (p[1], p[2]) if model in ("SIMPLE_RADIAL", "RADIAL") else (p[2], p[3])
        n = 7
        for i in range(n):
            for j in range(n):
                # undistorted pixels over 90% of the frame around the centre
                u = w * (0.05 + 0.9 * j / (n - 1))
                v = h * (0.05 + 0.9 * i / (n - 1))
                ud, vd = distort(model, p, (u - cx) / fx, (v - cy) / fy)
                if not (0 <= ud <= w and 0 <= vd <= h):
                    continue  # outside the distorted frame: not a point of the photo
                print(model, w, h, len(p), " ".join(repr(q) for q in p),
                      repr(u), repr(v), repr(ud), repr(vd))


if __name__ == "__main__":
    main()
