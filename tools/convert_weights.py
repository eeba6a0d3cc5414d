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

It is as strict as the loader (nn/weightfile.c): inputs are bounded before
anything is allocated for them (JSON depth, header and pickle sizes, tensor
counts, pickle memo indices, the loader's architecture limits), storage
members are streamed and never inflated past what their tensor needs, and
it never writes a file the loader would refuse (NaN or Inf values).

Every failure prints one line "convert_weights.py: IN: what is wrong" on
stderr (OUT instead of IN when the output is at fault or the conversion is
interrupted) and exits with status 1.
"""
import argparse
import array
import collections
import errno
import io
import itertools
import json
import math
import os
import pickle
import pickletools
import re
import signal
import stat
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

# The loader's architecture limits (nn/weightfile.c): a file beyond them would be refused there.
MAX_WIDTH, MAX_LAYERS, MAX_RESOLUTION = 65536, 4096, 16384
# What an input may describe, bounded by what a CLIP file can hold: an image and a text tower
# of at most MAX_LAYERS blocks, 16 tensors a block in Hugging Face's naming (q, k, v apart)
# and 16 outside the blocks; so at most 131 104 tensors.
MAX_TENSORS = 2 * (16 * MAX_LAYERS + 16)
# A tensor takes about 110 bytes of a safetensors header or of a data.pkl in OpenAI's and
# Hugging Face's files; 256 a tensor bounds either at 32 MiB.
MAX_DESCRIPTION_BYTES = 256 * MAX_TENSORS
# Headers nest 3 deep and config.json 3 or 4; json.loads recurses once a level.
MAX_JSON_DEPTH = 64
MAX_CONFIG_BYTES = 1 << 20                 # a CLIP config.json has a few kilobytes
MAX_MODULE_DEPTH = 64                      # OpenAI's TorchScript modules nest about 6 deep
# A CLIP tensor has at most 4 dimensions (conv1.weight). The bound comes before any product of
# a shape is taken: the product of 3 million dimensions is a 3-million-digit integer, each
# multiplication slower than the last.
MAX_DIMS = 8
# PyTorch writes a storage with exactly the bytes of its tensor; a member may hold this
# much more than the tensor reading it uses, and no more (it is read through to its end).
STORAGE_SLACK = 1 << 20
CHUNK = 1 << 20                            # bytes read, converted and written at a time


class ConvertError(Exception):
    """A refusal: one line naming path (the input when None) and what is wrong."""

    def __init__(self, message, path=None):
        super().__init__(message)
        self.path = path


class Interrupted(BaseException):
    """A stopping signal: unwinds like KeyboardInterrupt, so the temporary file is removed.
    Raised inside a codec, Python re-raises it with the codec's words around its message
    ("decoding with 'cp437' codec failed (Interrupted: SIGTERM)"), so the signal's name is
    kept apart, in `signal_name`."""

    signal_name = None


# The signals that end a conversion with its temporary file removed: Ctrl-C, kill, a closed
# terminal, the CPU time limit. SIGXFSZ (the file size limit) is ignored instead, so that the
# write past it fails with EFBIG and is reported as a write error naming OUT.
STOP_SIGNALS = (signal.SIGINT, signal.SIGTERM, signal.SIGHUP, signal.SIGXCPU)


def on_signal(signum, frame):
    """Raise Interrupted once; further signals are ignored so that cleanup runs to the end."""
    for s in STOP_SIGNALS:
        signal.signal(s, signal.SIG_IGN)
    Interrupted.signal_name = signal.Signals(signum).name
    raise Interrupted(Interrupted.signal_name)


def one_line(text):
    """text with control characters escaped: names from the input may hold newlines."""
    return "".join(c if c.isprintable() else repr(c)[1:-1] for c in text)


def brief(value):
    """A JSON value for a message: a printable string as is, else JSON, cut to 40 characters."""
    text = value if isinstance(value, str) and value.isprintable() else json.dumps(value)
    return text if len(text) <= 40 else text[:37] + "..."


def is_count(value):
    """An integer >= 0; bool is an int to Python but never a size or an offset."""
    return type(value) is int and value >= 0


def open_regular(path):
    """path opened for binary reading. Its type is checked with os.stat before opening, so
    a FIFO or a device is refused without blocking, and again on the descriptor (opened
    O_NONBLOCK, should the name have changed in between)."""
    try:
        mode = os.stat(path).st_mode
    except FileNotFoundError:
        raise ConvertError("no such file")
    if stat.S_ISDIR(mode):
        raise ConvertError("is a directory")
    if not stat.S_ISREG(mode):
        raise ConvertError("not a regular file")
    fd = os.open(path, os.O_RDONLY | os.O_NONBLOCK)
    if not stat.S_ISREG(os.fstat(fd).st_mode):
        os.close(fd)
        raise ConvertError("not a regular file")
    return os.fdopen(fd, "rb")


# --------------------------------------------------------------------------
# JSON (safetensors headers, config.json) with bounded depth and no duplicate keys

JSON_STRING = re.compile(rb'"[^"\\]*(?:\\.[^"\\]*)*"', re.S)
NOT_BRACKETS = bytes(b for b in range(256) if b not in b"[]{}")
BRACKET_STEP = [1 if b in b"[{" else -1 for b in range(256)]


def json_depth(raw):
    """How deep [ and { nest in JSON text, strings skipped: counted before json.loads, which
    recurses once a level and fails with a RecursionError long before the input ends."""
    brackets = JSON_STRING.sub(b"", raw).translate(None, NOT_BRACKETS)
    return max(itertools.accumulate(map(BRACKET_STEP.__getitem__, brackets)), default=0)


def parse_json(raw, what):
    """raw (bytes) parsed as JSON; refuses deep nesting and a key given twice, which
    json.loads would silently resolve to its last value."""
    if json_depth(raw) > MAX_JSON_DEPTH:
        raise ConvertError(f"{what} nests deeper than {MAX_JSON_DEPTH} levels")

    def no_duplicates(pairs):
        seen = set()
        for key, _ in pairs:
            if key in seen:
                raise ConvertError(f"{what} has the key {key} twice")
            seen.add(key)
        return dict(pairs)

    try:
        return json.loads(raw.decode("utf-8"), object_pairs_hook=no_duplicates)
    except ValueError as e:  # UnicodeDecodeError and JSONDecodeError alike
        raise ConvertError(f"malformed {what} ({e})")


# --------------------------------------------------------------------------
# Tensors: a dtype, a shape and a way to get its contiguous little-endian bytes

class Tensor:
    """chunks() yields the values, row-major little-endian, in pieces of whole elements."""

    def __init__(self, dtype, shape, chunks):
        self.dtype, self.shape, self.chunks = dtype, tuple(shape), chunks


def numel_of(shape):
    n = 1
    for d in shape:
        n *= d
    return n


# Inf and NaN have every exponent bit set. Per dtype: (byte, mask) of the element's top byte
# and of the byte below it (little-endian) that together hold the exponent.
EXPONENT_BYTES = {"f16": (1, 0x7c, 0, 0x00), "bf16": (1, 0x7f, 0, 0x80),
                  "f32": (3, 0x7f, 2, 0x80), "f64": (7, 0x7f, 6, 0xf0)}
ALL_SET = {mask: bytes(b & mask == mask for b in range(256)) for mask in (0x00, 0x7c, 0x7f, 0x80, 0xf0)}


def finite(raw, dtype):
    """Whether every element of raw is finite, tested on the exponent bits a byte column at a
    time (bytes.translate and an integer AND), not a Python step per element."""
    size = ELEMENT[dtype][0]
    top, top_mask, low, low_mask = EXPONENT_BYTES[dtype]
    high = int.from_bytes(raw[top::size].translate(ALL_SET[top_mask]), "little")
    return not high & int.from_bytes(raw[low::size].translate(ALL_SET[low_mask]), "little")


def encode(tensor, out_dtype, name):
    """The tensor's values as contiguous little-endian bytes of out_dtype, chunk by chunk, so
    that memory stays bounded whatever the tensor's size. NaN and Inf are refused here: the
    loader refuses a file holding them."""
    if tensor.dtype not in ELEMENT:
        raise ConvertError(f"tensor {name} has dtype {tensor.dtype}, not a floating type")
    size, code = ELEMENT[tensor.dtype]
    for raw in tensor.chunks():
        if not finite(raw, tensor.dtype):
            raise ConvertError(f"tensor {name} has NaN or Inf values")
        if tensor.dtype == out_dtype:
            yield raw
            continue
        n = len(raw) // size
        if tensor.dtype == "bf16":  # the upper half of an f32
            halves = array.array("H", raw)
            if sys.byteorder == "big":
                halves.byteswap()
            values = array.array("I", (h << 16 for h in halves)).tobytes()
            values = struct.unpack(f"<{n}f", values)
        else:
            values = struct.unpack(f"<{n}{code}", raw)
        try:
            converted = struct.pack(f"<{n}{ELEMENT[out_dtype][1]}", *values)
        except (OverflowError, struct.error):
            raise ConvertError(f"tensor {name} has values outside the f16 range; use --dtype f32")
        yield converted


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

class Record:
    """A record the Unpickler makes after checking its fields (a storage, its type, a tensor).
    The pickle's BUILD opcode would otherwise rewrite the checked fields afterwards (a storage
    of None, a size of "64", an offset of -4): it is refused."""

    def __setstate__(self, state):
        raise ConvertError(f"malformed data.pkl (it rewrites a {self.what} record: BUILD)")


class Storage(Record):
    what = "storage"

    def __init__(self, key, dtype, numel):
        self.key, self.dtype, self.numel = key, dtype, numel


class StorageType(Record):
    what = "storage type"

    def __init__(self, dtype):
        self.dtype = dtype


class ScriptObject:
    """A TorchScript module (__torch__.*): only its attribute dict is kept."""

    def __setstate__(self, state):
        self.state = state


class TorchTensor(Record):
    what = "tensor"

    def __init__(self, storage, offset, size, stride):
        self.storage, self.offset, self.size, self.stride = storage, offset, size, stride


def _ints(value, what):
    if not isinstance(value, tuple):
        raise ConvertError(f"malformed tensor {what} in the pickle")
    if len(value) > MAX_DIMS:
        raise ConvertError(f"a tensor {what} of {len(value)} dimensions in the pickle; no CLIP "
                           f"tensor has more than {MAX_DIMS}")
    if not all(is_count(v) for v in value):
        raise ConvertError(f"malformed tensor {what} in the pickle")
    return value


def _rebuild_tensor_v2(storage, storage_offset, size, stride, *rest):
    if not isinstance(storage, Storage) or not is_count(storage_offset):
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
# How each opcode's argument is laid out, from pickletools' table: a fixed byte count (>= 0),
# a line (-1; two for GLOBAL and INST), or a length of 1, 4 or 8 bytes before the bytes.
ARG_LAYOUT = {op.code.encode("latin-1")[0]: (op.arg.n if op.arg else 0) for op in pickletools.opcodes}
LINES = {ord("c"): 2, ord("i"): 2}
LENGTH_BYTES = {pickletools.TAKEN_FROM_ARGUMENT1: 1, pickletools.TAKEN_FROM_ARGUMENT4: 4,
                pickletools.TAKEN_FROM_ARGUMENT4U: 4, pickletools.TAKEN_FROM_ARGUMENT8U: 8}
PUT, LONG_BINPUT, STOP = ord("p"), ord("r"), ord(".")


def check_memo(data):
    """Refuses a memo index past the pickle's length. Picklers number their memo entries 0, 1,
    2, ...; the C Unpickler grows its memo to twice the largest index and zeroes it, so a
    9-byte data.pkl storing at index 2^31 would take 32 GB. Only PUT and LONG_BINPUT can name
    such an index (BINPUT's is one byte). The opcodes are walked by their argument layout
    alone, a few times faster than pickletools.genops, which decodes every argument (a 32 MiB
    data.pkl of small integers took it 30 s)."""
    def malformed(why):
        return ConvertError(f"malformed data.pkl ({why})")

    at, n = 0, len(data)
    while at < n:
        code = data[at]
        layout = ARG_LAYOUT.get(code)
        if layout is None:
            raise malformed(f"unknown opcode {bytes([code])!r} at byte {at}")
        at += 1
        if layout > 0:
            if code == LONG_BINPUT and at + 4 <= n:
                index = int.from_bytes(data[at:at + 4], "little")
                if index >= n:
                    raise malformed(f"memo index {index} in a pickle of {n} bytes")
            at += layout
        elif layout == -1:
            end = at
            for _ in range(LINES.get(code, 1)):
                end = data.find(b"\n", end) + 1
                if end == 0:
                    raise malformed(f"a line that does not end, at byte {at}")
            if code == PUT and data[at:end - 1].isdigit() and int(data[at:end - 1]) >= n:
                raise malformed(f"memo index {int(data[at:end - 1])} in a pickle of {n} bytes")
            at = end
        elif layout < -1:
            size = LENGTH_BYTES[layout]
            length = int.from_bytes(data[at:at + size], "little", signed=size == 4 and code in (0x54, 0x8b))
            at += size + max(length, 0)
        elif code == STOP:
            return
    if at > n:
        raise malformed("truncated")


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
                or not is_count(pid[4])):
            raise ConvertError("malformed storage reference in the pickle")
        return Storage(pid[2], pid[1].dtype, pid[4])


# Everything zipfile raises for a damaged member or archive (a flipped byte, a cut stream, an
# encrypted or unknown compression method); OSError for the input's own read errors.
ZIP_ERRORS = (zipfile.BadZipFile, zipfile.LargeZipFile, EOFError, zlib.error, NotImplementedError,
              RuntimeError, ValueError, struct.error, OSError)


class TorchArchive:
    def __init__(self, f):
        try:
            self.zip = zipfile.ZipFile(f)
        except ZIP_ERRORS as e:
            raise ConvertError(f"a damaged zip file ({e})")
        pkls = [n for n in self.zip.namelist() if n.count("/") == 1 and n.endswith("/data.pkl")]
        if len(pkls) != 1:
            raise ConvertError("a zip file but not a PyTorch archive (no single <name>/data.pkl)")
        self.root = pkls[0][:-len("data.pkl")]
        order = self.root + "byteorder"
        if order in self.zip.namelist() and self.read_member(order, 16).strip() != b"little":
            raise ConvertError("a big-endian PyTorch archive; re-save it on a little-endian machine")
        self.readers = {}  # storage key -> the name of the tensor that read it

    def member_chunks(self, name, begin, end):
        """Bytes begin..end of the member name, CHUNK at a time. The member is read through to
        its end, where zipfile checks its CRC-32: callers bound its size first."""
        try:
            with self.zip.open(name) as member:
                pos = 0
                while pos < begin:
                    skipped = len(member.read(min(CHUNK, begin - pos)))
                    if not skipped:
                        raise ConvertError(f"archive member {name} is truncated")
                    pos += skipped
                while pos < end:
                    want = min(CHUNK, end - pos)
                    block = member.read(want)
                    if len(block) != want:
                        raise ConvertError(f"archive member {name} is truncated")
                    yield block
                    pos += want
                while member.read(CHUNK):
                    pass
        except ZIP_ERRORS as e:
            raise ConvertError(f"archive member {name} is damaged ({e})")

    def read_member(self, name, limit):
        """A whole small member (data.pkl, byteorder), refused unread past limit bytes."""
        size = self.zip.getinfo(name).file_size
        if size > limit:
            raise ConvertError(f"archive member {name} has {size} bytes, more than the {limit} "
                               f"a CLIP model needs")
        return b"".join(self.member_chunks(name, 0, size))

    def load(self):
        data = self.read_member(self.root + "data.pkl", MAX_DESCRIPTION_BYTES)
        check_memo(data)
        unpickler = ClosedUnpickler(data)
        try:
            return unpickler.load()
        except (ConvertError, MemoryError):  # a refusal as it is; memory is not the file's fault
            raise
        except Exception as e:  # any malformed pickle: a one-line refusal
            raise ConvertError(f"malformed data.pkl ({type(e).__name__}: {e})")

    def storage_member(self, storage, used, name):
        """The member holding storage, read by tensor name up to byte used. Refused when
        another tensor of the tower read it, or when it holds more than used + STORAGE_SLACK
        bytes: PyTorch gives each weight a storage of its own size, and a bigger member (say
        3 GB of deflated zeros under a 100-byte tensor) would all be inflated."""
        member = f"{self.root}data/{storage.key}"
        try:
            info = self.zip.getinfo(member)
        except KeyError:
            raise ConvertError(f"storage {member} missing from the archive")
        need = storage.numel * STORAGE_ELEMENT[storage.dtype]
        if info.file_size < need:
            raise ConvertError(f"storage {member} has {info.file_size} bytes, needs {need}")
        if info.file_size > used + STORAGE_SLACK:
            raise ConvertError(f"storage {member} has {info.file_size} bytes, tensor {name} uses "
                               f"{used}; refusing to inflate the rest")
        if storage.key in self.readers:
            raise ConvertError(f"tensors {self.readers[storage.key]} and {name} share storage "
                               f"{member}")
        self.readers[storage.key] = name
        return member

    def tensor(self, name, t):
        """A Tensor reading the torch tensor t from its storage: contiguous tensors streamed,
        others (a transposed weight) gathered in memory. Either must be a dense block of its
        storage, every element once: a stride-0 view of a few bytes could otherwise claim
        gigabytes of output."""
        dtype = t.storage.dtype
        element = STORAGE_ELEMENT[dtype]
        numel = numel_of(t.size)
        last = t.offset + sum((d - 1) * s for d, s in zip(t.size, t.stride)) if numel else t.offset
        if numel and last >= t.storage.numel:
            raise ConvertError(f"a tensor reaches past its storage {t.storage.key}")
        dims = sorted((s, d) for d, s in zip(t.size, t.stride) if d != 1)

        def chunks():
            expect = 1
            for s, d in dims:
                if s != expect:
                    raise ConvertError(f"tensor {name} is not a dense block of its storage (a "
                                       f"stride-0, overlapping or gapped view)")
                expect *= d
            member = self.storage_member(t.storage, (t.offset + numel) * element, name)
            begin, end = t.offset * element, (t.offset + numel) * element
            contiguous, expect = True, 1
            for d, s in reversed(list(zip(t.size, t.stride))):
                if d != 1 and s != expect:
                    contiguous = False
                expect *= d
            if contiguous:
                yield from self.member_chunks(member, begin, end)
                return
            data = b"".join(self.member_chunks(member, begin, end))
            out = bytearray(numel * element)
            for i in range(numel):
                rem, src = i, 0
                for d, s in reversed(list(zip(t.size, t.stride))):
                    src += (rem % d) * s
                    rem //= d
                out[i * element:(i + 1) * element] = data[src * element:(src + 1) * element]
            yield bytes(out)

        return Tensor(dtype, t.size, chunks)


def named_tensors(archive, obj):
    """name -> Tensor for a state dict or a TorchScript module tree, at most MAX_TENSORS of
    them. The module tree is walked with an explicit stack, MAX_MODULE_DEPTH deep at most
    (recursion would end in a RecursionError on a hostile file), in the order a recursive walk
    takes."""
    named = {}

    def add(name, t):
        if len(named) == MAX_TENSORS:
            raise ConvertError(f"more than {MAX_TENSORS} tensors; no CLIP model has so many")
        named[name] = archive.tensor(name, t)

    if isinstance(obj, dict):
        for k, v in obj.items():
            if isinstance(k, str) and isinstance(v, TorchTensor):
                add(k, v)
        return named
    if not isinstance(obj, ScriptObject):
        raise ConvertError("neither a state dict nor a TorchScript module")
    if not isinstance(getattr(obj, "state", None), dict):
        return named
    seen, stack = {id(obj)}, [(iter(obj.state.items()), "")]
    while stack:
        items, prefix = stack[-1]
        for k, v in items:
            if not isinstance(k, str):
                continue
            if isinstance(v, TorchTensor):
                add(prefix + k, v)
            elif (isinstance(v, ScriptObject) and id(v) not in seen
                  and isinstance(getattr(v, "state", None), dict)):
                if len(stack) == MAX_MODULE_DEPTH:
                    raise ConvertError(f"TorchScript modules nested more than {MAX_MODULE_DEPTH} deep")
                seen.add(id(v))
                stack.append((iter(v.state.items()), prefix + k + "."))
                break
        else:
            stack.pop()
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
    """name -> Tensor of a safetensors file. Refuses a header past MAX_DESCRIPTION_BYTES or
    listing more than MAX_TENSORS tensors, an entry whose fields are not what the format says
    (a shape of [64.9], ["64"] or [true]), and entries sharing bytes."""
    header_len = struct.unpack("<Q", f.read(8))[0]
    if header_len > size - 8:
        raise ConvertError("truncated safetensors header")
    if header_len > MAX_DESCRIPTION_BYTES:
        raise ConvertError(f"safetensors header of {header_len} bytes; a CLIP model's takes less "
                           f"than {MAX_DESCRIPTION_BYTES}")
    header = parse_json(f.read(header_len), "safetensors header")
    if not isinstance(header, dict):
        raise ConvertError("malformed safetensors header")
    count = len(header) - ("__metadata__" in header)
    if count > MAX_TENSORS:
        raise ConvertError(f"safetensors header lists {count} tensors; no CLIP model has more "
                           f"than {MAX_TENSORS}")
    base, data_size = 8 + header_len, size - 8 - header_len
    named, spans = {}, []
    for name, info in header.items():
        if name == "__metadata__":
            continue
        if not isinstance(info, dict) or not {"dtype", "shape", "data_offsets"} <= info.keys():
            raise ConvertError(f"malformed safetensors entry {name}")
        dtype, shape, offsets = info["dtype"], info["shape"], info["data_offsets"]
        if not isinstance(dtype, str) or dtype not in SAFETENSORS_DTYPES:
            raise ConvertError(f"safetensors entry {name} has dtype {brief(dtype)}, which is not "
                               f"one of {', '.join(SAFETENSORS_DTYPES)}")
        if isinstance(shape, list) and len(shape) > MAX_DIMS:
            raise ConvertError(f"safetensors entry {name} has {len(shape)} dimensions; no CLIP "
                               f"tensor has more than {MAX_DIMS}")
        if not isinstance(shape, list) or not all(is_count(d) for d in shape):
            raise ConvertError(f"safetensors entry {name} has shape {brief(shape)}, not a list of "
                               f"integers >= 0")
        if not isinstance(offsets, list) or len(offsets) != 2 or not all(is_count(x) for x in offsets):
            raise ConvertError(f"safetensors entry {name} has data_offsets {brief(offsets)}, not "
                               f"two integers >= 0")
        dtype = SAFETENSORS_DTYPES[dtype]
        begin, end = offsets
        if not begin <= end <= data_size or end - begin != numel_of(shape) * STORAGE_ELEMENT[dtype]:
            raise ConvertError(f"safetensors entry {name} has bad data offsets")
        if begin < end:
            spans.append((begin, end, name))

        def chunks(begin=begin, end=end, name=name):
            try:
                f.seek(base + begin)
                while begin < end:
                    want = min(CHUNK, end - begin)
                    block = f.read(want)
                    if len(block) != want:
                        raise ConvertError(f"safetensors entry {name} is cut short (the file "
                                           f"shrank while being read)")
                    yield block
                    begin += want
            except OSError as e:
                raise ConvertError(f"cannot read ({e.strerror or e})")

        named[name] = Tensor(dtype, shape, chunks)
    spans.sort()
    for (_, end, first), (begin, _, second) in zip(spans, spans[1:]):
        if begin < end:
            raise ConvertError(f"safetensors entries {first} and {second} share bytes (their "
                               f"data_offsets overlap)")
    return named


def read_hf_config(path):
    """The vision part of the config.json beside a safetensors file, or None when there is
    none. Opened as the input is (a FIFO or a directory refused unread), bounded in size and
    depth, and its integer fields checked to be integers (true is not 1)."""
    config_path = os.path.join(os.path.dirname(os.path.abspath(path)), "config.json")
    if not os.path.lexists(config_path):
        return None
    try:
        with open_regular(config_path) as f:
            size = os.fstat(f.fileno()).st_size
            if size > MAX_CONFIG_BYTES:
                raise ConvertError(f"{size} bytes; a CLIP config.json has a few thousand")
            raw = f.read(MAX_CONFIG_BYTES + 1)
    except OSError as e:
        raise ConvertError(f"cannot read {config_path} ({e.strerror or e})")
    except ConvertError as e:
        raise ConvertError(f"cannot read {config_path} ({e})")
    config = parse_json(raw, config_path)
    # CLIPModel: nested (older files name it vision_config_dict); CLIPVisionModel: top level
    vision = None
    if isinstance(config, dict):
        vision = config.get("vision_config") or config.get("vision_config_dict") or config
    if not isinstance(vision, dict):
        raise ConvertError(f"{config_path} has no vision_config")
    act = vision.get("hidden_act", "quick_gelu")
    if act != "quick_gelu":
        raise ConvertError(f"{config_path} says hidden_act {brief(act)}; wiresketch implements "
                           f"OpenAI's quick_gelu only")
    eps = vision.get("layer_norm_eps", 1e-5)
    if eps != 1e-5:
        raise ConvertError(f"{config_path} says layer_norm_eps {brief(eps)}; wiresketch uses 1e-5")
    for key in ("num_attention_heads", "hidden_size", "num_hidden_layers", "patch_size", "image_size"):
        if key in vision and type(vision[key]) is not int:
            raise ConvertError(f"{config_path} says {key} {brief(vision[key])}, not an integer")
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
    if (width > MAX_WIDTH or layers > MAX_LAYERS or patch * grid > MAX_RESOLUTION
            or proj[1] > MAX_WIDTH):
        raise ConvertError(f"width {width}, {layers} layers, resolution {patch * grid}, output "
                           f"{proj[1]}: beyond what wiresketch loads (width and output {MAX_WIDTH}, "
                           f"{MAX_LAYERS} layers, resolution {MAX_RESOLUTION})")
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


def tensor_chunks(t, out_dtype, name):
    """The bytes of a tower tensor in out_dtype, in pieces: a Concat part by part, a Transposed
    one whole (the transpose needs it all; it is the projection, well under a megabyte)."""
    if isinstance(t, Concat):
        for p in t.parts:
            yield from encode(p, out_dtype, name)
    elif isinstance(t, Transposed):
        rows, cols = t.tensor.shape
        data = b"".join(encode(t.tensor, out_dtype, name))
        yield transpose2(data, rows, cols, ELEMENT[out_dtype][0])
    else:
        yield from encode(t, out_dtype, name)


def written_through(out_path):
    """Is OUT a character device, FIFO or socket (/dev/null, a named pipe), or one of the
    process's descriptors (/dev/stdout)? Such an OUT is written to, never replaced: renaming
    a file onto it would replace the device or the link, not write to what it stands for."""
    try:
        mode = os.stat(out_path).st_mode
    except OSError:
        return False
    if stat.S_ISCHR(mode) or stat.S_ISFIFO(mode) or stat.S_ISSOCK(mode):
        return True
    link = os.readlink(out_path) if os.path.islink(out_path) else ""
    parent = os.path.realpath(os.path.dirname(os.path.abspath(out_path)))
    return link.startswith("/proc/") or parent.startswith("/proc/")


def write_weight_file(out_path, arch, tower, expected, out_dtype, display):
    """Writes OUT.tmp.PID (created new) and renames it to OUT, so that OUT is complete or
    untouched; the temporary file is removed on any failure, SIGINT and SIGTERM included
    (Interrupted), and a write error names OUT, the file the user asked for. A character
    device, FIFO or descriptor OUT (written_through) is written to directly instead."""
    element = ELEMENT[out_dtype][0]
    count = len(expected)
    offset = HEADER.size + count * ENTRY.size
    table, offsets = [], []
    for name, shape in expected:
        offset = (offset + ALIGN - 1) // ALIGN * ALIGN
        nbytes = numel_of(shape) * element
        dims = list(shape) + [0] * (4 - len(shape))
        table.append(ENTRY.pack(name.encode("ascii"), OUT_DTYPES[out_dtype], len(shape), *dims,
                                offset, nbytes))
        offsets.append(offset)
        offset += nbytes
    head = HEADER.pack(MAGIC, VERSION, arch["width"], arch["layers"], arch["heads"], arch["patch"],
                       arch["resolution"], arch["output_dim"], count) + b"".join(table)
    through = written_through(out_path)
    tmp = None if through else f"{out_path}.tmp.{os.getpid()}"
    created = False
    try:
        # the temporary file is created new (O_EXCL), never opened through a link planted at its name;
        # a stopping signal waits until `created` says so, or the file it made would stay
        held = signal.pthread_sigmask(signal.SIG_BLOCK, STOP_SIGNALS)
        try:
            fd = (os.open(out_path, os.O_WRONLY | os.O_APPEND) if through else
                  os.open(tmp, os.O_WRONLY | os.O_CREAT | os.O_EXCL | os.O_NOFOLLOW, 0o666))
            created = not through
        finally:
            signal.pthread_sigmask(signal.SIG_SETMASK, held)
        with os.fdopen(fd, "wb") as f:
            crc, pos = 0, 0

            def put(b):
                nonlocal crc, pos
                f.write(b)
                crc = zlib.crc32(b, crc)
                pos += len(b)

            put(head)
            for (name, _), start in zip(expected, offsets):
                put(b"\0" * (start - pos))
                for piece in tensor_chunks(tower[name], out_dtype, display(name)):
                    put(piece)
            f.write(struct.pack("<I", crc & 0xffffffff))
            f.flush()
            if not through:
                os.fsync(f.fileno())
        if not through:
            os.replace(tmp, out_path)
    except BaseException as e:
        if created and os.path.lexists(tmp):
            os.unlink(tmp)
        if isinstance(e, OSError):  # reading the input raises ConvertError, not OSError
            raise ConvertError(f"cannot write ({e.strerror or e})", out_path) from None
        raise
    return pos + 4


def load_tower(f, path, heads):
    """(tower, architecture, display): OpenAI-named tensors of the image tower read from f,
    the open input path; display maps such a name back to the name in the input file."""
    size = os.fstat(f.fileno()).st_size
    try:
        is_zip = zipfile.is_zipfile(f)
    except ZIP_ERRORS as e:  # is_zipfile reads the end records, and can trip on them
        raise ConvertError(f"a damaged zip file ({e})")
    if is_zip:
        archive = TorchArchive(f)
        named = named_tensors(archive, archive.load())
        prefixed = any(k.startswith("visual.") for k in named)
        tower = image_tower_from_torch(named)

        def display(name):
            return "visual." + name if prefixed else name

        return tower, architecture(tower, heads, None, display), display
    f.seek(0)
    start = f.read(9)
    if len(start) == 9 and start[8:9] == b"{" and struct.unpack("<Q", start[:8])[0] <= size - 8:
        f.seek(0)
        tower = image_tower_from_hf(read_safetensors(f, size))
        return tower, architecture(tower, heads, read_hf_config(path), hf_name), hf_name
    if start[:2] == b"\x80\x02":
        raise ConvertError("a legacy (pre-1.6) torch.save file; re-save it with a current PyTorch")
    raise ConvertError("unknown format (expected a TorchScript archive such as ViT-B-32.pt, a "
                       "torch.save state dict, or a model.safetensors)")


def same_file(a, b):
    """Whether writing b would replace a: one path, or two names (a hard or symbolic link)
    of one file. Converting a model onto itself would destroy the user's original."""
    if os.path.abspath(a) == os.path.abspath(b):
        return True
    try:
        return os.path.samefile(a, b)
    except OSError:  # b does not exist yet
        return False


def convert(args):
    """Converts args.input to args.output; returns the success line or raises."""
    with open_regular(args.input) as f:
        if same_file(args.input, args.output):
            raise ConvertError(f"the same file as {args.output}; refusing to overwrite the model "
                               f"with its conversion")
        if os.path.isdir(args.output):
            raise ConvertError("is a directory", args.output)
        tower, arch, display = load_tower(f, args.input, args.heads)
        expected = check_tower(tower, arch, display)
        nbytes = write_weight_file(args.output, arch, tower, expected, args.dtype, display)
    return (f"{args.output}: ViT width {arch['width']}, {arch['layers']} layers, {arch['heads']} "
            f"heads, patch {arch['patch']}, resolution {arch['resolution']}, output "
            f"{arch['output_dim']}; {len(expected)} tensors, {args.dtype}, {nbytes} bytes")


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
    for s in STOP_SIGNALS:
        signal.signal(s, on_signal)
    signal.signal(signal.SIGXFSZ, signal.SIG_IGN)
    try:
        line = convert(args)
    except ConvertError as e:
        where, what = e.path or args.input, str(e)
    except OSError as e:  # opening or reading the input
        where, what = e.filename or args.input, e.strerror or str(e)
    except Interrupted:
        where, what = args.output, f"interrupted by {Interrupted.signal_name}; not written"
    except MemoryError:
        where, what = args.input, "out of memory converting it (a limit such as ulimit -v is too low)"
    else:
        return print_result(line)
    print(f"convert_weights.py: {one_line(str(where))}: {one_line(what)}", file=sys.stderr)
    return 1


def print_result(line):
    """Prints the success line; a closed or full stdout, or a reader gone (Python ignores
    SIGPIPE), is one line and exit 1, not a traceback at exit. OUT is written either way."""
    try:
        if sys.stdout is None:  # started with stdout closed
            raise OSError(errno.EBADF, os.strerror(errno.EBADF))
        print(line)
        sys.stdout.flush()
        return 0
    except OSError as e:
        why = e.strerror or str(e)
    if sys.stdout is not None:  # what is still buffered goes nowhere at exit, not into a traceback
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
        os.close(devnull)
    print(f"convert_weights.py: standard output: write failed: {why}", file=sys.stderr)
    return 1


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
