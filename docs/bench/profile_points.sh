#!/usr/bin/env bash
# Instructions and cache misses per limit point (cachegrind), as the difference of two run counts
# so that start-up and setup cancel out.
set -euo pipefail
exe=$1
one() { # cage depth runs_a runs_b points
  for r in $3 $4; do
    valgrind --tool=cachegrind --cache-sim=yes --cachegrind-out-file=/tmp/cg.$r "$exe" bench tessellate "$1" --depth "$2" --threads 1 --runs "$r" > /dev/null 2>&1
  done
  python3 - "$1" "$2" "$3" "$4" "$5" <<'PY'
import re, subprocess, sys
cage, depth, ra, rb, pts = sys.argv[1], sys.argv[2], int(sys.argv[3]), int(sys.argv[4]), int(sys.argv[5])
def tot(r):
    out = subprocess.run(['cg_annotate', f'/tmp/cg.{r}'], capture_output=True, text=True).stdout
    for l in out.splitlines():
        if 'PROGRAM TOTALS' in l:
            nums = [int(x.replace(',', '')) for x in re.findall(r'([\d,]+) \(', l)]
            return dict(zip('Ir I1mr ILmr Dr D1mr DLmr Dw D1mw DLmw'.split(), nums))
a, b = tot(ra), tot(rb)
n = (rb - ra) * pts
print(f'cage={cage} depth={depth} runs={ra},{rb} points={pts} per_point: ' + ' '.join(f'{k}={(b[k] - a[k]) / n:.3f}' for k in a))
PY
}
one fixtures/reference/shapes/catmark_helmet.obj 2 1000 2000 981
one fixtures/reference/shapes/catmark_helmet.obj 4 100 200 15057
one fixtures/reference/shapes/catmark_pawn.obj 2 500 1000 9457
one fixtures/reference/shapes/catmark_pawn.obj 5 10 20 602497
one fixtures/meshes/tri_bunny_3k.obj 2 50 100 29394
