#!/usr/bin/env bash
# Writes docs/figures/replay.gif, the README's animated replay: a FAM trained from the
# example square log follows the left wall of the circle by the paper's method alone, and
# the first 30 simulated seconds are drawn every third step.
set -euo pipefail
top=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
tvl=${TVL:-tvl}
scratch=$(mktemp -d)
trap 'rm -rf "$scratch"' EXIT
"$tvl" train "$top/logs/square-s1.h5" -o "$scratch/fam.h5" >/dev/null
"$tvl" run "$scratch/fam.h5" "$top/worlds/circle.txt" --behaviour wall-left --paper \
    --minutes 1 --log "$scratch/run.h5" >/dev/null
"$tvl" replay "$scratch/run.h5" --gif "$top/docs/figures/replay.gif" --to 30 --every 3 \
    --force >/dev/null
echo "wrote $top/docs/figures/replay.gif"
