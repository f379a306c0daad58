#!/usr/bin/env bash
# Figure 19 (paper §5.1): learning curves of the single FAM in the square, circle and corridor.
#
# For each world and trial (seed): learn, then per learning minute ΔV and the collisions while
# learning (from the log), and the competence of the FAM the learner had at that minute
# (`tvl train --until-minute`): collisions per minute and mean speed of a short avoid run.
# Beside it, on the same worlds and seeds: DWA (no learning) and tabular Q-learning.
#
#            worlds  trials  learning minutes  snapshots       avoid run
#   --tiny   square  1       1                 minute 1        0.2 min
#   --quick  all 3   3       15                every minute    5 min
#   --full   all 3   5       20                every minute    5 min
FIGURE=fig19_learning_curves
DESCRIPTION="Figure 19: learning curves (ΔV, collisions, competence) of the single FAM in
square, circle and corridor, with DWA and Q-learning beside."
# shellcheck source-path=SCRIPTDIR
source "$(dirname "${BASH_SOURCE[0]}")/lib.sh"
parse_options "$@"

read -r -a WORLD_NAMES <<<"$(pick square "square circle corridor" "square circle corridor")"
TRIALS=$(pick 1 3 5)
LEARN_MINUTES=$(pick 1 15 20)
FIRST_SNAPSHOT=$(pick 1 0 0) # minute 0: the untrained FAM
CONFIG=single

learning=() snapshots=() baselines=()
for world_name in "${WORLD_NAMES[@]}"; do
    for seed in $(seq "$TRIALS"); do
        learning+=("learn_job $world_name $CONFIG $seed $LEARN_MINUTES")
        for minute in $(seq "$FIRST_SNAPSHOT" "$LEARN_MINUTES"); do
            snapshots+=("snapshot_job $world_name $seed $CONFIG $CONFIG $minute avoid")
        done
        baselines+=("dwa_job $world_name $seed" "qlearn_job $world_name $seed $LEARN_MINUTES 1")
    done
done
pool "${learning[@]}"
pool "${baselines[@]}" "${snapshots[@]}" # the long baseline runs first
finish fig19
