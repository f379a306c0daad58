#!/usr/bin/env bash
# Figure 27 (paper §5.2): the lab, single against multi FAM, over a long learning session.
#
# For each FAM configuration and trial (seed): learn in the lab with that configuration, and at
# each snapshot minute train the FAM the learner had then and run avoid and wall following:
# mean speed and collisions per minute against learning time. DWA's avoid run is the reference.
#
#            trials  learning minutes  snapshots every  runs
#   --tiny   1       1                 minute 1 only    0.2 min
#   --quick  3       45                5 min            5 min
#   --full   5       60                5 min            5 min
FIGURE=fig27_lab
DESCRIPTION="Figure 27: mean speed and collision rate of avoid and wall following in the lab
against learning time, single and multi FAM, with DWA beside."
# shellcheck source-path=SCRIPTDIR
source "$(dirname "${BASH_SOURCE[0]}")/lib.sh"
parse_options "$@"

WORLD_NAME=lab
CONFIGS=(single multi)
BEHAVIOURS=(avoid wall)
TRIALS=$(pick 1 3 5)
LEARN_MINUTES=$(pick 1 45 60)
EVERY=$(pick 1 5 5)
FIRST_SNAPSHOT=$(pick 1 0 0) # minute 0: the untrained FAM

learning=() runs=()
for seed in $(seq "$TRIALS"); do
    for config in "${CONFIGS[@]}"; do
        learning+=("learn_job $WORLD_NAME $config $seed $LEARN_MINUTES")
        for minute in $(seq "$FIRST_SNAPSHOT" "$EVERY" "$LEARN_MINUTES"); do
            runs+=("snapshot_job $WORLD_NAME $seed $config $config $minute ${BEHAVIOURS[*]}")
        done
    done
    runs+=("dwa_job $WORLD_NAME $seed")
done
pool "${learning[@]}"
pool "${runs[@]}"
finish fig27
