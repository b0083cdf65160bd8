#!/usr/bin/env bash
# What carrying the UVs costs a diced surface: `subdiv tessellate --dicing-rate 0.5` of the cube
# with a cross unwrap (fixtures/meshes/fvar/cube_uv.obj, seams along 7 of its 12 edges), with
# its `vt` and with them removed (a copy without `vt` lines and `f` texture indices), ROUNDS
# times each, interleaved. Prints each run's own line (`tessellated ... in <ms> ms`).
#
#   docs/bench/record.sh dicing-uv docs/bench/dicing_uv.sh target/release/subdiv [ROUNDS]
set -euo pipefail
[ $# -ge 1 ] || { echo "usage: $0 SUBDIV [ROUNDS]" >&2; exit 2; }
exe=$1; rounds=${2:-5}
here=$(cd "$(dirname "$0")" && pwd)
cage="$here/../../fixtures/meshes/fvar/cube_uv.obj"
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
sed -e '/^vt /d' -e '/^f /s#/[0-9]*##g' "$cage" > "$tmp/cube_no_uv.obj"
camera=(--eye-relative 1.2,0.9,1.6 --size 800x600 --dicing-rate 0.5)
for r in $(seq 1 "$rounds"); do
  echo "round $r"
  echo -n "with uvs: ";    "$exe" tessellate "$cage" "${camera[@]}" -o "$tmp/a.obj" 2>&1 | grep tessellated
  echo -n "without uvs: "; "$exe" tessellate "$tmp/cube_no_uv.obj" "${camera[@]}" -o "$tmp/b.obj" 2>&1 | grep tessellated
done
