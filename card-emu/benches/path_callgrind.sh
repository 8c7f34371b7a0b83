#!/usr/bin/env bash
# Instructions the path engine spends on the dense benchmark (benches/path.rs run once with no
# clock reads, under callgrind): push (blending), tick_plan (look-ahead and speed planner),
# tick_move (interpolation), per segment and per tick. Instruction counts do not move with the
# machine's load, unlike the wall clock: compare changes with them.
#
#   card-emu/benches/path_callgrind.sh [callgrind output file [bench arguments]]
#
# (for instance `... target/path1.callgrind --plan-ticks 1`: the planner at every tick)
set -euo pipefail
cd "$(dirname "$0")/../.."
out="${1:-${CARGO_TARGET_DIR:-target}/path.callgrind}"
shift || true
exe=$(cargo bench -p card-emu --bench path --no-run --message-format=json 2>/dev/null |
    grep -o '"executable":"[^"]*benches/path[^"]*"\|"executable":"[^"]*deps/path-[^"]*"' |
    head -n1 | sed 's/"executable":"\(.*\)"/\1/')
[ -x "$exe" ] || { echo "no bench binary" >&2; exit 1; }
line=$(valgrind --tool=callgrind --callgrind-out-file="$out" "$exe" --once "$@" 2>/dev/null | grep ticks)
echo "$line"
ticks=$(echo "$line" | sed -n 's/.* \([0-9]*\) ticks.*/\1/p')
callgrind_annotate --inclusive=yes --threshold=100 "$out" 2>/dev/null |
    awk -v ticks="$ticks" -v segs=10000 '
        function num(s) { gsub(",", "", s); return s + 0 }
        /Path::push[^_a-z]/ && !p { p = num($1) }
        /::tick_plan/ && !l { l = num($1) }
        /::tick_move/ && !m { m = num($1) }
        END {
            printf "ticks %d (%.2f per segment)\n", ticks, ticks / segs
            printf "instructions per segment: push %.0f, plan %.0f, push + plan %.0f, move %.0f, total %.0f\n",
                p / segs, l / segs, (p + l) / segs, m / segs, (p + l + m) / segs
            printf "instructions per tick: plan %.0f, move %.0f\n", l / ticks, m / ticks
        }'
