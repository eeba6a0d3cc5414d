#!/usr/bin/env python3
"""A CLIP ViT-B/32 image tower with seeded random weights, as weight files.

usage: python3 tools/make_random_weights.py OUT [--dtype f32|f16] [--seed N] [--layers N]
       [--width N] [--heads N] [--patch N] [--resolution N] [--output-dim N]

No pretrained weights can be downloaded on the machines wiresketch is
benchmarked on, so `make bench` and the peak-memory measurement use a model
of the real size with random weights (activations, timings and memory are
those of the real model; only the values are meaningless). The same seed
gives the same values whatever the dtype, so an f32 and an f16 file made
with the same seed differ exactly by f16 rounding: what `convert --dtype
f16` costs in accuracy. Weights are drawn as nn/clip.c's clip_model_random
scales them (uniform, CLIP's initialisation scales), from Python's own
generator seeded per tensor, and written by tools/convert_weights.py's
writer. The architecture options (ViT-B/32's by default) make small
models too, for tests (tests/test_random_weights.c). Standard library only.
"""
import argparse
import array
import math
import os
import random
import sys
import zlib

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import convert_weights  # noqa: E402

VIT_B32 = {"width": 768, "layers": 12, "heads": 12, "patch": 32, "resolution": 224, "output_dim": 512}


def scale(name, arch):
    """(centre, standard deviation) of a tensor, as clip_model_random draws it."""
    w, layers, patch = arch["width"], arch["layers"], arch["patch"]
    sw = 1 / math.sqrt(w)
    if name.endswith(("ln_1.weight", "ln_2.weight")) or name in ("ln_pre.weight", "ln_post.weight"):
        return 1.0, 0.1
    if name.endswith(("ln_1.bias", "ln_2.bias")) or name in ("ln_pre.bias", "ln_post.bias"):
        return 0.0, 0.1
    if name == "conv1.weight":
        return 0.0, 1 / math.sqrt(3 * patch * patch)
    if name.endswith(("out_proj.weight", "c_proj.weight")):
        return 0.0, sw / math.sqrt(2 * layers)
    if name.endswith("c_fc.weight"):
        return 0.0, 1 / math.sqrt(2 * w)
    if name.endswith("bias"):
        return 0.0, 0.02
    return 0.0, sw  # embeddings, in_proj_weight, proj


def random_tensor(name, shape, arch, seed):
    """A convert_weights.Tensor whose f32 bytes are drawn when its chunks are read (one chunk)."""
    centre, std = scale(name, arch)
    half = math.sqrt(3) * std  # uniform on [-half, half) has this standard deviation

    def chunks():
        rng = random.Random(seed * 1000003 + zlib.crc32(name.encode()))
        n = math.prod(shape)
        values = array.array("f", (centre + half * (2 * rng.random() - 1) for _ in range(n)))
        if sys.byteorder == "big":
            values.byteswap()
        yield values.tobytes()

    return convert_weights.Tensor("f32", shape, chunks)


def architecture_problem(arch):
    """What makes arch no ViT image tower the C loader takes (None: nothing)."""
    for key, value in arch.items():
        if value < 1:
            return f"--{key.replace('_', '-')} {value}: must be at least 1"
    if arch["width"] % arch["heads"]:
        return f"--width {arch['width']} is not a multiple of --heads {arch['heads']}"
    if arch["resolution"] % arch["patch"]:
        return f"--resolution {arch['resolution']} is not a multiple of --patch {arch['patch']}"
    return None


def main(argv):
    parser = argparse.ArgumentParser(prog="make_random_weights.py", description=__doc__.split("\n")[0])
    parser.add_argument("output", metavar="OUT")
    parser.add_argument("--dtype", choices=sorted(convert_weights.OUT_DTYPES), default="f32")
    parser.add_argument("--seed", type=int, default=1)
    for key in VIT_B32:
        parser.add_argument("--" + key.replace("_", "-"), type=int, default=VIT_B32[key])
    args = parser.parse_args(argv)
    arch = {key: getattr(args, key) for key in VIT_B32}
    problem = architecture_problem(arch)
    if problem:
        print(f"make_random_weights.py: {problem}", file=sys.stderr)
        return 2
    tokens = (arch["resolution"] // arch["patch"]) ** 2 + 1
    expected = convert_weights.expected_tensors(arch["width"], arch["layers"], arch["patch"], tokens,
                                                arch["output_dim"])
    tower = {name: random_tensor(name, shape, arch, args.seed) for name, shape in expected}
    try:
        nbytes = convert_weights.write_weight_file(args.output, arch, tower, expected, args.dtype,
                                                   lambda name: name)
    except convert_weights.ConvertError as e:  # the writer's refusal names the file
        print(f"make_random_weights.py: {e.path or args.output}: {e}", file=sys.stderr)
        return 1
    name = "ViT-B/32" if arch == VIT_B32 else "ViT ({})".format(
        ", ".join(f"{key} {value}" for key, value in arch.items()))
    print(f"{args.output}: random {name} image tower (seed {args.seed}), {args.dtype}, {nbytes} bytes")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
