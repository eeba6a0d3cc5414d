#!/usr/bin/env bash
# Quality against wall time (METHOD.md sections 7 and 8; issue 10): fits the
# shared scenes rose and duck with the weight-free line loss and its
# defaults (docs/USAGE.md, "fit") from the visual hull and from the original's
# random sphere, side by side, at three budgets of schedule (6, 24 and 48
# epochs of 96 views x 5 steps: 2,880, 11,520 and 23,040 steps; 24 is the
# line loss's default), and
# tabulates the fit's wall time against the test loss, the surface distance
# (mean and 90th percentile over the ground truth's diagonal), the share of
# Gaussian centres within 1% of it and the stray curves (metrics.json).
#
# usage: bash tools/quality_vs_time.sh [EPOCHS ...]     (default: 6 24 48)
# env:   BUILD (build), SCENES (../shared/scenes), OUT (build/quality),
#        FIT_ARGS (extra fit options, e.g. "--threads 1" or
#        "--silhouette-weight 0")
# The table goes to stdout and to $OUT/table.md; each fit stays in
# $OUT/SCENE-INIT-eEPOCHS (report.html, test renders).
set -euo pipefail
cd "$(dirname "$0")/.."
ws=${BUILD:-build}/wiresketch
scenes=${SCENES:-../shared/scenes}
out=${OUT:-build/quality}
budgets=("$@")
[ ${#budgets[@]} -gt 0 ] || budgets=(6 24 48)
mkdir -p "$out"
table="$out/table.md"
{
    echo "| scene | init | epochs | steps | wall time (s) | test loss | surface mean | surface p90 | precision | stray curves |"
    echo "| --- | --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |"
} >"$table"
cat "$table"
for scene in rose duck; do
    for epochs in "${budgets[@]}"; do
        for init in hull random; do
            dir="$out/$scene-$init-e$epochs"
            rm -rf "$dir"
            # shellcheck disable=SC2086
            "$ws" fit "$scenes/$scene" --out "$dir" --loss edges --init "$init" --epochs "$epochs" --quiet \
                ${FIT_ARGS:-} 2>"$dir.log"
            row=$(python3 - "$dir/metrics.json" "$scene" "$init" "$epochs" <<'EOF'
import json, sys
m = json.load(open(sys.argv[1]))
print(f"| {sys.argv[2]} | {sys.argv[3]} | {sys.argv[4]} | {m['steps']} | {m['seconds']:.0f} | "
      f"{m['test_loss']:.4f} | {100 * m['surface_mean']:.2f}% | {100 * m['surface_p90']:.2f}% | "
      f"{m['surface_precision']:.2f} | {m['surface_stray_curves']} |")
EOF
)
            echo "$row" | tee -a "$table"
        done
    done
done
echo
echo "settings: --loss edges and its defaults ${FIT_ARGS:-}; surface distances of each Gaussian centre to the"
echo "nearest ground-truth point over the ground truth's bounding-box diagonal; precision: centres within 1% of it"
