#!/usr/bin/env python3
"""test_convert.py: checks of tools/convert_weights.py (standard library only).

Run by tests/test_convert.c (python3 tools/test_convert.py from the repository
root). Builds small inputs by hand: PyTorch zip archives whose pickles are
written opcode by opcode (no torch needed), safetensors files, and hostile
variants of both (deep nesting, a zip bomb, stride-0 views, damaged members,
malformed JSON fields, NaN, FIFOs, an output onto the input, signals); runs
the converter on each and checks the exit status, the exact one-line
message, and for the good inputs every value of the weight file it wrote. Prints one line per check, "ok NAME" or "FAIL NAME: detail", and
exits non-zero when any check failed.
"""
import hashlib
import json
import os
import random
import signal
import stat
import struct
import subprocess
import sys
import tempfile
import time
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
    """(exit status, stdout, stderr); status None when the converter blocked for 60 s."""
    try:
        p = subprocess.run([sys.executable, CONVERTER, *args], capture_output=True, text=True, timeout=60)
    except subprocess.TimeoutExpired:
        return None, "", "(blocked for 60 s)"
    return p.returncode, p.stdout.strip(), p.stderr.strip()


def expect_failure(name, args, where, message, absent=None):
    """The converter run on args exits 1 with the one line "convert_weights.py: where: message"
    and leaves no file at absent."""
    if absent and os.path.exists(absent):
        os.unlink(absent)
    rc, _, err = convert(*args)
    want = f"convert_weights.py: {where}: {message}"
    wrote = bool(absent) and os.path.exists(absent)
    check(name, rc == 1 and err == want and not wrote,
          f"exit {rc}, stderr\n  got  {err!r}\n  want {want!r}" + (f"\n  and {absent} written" if wrote else ""))


def expect_refusal(name, path, message, *extra):
    out = os.path.join(TMP, "refused.bin")
    expect_failure(name, (path, out, *extra), path, message, absent=out)


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
        if -2 ** 31 <= v < 2 ** 31:
            self.b += b"J" + struct.pack("<i", v)  # BININT
        else:
            data = v.to_bytes(v.bit_length() // 8 + 1, "little", signed=True)
            self.b += b"\x8a" + bytes([len(data)]) + data  # LONG1

    def ints(self, values):
        self.b += b"("
        for v in values:
            self.int_(v)
        self.b += b"t"

    def ordered_dict(self):
        self.glob("collections", "OrderedDict")
        self.b += b")R"

    def build(self, key, value):
        """BUILD on the object on top of the stack with the state {key: value} (value: str,
        int or None)."""
        self.b += b"}"
        self.string(key)
        if value is None:
            self.b += b"N"
        elif isinstance(value, str):
            self.string(value)
        else:
            self.int_(value)
        self.b += b"sb"  # SETITEM, BUILD

    def tensor(self, storage_type, key, storage_numel, offset, size, stride, rewrite=None):
        """rewrite: (record, key, value): BUILD on the record ("type", "storage" or "tensor")
        right after it is made."""
        self.glob("torch._utils", "_rebuild_tensor_v2")
        self.b += b"(("
        self.string("storage")
        self.glob("torch", storage_type)
        if rewrite and rewrite[0] == "type":
            self.build(*rewrite[1:])
        self.string(key)
        self.string("cpu")
        self.int_(storage_numel)
        self.b += b"tQ"  # TUPLE, BINPERSID
        if rewrite and rewrite[0] == "storage":
            self.build(*rewrite[1:])
        self.int_(offset)
        self.ints(size)
        self.ints(stride)
        self.b += b"\x89"  # NEWFALSE: requires_grad
        self.ordered_dict()
        self.b += b"tR"  # TUPLE, REDUCE
        if rewrite and rewrite[0] == "tensor":
            self.build(*rewrite[1:])


def write_torch_zip(path, pickle_bytes, storages, root="archive", compression=zipfile.ZIP_STORED):
    with zipfile.ZipFile(path, "w", compression) as z:
        z.writestr(f"{root}/data.pkl", bytes(pickle_bytes))
        for key, data in storages.items():
            z.writestr(f"{root}/data/{key}", data)
        z.writestr(f"{root}/version", "3\n")


STORAGE_TYPE = {"f32": "FloatStorage", "f16": "HalfStorage"}


def write_state_dict(path, tower, prefix="visual.", drop=(), reshape=None, extra_text=True, override=None,
                     compression=zipfile.ZIP_STORED):
    """A torch.save-style state dict: most tensors contiguous, proj a transposed view,
    class_embedding at an offset inside a larger storage, linear weights f16. override maps
    a name to (storage key, member bytes or None for no member, storage numel, offset, stride)."""
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
        if override and name in override:
            key, data, storage_numel, offset, stride = override[name]
            if data is not None:
                storages[key] = data
            p.tensor(STORAGE_TYPE[dtype], key, storage_numel, offset, shape, stride)
        elif name == "proj":  # stored as proj^T, read through strides
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
    write_torch_zip(path, p.b, storages, compression=compression)


def write_raw_zip(path, members):
    """A zip written field by field, so a member's bytes, sizes and CRC can be anything:
    members are (name, method, payload, crc, uncompressed size)."""
    local, central = bytearray(), bytearray()
    for name, method, payload, crc, size in members:
        n = name.encode()
        central += struct.pack("<IHHHHHHIIIHHHHHII", 0x02014B50, 20, 20, 0, method, 0, 0x21, crc,
                               len(payload), size, len(n), 0, 0, 0, 0, 0, len(local)) + n
        local += struct.pack("<IHHHHHIIIHH", 0x04034B50, 20, 0, method, 0, 0x21, crc, len(payload),
                             size, len(n), 0) + n + payload
    end = struct.pack("<IHHHHIIH", 0x06054B50, 0, 0, len(members), len(members), len(central),
                      len(local), 0)
    with open(path, "wb") as f:
        f.write(local + central + end)


def zip_bomb(path, tower, gib=3):
    """A state dict whose conv1.weight (192 bytes) sits in a storage of gib GiB of zeros,
    deflated to about a megabyte a GiB: a valid archive, CRC included."""
    size = gib << 30
    write_state_dict(path, tower, override={"conv1.weight": ("0", b"", size // 2, 0, (12, 4, 2, 1))})
    zeros, co = bytes(1 << 20), zlib.compressobj(9, zlib.DEFLATED, -15)
    first = co.compress(zeros) + co.flush(zlib.Z_FULL_FLUSH)
    rest = co.compress(zeros) + co.flush(zlib.Z_FULL_FLUSH)  # after a full flush every MiB deflates alike
    stream, crc = first + rest * ((size >> 20) - 1) + co.flush(), 0
    for _ in range(size >> 20):
        crc = zlib.crc32(zeros, crc)
    with zipfile.ZipFile(path) as z:
        members = [(i.filename, 0, z.read(i), zlib.crc32(z.read(i)), i.file_size) for i in z.infolist()]
    write_raw_zip(path, [(n, 8, stream, crc, size) if n == "archive/data/0" else (n, m, d, c, s)
                         for n, m, d, c, s in members])


HF_BLOCK = {"ln_1": "layer_norm1", "attn.out_proj": "self_attn.out_proj", "ln_2": "layer_norm2",
            "mlp.c_fc": "mlp.fc1", "mlp.c_proj": "mlp.fc2"}


def write_safetensors(path, tower, dtype="bf16", extra=None, heads=2, act="quick_gelu", drop=(), edit=None):
    """A model.safetensors and its config.json; edit(header) may change the header dict."""
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
    if edit:
        edit(header)
    text = json.dumps(header).encode()
    with open(path, "wb") as f:
        f.write(struct.pack("<Q", len(text)) + text + b"".join(blobs))
    config = {"vision_config": {"hidden_size": W, "num_attention_heads": heads, "num_hidden_layers": LAYERS,
                                "patch_size": PATCH, "image_size": PATCH * GRID, "hidden_act": act}}
    with open(os.path.join(os.path.dirname(path), "config.json"), "w") as f:
        json.dump(config, f)


def write_raw_safetensors(path, text, data=b""):
    with open(path, "wb") as f:
        f.write(struct.pack("<Q", len(text)) + text + data)


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


def hostile_json(tower, hf_dir, st):
    """Safetensors headers and config.json: nesting, duplicate keys, non-integer fields, shared
    bytes, NaN, and the bounds on header size and tensor count."""
    config = os.path.join(hf_dir, "config.json")
    deep = b'{"a": ' + b"[" * 100000 + b"]" * 100000 + b"}"
    write_raw_safetensors(st, deep)
    expect_refusal("safetensors header nested 100 000 deep", st, "safetensors header nests deeper than 64 levels")

    write_safetensors(st, tower)
    with open(config, "wb") as f:
        f.write(b'{"vision_config": ' + b"[" * 100000 + b"]" * 100000 + b"}")
    expect_refusal("config.json nested 100 000 deep", st, f"{config} nests deeper than 64 levels")
    with open(config, "w") as f:
        f.write('{"vision_config": {"num_attention_heads": 2, "num_attention_heads": 4}}')
    expect_refusal("config.json duplicate key", st, f"{config} has the key num_attention_heads twice")
    with open(config, "w") as f:
        json.dump({"vision_config": {"num_attention_heads": True}}, f)
    expect_refusal("config.json num_attention_heads true", st,
                   f"{config} says num_attention_heads true, not an integer")
    with open(config, "w") as f:
        json.dump({"vision_config": {"hidden_size": 8.0}}, f)
    expect_refusal("config.json hidden_size 8.0", st, f"{config} says hidden_size 8.0, not an integer")
    with open(config, "w") as f:
        f.write('{"vision_config": {}}' + " " * (1 << 20))
    expect_refusal("config.json past 1 MiB", st, f"cannot read {config} ({(1 << 20) + 21} bytes; a CLIP config.json "
                   f"has a few thousand)")

    write_safetensors(st, tower)
    with open(st, "rb") as f:
        n = struct.unpack("<Q", f.read(8))[0]
        text, data = f.read(n), f.read()
    ln = "vision_model.pre_layrnorm.weight"
    entry = json.dumps(json.loads(text)[ln]).encode()
    write_raw_safetensors(st, b'{"' + ln.encode() + b'": ' + entry + b", " + text[1:], data)
    expect_refusal("safetensors duplicate key", st, f"safetensors header has the key {ln} twice")

    for label, shape, shown in (("[64.9]", [64.9], "[64.9]"), ('["64"]', ["64"], '["64"]'),
                                ("[true]", [True], "[true]")):
        write_safetensors(st, tower, edit=lambda h: h[ln].update(shape=shape))
        expect_refusal(f"safetensors shape {label}", st,
                       f"safetensors entry {ln} has shape {shown}, not a list of integers >= 0")
    write_safetensors(st, tower, edit=lambda h: h[ln].update(data_offsets=[0, True]))
    expect_refusal("safetensors data_offsets [0, true]", st,
                   f"safetensors entry {ln} has data_offsets [0, true], not two integers >= 0")

    bias = "vision_model.pre_layrnorm.bias"
    write_safetensors(st, tower, edit=lambda h: h[bias].update(data_offsets=h[ln]["data_offsets"]))
    expect_refusal("safetensors shared data_offsets", st,  # equal offsets: named in sorted order
                   f"safetensors entries {min(ln, bias)} and {max(ln, bias)} share bytes (their data_offsets "
                   f"overlap)")

    def overlap(h):
        begin, end = h[ln]["data_offsets"]
        h[bias]["data_offsets"] = [begin + 2, end + 2]
    write_safetensors(st, tower, edit=overlap)
    expect_refusal("safetensors overlapping data_offsets", st,
                   f"safetensors entries {ln} and {bias} share bytes (their data_offsets overlap)")

    inf = dict(tower)
    inf["ln_pre.bias"] = ((W,), [1.0] * (W - 1) + [float("-inf")])
    write_safetensors(st, inf)
    expect_refusal("safetensors -Inf", st, f"tensor {bias} has NaN or Inf values")

    with open(st, "wb") as f:  # a sparse file: the header length is refused before reading
        f.write(struct.pack("<Q", 256 * 131104 + 1) + b"{")
        f.truncate(8 + 256 * 131104 + 1)
    expect_refusal("safetensors header past 32 MiB", st,
                   f"safetensors header of {256 * 131104 + 1} bytes; a CLIP model's takes less than "
                   f"{256 * 131104}")
    write_raw_safetensors(st, ("{" + ", ".join(f'"{i}": 0' for i in range(131105)) + "}").encode())
    expect_refusal("safetensors with 131 105 tensors", st,
                   "safetensors header lists 131105 tensors; no CLIP model has more than 131104")
    write_safetensors(st, tower)


def hostile_archives(tower):
    """PyTorch archives: deep module nesting, a memo bomb, a damaged member, stride-0 views, a
    zip bomb, shared storages, NaN and Inf, too many tensors, an oversized data.pkl, an
    architecture the loader refuses; and a deflated archive that must still convert."""
    path, out = os.path.join(TMP, "hostile.pt"), os.path.join(TMP, "hostile.bin")
    n = 5000
    write_torch_zip(path, b"\x80\x02" + b"c__torch__\nM\n)\x81}X\x01\x00\x00\x00a" * n + b"N" + b"sb" * n + b".", {})
    expect_refusal("TorchScript modules nested 5 000 deep", path, "TorchScript modules nested more than 64 deep")

    write_torch_zip(path, b"\x80\x02Nr\xff\xff\xff\x7f.", {})  # LONG_BINPUT 2^31 - 1
    expect_refusal("pickle memo index 2^31", path, "malformed data.pkl (memo index 2147483647 in a pickle of 9 bytes)")

    write_state_dict(path, tower)
    with zipfile.ZipFile(path) as z:
        info = z.getinfo("archive/data/5")
    with open(path, "r+b") as f:
        f.seek(info.header_offset + 30 + len(info.filename) + 1)
        byte = f.read(1)
        f.seek(-1, 1)
        f.write(bytes([byte[0] ^ 0x40]))
    expect_refusal("one flipped byte in a storage", path, "archive member archive/data/5 is damaged (Bad CRC-32 for "
                   "file 'archive/data/5')", "--heads", "2")

    write_state_dict(path, tower, override={"conv1.weight": ("0", pack([0.5], "f16"), 1, 0, (0, 0, 0, 0))})
    expect_refusal("stride-0 view", path, "tensor visual.conv1.weight is not a dense block of its storage (a stride-0, "
                   "overlapping or gapped view)", "--heads", "2")

    zip_bomb(path, tower)
    rc, _, err = convert(path, out, "--heads", "2")
    want = (f"convert_weights.py: {path}: storage archive/data/0 has {3 << 30} bytes, tensor visual.conv1.weight "
            f"uses 192; refusing to inflate the rest")
    check(f"zip bomb ({os.path.getsize(path) >> 20} MB, a 3 GiB storage)", rc == 1 and err == want,
          f"exit {rc}, stderr\n  got  {err!r}\n  want {want!r}")

    write_state_dict(path, tower, override={"ln_pre.bias": ("3", None, W, 0, (1,))})
    expect_refusal("two tensors sharing a storage", path, "tensors visual.ln_pre.weight and visual.ln_pre.bias share "
                   "storage archive/data/3", "--heads", "2")

    bad = dict(tower)
    bad["ln_pre.bias"] = ((W,), [float("nan")] + [0.0] * (W - 1))
    write_state_dict(path, bad)
    expect_refusal("NaN in an f32 tensor", path, "tensor visual.ln_pre.bias has NaN or Inf values", "--heads", "2")
    bad = dict(tower)
    shape, values = tower["conv1.weight"]
    bad["conv1.weight"] = (shape, values[:-1] + [float("inf")])
    write_state_dict(path, bad)
    expect_refusal("Inf in an f16 tensor", path, "tensor visual.conv1.weight has NaN or Inf values", "--heads", "2")

    p = Pickle()
    p.ordered_dict()
    p.b += b"("
    p.string("visual.conv1.weight")
    p.tensor("FloatStorage", "0", 1, 0, (1,), (1,))
    p.b += b"q\x00"  # BINPUT 0: the same tensor under 131 105 names
    for i in range(131104):
        p.string(f"t{i}")
        p.b += b"h\x00"  # BINGET 0
    p.b += b"u."
    write_torch_zip(path, p.b, {"0": pack([0.0], "f32")})
    expect_refusal("state dict with 131 105 tensors", path, "more than 131104 tensors; no CLIP model has so many")

    limit = 256 * 131104
    with zipfile.ZipFile(path, "w", zipfile.ZIP_DEFLATED) as z:
        z.writestr("archive/data.pkl", bytes(limit + 1))
    expect_refusal("data.pkl past 32 MiB", path, f"archive member archive/data.pkl has {limit + 1} bytes, more than "
                   f"the {limit} a CLIP model needs")

    wide, p = 65537, Pickle()  # storages declared, never read: the architecture is refused first
    p.ordered_dict()
    p.b += b"("
    for i, (name, shape) in enumerate((("conv1.weight", (wide, 3, 1, 1)), ("positional_embedding", (2, wide)),
                                       ("proj", (wide, 1)),
                                       ("transformer.resblocks.0.attn.in_proj_weight", (3 * wide, wide)))):
        p.string("visual." + name)
        p.tensor("FloatStorage", str(i), numel(shape), 0, shape, [numel(shape[d + 1:]) for d in range(len(shape))])
    p.b += b"u."
    write_torch_zip(path, p.b, {})
    expect_refusal("width past the loader's limit", path, "width 65537, 1 layers, resolution 1, output 1: beyond what "
                   "wiresketch loads (width and output 65536, 4096 layers, resolution 16384)", "--heads", "1")

    write_state_dict(path, tower, compression=zipfile.ZIP_DEFLATED)
    rc, _, err = convert(path, out, "--heads", "2")
    check("deflated state dict converts", rc == 0, err)
    check_output("deflated state dict", out, tower, 0, 2)


def rewritten_records(tower):
    """BUILD on the records the Unpickler checked (the converter's own objects) would rewrite
    them: a negative offset converted into a corrupt file (exit 0), a storage of None, of an
    integer dtype or a size "64" ended in tracebacks. Each is refused in one line."""
    path = os.path.join(TMP, "rewritten.pt")
    for record, key, value in (("tensor", "offset", -4), ("tensor", "storage", None), ("tensor", "size", "64"),
                               ("storage", "dtype", "i64"), ("storage", "numel", 10 ** 9),
                               ("type", "dtype", "bf16")):
        p = Pickle()
        p.ordered_dict()
        p.b += b"("
        p.string("visual.conv1.weight")
        p.tensor("FloatStorage", "0", 4, 0, (4,), (1,), rewrite=(record, key, value))
        p.b += b"u."
        write_torch_zip(path, p.b, {"0": pack([0.5] * 4, "f32")})
        what = {"type": "storage type"}.get(record, record)
        expect_refusal(f"BUILD rewriting a {what}'s {key}", path, f"malformed data.pkl (it rewrites a {what} "
                       f"record: BUILD)")


def huge_shapes(tower, st):
    """A shape of 2 million dimensions (a 10 MB data.pkl; 6 MB of safetensors header): refused
    by its dimension count in seconds, before any product of it is taken (each product of
    millions of factors is a bigger integer than the last: minutes)."""
    path = os.path.join(TMP, "dims.pt")
    p = Pickle()
    p.ordered_dict()
    p.b += b"("
    p.string("visual.conv1.weight")
    p.tensor("FloatStorage", "0", 4, 0, (2,) * 2000000, (1,) * 2000000)
    p.b += b"u."
    write_torch_zip(path, p.b, {"0": pack([0.5] * 4, "f32")})
    start = time.monotonic()
    expect_refusal("a pickled shape of 2 000 000 dimensions", path, "a tensor size of 2000000 dimensions in the "
                   "pickle; no CLIP tensor has more than 8")
    seconds = time.monotonic() - start
    ln = "vision_model.pre_layrnorm.weight"
    write_safetensors(st, tower, edit=lambda h: h[ln].update(shape=[2] * 2000000))
    start = time.monotonic()
    expect_refusal("a safetensors shape of 2 000 000 dimensions", st, f"safetensors entry {ln} has 2000000 "
                   f"dimensions; no CLIP tensor has more than 8")
    print(f"  (refused in {seconds:.1f} s and {time.monotonic() - start:.1f} s)")
    write_safetensors(st, tower)


def out_of_memory(sd):
    """Under a memory limit (ulimit -v) too low for a valid 30 MB data.pkl (a long string
    beside the tensors): one line, not a traceback, and no false "malformed"."""
    import resource
    path, out = os.path.join(TMP, "memory.pt"), os.path.join(TMP, "memory.bin")
    with zipfile.ZipFile(sd) as z:
        members = {i.filename: z.read(i) for i in z.infolist()}
    p = members["archive/data.pkl"]
    text = b"x" * (30 << 20)
    # before SETITEMS, STOP: one more item, "notes": the text
    members["archive/data.pkl"] = (p[:-2] + b"X" + struct.pack("<I", 5) + b"notes" + b"X" + struct.pack("<I", len(text))
                                   + text + b"u.")
    with zipfile.ZipFile(path, "w") as z:
        for name, data in members.items():
            z.writestr(name, data)
    limit = 100 << 20
    proc = subprocess.run([sys.executable, CONVERTER, path, out, "--heads", "2"], capture_output=True, text=True,
                          timeout=60, preexec_fn=lambda: resource.setrlimit(resource.RLIMIT_AS, (limit, limit)))
    want = f"convert_weights.py: {path}: out of memory converting it (a limit such as ulimit -v is too low)"
    check("out of memory under ulimit -v", proc.returncode == 1 and proc.stderr.strip() == want
          and not os.path.exists(out), f"exit {proc.returncode}, stderr {proc.stderr.strip()[-300:]!r}")
    rc, _, err = convert(path, out, "--heads", "2")
    check("the same file converts without the limit", rc == 0, err)


def standard_output(sd):
    """The success line into a full disk, a closed stdout, a pipe whose reader is gone: one
    line and exit 1, not a traceback (OUT is written: the line is what failed)."""
    out = os.path.join(TMP, "stdout.bin")
    cmd = [sys.executable, CONVERTER, sd, out, "--heads", "2"]
    with open("/dev/full", "w") as full:
        p = subprocess.run(cmd, stdout=full, stderr=subprocess.PIPE, text=True, timeout=60)
    cases = [("stdout into /dev/full", p, "No space left on device")]
    p = subprocess.run(cmd, stderr=subprocess.PIPE, text=True, timeout=60, preexec_fn=lambda: os.close(1))
    cases.append(("stdout closed", p, "Bad file descriptor"))
    r, w = os.pipe()
    os.close(r)
    p = subprocess.run(cmd, stdout=w, stderr=subprocess.PIPE, text=True, timeout=60)
    os.close(w)
    cases.append(("stdout a pipe whose reader is gone", p, "Broken pipe"))
    for name, p, why in cases:
        want = f"convert_weights.py: standard output: write failed: {why}"
        check(name, p.returncode == 1 and p.stderr.strip() == want, f"exit {p.returncode}, stderr {p.stderr!r}")


def signalled(name, signum, src, out):
    """The converter, held after its first tensor by a stand-in for tensor_chunks, gets signum
    once OUT.tmp.PID exists: one line naming OUT, exit 1, no temporary file left."""
    stub = ("import sys, time\nsys.path.insert(0, sys.argv[1])\nimport convert_weights as cw\n"
            "real = cw.tensor_chunks\n"
            "def held(*args):\n    yield from real(*args)\n    time.sleep(60)\n"
            "cw.tensor_chunks = held\nsys.exit(cw.main(sys.argv[2:]))\n")
    proc = subprocess.Popen([sys.executable, "-c", stub, os.path.dirname(CONVERTER), src, out, "--heads", "2"],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    tmp, deadline = f"{out}.tmp.{proc.pid}", time.monotonic() + 20
    while not os.path.exists(tmp) and proc.poll() is None and time.monotonic() < deadline:
        time.sleep(0.01)
    proc.send_signal(signum)
    try:
        _, err = proc.communicate(timeout=20)
    except subprocess.TimeoutExpired:
        proc.kill()
        _, err = proc.communicate()
    want = f"convert_weights.py: {out}: interrupted by {signal.Signals(signum).name}; not written"
    check(name, proc.returncode == 1 and err.strip() == want and not os.path.exists(tmp) and not os.path.exists(out),
          f"exit {proc.returncode}, stderr {err.strip()!r}, want {want!r}; {tmp} left: {os.path.exists(tmp)}")


def digest(path):
    with open(path, "rb") as f:
        return hashlib.sha256(f.read()).hexdigest()


def hostile_paths(tower, sd, hf_dir, st):
    """Inputs that are not regular files, an output onto the input, output errors, signals."""
    out = os.path.join(TMP, "paths.bin")
    expect_refusal("a directory as input", hf_dir, "is a directory")
    fifo = os.path.join(TMP, "fifo.pt")
    os.mkfifo(fifo)
    expect_refusal("a FIFO as input (refused without blocking)", fifo, "not a regular file")
    config = os.path.join(hf_dir, "config.json")
    os.unlink(config)
    os.mkfifo(config)
    expect_refusal("a FIFO as config.json", st, f"cannot read {config} (not a regular file)")
    os.unlink(config)
    os.mkdir(config)
    expect_refusal("a directory as config.json", st, f"cannot read {config} (is a directory)")
    os.rmdir(config)
    write_safetensors(st, tower)

    before = digest(sd)
    link, hard = os.path.join(TMP, "link.pt"), os.path.join(TMP, "hard.pt")
    os.symlink(sd, link)
    os.link(sd, hard)
    for label, target in (("the same path", sd), ("a symbolic link to it", link), ("a hard link to it", hard)):
        expect_failure(f"OUT is IN: {label}", (sd, target, "--heads", "2"), sd,
                       f"the same file as {target}; refusing to overwrite the model with its conversion")
    check("OUT is IN: the model is intact", digest(sd) == before, "the input changed")

    missing_dir = os.path.join(TMP, "no such dir", "out.bin")
    expect_failure("an unwritable OUT is named, not OUT.tmp.PID", (sd, missing_dir, "--heads", "2"), missing_dir,
                   "cannot write (No such file or directory)")
    out_dir = os.path.join(TMP, "out_dir")
    os.mkdir(out_dir)
    expect_failure("a directory as OUT", (sd, out_dir, "--heads", "2"), out_dir, "is a directory")

    # a special OUT is written through, never replaced; a link planted at OUT.tmp.PID is not followed
    fifo_out, got = os.path.join(TMP, "out_fifo"), []
    os.mkfifo(fifo_out)
    reader = subprocess.Popen(["timeout", "60", "cat", fifo_out], stdout=subprocess.PIPE)
    rc, _, err = convert(sd, fifo_out, "--heads", "2")
    got = reader.communicate()[0]
    check("a FIFO as OUT is written through", rc == 0 and stat.S_ISFIFO(os.lstat(fifo_out).st_mode) and
          got[:8] == b"WSKCLIP\0", f"exit {rc}: {err}")
    device = os.path.join(TMP, "null_copy")
    try:
        os.mknod(device, stat.S_IFCHR | 0o666, os.makedev(1, 3))  # a copy of /dev/null, as root
    except OSError:
        device = "/dev/null"  # without root, which cannot replace it
    rc, _, err = convert(sd, device, "--heads", "2")
    check("a character device as OUT stays one", rc == 0 and stat.S_ISCHR(os.lstat(device).st_mode), err)
    victim, planted = os.path.join(TMP, "victim.txt"), os.path.join(TMP, "planted.bin")
    with open(victim, "w") as f:
        f.write("precious")
    p = subprocess.run([sys.executable, CONVERTER, sd, planted, "--heads", "2"], capture_output=True, text=True,
                       timeout=60, preexec_fn=lambda: os.symlink(victim, f"{planted}.tmp.{os.getpid()}"))
    with open(victim, "rb") as f:
        kept = f.read() == b"precious"
    check("a link planted at OUT.tmp.PID is not written through", p.returncode == 1 and kept and
          p.stderr.strip() == f"convert_weights.py: {planted}: cannot write (File exists)",
          f"exit {p.returncode}, victim kept {kept}: {p.stderr.strip()}")

    signalled("SIGTERM removes OUT.tmp.PID", signal.SIGTERM, sd, out)
    signalled("SIGINT removes OUT.tmp.PID", signal.SIGINT, sd, out)
    signalled("SIGHUP removes OUT.tmp.PID", signal.SIGHUP, sd, out)
    signalled("SIGXCPU removes OUT.tmp.PID", signal.SIGXCPU, sd, out)


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
        hostile_json(tower, hf_dir, st)
        hostile_archives(tower)
        hostile_paths(tower, sd, hf_dir, st)
        rewritten_records(tower)
        huge_shapes(tower, st)
        out_of_memory(sd)
        standard_output(sd)
    print(f"{failures} checks failed" if failures else "all checks passed")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
