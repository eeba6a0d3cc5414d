#!/usr/bin/python3
"""make_fixtures.py: the tiny CLIP fixture of tests/test_clip_fixture.c.

Developers only (needs torch; run with the system python that has it):
    /usr/bin/python3 tools/make_fixtures.py
Rewrites tests/fixtures/clip_tiny/ (deterministic: seeded; about 1.4 MB).
Every file comes out byte-identical again except the TorchScript archive,
whose zip records differ from run to run (the script checks that it holds
exactly the same numbers): keep the committed one unless the model changes.

The model mirrors openai/CLIP's VisionTransformer exactly (conv1 without
bias, class token, positional embedding, ln_pre, pre-norm residual blocks of
torch's MultiheadAttention and a QuickGELU MLP, ln_post on the class token,
proj), at width 64, 2 layers, 4 heads, patch 16, resolution 64, output 32,
inside a CLIP wrapper with a toy text tower so that every file also holds
tensors the converter must leave out. Every weight (biases and LayerNorm
parameters included, so that a mix-up cannot hide behind ones and zeros) is
random and rounded to the nearest f16 value, so that the three files below
hold exactly the same numbers whatever their dtype, and one set of
expectations serves them all. All three store the tensors in OpenAI's mixed
precision (convert_weights: conv, linear, attention and projection weights
fp16; embeddings and LayerNorms fp32), which exercises both dtypes of every
reader and keeps the fixture small.

Files (tests/fixtures/clip_tiny/):
  clip_tiny_torchscript.pt  traced TorchScript archive like OpenAI's
                            ViT-B-32.pt
  clip_tiny_state_dict.pt   torch.save of the state dict (visual.* and text)
  hf/model.safetensors      Hugging Face names, hand-written format
  hf/config.json            its CLIPConfig (num_attention_heads 4)
  image.png                 the 64 x 64 RGB input (image 0 of the batch)
  expected.json, expected.bin  the reference values, layout below

expected.bin is a sequence of little-endian float32 arrays, each stored
row-major; expected.json gives "arch", "batch" and "arrays": for each name
{"shape": [...], "offset": byte offset into expected.bin}. Arrays:
  images       [B, 3, R, R]  input in [0, 1] (image 1 is image 0 mirrored
                             left-right); exactly the PNG's bytes / 255
  hidden_l     [B, T, W]     h_l, output of residual block l
  d_hidden_l   [B, T, W]     C_l, the cotangent of h_l
  embedding    [B, out]      e
  d_embedding  [B, out]      C_e
  d_images     [B, 3, R, R]  dL/d images for L = sum_l sum(h_l * C_l)
                             + sum(e * C_e), in [0, 1] pixel units (CLIP's
                             normalisation is inside the differentiated map)
  attention.json, attention.bin  the same layout, for the attention-map
                            variant of the geometric loss (same model,
                            same images):
    attention_l    [B, H, T, T]  P_l, block l's attention probabilities
                                 (query rows, key columns; torch's
                                 need_weights=True, average_attn_weights=False)
    d_attention_l  [B, H, T, T]  D_l, the cotangent of P_l
    d_images       [B, 3, R, R]  dL/d images for L = sum_l sum(P_l * D_l)
All expectations are computed in float64 from the f16-rounded weights.
"""
import copy
import json
import os
import struct
import sys
import zlib
from collections import OrderedDict

import torch
import torch.nn as nn

OUT_DIR = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tests", "fixtures", "clip_tiny")
WIDTH, LAYERS, HEADS, PATCH, RESOLUTION, OUTPUT = 64, 2, 4, 16, 64, 32
TEXT_WIDTH, TEXT_LAYERS, TEXT_HEADS, CONTEXT, VOCAB = 32, 1, 2, 8, 48
BATCH = 2
MEAN = (0.48145466, 0.4578275, 0.40821073)
STD = (0.26862954, 0.26130258, 0.27577711)


# ---- openai/CLIP's image tower, written out again -------------------------

class LayerNorm(nn.LayerNorm):
    """OpenAI's LayerNorm computes in fp32 for fp16 inputs; float64 inputs
    stay float64 here so that the expectations are float64 throughout."""

    def forward(self, x):
        if x.dtype == torch.float16:
            return super().forward(x.float()).half()
        return super().forward(x)


class QuickGELU(nn.Module):
    def forward(self, x):
        return x * torch.sigmoid(1.702 * x)


class ResidualAttentionBlock(nn.Module):
    def __init__(self, width, heads, attn_mask=None):
        super().__init__()
        self.attn = nn.MultiheadAttention(width, heads)
        self.ln_1 = LayerNorm(width)
        self.mlp = nn.Sequential(OrderedDict([
            ("c_fc", nn.Linear(width, width * 4)),
            ("gelu", QuickGELU()),
            ("c_proj", nn.Linear(width * 4, width))]))
        self.ln_2 = LayerNorm(width)
        self.attn_mask = attn_mask

    def forward(self, x):
        mask = self.attn_mask.to(x.dtype) if self.attn_mask is not None else None
        y = self.ln_1(x)
        x = x + self.attn(y, y, y, need_weights=False, attn_mask=mask)[0]
        return x + self.mlp(self.ln_2(x))

    def forward_with_probs(self, x):
        """(forward(x), the attention probabilities [B, H, T, T]); no mask (the image tower's)."""
        y = self.ln_1(x)
        a, probs = self.attn(y, y, y, need_weights=True, average_attn_weights=False)
        x = x + a
        return x + self.mlp(self.ln_2(x)), probs


class Transformer(nn.Module):
    def __init__(self, width, layers, heads, attn_mask=None):
        super().__init__()
        self.width, self.layers = width, layers
        self.resblocks = nn.Sequential(*[ResidualAttentionBlock(width, heads, attn_mask) for _ in range(layers)])

    def forward(self, x):
        return self.resblocks(x)


class VisionTransformer(nn.Module):
    def __init__(self, input_resolution, patch_size, width, layers, heads, output_dim):
        super().__init__()
        scale = width ** -0.5
        self.conv1 = nn.Conv2d(3, width, kernel_size=patch_size, stride=patch_size, bias=False)
        self.class_embedding = nn.Parameter(scale * torch.randn(width))
        self.positional_embedding = nn.Parameter(scale * torch.randn((input_resolution // patch_size) ** 2 + 1, width))
        self.ln_pre = LayerNorm(width)
        self.transformer = Transformer(width, layers, heads)
        self.ln_post = LayerNorm(width)
        self.proj = nn.Parameter(scale * torch.randn(width, output_dim))

    def embed(self, x):
        """Input tokens of the transformer, LND."""
        x = self.conv1(x)
        x = x.reshape(x.shape[0], x.shape[1], -1).permute(0, 2, 1)
        cls = self.class_embedding.to(x.dtype) + torch.zeros(x.shape[0], 1, x.shape[-1], dtype=x.dtype)
        x = torch.cat([cls, x], dim=1) + self.positional_embedding.to(x.dtype)
        return self.ln_pre(x).permute(1, 0, 2)

    def head(self, x):
        """e from the last block's output, LND."""
        return self.ln_post(x.permute(1, 0, 2)[:, 0, :]) @ self.proj

    def forward(self, x):
        return self.head(self.transformer(self.embed(x)))

    def forward_with_hidden(self, x):
        """(every h_l as [B, T, W], e): the same computation, block by block."""
        x = self.embed(x)
        hidden = []
        for block in self.transformer.resblocks:
            x = block(x)
            hidden.append(x.permute(1, 0, 2))
        return hidden, self.head(x)

    def attention_probs(self, x):
        """Every block's attention probabilities, [B, H, T, T] each."""
        x = self.embed(x)
        probs = []
        for block in self.transformer.resblocks:
            x, p = block.forward_with_probs(x)
            probs.append(p)
        return probs


class CLIP(nn.Module):
    """OpenAI's CLIP with a ViT image tower and a toy text tower."""

    def __init__(self, width=WIDTH, layers=LAYERS, heads=HEADS, patch=PATCH, resolution=RESOLUTION,
                 output_dim=OUTPUT):
        super().__init__()
        self.visual = VisionTransformer(resolution, patch, width, layers, heads, output_dim)
        mask = torch.full((CONTEXT, CONTEXT), float("-inf")).triu_(1)
        self.transformer = Transformer(TEXT_WIDTH, TEXT_LAYERS, TEXT_HEADS, mask)
        self.token_embedding = nn.Embedding(VOCAB, TEXT_WIDTH)
        self.positional_embedding = nn.Parameter(0.01 * torch.randn(CONTEXT, TEXT_WIDTH))
        self.ln_final = LayerNorm(TEXT_WIDTH)
        self.text_projection = nn.Parameter(TEXT_WIDTH ** -0.5 * torch.randn(TEXT_WIDTH, output_dim))
        self.logit_scale = nn.Parameter(torch.tensor(2.6592))
        # OpenAI's JIT archives carry these as tensors (clip.py reads input_resolution.item())
        self.register_buffer("input_resolution", torch.tensor(resolution))
        self.register_buffer("context_length", torch.tensor(CONTEXT))
        self.register_buffer("vocab_size", torch.tensor(VOCAB))

    def encode_image(self, image):
        return self.visual(image)

    def encode_text(self, text):
        x = self.token_embedding(text) + self.positional_embedding
        x = self.ln_final(self.transformer(x.permute(1, 0, 2)).permute(1, 0, 2))
        return x[torch.arange(x.shape[0]), text.argmax(dim=-1)] @ self.text_projection

    def forward(self, image, text):
        i = self.encode_image(image)
        t = self.encode_text(text)
        i = i / i.norm(dim=-1, keepdim=True)
        t = t / t.norm(dim=-1, keepdim=True)
        logits = self.logit_scale.exp() * i @ t.t()
        return logits, logits.t()


def randomise(model, seed):
    """Random weights of trained-model scale, every one f16-representable."""
    g = torch.Generator().manual_seed(seed)
    with torch.no_grad():
        for name, p in model.named_parameters():
            if ".ln_" in "." + name and name.endswith(".weight"):
                p.copy_(1 + 0.2 * torch.randn(p.shape, generator=g))
            elif name.endswith("bias"):
                p.copy_(0.1 * torch.randn(p.shape, generator=g))
            elif name != "logit_scale":
                # x @ proj reads proj's rows; nn weights [out, in...] read a row each
                fan_in = p.shape[0] if name.endswith("proj") or p.dim() == 1 else p[0].numel()
                p.copy_(torch.randn(p.shape, generator=g) * fan_in ** -0.5)
            p.copy_(p.half().float())


# OpenAI's convert_weights: these become fp16, everything else stays fp32
def is_fp16_in_openai(name):
    leaf = name.rsplit(".", 1)[-1]
    return (name.endswith(("in_proj_weight", "in_proj_bias", "text_projection")) or leaf == "proj"
            or any(f".{m}." in f".{name}" for m in ("conv1", "out_proj", "c_fc", "c_proj")))


# ---- the three files -----------------------------------------------------

def save_torchscript(model, path):
    resolution = int(model.input_resolution)
    image = torch.rand(1, 3, resolution, resolution)
    text = torch.randint(0, VOCAB, (1, CONTEXT))
    # a traced module shares its parameters with the original: trace a copy
    traced = torch.jit.trace_module(copy.deepcopy(model), {"forward": (image, text), "encode_image": image,
                                            "encode_text": text}, check_trace=False)
    for name, p in traced.named_parameters():
        if is_fp16_in_openai(name):
            p.data = p.data.half()
    torch.jit.save(traced, path)
    loaded = torch.jit.load(path).state_dict()
    for name, t in model.state_dict().items():  # the archive holds exactly our numbers
        assert torch.equal(loaded[name].float(), t.float()), name
        assert (loaded[name].dtype == torch.float16) == is_fp16_in_openai(name), name


def openai_precision(model):
    """The state dict as OpenAI's convert_weights leaves it: fp16 and fp32 mixed."""
    return OrderedDict((k, v.half() if is_fp16_in_openai(k) else v) for k, v in model.state_dict().items())


def hf_tensors(sd):
    """A state dict under Hugging Face's CLIPModel names (vision + a few text)."""
    out = OrderedDict()
    v = "vision_model."
    out[v + "embeddings.class_embedding"] = sd["visual.class_embedding"]
    out[v + "embeddings.patch_embedding.weight"] = sd["visual.conv1.weight"]
    out[v + "embeddings.position_embedding.weight"] = sd["visual.positional_embedding"]
    out[v + "embeddings.position_ids"] = torch.arange(sd["visual.positional_embedding"].shape[0]).unsqueeze(0)
    for kind in ("weight", "bias"):
        out[v + "pre_layrnorm." + kind] = sd["visual.ln_pre." + kind]
        out[v + "post_layernorm." + kind] = sd["visual.ln_post." + kind]
    layers = sum(1 for k in sd if k.startswith("visual.") and k.endswith(".attn.in_proj_weight"))
    for i in range(layers):
        o, h = f"visual.transformer.resblocks.{i}.", f"{v}encoder.layers.{i}."
        for kind in ("weight", "bias"):
            q, k, vv = sd[o + "attn.in_proj_" + kind].chunk(3)
            out[h + "self_attn.q_proj." + kind] = q
            out[h + "self_attn.k_proj." + kind] = k
            out[h + "self_attn.v_proj." + kind] = vv
            out[h + "self_attn.out_proj." + kind] = sd[o + "attn.out_proj." + kind]
            out[h + "layer_norm1." + kind] = sd[o + "ln_1." + kind]
            out[h + "layer_norm2." + kind] = sd[o + "ln_2." + kind]
            out[h + "mlp.fc1." + kind] = sd[o + "mlp.c_fc." + kind]
            out[h + "mlp.fc2." + kind] = sd[o + "mlp.c_proj." + kind]
    out["visual_projection.weight"] = sd["visual.proj"].t()
    out["text_model.embeddings.token_embedding.weight"] = sd["token_embedding.weight"]
    out["text_projection.weight"] = sd["text_projection"].t()
    out["logit_scale"] = sd["logit_scale"]
    return out


def save_safetensors(tensors, path):
    """The safetensors layout by hand: u64 header length, JSON header, data."""
    header, blobs, offset = {"__metadata__": {"format": "pt"}}, [], 0
    for name, t in tensors.items():
        t = t.contiguous()
        dtype = {torch.float32: "F32", torch.float16: "F16", torch.int64: "I64"}[t.dtype]
        blob = t.numpy().tobytes()
        header[name] = {"dtype": dtype, "shape": list(t.shape), "data_offsets": [offset, offset + len(blob)]}
        blobs.append(blob)
        offset += len(blob)
    text = json.dumps(header, separators=(",", ":")).encode()
    text += b" " * (-len(text) % 8)
    with open(path, "wb") as f:
        f.write(struct.pack("<Q", len(text)) + text + b"".join(blobs))


def save_hf_config(path, width, layers, heads, patch, resolution, output_dim):
    config = {"model_type": "clip", "projection_dim": output_dim,
              "vision_config": {"hidden_size": width, "num_hidden_layers": layers, "num_attention_heads": heads,
                                "patch_size": patch, "image_size": resolution, "intermediate_size": 4 * width,
                                "hidden_act": "quick_gelu", "layer_norm_eps": 1e-5},
              "text_config": {"hidden_size": TEXT_WIDTH, "num_hidden_layers": TEXT_LAYERS,
                              "num_attention_heads": TEXT_HEADS, "vocab_size": VOCAB}}
    with open(path, "w") as f:
        json.dump(config, f, indent=1)
        f.write("\n")


def save_png(path, rgb_u8):
    """An 8-bit RGB PNG from a [3, H, W] uint8 tensor."""
    _, h, w = rgb_u8.shape
    rows = rgb_u8.permute(1, 2, 0).contiguous().numpy()
    raw = b"".join(b"\0" + rows[i].tobytes() for i in range(h))

    def chunk(kind, data):
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data))

    with open(path, "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 2, 0, 0, 0))
                + chunk(b"IDAT", zlib.compress(raw, 9)) + chunk(b"IEND", b""))


def test_image(size, seed):
    """A smooth image with some structure: gradients plus soft blobs."""
    g = torch.Generator().manual_seed(seed)
    ys, xs = torch.meshgrid(torch.linspace(0, 1, size), torch.linspace(0, 1, size), indexing="ij")
    img = torch.stack([xs, ys, 0.5 * (1 - xs) + 0.3 * ys])
    for _ in range(6):
        cy, cx, r = torch.rand(3, generator=g)
        color = torch.rand(3, 1, 1, generator=g)
        blob = torch.exp(-((ys - cy) ** 2 + (xs - cx) ** 2) / (0.02 + 0.05 * r))
        img = img * (1 - blob) + color * blob
    return (img.clamp(0, 1) * 255).round().to(torch.uint8)


def normalise(x):
    """CLIP's per-channel normalisation of [0, 1] images."""
    mean = torch.tensor(MEAN, dtype=x.dtype).view(1, 3, 1, 1)
    std = torch.tensor(STD, dtype=x.dtype).view(1, 3, 1, 1)
    return (x - mean) / std


def expectations(model, images):
    visual = model.visual.double()
    x = images.double().requires_grad_(True)
    hidden, e = visual.forward_with_hidden(normalise(x))
    assert torch.allclose(e, visual(normalise(x)), rtol=0, atol=1e-12)
    g = torch.Generator().manual_seed(5)
    d_hidden = [torch.randn(h.shape, generator=g, dtype=torch.float64) for h in hidden]
    d_e = torch.randn(e.shape, generator=g, dtype=torch.float64)
    loss = sum((h * c).sum() for h, c in zip(hidden, d_hidden)) + (e * d_e).sum()
    loss.backward()
    arrays = OrderedDict(images=images)
    for i, (h, c) in enumerate(zip(hidden, d_hidden)):
        arrays[f"hidden_{i}"] = h.detach()
        arrays[f"d_hidden_{i}"] = c
    arrays["embedding"] = e.detach()
    arrays["d_embedding"] = d_e
    arrays["d_images"] = x.grad
    model.visual.float()
    return arrays


def attention_expectations(model, images):
    visual = model.visual.double()
    x = images.double().requires_grad_(True)
    probs = visual.attention_probs(normalise(x))
    g = torch.Generator().manual_seed(13)
    d_probs = [torch.randn(p.shape, generator=g, dtype=torch.float64) for p in probs]
    sum(((p * c).sum() for p, c in zip(probs, d_probs))).backward()
    arrays = OrderedDict()
    for i, (p, c) in enumerate(zip(probs, d_probs)):
        assert torch.allclose(p.sum(-1), torch.ones((), dtype=p.dtype), rtol=0, atol=1e-12)
        arrays[f"attention_{i}"] = p.detach()
        arrays[f"d_attention_{i}"] = c
    arrays["d_images"] = x.grad
    model.visual.float()
    return arrays


def save_expected(arrays, json_path, bin_path):
    index, blobs, offset = OrderedDict(), [], 0
    for name, a in arrays.items():
        blob = a.float().contiguous().numpy().astype("<f4").tobytes()
        index[name] = {"shape": list(a.shape), "offset": offset}
        blobs.append(blob)
        offset += len(blob)
    with open(bin_path, "wb") as f:
        f.write(b"".join(blobs))
    meta = {"format": "little-endian float32 arrays in expected.bin, row-major; see tools/make_fixtures.py",
            "arch": {"width": WIDTH, "layers": LAYERS, "heads": HEADS, "patch": PATCH,
                     "resolution": RESOLUTION, "output_dim": OUTPUT},
            "batch": BATCH, "arrays": index}
    with open(json_path, "w") as f:
        json.dump(meta, f, indent=1)
        f.write("\n")


def main():
    torch.manual_seed(3)
    model = CLIP().eval()
    randomise(model, 7)
    os.makedirs(os.path.join(OUT_DIR, "hf"), exist_ok=True)
    save_torchscript(model, os.path.join(OUT_DIR, "clip_tiny_torchscript.pt"))
    torch.save(openai_precision(model), os.path.join(OUT_DIR, "clip_tiny_state_dict.pt"))
    save_safetensors(hf_tensors(openai_precision(model)), os.path.join(OUT_DIR, "hf", "model.safetensors"))
    save_hf_config(os.path.join(OUT_DIR, "hf", "config.json"), WIDTH, LAYERS, HEADS, PATCH, RESOLUTION, OUTPUT)
    u8 = test_image(RESOLUTION, 11)
    save_png(os.path.join(OUT_DIR, "image.png"), u8)
    # exactly the values a [0, 1] reader of the PNG produces, as float32
    image = (u8.float() / 255).unsqueeze(0)
    images = torch.cat([image, image.flip(-1)])
    arrays = expectations(model, images)
    save_expected(arrays, os.path.join(OUT_DIR, "expected.json"), os.path.join(OUT_DIR, "expected.bin"))
    arrays = attention_expectations(model, images)
    save_expected(arrays, os.path.join(OUT_DIR, "attention.json"), os.path.join(OUT_DIR, "attention.bin"))
    total = sum(os.path.getsize(os.path.join(d, n)) for d, _, names in os.walk(OUT_DIR) for n in names)
    print(f"{OUT_DIR}: {total} bytes")


if __name__ == "__main__":
    sys.exit(main())
