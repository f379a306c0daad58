#!/usr/bin/env bash
# Learning while behaving (`tvl run --learn`): does a robot that goes on learning from what it
# meets while it avoids, its collision points estimated from the sonar returns it gathers on
# the way, meet things less often as the run goes on than one whose FAM stays fixed?
#
# In generated rooms worlds nobody tuned on (the generalization test seeds, `tvl world new
# rooms --seed N`): for each world and trial (seed), learn by exploring and train single FAMs
# from the log as it stood after 0 (nothing learnt), 5 and 15 minutes; then avoid, with every
# reflex, with the FAM fixed and with --learn. A FAM that has learnt nothing perceives nothing
# as fast at the usual threshold, so from scratch the robot also runs at threshold 0.15, below
# the initial velocity's fraction of every maximum: everything looks fast until learnt slow.
#
#            worlds                 trials  exploration minutes  runs
#   --tiny   rooms 1001             1       0, 1                 0.2 min
#   --quick  rooms 1001-1005        2       0, 5, 15             10 min
#   --full   rooms 1001-1020        3       0, 5, 15             10 min
FIGURE=online
DESCRIPTION="Learning while behaving: contacts a minute over avoid runs with the FAM fixed and
learning as it goes (tvl run --learn), after 0, 5 and 15 minutes of exploration."
# shellcheck source-path=SCRIPTDIR
source "$(dirname "${BASH_SOURCE[0]}")/lib.sh"
parse_options "$@"

read -r -a WORLD_SEEDS <<<"$(pick 1001 "$(seq -s ' ' 1001 1005)" "$(seq -s ' ' 1001 1020)")"
TRIALS=$(pick 1 2 3)
read -r -a STARTS <<<"$(pick "0 1" "0 5 15" "0 5 15")"
RUN_MINUTES=$(pick 0.2 10 10)
THRESHOLD=0.85
SCRATCH_THRESHOLD=0.15
CONFIG=single

# Generated worlds live beside the work files.
GENERATED=$OUT/work/worlds
mkdir -p "$GENERATED"
world() {
    echo "$GENERATED/$1.txt"
}

fam_job() { # WORLD_SEED TRIAL: the world, its exploratory log, and a FAM per start
    local name=rooms-$1 start
    [[ -s $(world "$name") ]] ||
        "$TVL" world new rooms --seed "$1" -o "$(world "$name")" --force >/dev/null
    learn_log "$(log_of "$name" "$CONFIG" "$2")" "$name" "$2" "$CONFIG" "${STARTS[-1]}"
    for start in "${STARTS[@]}"; do
        # --until-minute 0 trains on no episode: every entry keeps its initial velocity.
        train_fam "$OUT/work/$name-$CONFIG-s$2-m$start.h5" "$(log_of "$name" "$CONFIG" "$2")" \
            "$CONFIG" "$start"
    done
}

run_job() { # WORLD_SEED TRIAL START THRESHOLD SETTING (fixed|learns)
    local name=rooms-$1 learn=()
    [[ $5 == learns ]] && learn=(--learn)
    once "$OUT/runs/$name-s$2-m$3-t$4-$5.json" \
        "$(params kind tvl world "$name" seed "$2" config "$CONFIG" start_minutes "$3" \
            behaviour avoid threshold "$4" run_minutes "$RUN_MINUTES" reflexes all online "$5")" \
        "$TVL" run "$OUT/work/$name-$CONFIG-s$2-m$3.h5" "$(world "$name")" --behaviour avoid \
        --threshold "$4" --minutes "$RUN_MINUTES" --seed "$2" "${learn[@]}" --json
}

fams=() runs=()
for world_seed in "${WORLD_SEEDS[@]}"; do
    for trial in $(seq "$TRIALS"); do
        fams+=("fam_job $world_seed $trial")
        for setting in fixed learns; do
            for start in "${STARTS[@]}"; do
                runs+=("run_job $world_seed $trial $start $THRESHOLD $setting")
            done
            runs+=("run_job $world_seed $trial 0 $SCRATCH_THRESHOLD $setting")
        done
    done
done
pool "${fams[@]}"
pool "${runs[@]}"
finish online
