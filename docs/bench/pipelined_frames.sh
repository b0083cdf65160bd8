#!/bin/sh
# Rendered helmet40 (640x480, one sample), interleaved between two binaries (three rounds, the
# baseline first): each frame waited for before the next frame's update, or the next frame's
# update overlapping its drawing (as in the viewer). Prints each run's summary line, the
# calibration line, and the mean triangles a frame.
#   docs/bench/pipelined_frames.sh BASELINE_BINARY NEW_BINARY
A=${1:?usage: pipelined_frames.sh BASELINE_BINARY NEW_BINARY}
B=${2:?usage: pipelined_frames.sh BASELINE_BINARY NEW_BINARY}
S="--scene helmet40 --size 640x480 --samples 1"
for round in 1 2 3; do
  for c in "--calibrate --target-fps 30 --frames 200" "--target-fps 15 --switch-fps 40 --frames 200" \
           "--frames 150" "--depth 3 --frames 100"; do
    for bin in "$A" "$B"; do
      echo "== round $round: $bin bench framerate $c"
      $bin bench framerate $S $c 2>&1 | awk '
        /^frame=/ { for (i = 1; i <= NF; i++) { split($i, kv, "="); if (kv[1] == "triangles") { t += kv[2]; n++ } } }
        /^summary|^calibrate/ { printf "%s ", $0 }
        END { printf "triangles_mean=%.0f\n", t / n }'
    done
  done
done
