# Helpers for the scripts that read `subdiv bench framerate` raw files (sourced, not run).

# The median of the fps= field of frames 1.. of a raw file.
median_fps() {
  grep '^frame=' "$1" | tail -n +2 | sed 's/.* fps=\([0-9.]*\).*/\1/' | sort -g |
    awk '{v[NR]=$1} END {print v[int(NR/2)+1]}'
}
# Mean triangles, worst silhouette_px_max and median shading_deg_p99 of a raw file's frames.
errors_of() {
  local tw shade
  tw=$(grep '^frame=' "$1" | awk '
    { for (i = 1; i <= NF; i++) { split($i, kv, "=");
        if (kv[1] == "triangles") { t += kv[2]; n++ }
        if (kv[1] == "silhouette_px_max" && kv[2] + 0 > w) w = kv[2] + 0 } }
    END { printf "%.0f %.3f\n", t / n, w }')
  shade=$(grep -o 'shading_deg_p99=[0-9.]*' "$1" | cut -d= -f2 | sort -g |
    awk '{v[NR]=$1} END {print v[int(NR/2)+1]}')
  echo "$tw $shade"
}
