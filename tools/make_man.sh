#!/usr/bin/env bash
# Writes the man page of wiresketch (roff, section 1) to stdout, made from
# the program's own --help texts, so that it lists every command and option
# the program has: `make man` / `make install` run it, test_install checks
# it against --help.
#   usage: bash tools/make_man.sh BIN VERSION > wiresketch.1
set -euo pipefail
bin=$1
version=$2

# roff: backslashes doubled, dashes escaped, a leading . or ' protected.
esc() { sed -e 's/\\/\\e/g' -e 's/-/\\-/g' -e "s/^\([.']\)/\\\\\&\1/"; }

commands=$("$bin" --help | awk '/^commands:/ {on = 1; next} on && /^  [a-z]/ {print $1}')

cat <<HEAD
.TH WIRESKETCH 1 "" "wiresketch $version" "User Commands"
.SH NAME
wiresketch \- 3D wireframe sketches of an object from multi-view photos
.SH SYNOPSIS
.B wiresketch
.I COMMAND
[options]
.br
.B wiresketch
.I COMMAND
.B \-\-help
.SH DESCRIPTION
wiresketch fits cubic B\('ezier curves to multi-view photos of an object
(NeRF-synthetic or nerfstudio scenes) and writes them as a curve file,
renders, animations and a report. Option names accept underscores for
dashes. Exit status: 0 on success, 1 for bad input or an output that could
not be written (a full disk, a closed stdout, ulimit -f), 2 for bad usage,
128 + N for a fit stopped by signal N (130 for SIGINT; also SIGHUP, SIGTERM,
SIGXCPU, SIGXFSZ, and 141 when the reader of its progress is gone), which
writes its checkpoint and outputs first.
.SH COMMANDS
HEAD
"$bin" --help | awk '/^commands:/ {on = 1; next} /^[^ ]/ {on = 0} on && /^  [a-z]/' | while read -r name summary; do
    printf '.TP\n.B %s\n%s\n' "$name" "$(printf '%s\n' "$summary" | esc)"
done
for c in $commands; do
    printf '.SH "%s"\n' "$(printf 'wiresketch %s' "$c" | tr a-z A-Z)"
    "$bin" "$c" --help | awk '
        /^usage: / { sub(/^usage: /, ""); print "USAGE\t" $0; next }
        /^[a-z ]+:$/ { print "SECTION\t" $0; next }
        /^  [^ ]/ { line = substr($0, 3); i = index(line, "  ");
                    if (i == 0) { print "TEXT\t" line; next }
                    key = substr(line, 1, i - 1); rest = substr(line, i); sub(/^ +/, "", rest);
                    print "ITEM\t" key "\t" rest; next }
        /^$/ { next }
        { print "TEXT\t" $0 }' |
    while IFS=$'\t' read -r kind a b; do
        case $kind in
            USAGE) printf '.PP\n.B %s\n' "$(printf '%s\n' "$a" | esc)" ;;
            SECTION) printf '.SS "%s"\n' "$(printf '%s\n' "${a%:}" | esc)" ;; # "input options", ...
            ITEM) printf '.TP\n.B %s\n%s\n' "$(printf '%s\n' "$a" | esc)" "$(printf '%s\n' "$b" | esc)" ;;
            TEXT) printf '%s\n.br\n' "$(printf '%s\n' "$a" | esc)" ;;
        esac
    done
done
cat <<TAIL
.SH FILES
.TP
.I weights/clip-vit-b32.bin
the CLIP weight file (made once from OpenAI's ViT-B-32.pt; without it, use
.B \-\-loss edges
)
.SH SEE ALSO
README.md, docs/USAGE.md (every command in full), docs/METHOD.md (the method)
and docs/RESULTS.md (the measurements) in the source tree.
TAIL
