#!/usr/bin/env bash
# Figure 21 (paper §5.1): wall following against the velocity threshold, square and circle.
#
# For each world and trial (seed): learn with the single FAM and train it, then follow the wall
# on the left and on the right at thresholds 0.65 to 0.95 in steps of 0.05: mean wall clearance
# and mean speed; settings with more than 0.2 collisions per minute are drawn dashed.
#
#            trials  learning minutes  thresholds        wall runs
#   --tiny   1       1                 0.65, 0.95        0.2 min, left only
#   --quick  3       15                0.65 … 0.95       5 min
#   --full   5       15                0.65 … 0.95       10 min
FIGURE=fig21_threshold
DESCRIPTION="Figure 21: wall clearance and speed of wall following against the velocity
threshold (0.65 to 0.95) in square and circle, single FAM."
# shellcheck source-path=SCRIPTDIR
source "$(dirname "${BASH_SOURCE[0]}")/lib.sh"
parse_options "$@"

WORLD_NAMES=(square circle)
TRIALS=$(pick 1 3 5)
LEARN_MINUTES=15
[[ $SIZE == tiny ]] && LEARN_MINUTES=1
ALL_THRESHOLDS="0.65 0.70 0.75 0.80 0.85 0.90 0.95"
read -r -a THRESHOLDS <<<"$(pick "0.65 0.95" "$ALL_THRESHOLDS" "$ALL_THRESHOLDS")"
read -r -a BEHAVIOURS <<<"$(pick wall-left "wall-left wall-right" "wall-left wall-right")"
RUN_MINUTES=$(pick 0.2 5 10)
CONFIG=single

fam_job() { # WORLD SEED
    local log
    log=$(log_of "$1" "$CONFIG" "$2")
    learn_log "$log" "$1" "$2" "$CONFIG" "$LEARN_MINUTES"
    train_fam "${log%.h5}-fam.h5" "$log" "$CONFIG"
}

wall_job() { # WORLD SEED BEHAVIOUR THRESHOLD
    once "$OUT/runs/$3-$1-s$2-t$4.json" \
        "$(params kind tvl world "$1" seed "$2" config "$CONFIG" learn_minutes "$LEARN_MINUTES" \
            behaviour "$3" threshold "$4" run_minutes "$RUN_MINUTES" reflexes "$TVL_REFLEX")" \
        "$TVL" run "$OUT/work/$1-$CONFIG-s$2-fam.h5" "$(world "$1")" --behaviour "$3" --threshold "$4" \
        --minutes "$RUN_MINUTES" --seed "$2" --reflex "$TVL_REFLEX" --json
}

fams=() runs=()
for world_name in "${WORLD_NAMES[@]}"; do
    for seed in $(seq "$TRIALS"); do
        fams+=("fam_job $world_name $seed")
        for behaviour in "${BEHAVIOURS[@]}"; do
            for threshold in "${THRESHOLDS[@]}"; do
                runs+=("wall_job $world_name $seed $behaviour $threshold")
            done
        done
    done
done
pool "${fams[@]}"
pool "${runs[@]}"
finish fig21
