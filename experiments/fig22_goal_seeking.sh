#!/usr/bin/env bash
# Figure 22 (and 26, paper §5.1–5.2): goal seeking among obstacles (4 goals) and into a narrow
# passage, with the single and the multi FAM.
#
# For each world, FAM configuration and trial (seed): learn with that configuration, train its
# FAM, then seek each of the world's goals (from `tvl world show --json`) from the start: goals
# reached and time to reach them. The first trial's paths are kept as run traces (drawn in the
# figure) and as one PNG per run under paths/. DWA seeks the same goals beside them.
#
#            worlds and goals        trials  learning minutes  goal run (at most)  paths/*.png
#   --tiny   obstacles' first goal   1       1                 0.2 min             none
#   --quick  both, all goals         3       20                3 min               first trial
#   --full   both, all goals         5       25                5 min               first trial
FIGURE=fig22_goal_seeking
DESCRIPTION="Figure 22: goal seeking in obstacles (4 goals) and narrow with the single and
multi FAM: goals reached and paths, with DWA beside."
# shellcheck source-path=SCRIPTDIR
source "$(dirname "${BASH_SOURCE[0]}")/lib.sh"
parse_options "$@"

read -r -a WORLD_NAMES <<<"$(pick obstacles "obstacles narrow" "obstacles narrow")"
CONFIGS=(single multi)
TRIALS=$(pick 1 3 5)
LEARN_MINUTES=$(pick 1 20 25)
RUN_MINUTES=$(pick 0.2 3 5)
GOALS_PER_WORLD=$(pick 1 100 100)
PNG_PER_RUN=$(pick no yes yes) # drawing costs more than a tiny run
mkdir -p "$OUT/paths" "$OUT/work/traces"

fam_job() { # WORLD SEED CONFIG
    local log
    log=$(log_of "$1" "$3" "$2")
    learn_log "$log" "$1" "$2" "$3" "$LEARN_MINUTES"
    train_fam "${log%.h5}-fam.h5" "$log" "$3"
}

goal_job() { # WORLD SEED CONFIG GOAL_INDEX X,Y
    local name=$1-$3-s$2-g$4 drawn=() traced=()
    if (($2 == 1)); then # the first trial's paths, to draw
        drawn=(--log "$OUT/work/traces/$name.h5" --force)
        traced=(trace "work/traces/$name.h5") # relative to results.jsonl
    fi
    if (($2 == 1)) && [[ $PNG_PER_RUN == yes ]]; then
        drawn+=(--png "$OUT/paths/$name.png")
    fi
    once "$OUT/runs/goal-$name.json" \
        "$(params kind tvl world "$1" seed "$2" config "$3" learn_minutes "$LEARN_MINUTES" \
            behaviour goal threshold 0.85 goal_index "$4" goal "$5" run_minutes "$RUN_MINUTES" \
            reflexes "$TVL_REFLEX" "${traced[@]}")" \
        "$TVL" run "$OUT/work/$1-$3-s$2-fam.h5" "$(world "$1")" --behaviour goal --goal "$5" \
        --minutes "$RUN_MINUTES" --seed "$2" --reflex "$TVL_REFLEX" "${drawn[@]}" --json
}

dwa_job() { # WORLD SEED GOAL_INDEX X,Y
    once "$OUT/runs/dwa-$1-s$2-g$3.json" \
        "$(params kind dwa world "$1" seed "$2" behaviour goal goal_index "$3" goal "$4" \
            run_minutes "$RUN_MINUTES" reflexes "$BASELINE_REFLEX")" \
        "$TVL" baseline dwa "$(world "$1")" --behaviour goal --goal "$4" \
        --minutes "$RUN_MINUTES" --seed "$2" --reflex "$BASELINE_REFLEX" --json
}

fams=() runs=()
for world_name in "${WORLD_NAMES[@]}"; do
    mapfile -t goals < <(world_goals "$world_name")
    goals=("${goals[@]:0:GOALS_PER_WORLD}")
    ((${#goals[@]})) || die "$(world "$world_name"): no goals"
    for seed in $(seq "$TRIALS"); do
        for config in "${CONFIGS[@]}"; do
            fams+=("fam_job $world_name $seed $config")
        done
        for index in "${!goals[@]}"; do
            for config in "${CONFIGS[@]}"; do
                runs+=("goal_job $world_name $seed $config $((index + 1)) ${goals[index]}")
            done
            runs+=("dwa_job $world_name $seed $((index + 1)) ${goals[index]}")
        done
    done
done
pool "${fams[@]}"
pool "${runs[@]}"
finish fig22
