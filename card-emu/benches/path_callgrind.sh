#!/usr/bin/env bash
# Instructions the path engine spends on the dense benchmark (benches/path.rs run once with no
# clock reads, under callgrind): push (blending), tick_plan (look-ahead and speed planner),
# tick_move (interpolation), per segment and per tick. Instruction counts do not move with the
# machine's load, unlike the wall clock: compare changes with them. Each is counted in a run of
# its own (callgrind collecting only inside that call), since the engine's calls are inlined
# into them and a profile's per-function figures split inlined code by source file.
# (The engine is generic over its dimension, `Path<D>`: its methods' symbols read `Path<_>`.)
#
#   card-emu/benches/path_callgrind.sh [bench arguments]
#
# (for instance `... --plan-ticks 1`: the planner at every tick; `... --baseline`: the
# engine's baseline x86-64 build instead of its x86-64-v3 one, see `motion/path/v3.rs`)
set -euo pipefail
cd "$(dirname "$0")/../.."
exe=$(cargo bench -p card-emu --bench path --no-run --message-format=json 2>/dev/null |
    grep -o '"executable":"[^"]*deps/path-[^"]*"' |
    head -n1 | sed 's/"executable":"\(.*\)"/\1/')
[ -x "$exe" ] || { echo "no bench binary" >&2; exit 1; }
out=$(mktemp)
trap 'rm -f "$out"' EXIT
count() {
    valgrind --tool=callgrind --callgrind-out-file="$out" --toggle-collect="$1" \
        "$exe" --once "${@:2}" >/dev/null 2>&1
    sed -n 's/^summary: *//p' "$out"
}
push=$(count '*Path<_>>::push' "$@")
plan=$(count '*Path<_>>::tick_plan' "$@" 2>/dev/null)
move=$(count '*Path<_>>::tick_move' "$@" 2>/dev/null)
ticks=$("$exe" --once "$@" | sed -n 's/.* \([0-9]*\) ticks.*/\1/p')
awk -v p="$push" -v l="$plan" -v m="$move" -v ticks="$ticks" -v segs=10000 'BEGIN {
    printf "ticks %d (%.2f per segment)\n", ticks, ticks / segs
    printf "instructions per segment: push %.0f, plan %.0f, push + plan %.0f, move %.0f, total %.0f\n",
        p / segs, l / segs, (p + l) / segs, m / segs, (p + l + m) / segs
    printf "instructions per tick: plan %.0f, move %.0f\n", l / ticks, m / ticks
}'
