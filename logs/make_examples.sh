#!/usr/bin/env bash
# Writes the example learning logs beside this script: one session of 15 simulated minutes,
# seed 1, with the default single configuration, in the bundled square and lab, each through
# no echo memory (the paper's perception): a log keeps the raw rings, so it trains a FAM of
# any memory (`tvl train LOG --memory patches`), and the README's figures on these logs
# were measured that way. Run it again when learning changes; tests/test_example_logs.py
# fails until it is.
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
tvl=${TVL:-tvl}
for world in square lab; do
    rm -f "$here/$world-s1.h5"
    "$tvl" learn "$here/../worlds/$world.txt" --log "$here/$world-s1.h5" --seed 1 \
        --minutes 15 --memory none --json >/dev/null
    echo "wrote $here/$world-s1.h5"
done
