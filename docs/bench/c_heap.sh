#!/bin/sh
# Rendered frame rates of helmet40 (640x480, one sample) with and without the C heap kept
# (`subdiv_vk::keep_freed_heap`), interleaved: three rounds of each configuration, the
# baseline binary first. Prints each run's summary line and its user/sys CPU seconds.
#   docs/bench/c_heap.sh BASELINE_BINARY NEW_BINARY
A=${1:?usage: c_heap.sh BASELINE_BINARY NEW_BINARY}
B=${2:?usage: c_heap.sh BASELINE_BINARY NEW_BINARY}
S="--scene helmet40 --size 640x480 --samples 1"
for round in 1 2 3; do
  for c in "--depth 2 --frames 300" "--depth 3 --frames 150" "--depth 4 --frames 40" \
           "--frames 150" "--target-fps 30 --frames 200" "--target-fps 15 --switch-fps 40 --frames 200"; do
    for bin in "$A" "$B"; do
      echo "== round $round: $bin bench framerate $c"
      /usr/bin/time -f "cpu user=%U sys=%S real=%e" $bin bench framerate $S $c 2>&1 |
        grep -E '^summary|^cpu' | tr '\n' ' '
      echo
    done
  done
done
