#!/bin/sh
# first budgeted frame (patch errors measured once per cage): depths_ms of frame 0, 3 runs each
B=${1:?usage: first_budget_frame.sh SUBDIV_BINARY}
for i in 1 2 3; do
  for c in "--scene helmet40" "fixtures/reference/shapes/catmark_pawn.obj" "fixtures/meshes/tri_bunny_3k.obj --scheme loop"; do
    echo "== $c"; $B bench framerate $c --no-render --target-fps 30 --frames 1 2>&1 | grep "^frame=0"
  done
done
