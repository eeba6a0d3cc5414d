#!/usr/bin/env bash
# Quality against wall time (METHOD.md sections 7 and 8): fits the shared scenes
# rose and duck with the weight-free edge loss at three budgets of schedule
# (1, 3 and 10 epochs: the last is the original's whole default schedule,
# 10 x 96 views x 30 steps = 28,800 steps) and tabulates the fit's wall time
# against the test loss and the surface distance of `wiresketch eval`.
#
# usage: bash tools/quality_vs_time.sh [EPOCHS ...]     (default: 1 3 10)
# env:   BUILD (build), SCENES (../shared/scenes), OUT (build/quality),
#        FIT_ARGS (extra fit options)
# The table goes to stdout and to $OUT/table.md; each fit stays in
# $OUT/SCENE-eEPOCHS (report.html, test renders).
#
# Settings: the defaults of METHOD.md section 7 except --radius 0.5 and
# --length 0.3 (the initial curves start inside these objects, which fill
# about a third of the frame, and long enough to be seen); chosen on
# one-epoch runs of both scenes, where they gave the lowest surface
# distance of the settings tried (README, "Speed and accuracy").
set -euo pipefail
cd "$(dirname "$0")/.."
ws=${BUILD:-build}/wiresketch
scenes=${SCENES:-../shared/scenes}
out=${OUT:-build/quality}
budgets=("$@")
[ ${#budgets[@]} -gt 0 ] || budgets=(1 3 10)
settings="--loss edges --radius 0.5 --length 0.3 ${FIT_ARGS:-}"
mkdir -p "$out"
table="$out/table.md"
{
    echo "| scene | epochs | steps | wall time (s) | steps/s | test loss | surface mean | surface p90 |"
    echo "| --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: |"
} >"$table"
cat "$table"
for scene in rose duck; do
    for epochs in "${budgets[@]}"; do
        dir="$out/$scene-e$epochs"
        rm -rf "$dir"
        # shellcheck disable=SC2086
        "$ws" fit "$scenes/$scene" --out "$dir" --epochs "$epochs" --quiet $settings 2>"$dir.log"
        eval_json=$("$ws" eval "$scenes/$scene" --curves "$dir/curves.json" --loss edges)
        row=$(python3 - "$dir/metrics.json" "$eval_json" "$scene" "$epochs" <<'EOF'
import json, sys
metrics = json.load(open(sys.argv[1]))
ev = json.loads(sys.argv[2])
steps, seconds = metrics["steps"], metrics["seconds"]
print(f"| {sys.argv[3]} | {sys.argv[4]} | {steps} | {seconds:.0f} | {steps / seconds:.0f} | "
      f"{ev['loss']:.5f} | {ev['surface_mean']:.4f} | {ev['surface_p90']:.4f} |")
EOF
)
        echo "$row" | tee -a "$table"
    done
done
echo
echo "settings: $settings; threads: all cores; test loss and surface distances (of each Gaussian centre to"
echo "the nearest ground-truth point, over the ground truth's bounding-box diagonal) from wiresketch eval"
