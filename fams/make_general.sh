#!/usr/bin/env bash
# Writes the general FAMs beside this script: one log of 15 simulated minutes in each of the
# generated rooms worlds of seeds 11 to 20 (the tuning set's second half; never a test
# world), learnt one after another with every default, seed 1; then one FAM a shipped
# configuration trained from it, by the default method's labels too. They are what a
# newcomer runs in a world of their own, with no learning there. Run it again when learning
# or training changes; tests/test_general_fams.py fails until it is.
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
cd "$here"  # the FAMs name their log as it lies beside them
tvl=${TVL:-tvl}
rm -f general-log.h5
"$tvl" learn rooms:11-20 --log general-log.h5 --seed 1 --minutes 15 --json >/dev/null
echo "wrote $here/general-log.h5"
for config in single multi designed; do
    "$tvl" train general-log.h5 --config "$config" -o "general-$config.h5" --force --json >/dev/null
    echo "wrote $here/general-$config.h5"
done
