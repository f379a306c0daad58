#!/usr/bin/env bash
# Figure 24 (paper §5.2): single against multi FAM in the square and the lab, trained from the
# same learning logs, so that only the FAM's structure differs.
#
# For each world and trial (seed): learn once (exploring with the single FAM), then train a
# single and a multi FAM from that log as it stood at each snapshot minute and run avoid with
# each: collision rate, speed and clearance against learning time, and time to competence.
# Beside them, on the same worlds and seeds: DWA (no learning) and tabular Q-learning.
#
#            trials  learning minutes (square, lab)  snapshots every  avoid run
#   --tiny   1       1 (square only)                 minute 1 only    0.2 min
#   --quick  3       15, 30                          1, 2 min         5 min
#   --full   5       20, 60                          1, 2 min         5 min
FIGURE=fig24_single_vs_multi
DESCRIPTION="Figure 24: time to competence and collision rate of single and multi FAMs trained
from the same logs in square and lab, with DWA and Q-learning beside."
# shellcheck source-path=SCRIPTDIR
source "$(dirname "${BASH_SOURCE[0]}")/lib.sh"
parse_options "$@"

read -r -a WORLD_NAMES <<<"$(pick square "square lab" "square lab")"
CONFIGS=(single multi)
LEARN_CONFIG=single
TRIALS=$(pick 1 3 5)
declare -A LEARN_MINUTES=([square]=$(pick 1 15 20) [lab]=$(pick 1 30 60))
declare -A EVERY=([square]=1 [lab]=$(pick 1 2 2))
FIRST_SNAPSHOT=$(pick 1 0 0) # minute 0: the untrained FAMs

learning=() snapshots=() baselines=()
for world_name in "${WORLD_NAMES[@]}"; do
    minutes=${LEARN_MINUTES[$world_name]} every=${EVERY[$world_name]}
    for seed in $(seq "$TRIALS"); do
        learning+=("learn_job $world_name $LEARN_CONFIG $seed $minutes")
        for minute in $(seq "$FIRST_SNAPSHOT" "$every" "$minutes"); do
            for config in "${CONFIGS[@]}"; do
                snapshots+=("snapshot_job $world_name $seed $LEARN_CONFIG $config $minute avoid")
            done
        done
        baselines+=("dwa_job $world_name $seed" "qlearn_job $world_name $seed $minutes $every")
    done
done
pool "${learning[@]}"
pool "${baselines[@]}" "${snapshots[@]}" # the long baseline runs first
finish fig24
