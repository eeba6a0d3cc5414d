#!/usr/bin/python3
"""reference_splat.py: an independent float64 implementation of METHOD.md sections
1-3 (cameras, curve sampling, exact splatting) and of the l2 loss, to check
`wiresketch render` and `wiresketch grad` against. A developer tool: the tests
never run it (they use the fixture it writes).

    /usr/bin/python3 tools/reference_splat.py compare [--bin build/wiresketch]
        [--scene ../shared/scenes/rose] [--split test] [--sets 3] [--views 0,7,19]
    /usr/bin/python3 tools/reference_splat.py fixture tests/fixtures/splat_ref.json

`compare` draws random curve sets, renders every view of the split with
`render --cutoff inf` and compares the PNGs with the reference alpha (in
1/255), then compares `grad --cutoff inf --loss l2` on a few views with the
reference gradient (torch autograd in float64, t_k held constant). `fixture`
writes a few Gaussians, one camera, the exact alpha of every pixel and dL/dmu
for a fixed dL/dalpha, which tests/test_splat.c checks the C code against.

Written from docs/METHOD.md, sharing no code with the C implementation: the
camera is the inverse of the 4x4 camera-to-world matrix, sampling inverts
the arc-length table with np.interp, the splat is one dense product over all
Gaussians and pixels, and the gradient comes from autograd.
"""
import argparse
import json
import math
import os
import subprocess
import sys
import tempfile

import numpy as np
import torch
from PIL import Image

torch.set_default_dtype(torch.float64)
NEAR = 1e-3
ARC_SAMPLES = 300
MAX_PER_CURVE = 4096


def bernstein(t):
    t = np.asarray(t, dtype=np.float64)[:, None]
    k = np.arange(4)[None, :]
    binom = np.array([1.0, 3.0, 3.0, 1.0])[None, :]
    return binom * t ** k * (1 - t) ** (3 - k)


def load_cameras(scene, split, size):
    with open(os.path.join(scene, "transforms_%s.json" % split)) as f:
        meta = json.load(f)
    focal = 0.5 * size / math.tan(0.5 * meta["camera_angle_x"])
    cams = []
    for frame in meta["frames"]:
        c2w = np.array(frame["transform_matrix"], dtype=np.float64)
        w2c = np.linalg.inv(c2w)
        name = os.path.basename(frame["file_path"])
        cams.append(dict(R=w2c[:3, :3], t=w2c[:3, 3], focal=focal, W=size, H=size, name=name,
                         c2w=c2w, file_path=frame["file_path"]))
    return cams


def scene_center(cams):
    """Least-squares intersection of the optical axes (the cameras look down -z)."""
    A = np.zeros((3, 3))
    b = np.zeros(3)
    for c in cams:
        o = c["c2w"][:3, 3]
        d = -c["c2w"][:3, 2]
        d = d / np.linalg.norm(d)
        proj = np.eye(3) - np.outer(d, d)
        A += proj
        b += proj @ o
    return np.linalg.solve(A, b)


def sample_parameters(P, thickness, overlap):
    """P: n x 4 x 3 -> list over curves of the sample parameters t_k."""
    spacing = 2 * thickness * (1 - overlap)
    ts = np.linspace(0.0, 1.0, ARC_SAMPLES)
    B = bernstein(ts)
    out = []
    for curve in P:
        pts = B @ curve
        cum = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(pts, axis=0), axis=1))])
        L = cum[-1]
        M = int(min(max(1, math.ceil(L / spacing)), MAX_PER_CURVE))
        if M == 1:
            t = np.array([np.interp(0.5 * L, cum, ts) if L > 0 else 0.5])
        else:
            t = np.interp(np.linspace(0.0, L, M), cum, ts)
            t[0], t[-1] = 0.0, 1.0
        out.append(t)
    return out


def splat(cam, mu, radius):
    """Exact alpha (H x W) for centres mu (G x 3, torch): 1 - prod (1 - w)."""
    R = torch.from_numpy(cam["R"])
    t = torch.from_numpy(cam["t"])
    c = mu @ R.T + t
    d = -c[:, 2]
    keep = d > NEAR
    c, d = c[keep], d[keep]
    f, W, H = cam["focal"], cam["W"], cam["H"]
    u = W / 2 + f * c[:, 0] / d
    v = H / 2 - f * c[:, 1] / d
    sigma = f * radius / d
    # pixel (row i, column j) has its centre at (u, v) = (j + 1/2, i + 1/2)
    jj = torch.arange(W, dtype=torch.float64) + 0.5
    ii = torch.arange(H, dtype=torch.float64) + 0.5
    T = torch.ones(H, W)
    for s in range(0, len(u), 256):
        du = jj[None, None, :] - u[s:s + 256, None, None]
        dv = ii[None, :, None] - v[s:s + 256, None, None]
        w = torch.exp(-(du ** 2 + dv ** 2) / (2 * sigma[s:s + 256, None, None] ** 2))
        T = T * torch.prod(1 - w, dim=0)
    return 1 - T


def load_photo(scene, file_path, size):
    """The photo composited on black; SCENE/<file_path>.png or SCENE/rgb/<file_path>.png."""
    path = os.path.join(scene, file_path + ".png")
    if not os.path.exists(path):
        path = os.path.join(scene, "rgb", file_path + ".png")
    img = np.asarray(Image.open(path).convert("RGBA"), dtype=np.float64) / 255.0
    assert img.shape[:2] == (size, size), "reference handles working-size photos only"
    return img[:, :, :3] * img[:, :, 3:4]


def curves_grad(cam, P, thickness, overlap, photo):
    """l2 loss of one view and dL/dP (n x 4 x 3), t_k constant."""
    tks = sample_parameters(P, thickness, overlap)
    Pt = torch.tensor(P, requires_grad=True)
    mu = torch.cat([torch.from_numpy(bernstein(t)) @ Pt[k] for k, t in enumerate(tks)])
    alpha = splat(cam, mu, thickness)
    target = torch.from_numpy(photo)
    loss = ((alpha[:, :, None] - target) ** 2).mean()
    loss.backward()
    return loss.item(), Pt.grad.numpy()


def random_curves(rng, center, n, spread, thickness):
    P = center + rng.normal(size=(n, 1, 3)) * spread + rng.normal(size=(n, 4, 3)) * spread / 2
    return dict(thickness=thickness, overlap=0.6, curves=P.tolist())


def run(cmd):
    res = subprocess.run(cmd, capture_output=True, text=True)
    if res.returncode:
        sys.exit("command failed: %s\n%s" % (" ".join(cmd), res.stderr))
    return res.stdout


def compare(args):
    cams = load_cameras(args.scene, args.split, args.size)
    center = scene_center(cams)
    rng = np.random.default_rng(args.seed)
    views = [int(v) for v in args.views.split(",")]
    worst_px, worst_rel = 0.0, 0.0
    with tempfile.TemporaryDirectory() as tmp:
        for k in range(args.sets):
            thickness = [0.02, 0.05, 0.01][k % 3]
            sketch = random_curves(rng, center, 25, 0.25, thickness)
            path = os.path.join(tmp, "c%d.json" % k)
            with open(path, "w") as f:
                json.dump(sketch, f)
            P = np.array(sketch["curves"])
            tks = sample_parameters(P, thickness, 0.6)
            mu = torch.from_numpy(np.concatenate([bernstein(t) @ P[i] for i, t in enumerate(tks)]))
            out = os.path.join(tmp, "r%d" % k)
            run([args.bin, "render", path, "--alpha", "--scene", args.scene, "--split", args.split, "--out",
                 out, "--cutoff", "inf", "--size", str(args.size)])
            set_px = 0.0
            for cam in cams:
                ref = splat(cam, mu, thickness).numpy()
                png = np.asarray(Image.open(os.path.join(out, cam["name"] + ".png")), np.float64)
                set_px = max(set_px, np.abs(png - 255 * ref).max())
            set_rel = 0.0
            for view in views:
                cam = cams[view]
                photo = load_photo(args.scene, cam["file_path"], args.size)
                loss, grad = curves_grad(cam, P, thickness, 0.6, photo)
                got = json.loads(run([args.bin, "grad", args.scene, "--curves", path, "--split",
                                      args.split, "--view", str(view), "--cutoff", "inf",
                                      "--size", str(args.size)]))
                g = np.array(got["grad"])
                rel = max(abs(got["loss"] - loss) / abs(loss),
                          np.abs(g - grad).max() / np.abs(grad).max())
                set_rel = max(set_rel, rel)
            print("set %d: %d Gaussians, thickness %g: render max |png - 255 alpha| = %.3f "
                  "(/255) over %d views; grad max |diff| / max |grad| = %.3g over views %s"
                  % (k, len(mu), thickness, set_px, len(cams), set_rel, args.views))
            worst_px, worst_rel = max(worst_px, set_px), max(worst_rel, set_rel)
    print("worst: render %.3f/255 (target 2), grad %.3g relative (target 1e-3)"
          % (worst_px, worst_rel))
    return 0 if worst_px <= 2 and worst_rel <= 1e-3 else 1


def fixture(args):
    """A 20 x 16 camera looking at a handful of Gaussians, one of them on an
    exact pixel centre, one behind the camera, one partly off the image."""
    W, H = 20, 16
    c2w = np.array([[0.8, 0.0, 0.6, 2.4], [0.0, 1.0, 0.0, 0.3], [-0.6, 0.0, 0.8, 3.2],
                    [0.0, 0.0, 0.0, 1.0]])
    angle = 0.9
    focal = 0.5 * W / math.tan(0.5 * angle)
    w2c = np.linalg.inv(c2w)
    cam = dict(R=w2c[:3, :3], t=w2c[:3, 3], focal=focal, W=W, H=H)
    radius = 0.15
    rng = np.random.default_rng(7)
    cam_pts = [np.array([x, y, -4.0]) for x, y in rng.uniform(-0.8, 0.8, size=(6, 2))]
    # exactly on the centre of pixel (row 5, column 12): u = 12.5, v = 5.5 at depth 3.5
    d = 3.5
    cam_pts.append(np.array([(12.5 - W / 2) * d / focal, -(5.5 - H / 2) * d / focal, -d]))
    cam_pts.append(np.array([0.1, 0.2, 1.0]))     # behind the camera
    cam_pts.append(np.array([1.55, -0.1, -4.0]))  # centre beyond the right edge
    mu = np.array([c2w[:3, :3] @ p + c2w[:3, 3] for p in cam_pts])
    mut = torch.tensor(mu, requires_grad=True)
    alpha = splat(cam, mut, radius)
    ii, jj = np.meshgrid(np.arange(H), np.arange(W), indexing="ij")
    dalpha = np.sin(0.7 * ii + 0.3) * np.cos(0.45 * jj - 0.2)
    (alpha * torch.from_numpy(dalpha)).sum().backward()
    out = dict(
        comment="written by tools/reference_splat.py fixture: exact splat (cutoff inf) of mu "
                "with radius into the camera; dmu = dL/dmu for L = sum(alpha * dalpha)",
        width=W, height=H, camera_angle_x=angle, transform_matrix=c2w.tolist(), radius=radius,
        mu=mu.tolist(), alpha=alpha.detach().numpy().tolist(), dalpha=dalpha.tolist(),
        dmu=mut.grad.numpy().tolist())
    with open(args.out, "w") as f:
        json.dump(out, f, indent=1)
    print("wrote %s: %d Gaussians, %d x %d" % (args.out, len(mu), W, H))
    return 0


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    sub = ap.add_subparsers(dest="cmd", required=True)
    c = sub.add_parser("compare")
    c.add_argument("--bin", default="build/wiresketch")
    c.add_argument("--scene", default="../shared/scenes/rose")
    c.add_argument("--split", default="test")
    c.add_argument("--size", type=int, default=224)
    c.add_argument("--sets", type=int, default=3)
    c.add_argument("--views", default="0,7,19")
    c.add_argument("--seed", type=int, default=1)
    x = sub.add_parser("fixture")
    x.add_argument("out")
    args = ap.parse_args()
    return compare(args) if args.cmd == "compare" else fixture(args)


if __name__ == "__main__":
    sys.exit(main())
