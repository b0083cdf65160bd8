#!/usr/bin/env bash
# Runs one benchmark command and keeps its raw output under docs/bench/:
#
#   docs/bench/record.sh NAME COMMAND [ARGS...]
#
# writes docs/bench/NAME-<date>-<commit>.txt: the command, commit (+dirty for local changes),
# UTC start and end, host, load average before and after, then everything the command printed
# (stdout and stderr). The figures docs/performance.md quotes come from such files.
set -euo pipefail
[ $# -ge 2 ] || { echo "usage: $0 NAME COMMAND [ARGS...]" >&2; exit 2; }
name=$1; shift
root=$(cd "$(dirname "$0")/../.." && pwd)
commit=$(git -C "$root" rev-parse --short=12 HEAD)
git -C "$root" diff --quiet HEAD -- || commit="$commit+dirty"
out="$root/docs/bench/$name-$(date -u +%Y-%m-%d)-$commit.txt"
{
  echo "# command: $*"
  echo "# commit: $commit"
  echo "# start: $(date -u +%Y-%m-%dT%H:%M:%SZ)"
  echo "# host: $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //'), $(nproc) threads"
  echo "# load average before: $(cut -d' ' -f1-3 /proc/loadavg)"
} > "$out"
status=0
"$@" >> "$out" 2>&1 || status=$?
{
  echo "# end: $(date -u +%Y-%m-%dT%H:%M:%SZ)"
  echo "# load average after: $(cut -d' ' -f1-3 /proc/loadavg)"
  echo "# exit status: $status"
} >> "$out"
echo "$out"
exit $status
