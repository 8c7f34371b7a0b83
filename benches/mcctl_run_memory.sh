#!/usr/bin/env bash
# Peak resident memory and wall time of `mcctl run` on the stepped `sim` card at default
# settings, for a program of 10^6 lines and for a one-hour dwell (BENCHMARKS.md, "Inputs that
# eat memory or never end"). Needs GNU time (/usr/bin/time, Debian's `time`). Usage, from the
# workspace root:
#   cargo build --release --bin mcctl && benches/mcctl_run_memory.sh [lines] [dwell seconds]
# MCCTL=path picks another binary.
set -euo pipefail
lines=${1:-1000000}
dwell=${2:-3600}
mcctl=${MCCTL:-target/release/mcctl}
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
# Chords of a spiral: radius 50 mm growing 0.5 um a chord, 1 mrad a chord (about 50 um
# long), at F6000.
awk -v n="$lines" 'BEGIN {
    print "G21 G90 G1 F6000";
    for (i = 0; i < n; i++) {
        th = i * 0.001; r = 50 + 0.0005 * i;
        printf "X%.4f Y%.4f\n", r * cos(th), r * sin(th);
    }
}' > "$dir/chords.ngc"
printf 'G1 X1 F600\nG4 P%s\nX2\n' "$dwell" > "$dir/dwell.ngc"
for prog in chords dwell; do
    /usr/bin/time -f "$prog: %e s wall, %U s user, %S s system, %M kB peak RSS" \
        "$mcctl" run "$dir/$prog.ngc" --json
done
