#!/usr/bin/env bash
# The predictive controller held at two frame rates with the image error of every 10th frame
# measured (the runs behind "a level of quality for free"), interleaved between two binaries
# (two rounds, the baseline first): the error renders drawn on the frames' own renderer, or on
# a renderer of their own. Each run goes through record.sh (raw file under docs/bench/); prints
# per run the mean triangles, the worst frame's silhouette px, the median frame's shading p99,
# the frames more than 1.5x the target's time and the summary line.
#   [SCENE="INPUT --instances N"] docs/bench/error_renderer.sh NAME BASELINE NEW FPS...
set -euo pipefail
[ $# -ge 4 ] || { echo "usage: $0 NAME BASELINE NEW FPS..." >&2; exit 2; }
name=$1; a=$2; b=$3; shift 3
here=$(cd "$(dirname "$0")" && pwd)
. "$here/framerate_lib.sh"
read -r -a scene <<< "${SCENE:---scene helmet40}"
common=(--size 640x480 --orbit-step 2 --max-depth 4 --samples 1 --frames "${FRAMES:-200}"
  --error-every 10 --error-size 640x480 --reference-depth 5)
for round in 1 2; do
  for fps in "$@"; do
    for bin in "$a" "$b"; do
      tag=base; [ "$bin" = "$b" ] && tag=new
      f=$("$here/record.sh" "$name-$tag-$fps-r$round" "$bin" bench framerate "${scene[@]}" \
        "${common[@]}" --target-fps "$fps" | tail -n 1)
      slow=$(grep '^frame=' "$f" | tail -n +2 | sed 's/.* ms=\([0-9.]*\) .*/\1/' |
        awk -v t="$fps" '$1 > 1500 / t { n++ } END { print n + 0 }')
      echo "round=$round fps=$fps $tag: tris/silhouette/shading=$(errors_of "$f") slow_frames=$slow $(grep '^summary' "$f")"
    done
  done
done
