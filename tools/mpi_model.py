#!/usr/bin/env python3
"""The step time of an MPI fit on N ranks, modelled from per-image costs.

usage: python3 tools/mpi_model.py --stroke MS --photo MS --view MS
           [--latency US] [--bandwidth GBPS] [--size 224] [--num-aug 4] [--curves 25]

Each rank computes the units of work that src/objective/objective.c gives
it (one CLIP pass of one stroke image, --clip-batch 1: units
U r / N .. U (r + 1) / N of U = B (1 + A)): a stroke image's CLIP forward
and backward (--stroke), plus the forward of its augmented photo for items
a > 0 (--photo; item 0's photo features are cached), and for every view it
touches the splatting, augmentation and combination (--view, charged in
full to every rank that touches the view). The slowest rank sets the
pace. Communication: the owner of a view split over ranks receives those
ranks' dL/dalpha images (size x size float32) and item losses; then an
all-gather of every view's loss and dL/dP (1 + 12 x curves doubles) and an
all-reduce of the stop flag: each collective costs the latency times
ceil(log2 N) plus its bytes over the bandwidth. Prints a Markdown table
of step time (ms) and speed-up for batch sizes 1, 4 and 16 and N = 1..64.
Standard library only.
"""
import argparse
import math


def unit_start(U, r, N):
    return U * r // N


def step_time(N, B, G, a):
    """(step ms, bytes sent per step) for N ranks, B views of 1 + A items, passes of G."""
    n = 1 + a.num_aug
    P = -(-n // G)
    U = B * P
    stroke, photo = (a.stroke, a.photo) if G == 1 else (a.stroke_batched, a.photo_batched)
    image = a.size * a.size * 4 + 8
    record = (1 + 12 * a.curves) * 8
    lat = a.latency * 1e-3  # ms
    per_ms = a.bandwidth * 1e6  # bytes per ms

    def items(u):  # (first, count) of unit u's pass
        first = (u % P) * G
        return first, min(G, n - first)

    worst, sent = 0.0, 0
    for r in range(N):
        lo, hi = unit_start(U, r, N), unit_start(U, r + 1, N)
        compute = 0.0
        for u in range(lo, hi):
            first, count = items(u)
            compute += count * stroke + (count - (first == 0)) * photo
        views = sorted({u // P for u in range(lo, hi)})
        compute += a.view * len(views)
        received = 0
        for k in views:
            if k * P >= lo and (k + 1) * P > hi:  # owns view k; later ranks hold its tail
                received += sum(items(u)[1] for u in range(hi, (k + 1) * P)) * image
        if lo < hi and (lo // P) * P < lo:  # its first view belongs to an earlier rank
            sent += sum(items(u)[1] for u in range(lo, min(hi, (lo // P + 1) * P))) * image
        worst = max(worst, compute + ((lat + received / per_ms) if received else 0.0))
    if N == 1:
        return worst, 0
    rounds = math.ceil(math.log2(N))
    sent += B * record * (N - 1) + 4 * N * (N - 1)
    return worst + 3 * lat * rounds + B * record / per_ms, sent


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--stroke", type=float, required=True, help="ms: a stroke image's CLIP forward + backward")
    p.add_argument("--photo", type=float, required=True, help="ms: an augmented photo's CLIP forward")
    p.add_argument("--stroke-batched", type=float, required=True,
                   help="ms per image: stroke images' CLIP forward + backward in a pass of 1 + A")
    p.add_argument("--photo-batched", type=float, required=True,
                   help="ms per image: augmented photos' CLIP forward in a pass of A")
    p.add_argument("--view", type=float, required=True, help="ms per view: splatting, augmentation, combining")
    p.add_argument("--latency", type=float, default=50.0, help="microseconds per message [50]")
    p.add_argument("--bandwidth", type=float, default=1.25, help="GB/s [1.25: 10 Gb/s Ethernet]")
    p.add_argument("--size", type=int, default=224)
    p.add_argument("--num-aug", type=int, default=4)
    p.add_argument("--curves", type=int, default=25)
    a = p.parse_args()
    ranks = [1, 2, 3, 4, 5, 8, 10, 16, 20, 32, 40, 64]
    batches = [1, 4, 16]
    whole = 1 + a.num_aug
    print("| ranks | " + " | ".join(f"B = {b}: step (ms) | speed-up | G | MB sent/step" for b in batches) + " |")
    print("| ---: | " + " | ".join("---: | ---: | ---: | ---:" for _ in batches) + " |")
    base = {b: step_time(1, b, whole, a)[0] for b in batches}
    for n in ranks:
        cells = []
        for b in batches:
            t, sent, g = min(step_time(n, b, g, a) + (g,) for g in (whole, 1))
            cells.append(f"{t:.0f} | {base[b] / t:.1f} | {g} | {sent / 1e6:.2f}")
        print(f"| {n} | " + " | ".join(cells) + " |")


if __name__ == "__main__":
    main()
