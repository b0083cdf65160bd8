#!/usr/bin/env bash
# The paper's adaptive mode (curvature, classification, projected size) against the uniform
# depths on any scene, measured as Fig. 5 measures it (`cargo xtask figures cc`: the same orbit,
# size, maximum depth and error measurement):
#
#   docs/bench/paper_mode.sh NAME SUBDIV [SCENE ARGS...]
#
# e.g. docs/bench/paper_mode.sh helmet40 target/release/subdiv --scene helmet40
#      BANDS="1,4 0.9,4 0.75,4" docs/bench/paper_mode.sh helmet40-rmin target/release/subdiv
#
# Runs (each through docs/bench/record.sh, so each raw file has its command, commit, load
# average and host) uniform depths 2, 3 and 4 and the paper's mode with its defaults, or with
# each `--projected-size` band of BANDS, all with the image error of every 10th frame against
# uniform depth 5; then prints one line per run:
#   run=<name> triangles=<mean> silhouette_worst=<px> shading_median=<deg>
# and for each adaptive run the least uniform depth whose picture is no worse (worst-frame
# silhouette and median shading both at most the run's) and the run's share of its triangles:
#   least_uniform_no_worse=<d|none> share=<adaptive triangles / uniform triangles>
# (FRAMES=N for fewer frames than Fig. 5's 180.)
set -euo pipefail
[ $# -ge 2 ] || { echo "usage: $0 NAME SUBDIV [SCENE ARGS...]" >&2; exit 2; }
name=$1; exe=$2; shift 2
here=$(cd "$(dirname "$0")" && pwd)
common=(--size 640x480 --orbit-step 2 --max-depth 4 --samples 1 --frames "${FRAMES:-180}"
  --no-render --error-every 10 --error-size 640x480 --reference-depth 5)
record() { "$here/record.sh" "$@" | tail -n 1; }
. "$here/framerate_lib.sh"

declare -A uni
for d in 2 3 4; do
  f=$(record "$name-uniform$d" "$exe" bench framerate "$@" "${common[@]}" --depth "$d")
  uni[$d]=$(errors_of "$f")
  echo "run=uniform$d $(awk '{print "triangles=" $1 " silhouette_worst=" $2 " shading_median=" $3}' <<< "${uni[$d]}")"
done
bands=${BANDS:-default}
for b in $bands; do
  if [ "$b" = default ]; then
    f=$(record "$name-paper" "$exe" bench framerate "$@" "${common[@]}")
  else
    f=$(record "$name-paper-size${b/,/-}" "$exe" bench framerate "$@" "${common[@]}" --projected-size "$b")
  fi
  read -r tris sil shade <<< "$(errors_of "$f")"
  least=none share=
  for d in 2 3 4; do
    read -r ut us ush <<< "${uni[$d]}"
    if awk -v a="$us" -v b="$sil" -v c="$ush" -v e="$shade" 'BEGIN { exit !(a <= b && c <= e) }'; then
      least=$d share=$(awk -v a="$tris" -v u="$ut" 'BEGIN { printf "%.3f", a / u }')
      break
    fi
  done
  echo "run=paper-$b triangles=$tris silhouette_worst=$sil shading_median=$shade least_uniform_no_worse=$least share=${share:-none}"
done
