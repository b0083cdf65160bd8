#!/bin/sh
# Rendered helmet40 or SCENE (640x480, one sample) under the predictive controller, interleaved between
# two binaries (three rounds, the baseline first): the frames in which new blocks are appended
# to the vertex buffer, written in full or only the new blocks. Prints each run's summary line
# (median fps and the share of frames within 10 % of the target) and the calibration line.
#   [SCENE="INPUT --instances N"] docs/bench/appended_upload.sh BASELINE_BINARY NEW_BINARY
# (SCENE: the cage and its layout; helmet40 without it)
A=${1:?usage: appended_upload.sh BASELINE_BINARY NEW_BINARY}
B=${2:?usage: appended_upload.sh BASELINE_BINARY NEW_BINARY}
S="${SCENE:---scene helmet40} --size 640x480 --samples 1"
for round in 1 2 3; do
  for c in "--calibrate --target-fps 30 --frames 200" "--target-fps 15 --switch-fps 40 --frames 200" \
           "--target-fps 20 --frames 200"; do
    for bin in "$A" "$B"; do
      echo "== round $round: $bin bench framerate $c"
      $bin bench framerate $S $c 2>&1 | grep -E '^summary|^calibrate' | tr '\n' ' '
      echo
    done
  done
done
