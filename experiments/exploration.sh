#!/usr/bin/env bash
# Exploration strategies and coverage (`tvl learn --explore`): how much of the floor each
# choice rule covers while learning, and how soon the FAM it learns makes avoid competent, in
# the lab and in generated rooms worlds nobody tuned on (`tvl world new rooms --seed N`).
#
# For each world, rule and trial (seed): learn for the longest time and record the coverage
# at the end of every minute (`tvl replay --json`); train a single FAM from the log as it stood
# after each snapshot length and run avoid with it for a competence run's length. Time to
# competence is the shortest snapshot length whose avoid run is competent. In the lab each rule
# also learns with collision points from bumps alone (`--near 0`; coverage only), as the
# learner's sonar collision points stop it short of gaps its body would pass.
#
#            lab trials  rooms worlds, trials  learning min  snapshots  avoid run
#   --tiny   1           1001, 1               1             1          0.2 min
#   --quick  3           1001-1005, 1          45            5, 15, 45  5 min
#   --full   5           1001-1005, 3          45            5, 15, 45  5 min
FIGURE=exploration
DESCRIPTION="Exploration strategies: coverage while learning in the lab, and time to competence
in the lab and generated rooms worlds, for each tvl learn --explore rule."
# shellcheck source-path=SCRIPTDIR
source "$(dirname "${BASH_SOURCE[0]}")/lib.sh"
parse_options "$@"

RULES=(least-experience novelty random)
LAB_TRIALS=$(pick 1 3 5)
read -r -a ROOMS_SEEDS <<<"$(pick 1001 "$(seq -s ' ' 1001 1005)" "$(seq -s ' ' 1001 1005)")"
ROOMS_TRIALS=$(pick 1 1 3)
read -r -a SNAPSHOTS <<<"$(pick 1 "5 15 45" "5 15 45")"
LEARN_MINUTES=${SNAPSHOTS[-1]}
CONFIG=single

# Generated worlds live beside the work files; the lab is a bundled one.
GENERATED=$OUT/work/worlds
mkdir -p "$GENERATED"
world() {
    if [[ $1 == rooms-* ]]; then
        echo "$GENERATED/$1.txt"
    else
        echo "$WORLDS_DIR/$1.txt"
    fi
}

log_name() { # WORLD RULE COLLISION_POINTS SEED
    echo "$OUT/work/$1-$2-$3-s$4.h5"
}

# learn_job WORLD RULE COLLISION_POINTS SEED: learn once into a log (made as LOG.part, so a
# half-made one is started again), its collision points found by the sonars as well (`sonar`,
# the default) or by bumps alone (`bumps`, --near 0); record its per-minute coverage as a
# "learn" run.
learn_job() {
    local world_name=$1 rule=$2 points=$3 seed=$4 log near=()
    log=$(log_name "$@")
    [[ $points == bumps ]] && near=(--near 0)
    if [[ ! -s $log ]]; then
        rm -f "$log.part"
        if ! "$TVL" learn "$(world "$world_name")" --log "$log.part" --minutes "$LEARN_MINUTES" \
            --seed "$seed" --config "$CONFIG" --explore "$rule" "${near[@]}" \
            --json >/dev/null 2>"$log.err"; then
            echo "failed: tvl learn $world_name --explore $rule seed $seed (see $log.err)" >&2
            return 1
        fi
        rm -f "$log.err"
        mv "$log.part" "$log"
    fi
    once "$OUT/runs/learn-$world_name-$rule-$points-s$seed.json" \
        "$(params kind learn world "$world_name" explore "$rule" collision_points "$points" \
            seed "$seed" learn_minutes "$LEARN_MINUTES")" \
        "$TVL" replay "$log" --json
}

# competence_job WORLD RULE SEED: for each snapshot length, train a FAM from the default
# learner's log as it stood then and run avoid with it; the FAM is deleted once its run is kept.
competence_job() {
    local world_name=$1 rule=$2 seed=$3 minutes snapshot fam result
    minutes=$(competence_run_minutes)
    for snapshot in "${SNAPSHOTS[@]}"; do
        fam=$OUT/work/$world_name-$rule-s$seed-m$snapshot.h5
        result=$OUT/runs/avoid-$world_name-$rule-s$seed-m$snapshot.json
        [[ -s $result ]] && continue
        train_fam "$fam" "$(log_name "$world_name" "$rule" sonar "$seed")" "$CONFIG" "$snapshot"
        once "$result" \
            "$(params kind tvl world "$world_name" explore "$rule" seed "$seed" config "$CONFIG" \
                learnt_minutes "$snapshot" behaviour avoid run_minutes "$minutes" \
                reflexes "$TVL_REFLEX")" \
            "$TVL" run "$fam" "$(world "$world_name")" --behaviour avoid --minutes "$minutes" \
            --seed "$seed" --reflex "$TVL_REFLEX" --json
        rm -f "$fam"
    done
}

for world_seed in "${ROOMS_SEEDS[@]}"; do
    [[ -s $(world "rooms-$world_seed") ]] ||
        "$TVL" world new rooms --seed "$world_seed" -o "$(world "rooms-$world_seed")" \
            --force >/dev/null
done
learning=() runs=()
for rule in "${RULES[@]}"; do
    for seed in $(seq "$LAB_TRIALS"); do
        learning+=("learn_job lab $rule sonar $seed" "learn_job lab $rule bumps $seed")
        runs+=("competence_job lab $rule $seed")
    done
    for world_seed in "${ROOMS_SEEDS[@]}"; do
        for seed in $(seq "$ROOMS_TRIALS"); do
            learning+=("learn_job rooms-$world_seed $rule sonar $seed")
            runs+=("competence_job rooms-$world_seed $rule $seed")
        done
    done
done
pool "${learning[@]}"
pool "${runs[@]}"
finish exploration
