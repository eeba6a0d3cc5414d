#!/usr/bin/env bash
# make demo: synthetic scenes made by wiresketch itself: a solid cube
# fitted with the weight-free line loss, and (when weights/clip-vit-b32.bin
# exists) the trefoil with CLIP; each evaluated against its ground-truth
# curves. Outputs in demo/.
set -euo pipefail
cd "$(dirname "$0")/.."
ws=${BUILD:-build}/wiresketch
mkdir -p demo
[ -f demo/trefoil/transforms_train.json ] || "$ws" scene trefoil --out demo/trefoil
[ -f demo/cube/transforms_train.json ] || "$ws" scene cube --out demo/cube
# the line loss with its own defaults, on a solid: it draws edges
"$ws" fit demo/cube --out demo/fit-edges --loss edges --seed 1
echo "evaluation against the ground-truth edges (demo/fit-edges):"
"$ws" eval demo/cube --curves demo/fit-edges/curves.json --loss edges
report=demo/fit-edges/report.html
fit="--epochs 6 --inner-steps 30 --length 0.3 --seed 1"
if [ -f weights/clip-vit-b32.bin ]; then
    "$ws" fit demo/trefoil --out demo/fit-clip --loss clip+edges $fit
    echo "evaluation against the ground-truth curves (demo/fit-clip):"
    "$ws" eval demo/trefoil --curves demo/fit-clip/curves.json --loss clip+edges
    report="$report and demo/fit-clip/report.html"
else
    echo "(no weights/clip-vit-b32.bin: CLIP fit skipped; see weights/README.md)"
fi
echo "report: $report"
