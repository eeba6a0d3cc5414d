#!/usr/bin/env python3
"""test_convert.py: checks of tools/convert_weights.py (standard library only).

Run by tests/test_convert.c (python3 tools/test_convert.py from the repository
root). Builds small inputs by hand: PyTorch zip archives whose pickles are
written opcode by opcode (no torch needed), safetensors files, and hostile
variants of both; runs the converter on each and checks the exit status, the
exact message, and for the good inputs every value of the weight file it
wrote. Prints one line per check, "ok NAME" or "FAIL NAME: detail", and
exits non-zero when any check failed.
"""
import json
import os
import random
import struct
import subprocess
import sys
import tempfile
import zipfile
import zlib

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
CONVERTER = os.path.join(ROOT, "tools", "convert_weights.py")
failures = 0


def check(name, cond, detail=""):
    global failures
    if cond:
        print(f"ok {name}")
    else:
        failures += 1
        print(f"FAIL {name}: {detail}")


def convert(*args):
    p = subprocess.run([sys.executable, CONVERTER, *args], capture_output=True, text=True)
    return p.returncode, p.stdout.strip(), p.stderr.strip()


def expect_refusal(name, path, message, *extra):
    rc, _, err = convert(path, os.path.join(TMP, "refused.bin"), *extra)
    want = f"convert_weights.py: {path}: {message}"
    check(name, rc == 1 and err == want and not os.path.exists(os.path.join(TMP, "refused.bin")),
          f"exit {rc}, stderr\n  got  {err!r}\n  want {want!r}")


# ---- a tiny image tower: OpenAI name -> (shape, values) --------------------

W, LAYERS, PATCH, GRID, OUT = 8, 1, 2, 2, 3


def tower_shapes():
    names = [("conv1.weight", (W, 3, PATCH, PATCH)), ("class_embedding", (W,)),
             ("positional_embedding", (GRID * GRID + 1, W)), ("ln_pre.weight", (W,)), ("ln_pre.bias", (W,))]
    for i in range(LAYERS):
        p = f"transformer.resblocks.{i}."
        names += [(p + "ln_1.weight", (W,)), (p + "ln_1.bias", (W,)), (p + "attn.in_proj_weight", (3 * W, W)),
                  (p + "attn.in_proj_bias", (3 * W,)), (p + "attn.out_proj.weight", (W, W)),
                  (p + "attn.out_proj.bias", (W,)), (p + "ln_2.weight", (W,)), (p + "ln_2.bias", (W,)),
                  (p + "mlp.c_fc.weight", (4 * W, W)), (p + "mlp.c_fc.bias", (4 * W,)),
                  (p + "mlp.c_proj.weight", (W, 4 * W)), (p + "mlp.c_proj.bias", (W,))]
    return names + [("ln_post.weight", (W,)), ("ln_post.bias", (W,)), ("proj", (W, OUT))]


def numel(shape):
    n = 1
    for d in shape:
        n *= d
    return n


def make_tower(seed):
    """Values k/64, exact in f32, f16 and bf16, so every path must reproduce them bit for bit."""
    rng = random.Random(seed)
    return {name: (shape, [rng.randint(-128, 128) / 64 for _ in range(numel(shape))])
            for name, shape in tower_shapes()}


def pack(values, dtype):
    if dtype == "bf16":
        return b"".join(struct.pack("<f", v)[2:] for v in values)
    return struct.pack(f"<{len(values)}{ {'f32': 'f', 'f16': 'e'}[dtype]}", *values)


# ---- PyTorch zip archives, the pickle written by hand -----------------------

class Pickle:
    """Protocol-2 opcodes for a state dict of _rebuild_tensor_v2 tensors."""

    def __init__(self):
        self.b = bytearray(b"\x80\x02")

    def glob(self, module, name):
        self.b += b"c" + f"{module}\n{name}\n".encode()

    def string(self, s):
        data = s.encode()
        self.b += b"X" + struct.pack("<I", len(data)) + data

    def int_(self, v):
        self.b += b"J" + struct.pack("<i", v)

    def ints(self, values):
        self.b += b"("
        for v in values:
            self.int_(v)
        self.b += b"t"

    def ordered_dict(self):
        self.glob("collections", "OrderedDict")
        self.b += b")R"

    def tensor(self, storage_type, key, storage_numel, offset, size, stride):
        self.glob("torch._utils", "_rebuild_tensor_v2")
        self.b += b"(("
        self.string("storage")
        self.glob("torch", storage_type)
        self.string(key)
        self.string("cpu")
        self.int_(storage_numel)
        self.b += b"tQ"  # TUPLE, BINPERSID
        self.int_(offset)
        self.ints(size)
        self.ints(stride)
        self.b += b"\x89"  # NEWFALSE: requires_grad
        self.ordered_dict()
        self.b += b"tR"  # TUPLE, REDUCE


def write_torch_zip(path, pickle_bytes, storages, root="archive"):
    with zipfile.ZipFile(path, "w", zipfile.ZIP_STORED) as z:
        z.writestr(f"{root}/data.pkl", bytes(pickle_bytes))
        for key, data in storages.items():
            z.writestr(f"{root}/data/{key}", data)
        z.writestr(f"{root}/version", "3\n")


STORAGE_TYPE = {"f32": "FloatStorage", "f16": "HalfStorage"}


def write_state_dict(path, tower, prefix="visual.", drop=(), reshape=None, extra_text=True):
    """A torch.save-style state dict: most tensors contiguous, proj a transposed view,
    class_embedding at an offset inside a larger storage, linear weights f16."""
    p, storages = Pickle(), {}
    p.ordered_dict()
    p.b += b"("  # MARK for SETITEMS
    for i, (name, (shape, values)) in enumerate(tower.items()):
        if name in drop:
            continue
        shape = reshape.get(name, shape) if reshape else shape
        dtype = "f16" if name.endswith("weight") and not ".ln_" in "." + name else "f32"
        key = str(i)
        p.string(prefix + name)
        if name == "proj":  # stored as proj^T, read through strides
            rows, cols = shape
            t = [values[r * cols + c] for c in range(cols) for r in range(rows)]
            storages[key] = pack(t, dtype)
            p.tensor(STORAGE_TYPE[dtype], key, len(t), 0, shape, (1, rows))
        elif name == "class_embedding":
            storages[key] = pack([9.0, 9.0, 9.0] + values + [9.0], dtype)
            p.tensor(STORAGE_TYPE[dtype], key, len(values) + 4, 3, shape, (1,))
        else:
            storages[key] = pack(values, dtype)
            strides = [numel(shape[d + 1:]) for d in range(len(shape))]
            p.tensor(STORAGE_TYPE[dtype], key, numel(shape), 0, shape, strides)
    if extra_text:  # a text-tower tensor the converter must leave out
        p.string("token_embedding.weight")
        storages["text"] = pack([0.5] * 12, "f32")
        p.tensor("FloatStorage", "text", 12, 0, (4, 3), (3, 1))
    p.b += b"u."  # SETITEMS, STOP
    write_torch_zip(path, p.b, storages)


HF_BLOCK = {"ln_1": "layer_norm1", "attn.out_proj": "self_attn.out_proj", "ln_2": "layer_norm2",
            "mlp.c_fc": "mlp.fc1", "mlp.c_proj": "mlp.fc2"}


def write_safetensors(path, tower, dtype="bf16", extra=None, heads=2, act="quick_gelu", drop=()):
    named = {}
    for name, (shape, values) in tower.items():
        if name == "conv1.weight":
            named["vision_model.embeddings.patch_embedding.weight"] = (shape, values)
        elif name == "class_embedding":
            named["vision_model.embeddings.class_embedding"] = (shape, values)
        elif name == "positional_embedding":
            named["vision_model.embeddings.position_embedding.weight"] = (shape, values)
        elif name.startswith(("ln_pre.", "ln_post.")):
            hf = {"ln_pre": "pre_layrnorm", "ln_post": "post_layernorm"}[name.split(".")[0]]
            named[f"vision_model.{hf}.{name.split('.')[1]}"] = (shape, values)
        elif name == "proj":
            rows, cols = shape
            named["visual_projection.weight"] = ((cols, rows), [values[r * cols + c] for c in range(cols)
                                                                for r in range(rows)])
        else:
            i, _, rest = name[len("transformer.resblocks."):].partition(".")
            layer = f"vision_model.encoder.layers.{i}."
            if rest.startswith("attn.in_proj_"):
                kind = rest[len("attn.in_proj_"):]
                third = len(values) // 3
                part_shape = (shape[0] // 3,) + shape[1:]
                for j, letter in enumerate("qkv"):
                    named[f"{layer}self_attn.{letter}_proj.{kind}"] = (part_shape, values[j * third:(j + 1) * third])
            else:
                module, _, kind = rest.rpartition(".")
                named[f"{layer}{HF_BLOCK[module]}.{kind}"] = (shape, values)
    named["text_model.embeddings.token_embedding.weight"] = ((4, 3), [0.25] * 12)
    named.update(extra or {})
    for name in drop:
        del named[name]
    header, blobs, offset = {"__metadata__": {"format": "pt"}}, [], 0
    for name, (shape, values) in named.items():
        d = "f32" if name.startswith("text_model.") else dtype
        blob = pack(values, d)
        header[name] = {"dtype": {"f32": "F32", "f16": "F16", "bf16": "BF16"}[d], "shape": list(shape),
                        "data_offsets": [offset, offset + len(blob)]}
        blobs.append(blob)
        offset += len(blob)
    text = json.dumps(header).encode()
    with open(path, "wb") as f:
        f.write(struct.pack("<Q", len(text)) + text + b"".join(blobs))
    config = {"vision_config": {"hidden_size": W, "num_attention_heads": heads, "num_hidden_layers": LAYERS,
                                "patch_size": PATCH, "image_size": PATCH * GRID, "hidden_act": act}}
    with open(os.path.join(os.path.dirname(path), "config.json"), "w") as f:
        json.dump(config, f)


# ---- reading a weight file back ----------------------------------------------

def read_weight_file(path):
    data = open(path, "rb").read()
    if zlib.crc32(data[:-4]) != struct.unpack("<I", data[-4:])[0]:
        raise ValueError("bad checksum")
    magic, version, *arch, count = struct.unpack_from("<8sI6II", data, 0)
    tensors = []
    for i in range(count):
        name, dtype, ndim, *rest = struct.unpack_from("<64sII4QQQ", data, 40 + 120 * i)
        shape, offset, nbytes = tuple(rest[:ndim]), rest[4], rest[5]
        code, size = ("f", 4) if dtype == 0 else ("e", 2)
        values = list(struct.unpack_from(f"<{nbytes // size}{code}", data, offset))
        tensors.append((name.rstrip(b"\0").decode(), dtype, shape, offset, values))
    return magic, version, arch, tensors


def check_output(name, out, tower, dtype, heads):
    try:
        magic, version, arch, tensors = read_weight_file(out)
    except (OSError, ValueError, struct.error) as e:
        check(name, False, f"cannot read {out}: {e}")
        return
    want_arch = [W, LAYERS, heads, PATCH, PATCH * GRID, OUT]
    check(name + " header", magic == b"WSKCLIP\0" and version == 1 and arch == want_arch,
          f"{magic} {version} {arch}")
    expected = tower_shapes()
    names_ok = [t[0] for t in tensors] == [n for n, _ in expected]
    check(name + " tensor order", names_ok, [t[0] for t in tensors])
    bad = [t[0] for t in tensors if t[0] in tower and (t[2] != tower[t[0]][0] or t[4] != tower[t[0]][1]
                                                       or t[1] != dtype or t[3] % 64)]
    check(name + " values", names_ok and not bad, f"wrong: {bad}")


def main():
    global TMP
    with tempfile.TemporaryDirectory() as TMP:
        tower = make_tower(1)

        sd = os.path.join(TMP, "state_dict.pt")
        write_state_dict(sd, tower)
        out = os.path.join(TMP, "sd.bin")
        rc, msg, err = convert(sd, out, "--heads", "2")
        check("state dict converts", rc == 0 and msg.startswith(f"{out}: ViT width 8, 1 layers, 2 heads"),
              f"exit {rc}: {msg} {err}")
        check_output("state dict f32", out, tower, 0, 2)
        rc, _, err = convert(sd, out, "--heads", "2", "--dtype", "f16")
        check_output("state dict f16", out, tower, 1, 2)

        bare = os.path.join(TMP, "bare.pt")
        write_state_dict(bare, tower, prefix="", extra_text=False)
        rc, _, err = convert(bare, out, "--heads", "4")
        check("visual tower alone converts", rc == 0, err)
        check_output("visual tower alone", out, tower, 0, 4)

        hf_dir = os.path.join(TMP, "hf")
        os.mkdir(hf_dir)
        st = os.path.join(hf_dir, "model.safetensors")
        write_safetensors(st, tower)
        rc, _, err = convert(st, out)
        check("safetensors bf16 converts (heads from config.json)", rc == 0, err)
        check_output("safetensors bf16", out, tower, 0, 2)
        write_safetensors(st, tower, dtype="f16", heads=4)
        rc, _, err = convert(st, out, "--dtype", "f16")
        check_output("safetensors f16", out, tower, 1, 4)

        # ---- refusals ----
        junk = os.path.join(TMP, "junk.bin")
        with open(junk, "wb") as f:
            f.write(bytes(range(256)) * 4)
        expect_refusal("unknown format", junk, "unknown format (expected a TorchScript archive such as "
                       "ViT-B-32.pt, a torch.save state dict, or a model.safetensors)")
        with open(junk, "wb") as f:
            f.write(b"\x80\x02\x8a\x0a" + bytes(100))
        expect_refusal("legacy torch.save", junk,
                       "a legacy (pre-1.6) torch.save file; re-save it with a current PyTorch")
        expect_refusal("missing input", os.path.join(TMP, "nope.pt"), "no such file")

        marker = os.path.join(TMP, "pwned")
        for label, module in (("os.system", "os"), ("posix.system", "posix")):
            evil = os.path.join(TMP, "evil.pt")
            p = Pickle()
            p.glob(module, "system")
            p.string(f"touch {marker}")
            p.b += b"\x85R."  # TUPLE1, REDUCE, STOP
            write_torch_zip(evil, p.b, {})
            expect_refusal(f"pickle asking for {label}", evil,
                           f"the pickle asks for the global {module}.system, which no weight file needs; "
                           f"refusing to load it")
            check(f"{label} never ran", not os.path.exists(marker), "the marker file exists")

        p = Pickle()
        p.glob("builtins", "eval")
        p.string("1")
        p.b += b"\x85R."
        write_torch_zip(os.path.join(TMP, "evil2.pt"), p.b, {})
        expect_refusal("pickle asking for builtins.eval", os.path.join(TMP, "evil2.pt"),
                       "the pickle asks for the global builtins.eval, which no weight file needs; "
                       "refusing to load it")

        missing = os.path.join(TMP, "missing.pt")
        write_state_dict(missing, tower, drop=("ln_post.bias",))
        expect_refusal("missing key", missing, "tensor visual.ln_post.bias missing", "--heads", "2")
        write_state_dict(missing, tower, drop=("transformer.resblocks.0.attn.in_proj_weight",))
        expect_refusal("missing block", missing, "tensor visual.transformer.resblocks.0.attn.in_proj_weight "
                       "missing", "--heads", "2")
        shaped = os.path.join(TMP, "shaped.pt")
        write_state_dict(shaped, tower, reshape={"transformer.resblocks.0.mlp.c_fc.bias": (31,)})
        expect_refusal("mis-shaped tensor", shaped, "tensor visual.transformer.resblocks.0.mlp.c_fc.bias has "
                       "shape [31], expected [32]", "--heads", "2")
        expect_refusal("heads not inferable", sd, "cannot split width 8 into 0 heads; pass --heads N")
        expect_refusal("heads not dividing", sd, "cannot split width 8 into 3 heads; pass --heads N",
                       "--heads", "3")

        text_only = os.path.join(TMP, "text.pt")
        write_state_dict(text_only, {}, extra_text=True)
        expect_refusal("no image tower", text_only, "no image tower in it (no visual.* keys, no conv1.weight)")

        resnet = dict(tower)
        resnet["layer1.0.conv1.weight"] = ((2, 2), [0.0] * 4)
        write_state_dict(os.path.join(TMP, "rn.pt"), resnet)
        expect_refusal("ResNet tower", os.path.join(TMP, "rn.pt"),
                       "a ResNet image tower (RN50 and the like); only ViT models are supported")

        extra = dict(tower)
        extra["transformer.resblocks.0.ls_1.gamma"] = ((W,), [1.0] * W)
        write_state_dict(os.path.join(TMP, "extra.pt"), extra)
        expect_refusal("unexpected tensor", os.path.join(TMP, "extra.pt"),
                       "unexpected tensor visual.transformer.resblocks.0.ls_1.gamma (not a CLIP ViT image "
                       "tower?)", "--heads", "2")

        p = Pickle()
        p.ordered_dict()
        p.b += b"("
        p.string("visual.conv1.weight")
        p.tensor("FloatStorage", "0", 4, 2, (3,), (1,))  # elements 2..4 of a 4-element storage
        p.b += b"u."
        write_torch_zip(os.path.join(TMP, "past.pt"), p.b, {"0": pack([0.0] * 4, "f32")})
        expect_refusal("tensor past its storage", os.path.join(TMP, "past.pt"),
                       "a tensor reaches past its storage 0")

        big = dict(tower)
        big["ln_pre.bias"] = ((W,), [1e6] * W)
        write_state_dict(os.path.join(TMP, "big.pt"), big)
        expect_refusal("f16 overflow", os.path.join(TMP, "big.pt"),
                       "tensor visual.ln_pre.bias has values outside the f16 range; use --dtype f32",
                       "--heads", "2", "--dtype", "f16")

        write_safetensors(st, tower, act="gelu")
        expect_refusal("HF gelu model", st, f"{os.path.join(hf_dir, 'config.json')} says hidden_act gelu; "
                       "wiresketch implements OpenAI's quick_gelu only")
        write_safetensors(st, tower, extra={"vision_model.encoder.layers.0.self_attn.extra": ((1,), [0.0])})
        expect_refusal("HF unexpected tensor", st, "unexpected tensor vision_model.encoder.layers.0.self_attn."
                       "extra (not a CLIP ViT image tower?)")
        write_safetensors(st, tower, drop=("vision_model.encoder.layers.0.self_attn.v_proj.weight",))
        expect_refusal("HF missing v_proj", st, "tensor vision_model.encoder.layers.0.self_attn.v_proj.weight "
                       "missing")
        write_safetensors(st, tower, drop=("vision_model.post_layernorm.bias",))
        expect_refusal("HF missing key", st, "tensor vision_model.post_layernorm.bias missing")
        write_safetensors(st, tower)
        with open(st, "r+b") as f:
            f.truncate(os.path.getsize(st) - 10)
        expect_refusal("HF truncated data", st, "safetensors entry text_model.embeddings.token_embedding.weight "
                       "has bad data offsets")
    print(f"{failures} checks failed" if failures else "all checks passed")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
