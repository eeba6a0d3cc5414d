#!/usr/bin/python3
"""check_full_size.py: the converter and the C image tower at full ViT-B/32 size.

Developers only (needs torch; run with the system python that has it, from
the repository root, after `make`):
    /usr/bin/python3 tools/check_full_size.py [--work DIR] [--wiresketch build/wiresketch]

Builds a CLIP ViT-B/32 (width 768, 12 layers, 12 heads, patch 32, resolution
224, output 512) with random f16-representable weights, saves it the three
ways users bring OpenAI's weights (a traced fp16 TorchScript archive like
ViT-B-32.pt, a torch.save state dict, a Hugging Face model.safetensors),
converts each with tools/convert_weights.py, embeds a test image with
`wiresketch embed --weights FILE IMAGE` and reports, per format, the largest
difference from PyTorch's float64 embedding relative to the embedding's
largest magnitude (target: 1e-4). The big files (about 1.5 GB in all) go to
--work (default /tmp/ws_full_size) and are deleted at the end unless --keep.
"""
import argparse
import os
import re
import shutil
import subprocess
import sys
import time

import torch

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import make_fixtures as mf  # noqa: E402  (the model and the writers of the fixture)

ARCH = dict(width=768, layers=12, heads=12, patch=32, resolution=224, output_dim=512)
NUMBER = re.compile(r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?")


def embed_with_wiresketch(wiresketch, weights, image, dim):
    """The last `dim` numbers `wiresketch embed` prints."""
    p = subprocess.run([wiresketch, "embed", "--weights", weights, image], capture_output=True, text=True)
    if p.returncode != 0:
        sys.exit(f"check_full_size.py: {wiresketch} embed failed ({p.returncode}): {p.stderr.strip()}")
    values = [float(v) for v in NUMBER.findall(p.stdout)]
    if len(values) < dim:
        sys.exit(f"check_full_size.py: {wiresketch} embed printed {len(values)} numbers, expected {dim}")
    return torch.tensor(values[-dim:], dtype=torch.float64)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--work", default="/tmp/ws_full_size")
    parser.add_argument("--wiresketch", default="build/wiresketch")
    parser.add_argument("--keep", action="store_true", help="keep the big files in --work")
    args = parser.parse_args()
    os.makedirs(os.path.join(args.work, "hf"), exist_ok=True)

    torch.manual_seed(1)
    model = mf.CLIP(**ARCH).eval()
    mf.randomise(model, 2)
    files = {  # OpenAI's head count is width / 64, the converter's default: no --heads
        "TorchScript (fp16)": os.path.join(args.work, "ViT-B-32.pt"),
        "state dict": os.path.join(args.work, "state_dict.pt"),
        "safetensors": os.path.join(args.work, "hf", "model.safetensors"),
    }
    t = time.time()
    mf.save_torchscript(model, files["TorchScript (fp16)"])
    torch.save(mf.openai_precision(model), files["state dict"])
    mf.save_safetensors(mf.hf_tensors(mf.openai_precision(model)), files["safetensors"])
    mf.save_hf_config(os.path.join(args.work, "hf", "config.json"), *ARCH.values())
    print(f"saved the three inputs in {time.time() - t:.1f} s")

    image_path = os.path.join(args.work, "image.png")
    u8 = mf.test_image(ARCH["resolution"], 13)
    mf.save_png(image_path, u8)
    with torch.no_grad():
        visual = model.visual.double()
        want = visual(mf.normalise((u8.float() / 255).unsqueeze(0).double()))[0]

    worst = 0.0
    for label, path in files.items():
        out = path + ".bin"
        t = time.time()
        p = subprocess.run([sys.executable, "tools/convert_weights.py", path, out], capture_output=True, text=True)
        if p.returncode != 0:
            sys.exit(f"check_full_size.py: converting {path} failed: {p.stderr.strip()}")
        seconds = time.time() - t
        got = embed_with_wiresketch(args.wiresketch, out, image_path, ARCH["output_dim"])
        err = ((got - want).abs().max() / want.abs().max()).item()
        worst = max(worst, err)
        print(f"{label:20s} converted in {seconds:5.1f} s ({os.path.getsize(out) / 1e6:.0f} MB); "
              f"embedding max error / max |e| = {err:.2e}")
        os.unlink(out)
    if not args.keep:
        shutil.rmtree(args.work)
    print(f"worst {worst:.2e} (target 1e-4): {'ok' if worst <= 1e-4 else 'TOO LARGE'}")
    return 0 if worst <= 1e-4 else 1


if __name__ == "__main__":
    sys.exit(main())
