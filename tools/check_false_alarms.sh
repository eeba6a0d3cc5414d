#!/bin/sh
# check_false_alarms.sh: `wiresketch check` on correct scenes, which it must
# never call wrong (issue 22, item 5). Every synthetic scene that
# `wiresketch scene --help` lists, made six ways: NeRF layout 224 px on
# black with the principal point centred; nerfstudio 224 px on white with it
# (9, -6) px off the centre; 288 x 224 on black (-24, 10) px off; 224 x 288
# on white, centred; 288 x 224 in the box room with masks, (16, -8) px off;
# the same without masks (where `check` must say that no silhouette is
# usable, not name a camera fault); then the shared scenes (rose, duck).
# Prints a markdown table: scene, how it was made, how far its working
# views' crops lie off the frames' centres, check's exit status and its
# verdict (the first words of its line), the focal estimate of each split. Usage: tools/check_false_alarms.sh [WORK_DIR] [SHARED_SCENES_DIR]
# (defaults /tmp/ws_false_alarms and ../../shared/scenes); run from the
# repository root after `make`.
set -u
bin=${WS_BIN:-build/wiresketch}
work=${1:-/tmp/ws_false_alarms}
shared=${2:-../../shared/scenes}
mkdir -p "$work"
objects="trefoil chair spring flat cube dodecahedron nut"
variants="nerf-black ns-white-off ns-wide-black-off ns-tall-white ns-room-masks-off ns-room"

options() {
    case $1 in
    nerf-black) echo "" ;;
    ns-white-off) echo "--layout nerfstudio --background white --principal 9,-6" ;;
    ns-wide-black-off) echo "--layout nerfstudio --size 288x224 --principal -24,10" ;;
    ns-tall-white) echo "--layout nerfstudio --size 224x288 --background white" ;;
    ns-room-masks-off) echo "--layout nerfstudio --size 288x224 --background room --masks --principal 16,-8" ;;
    ns-room) echo "--layout nerfstudio --size 288x224 --background room" ;;
    esac
}

row() { # name, made, dir
    out=$("$bin" check "$3" 2>/dev/null)
    rc=$?
    verdict=$(printf '%s\n' "$out" | grep -v '^split\|^train\|^val\|^test\|^$\|the working views are\|: masks for ' | head -1 |
        sed "s|^$3/||" | cut -c1-90)
    crop=$(printf '%s\n' "$out" | grep -o 'up to [0-9]* px off' | head -1)
    focal=$(printf '%s\n' "$out" | sed '/^$/q' | awk '$1 == "train" || $1 == "val" || $1 == "test" { printf "%s%s %s", sep, $1, $5; sep = ", " }' | head -1)
    echo "| $1 | $2 | ${crop:--} | $rc | $verdict | $focal |"
}

echo "| scene | made | crops | exit | check says | focal estimate |"
echo "|---|---|---|---|---|---|"
for o in $objects; do
    for v in $variants; do
        d="$work/$o-$v"
        [ -f "$d/gt_curves.json" ] || "$bin" scene "$o" --out "$d" $(options "$v") >/dev/null || exit 1
        row "$o" "$v: $(options "$v")" "$d"
    done
done
for s in rose duck; do
    [ -d "$shared/$s" ] && row "$s" "shared scene" "$shared/$s"
done
