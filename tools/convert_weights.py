#!/usr/bin/env python3
"""convert_weights.py: a CLIP ViT image tower -> wiresketch weight file.

usage: python3 tools/convert_weights.py IN OUT [--dtype f32|f16] [--heads N]

IN is one of
  * OpenAI's released TorchScript archive (ViT-B-32.pt, fp16),
  * a torch.save state dict in PyTorch's zip format (keys visual.*, with or
    without the text tower beside them, or the image tower alone),
  * a Hugging Face model.safetensors (vision_model.* and visual_projection.*;
    config.json beside it, when present, gives the head count).
OUT is written in the flat format of weights/README.md (image tower only).

Python 3 standard library only. Pickles are read with an Unpickler that
knows a handful of names (the tensor rebuild functions, storage types,
OrderedDict, TorchScript module classes as inert records) and refuses every
other global: it never imports or runs anything a file asks for.

Every failure prints one line "convert_weights.py: IN: what is wrong" on
stderr and exits with status 1.
"""
import argparse
import array
import collections
import io
import json
import math
import os
import pickle
import struct
import sys
import zipfile
import zlib

MAGIC = b"WSKCLIP\0"
VERSION = 1
HEADER = struct.Struct("<8sI6II")          # magic, version, architecture, tensor count
ENTRY = struct.Struct("<64sII4QQQ")        # name, dtype, ndim, shape, offset, nbytes
ALIGN = 64
OUT_DTYPES = {"f32": 0, "f16": 1}

# element size and struct code of every dtype a visual tensor may have
ELEMENT = {"f32": (4, "f"), "f16": (2, "e"), "bf16": (2, None), "f64": (8, "d")}
# torch storage classes: only the floating ones can hold weights; the rest
# (e.g. LongStorage for OpenAI's input_resolution) are read as inert records
STORAGE_DTYPES = {
    "FloatStorage": "f32", "HalfStorage": "f16", "BFloat16Storage": "bf16", "DoubleStorage": "f64",
    "LongStorage": "i64", "IntStorage": "i32", "ShortStorage": "i16", "CharStorage": "i8",
    "ByteStorage": "u8", "BoolStorage": "bool",
}
STORAGE_ELEMENT = {"f32": 4, "f16": 2, "bf16": 2, "f64": 8, "i64": 8, "i32": 4, "i16": 2, "i8": 1,
                   "u8": 1, "bool": 1}
SAFETENSORS_DTYPES = {"F32": "f32", "F16": "f16", "BF16": "bf16", "F64": "f64", "I64": "i64",
                      "I32": "i32", "I16": "i16", "I8": "i8", "U8": "u8", "BOOL": "bool"}


class ConvertError(Exception):
    pass


# --------------------------------------------------------------------------
# Tensors: a dtype, a shape and a way to get its contiguous little-endian bytes

class Tensor:
    def __init__(self, dtype, shape, read):
        self.dtype, self.shape, self.read = dtype, tuple(shape), read

    def numel(self):
        n = 1
        for d in self.shape:
            n *= d
        return n


def encode(tensor, out_dtype, name):
    """The tensor's values as contiguous little-endian bytes of out_dtype."""
    if tensor.dtype not in ELEMENT:
        raise ConvertError(f"tensor {name} has dtype {tensor.dtype}, not a floating type")
    raw = tensor.read()
    if tensor.dtype == out_dtype:
        return raw
    n = tensor.numel()
    if tensor.dtype == "bf16":  # the upper half of an f32
        halves = array.array("H", raw)
        if sys.byteorder == "big":
            halves.byteswap()
        values = array.array("I", (h << 16 for h in halves)).tobytes()
        values = struct.unpack(f"<{n}f", values)
    else:
        values = struct.unpack(f"<{n}{ELEMENT[tensor.dtype][1]}", raw)
    try:
        return struct.pack(f"<{n}{ELEMENT[out_dtype][1]}", *values)
    except (OverflowError, struct.error):
        raise ConvertError(f"tensor {name} has values outside the f16 range; use --dtype f32")


def transpose2(data, rows, cols, element):
    """Row-major [rows, cols] bytes -> [cols, rows]."""
    out = bytearray(len(data))
    for r in range(rows):
        for c in range(cols):
            src = (r * cols + c) * element
            dst = (c * rows + r) * element
            out[dst:dst + element] = data[src:src + element]
    return bytes(out)


# --------------------------------------------------------------------------
# PyTorch zip archives (TorchScript and torch.save) read with a closed Unpickler

class Storage:
    def __init__(self, key, dtype, numel):
        self.key, self.dtype, self.numel = key, dtype, numel


class StorageType:
    def __init__(self, dtype):
        self.dtype = dtype


class ScriptObject:
    """A TorchScript module (__torch__.*): only its attribute dict is kept."""

    def __setstate__(self, state):
        self.state = state


class TorchTensor:
    def __init__(self, storage, offset, size, stride):
        self.storage, self.offset, self.size, self.stride = storage, offset, size, stride


def _ints(value, what):
    if not isinstance(value, tuple) or not all(isinstance(v, int) and v >= 0 for v in value):
        raise ConvertError(f"malformed tensor {what} in the pickle")
    return value


def _rebuild_tensor_v2(storage, storage_offset, size, stride, *rest):
    if not isinstance(storage, Storage) or not isinstance(storage_offset, int) or storage_offset < 0:
        raise ConvertError("malformed tensor in the pickle")
    size, stride = _ints(size, "size"), _ints(stride, "stride")
    if len(size) != len(stride):
        raise ConvertError("malformed tensor in the pickle")
    return TorchTensor(storage, storage_offset, size, stride)


def _rebuild_parameter(data, *rest):
    return data


def _identity(value, *rest):
    return value


ALLOWED_GLOBALS = {
    ("torch._utils", "_rebuild_tensor_v2"): _rebuild_tensor_v2,
    ("torch._utils", "_rebuild_parameter"): _rebuild_parameter,
    ("collections", "OrderedDict"): collections.OrderedDict,
    # TorchScript's typed containers
    ("torch.jit._pickle", "restore_type_tag"): _identity,
    ("torch.jit._pickle", "build_intlist"): _identity,
    ("torch.jit._pickle", "build_doublelist"): _identity,
    ("torch.jit._pickle", "build_boollist"): _identity,
    ("torch.jit._pickle", "build_tensorlist"): _identity,
}


class ClosedUnpickler(pickle.Unpickler):
    def __init__(self, data):
        super().__init__(io.BytesIO(data))

    def find_class(self, module, name):
        if (module, name) in ALLOWED_GLOBALS:
            return ALLOWED_GLOBALS[(module, name)]
        if module == "torch" and name in STORAGE_DTYPES:
            return StorageType(STORAGE_DTYPES[name])
        if module == "__torch__" or module.startswith("__torch__."):
            return ScriptObject
        raise ConvertError(f"the pickle asks for the global {module}.{name}, which no weight file "
                           f"needs; refusing to load it")

    def persistent_load(self, pid):
        if (not isinstance(pid, tuple) or len(pid) != 5 or pid[0] != "storage"
                or not isinstance(pid[1], StorageType) or not isinstance(pid[2], str)
                or not isinstance(pid[4], int) or pid[4] < 0):
            raise ConvertError("malformed storage reference in the pickle")
        return Storage(pid[2], pid[1].dtype, pid[4])


class TorchArchive:
    def __init__(self, path):
        self.path = path
        self.zip = zipfile.ZipFile(path)
        pkls = [n for n in self.zip.namelist() if n.count("/") == 1 and n.endswith("/data.pkl")]
        if len(pkls) != 1:
            raise ConvertError("a zip file but not a PyTorch archive (no single <name>/data.pkl)")
        self.root = pkls[0][:-len("data.pkl")]
        order = self.root + "byteorder"
        if order in self.zip.namelist() and self.zip.read(order).strip() != b"little":
            raise ConvertError("a big-endian PyTorch archive; re-save it on a little-endian machine")
        self.storages = {}

    def load(self):
        unpickler = ClosedUnpickler(self.zip.read(self.root + "data.pkl"))
        try:
            return unpickler.load()
        except ConvertError:
            raise
        except Exception as e:  # any malformed pickle: a one-line refusal
            raise ConvertError(f"malformed data.pkl ({type(e).__name__}: {e})")

    def storage_bytes(self, storage):
        if storage.key not in self.storages:
            name = f"{self.root}data/{storage.key}"
            try:
                info = self.zip.getinfo(name)
            except KeyError:
                raise ConvertError(f"storage {name} missing from the archive")
            need = storage.numel * STORAGE_ELEMENT[storage.dtype]
            if info.file_size < need:
                raise ConvertError(f"storage {name} has {info.file_size} bytes, needs {need}")
            self.storages[storage.key] = self.zip.read(name)[:need]
        return self.storages[storage.key]

    def tensor(self, t):
        """A Tensor reading the torch tensor t (any strides) from its storage."""
        dtype = t.storage.dtype
        element = STORAGE_ELEMENT[dtype]
        numel = 1
        for d in t.size:
            numel *= d
        last = t.offset + sum((d - 1) * s for d, s in zip(t.size, t.stride)) if numel else t.offset
        if numel and last >= t.storage.numel:
            raise ConvertError(f"a tensor reaches past its storage {t.storage.key}")

        def read():
            data = self.storage_bytes(t.storage)
            contiguous, expect = True, 1
            for d, s in reversed(list(zip(t.size, t.stride))):
                if d != 1 and s != expect:
                    contiguous = False
                expect *= d
            if contiguous:
                return data[t.offset * element:(t.offset + numel) * element]
            out = bytearray(numel * element)
            for i in range(numel):
                rem, src = i, t.offset
                for d, s in reversed(list(zip(t.size, t.stride))):
                    src += (rem % d) * s
                    rem //= d
                out[i * element:(i + 1) * element] = data[src * element:(src + 1) * element]
            return bytes(out)

        return Tensor(dtype, t.size, read)


def named_tensors(archive, obj):
    """name -> Tensor for a state dict or a TorchScript module tree."""
    named = {}
    if isinstance(obj, dict):
        for k, v in obj.items():
            if isinstance(k, str) and isinstance(v, TorchTensor):
                named[k] = archive.tensor(v)
        return named
    if not isinstance(obj, ScriptObject):
        raise ConvertError("neither a state dict nor a TorchScript module")
    seen = set()

    def walk(o, prefix):
        if id(o) in seen or not isinstance(getattr(o, "state", None), dict):
            return
        seen.add(id(o))
        for k, v in o.state.items():
            if not isinstance(k, str):
                continue
            if isinstance(v, TorchTensor):
                named[prefix + k] = archive.tensor(v)
            elif isinstance(v, ScriptObject):
                walk(v, prefix + k + ".")

    walk(obj, "")
    return named


def image_tower_from_torch(named):
    """The visual.* tensors under OpenAI's names minus "visual."."""
    if any(k.startswith("visual.") for k in named):
        return {k[len("visual."):]: v for k, v in named.items() if k.startswith("visual.")}
    if "conv1.weight" in named:
        return named
    raise ConvertError("no image tower in it (no visual.* keys, no conv1.weight)")


# --------------------------------------------------------------------------
# Hugging Face safetensors

def read_safetensors(f, size):
    header_len = struct.unpack("<Q", f.read(8))[0]
    if header_len > size - 8:
        raise ConvertError("truncated safetensors header")
    try:
        header = json.loads(f.read(header_len).decode("utf-8"))
    except (UnicodeDecodeError, ValueError) as e:
        raise ConvertError(f"malformed safetensors header ({e})")
    if not isinstance(header, dict):
        raise ConvertError("malformed safetensors header")
    base, data_size = 8 + header_len, size - 8 - header_len
    named = {}
    for name, info in header.items():
        if name == "__metadata__":
            continue
        try:
            dtype = SAFETENSORS_DTYPES[info["dtype"]]
            shape = [int(d) for d in info["shape"]]
            begin, end = (int(x) for x in info["data_offsets"])
        except (KeyError, TypeError, ValueError):
            raise ConvertError(f"malformed safetensors entry {name}")
        numel = 1
        for d in shape:
            if d < 0:
                raise ConvertError(f"malformed safetensors entry {name}")
            numel *= d
        if not 0 <= begin <= end <= data_size or end - begin != numel * STORAGE_ELEMENT[dtype]:
            raise ConvertError(f"safetensors entry {name} has bad data offsets")

        def read(begin=begin, end=end):
            f.seek(base + begin)
            return f.read(end - begin)

        named[name] = Tensor(dtype, shape, read)
    return named


def read_hf_config(path):
    config_path = os.path.join(os.path.dirname(os.path.abspath(path)), "config.json")
    if not os.path.exists(config_path):
        return None
    try:
        with open(config_path) as f:
            config = json.load(f)
    except (OSError, ValueError) as e:
        raise ConvertError(f"cannot read {config_path} ({e})")
    # CLIPModel: nested (older files name it vision_config_dict); CLIPVisionModel: top level
    vision = None
    if isinstance(config, dict):
        vision = config.get("vision_config") or config.get("vision_config_dict") or config
    if not isinstance(vision, dict):
        raise ConvertError(f"{config_path} has no vision_config")
    act = vision.get("hidden_act", "quick_gelu")
    if act != "quick_gelu":
        raise ConvertError(f"{config_path} says hidden_act {act}; wiresketch implements OpenAI's "
                           f"quick_gelu only")
    eps = vision.get("layer_norm_eps", 1e-5)
    if eps != 1e-5:
        raise ConvertError(f"{config_path} says layer_norm_eps {eps}; wiresketch uses 1e-5")
    return vision


HF_TOP_NAMES = {
    "vision_model.embeddings.patch_embedding.weight": "conv1.weight",
    "vision_model.embeddings.class_embedding": "class_embedding",
    "vision_model.embeddings.position_embedding.weight": "positional_embedding",
    "vision_model.pre_layrnorm.weight": "ln_pre.weight",
    "vision_model.pre_layrnorm.bias": "ln_pre.bias",
    "vision_model.post_layernorm.weight": "ln_post.weight",
    "vision_model.post_layernorm.bias": "ln_post.bias",
}
HF_LAYER = "vision_model.encoder.layers."
HF_BLOCK_NAMES = {
    "layer_norm1.weight": "ln_1.weight", "layer_norm1.bias": "ln_1.bias",
    "self_attn.out_proj.weight": "attn.out_proj.weight", "self_attn.out_proj.bias": "attn.out_proj.bias",
    "layer_norm2.weight": "ln_2.weight", "layer_norm2.bias": "ln_2.bias",
    "mlp.fc1.weight": "mlp.c_fc.weight", "mlp.fc1.bias": "mlp.c_fc.bias",
    "mlp.fc2.weight": "mlp.c_proj.weight", "mlp.fc2.bias": "mlp.c_proj.bias",
}
# HF keeps q, k, v apart; OpenAI (torch's MultiheadAttention) stacks them in this order
HF_QKV = {f"self_attn.{letter}_proj.{kind}": (f"attn.in_proj_{kind}", letter)
          for letter in "qkv" for kind in ("weight", "bias")}


class Concat:
    """in_proj_weight/bias: HF's q, k, v stacked along the first axis."""

    def __init__(self, parts):
        self.parts = parts
        self.shape = (sum(p.shape[0] for p in parts),) + parts[0].shape[1:]


class Transposed:
    """proj: HF's visual_projection.weight is [out, W], OpenAI's proj [W, out]."""

    def __init__(self, tensor):
        self.tensor = tensor
        self.shape = tuple(reversed(tensor.shape))


def hf_name(name):
    """The Hugging Face name of an OpenAI image-tower name (for messages)."""
    for hf, openai in HF_TOP_NAMES.items():
        if openai == name:
            return hf
    if name == "proj":
        return "visual_projection.weight^T"
    block = "transformer.resblocks."
    if name.startswith(block):
        index, _, rest = name[len(block):].partition(".")
        for hf, openai in HF_BLOCK_NAMES.items():
            if openai == rest:
                return f"{HF_LAYER}{index}.{hf}"
        if rest.startswith("attn.in_proj_"):
            return f"{HF_LAYER}{index}.self_attn.{{q,k,v}}_proj.{rest[len('attn.in_proj_'):]}"
    return name


def image_tower_from_hf(named):
    tower, qkv = {}, collections.defaultdict(dict)
    for name, t in named.items():
        index, _, rest = name[len(HF_LAYER):].partition(".")
        if name in HF_TOP_NAMES:
            tower[HF_TOP_NAMES[name]] = t
        elif name == "visual_projection.weight":
            if len(t.shape) != 2:
                raise ConvertError(f"tensor {name} has shape {list(t.shape)}, expected [out, W]")
            tower["proj"] = Transposed(t)
        elif name == "vision_model.embeddings.position_ids":
            continue  # a buffer holding the token indices 0..T-1
        elif name.startswith(HF_LAYER) and index.isdigit() and rest in HF_BLOCK_NAMES:
            tower[f"transformer.resblocks.{int(index)}.{HF_BLOCK_NAMES[rest]}"] = t
        elif name.startswith(HF_LAYER) and index.isdigit() and rest in HF_QKV:
            target, letter = HF_QKV[rest]
            qkv[f"transformer.resblocks.{int(index)}.{target}"][letter] = t
        elif name.startswith("vision_model."):
            raise ConvertError(f"unexpected tensor {name} (not a CLIP ViT image tower?)")
    for target, parts in qkv.items():
        for letter in "qkv":
            if letter not in parts:
                raise ConvertError(f"tensor {hf_name(target).replace('{q,k,v}', letter)} missing")
        if not parts["q"].shape == parts["k"].shape == parts["v"].shape:
            raise ConvertError(f"tensors {hf_name(target)} differ in shape")
        tower[target] = Concat([parts["q"], parts["k"], parts["v"]])
    if not tower:
        raise ConvertError("no image tower in it (no vision_model.* tensors)")
    return tower


# --------------------------------------------------------------------------
# The image tower: architecture from shapes, every tensor checked

def expected_tensors(width, layers, patch, tokens, out):
    w = width
    names = [("conv1.weight", (w, 3, patch, patch)), ("class_embedding", (w,)),
             ("positional_embedding", (tokens, w)), ("ln_pre.weight", (w,)), ("ln_pre.bias", (w,))]
    for i in range(layers):
        p = f"transformer.resblocks.{i}."
        names += [(p + "ln_1.weight", (w,)), (p + "ln_1.bias", (w,)),
                  (p + "attn.in_proj_weight", (3 * w, w)), (p + "attn.in_proj_bias", (3 * w,)),
                  (p + "attn.out_proj.weight", (w, w)), (p + "attn.out_proj.bias", (w,)),
                  (p + "ln_2.weight", (w,)), (p + "ln_2.bias", (w,)),
                  (p + "mlp.c_fc.weight", (4 * w, w)), (p + "mlp.c_fc.bias", (4 * w,)),
                  (p + "mlp.c_proj.weight", (w, 4 * w)), (p + "mlp.c_proj.bias", (w,))]
    names += [("ln_post.weight", (w,)), ("ln_post.bias", (w,)), ("proj", (w, out))]
    return names


def architecture(tower, heads, hf_config, display):
    if any(k.startswith("layer1.") or k.startswith("attnpool.") for k in tower):
        raise ConvertError("a ResNet image tower (RN50 and the like); only ViT models are supported")
    for key in ("conv1.weight", "positional_embedding", "proj"):
        if key not in tower:
            raise ConvertError(f"tensor {display(key)} missing")
    conv, pos, proj = tower["conv1.weight"].shape, tower["positional_embedding"].shape, tower["proj"].shape
    if len(conv) != 4 or conv[1] != 3 or conv[2] != conv[3] or conv[0] < 1 or conv[2] < 1:
        raise ConvertError(f"tensor {display('conv1.weight')} has shape {list(conv)}, expected [W, 3, p, p]")
    width, patch = conv[0], conv[2]
    grid = math.isqrt(pos[0] - 1) if len(pos) == 2 and pos[0] >= 2 else 0
    if grid < 1 or grid * grid + 1 != pos[0]:
        raise ConvertError(f"tensor {display('positional_embedding')} has shape {list(pos)}, "
                           f"expected [1 + grid^2, {width}]")
    if len(proj) != 2 or proj[1] < 1:
        raise ConvertError(f"tensor {display('proj')} has shape {list(proj)}, expected [{width}, out]")
    layers = 0
    while f"transformer.resblocks.{layers}.attn.in_proj_weight" in tower:
        layers += 1
    if layers == 0:
        raise ConvertError(f"tensor {display('transformer.resblocks.0.attn.in_proj_weight')} missing")
    if heads is None and hf_config is not None:
        heads = hf_config.get("num_attention_heads")
    if heads is None:
        heads = width // 64
    if not isinstance(heads, int) or heads < 1 or width % heads:
        raise ConvertError(f"cannot split width {width} into {heads} heads; pass --heads N")
    arch = {"width": width, "layers": layers, "heads": heads, "patch": patch,
            "resolution": patch * grid, "output_dim": proj[1]}
    if hf_config is not None:
        for key, config_key in (("width", "hidden_size"), ("layers", "num_hidden_layers"),
                                ("patch", "patch_size"), ("resolution", "image_size")):
            if config_key in hf_config and hf_config[config_key] != arch[key]:
                raise ConvertError(f"config.json says {config_key} {hf_config[config_key]}, the "
                                   f"tensors say {arch[key]}")
    return arch


def check_tower(tower, arch, display):
    expected = expected_tensors(arch["width"], arch["layers"], arch["patch"],
                                (arch["resolution"] // arch["patch"]) ** 2 + 1, arch["output_dim"])
    for name, shape in expected:
        if name not in tower:
            raise ConvertError(f"tensor {display(name)} missing")
        if tuple(tower[name].shape) != shape:
            raise ConvertError(f"tensor {display(name)} has shape {list(tower[name].shape)}, "
                               f"expected {list(shape)}")
    known = {name for name, _ in expected}
    for name in tower:
        if name not in known:
            raise ConvertError(f"unexpected tensor {display(name)} (not a CLIP ViT image tower?)")
    return expected


def tensor_bytes(t, out_dtype, name):
    if isinstance(t, Concat):
        return b"".join(encode(p, out_dtype, name) for p in t.parts)
    if isinstance(t, Transposed):
        rows, cols = t.tensor.shape
        return transpose2(encode(t.tensor, out_dtype, name), rows, cols, ELEMENT[out_dtype][0])
    return encode(t, out_dtype, name)


def write_weight_file(out_path, arch, tower, expected, out_dtype, display):
    element = ELEMENT[out_dtype][0]
    count = len(expected)
    offset = HEADER.size + count * ENTRY.size
    table, offsets = [], []
    for name, shape in expected:
        offset = (offset + ALIGN - 1) // ALIGN * ALIGN
        numel = 1
        for d in shape:
            numel *= d
        dims = list(shape) + [0] * (4 - len(shape))
        table.append(ENTRY.pack(name.encode("ascii"), OUT_DTYPES[out_dtype], len(shape), *dims,
                                offset, numel * element))
        offsets.append(offset)
        offset += numel * element
    head = HEADER.pack(MAGIC, VERSION, arch["width"], arch["layers"], arch["heads"], arch["patch"],
                       arch["resolution"], arch["output_dim"], count) + b"".join(table)
    tmp = f"{out_path}.tmp.{os.getpid()}"
    try:
        with open(tmp, "wb") as f:
            crc, pos = 0, 0

            def put(b):
                nonlocal crc, pos
                f.write(b)
                crc = zlib.crc32(b, crc)
                pos += len(b)

            put(head)
            for (name, _), start in zip(expected, offsets):
                put(b"\0" * (start - pos))
                put(tensor_bytes(tower[name], out_dtype, display(name)))
            f.write(struct.pack("<I", crc & 0xffffffff))
            f.flush()
            os.fsync(f.fileno())
        os.replace(tmp, out_path)
    except BaseException:
        if os.path.exists(tmp):
            os.unlink(tmp)
        raise
    return pos + 4


def load_tower(path, heads):
    """(tower, architecture, display): OpenAI-named tensors of the image tower;
    display maps such a name back to the name in the input file."""
    size = os.path.getsize(path)
    if zipfile.is_zipfile(path):
        archive = TorchArchive(path)
        named = named_tensors(archive, archive.load())
        prefixed = any(k.startswith("visual.") for k in named)
        tower = image_tower_from_torch(named)

        def display(name):
            return "visual." + name if prefixed else name

        return tower, architecture(tower, heads, None, display), display
    with open(path, "rb") as f:
        start = f.read(9)
    if len(start) == 9 and start[8:9] == b"{" and struct.unpack("<Q", start[:8])[0] <= size - 8:
        f = open(path, "rb")  # stays open for the lazy reads until the process ends
        tower = image_tower_from_hf(read_safetensors(f, size))
        return tower, architecture(tower, heads, read_hf_config(path), hf_name), hf_name
    if start[:2] == b"\x80\x02":
        raise ConvertError("a legacy (pre-1.6) torch.save file; re-save it with a current PyTorch")
    raise ConvertError("unknown format (expected a TorchScript archive such as ViT-B-32.pt, a "
                       "torch.save state dict, or a model.safetensors)")


def main(argv):
    parser = argparse.ArgumentParser(
        prog="convert_weights.py",
        description="Convert a CLIP ViT image tower to the wiresketch weight file format.")
    parser.add_argument("input", metavar="IN")
    parser.add_argument("output", metavar="OUT")
    parser.add_argument("--dtype", choices=sorted(OUT_DTYPES), default="f32",
                        help="stored precision (default f32; f16 halves the file)")
    parser.add_argument("--heads", type=int, default=None,
                        help="attention heads (default: config.json beside a safetensors file, "
                             "else width / 64 as in OpenAI's models)")
    args = parser.parse_args(argv)
    try:
        if not os.path.isfile(args.input):
            raise ConvertError("no such file")
        tower, arch, display = load_tower(args.input, args.heads)
        expected = check_tower(tower, arch, display)
        nbytes = write_weight_file(args.output, arch, tower, expected, args.dtype, display)
    except ConvertError as e:
        print(f"convert_weights.py: {args.input}: {e}", file=sys.stderr)
        return 1
    except OSError as e:
        print(f"convert_weights.py: {e.filename or args.input}: {e.strerror or e}", file=sys.stderr)
        return 1
    print(f"{args.output}: ViT width {arch['width']}, {arch['layers']} layers, {arch['heads']} heads, "
          f"patch {arch['patch']}, resolution {arch['resolution']}, output {arch['output_dim']}; "
          f"{len(expected)} tensors, {args.dtype}, {nbytes} bytes")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
