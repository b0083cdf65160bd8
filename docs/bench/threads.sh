#!/usr/bin/env bash
# Two threads against one on the bench-osd cages, idle machine: `subdiv bench tessellate` at
# depths 3-5 (the armadillo and the holed bunny at 3), each run writing points, normals and
# indices (frame) or points and normals only (points-only, a renderer keeping its index
# buffer), 1 and 2 threads interleaved over 3 rounds, 101 runs each (31 at depth 5).
#
#   docs/bench/record.sh threads docs/bench/threads.sh target/release/subdiv
#
# Prints each run's first line, then one summary line per cage, depth and timing:
#   cage=<file> depth=<d> timed=<frame|points-only> t1_ms=<median of rounds> t2_ms=<...> ratio=<t1/t2>
set -euo pipefail
exe=${1:-target/release/subdiv}
s=fixtures/reference/shapes; m=fixtures/meshes
cases=(
  "$s/catmark_pawn.obj catmull-clark 3 4 5"
  "$s/catmark_helmet.obj catmull-clark 3 4 5"
  "$m/cc_3torus.obj catmull-clark 3 4 5"
  "$m/tri_bunny_3k.obj loop 3 4 5"
  "../shared/meshes/tri_armadillo_52k.obj loop 3"
  "../shared/meshes/tri_bunny_69k_holes.obj loop 3"
)
summary=()
median() { sort -g | awk '{v[NR]=$1} END {print v[int((NR+1)/2)]}'; }
for c in "${cases[@]}"; do
  read -r cage scheme depths <<<"$(echo "$c" | awk '{print $1, $2; }')"
  depths=$(echo "$c" | cut -d' ' -f3-)
  for d in $depths; do
    runs=101; [ "$d" -ge 5 ] && runs=31
    for timed in frame points-only; do
      extra=(); [ "$timed" = points-only ] && extra=(--points-only)
      t1=(); t2=()
      for round in 1 2 3; do
        for t in 1 2; do
          line=$("$exe" bench tessellate "$cage" --scheme "$scheme" --depth "$d" --threads "$t" \
            --runs "$runs" "${extra[@]}" | head -n 1)
          echo "$line"
          ms=$(echo "$line" | sed 's/.* median_ms=\([0-9.]*\).*/\1/')
          if [ "$t" = 1 ]; then t1+=("$ms"); else t2+=("$ms"); fi
        done
      done
      a=$(printf '%s\n' "${t1[@]}" | median); b=$(printf '%s\n' "${t2[@]}" | median)
      summary+=("cage=$(basename "$cage") depth=$d timed=$timed t1_ms=$a t2_ms=$b ratio=$(awk -v a="$a" -v b="$b" 'BEGIN {printf "%.2f", a / b}')")
    done
  done
done
printf '%s\n' "${summary[@]}"
