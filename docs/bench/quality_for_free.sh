#!/usr/bin/env bash
# "A level of quality for free" on any scene: the predictive frame-rate control held at the
# frame rate of uniform depth d (d = 2 and 3), its picture measured against uniform depth d + 1's.
#
#   docs/bench/quality_for_free.sh NAME SUBDIV [SCENE ARGS...]
#
# e.g. docs/bench/quality_for_free.sh torus40 target/release/subdiv fixtures/meshes/cc_3torus.obj --instances 40
#
# Runs (each through docs/bench/record.sh, so each raw file has its command, commit, load
# average and host): uniform depths 2 and 3 rendered (their median rates), uniform depths 3 and 4
# not rendered with the image error of every 10th frame, and the predictive control held at
# each of the two rates with the same error measurement; then prints one line per comparison:
#   held_at=<d> fps=<median> triangles=<mean> silhouette_worst=<px> shading_median=<deg>
#   vs_uniform=<d+1> silhouette_worst=<px> shading_median=<deg> verdict=<no worse|worse>
# Same camera path, size, samples and max depth as `cargo xtask figures cc` (FRAMES=N for fewer
# frames than its 200).
set -euo pipefail
[ $# -ge 2 ] || { echo "usage: $0 NAME SUBDIV [SCENE ARGS...]" >&2; exit 2; }
name=$1; exe=$2; shift 2
here=$(cd "$(dirname "$0")" && pwd)
common=(--size 640x480 --orbit-step 2 --max-depth 4 --samples 1 --frames "${FRAMES:-200}")
errors=(--error-every 10 --error-size 640x480 --reference-depth 5)
record() { "$here/record.sh" "$@" | tail -n 1; }

. "$here/framerate_lib.sh"

declare -A rate err
for d in 2 3; do
  f=$(record "$name-uniform$d-rendered" "$exe" bench framerate "$@" "${common[@]}" --depth "$d")
  rate[$d]=$(median_fps "$f")
done
for d in 3 4; do
  f=$(record "$name-uniform$d-errors" "$exe" bench framerate "$@" "${common[@]}" --no-render --depth "$d" "${errors[@]}")
  err[$d]=$(errors_of "$f")
done
for d in 2 3; do
  f=$(record "$name-held$d" "$exe" bench framerate "$@" "${common[@]}" --target-fps "${rate[$d]}" "${errors[@]}")
  read -r tris sil shade <<< "$(errors_of "$f")"
  read -r _ usil ushade <<< "${err[$((d + 1))]}"
  verdict=$(awk -v a="$sil" -v b="$usil" -v c="$shade" -v e="$ushade" \
    'BEGIN { print (a <= b && c <= e) ? "no worse" : "worse" }')
  echo "held_at=$d fps=$(median_fps "$f") target=${rate[$d]} triangles=$tris silhouette_worst=$sil shading_median=$shade vs_uniform=$((d + 1)) silhouette_worst=$usil shading_median=$ushade verdict=$verdict"
done
