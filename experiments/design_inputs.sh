#!/usr/bin/env bash
# FAM inputs chosen from data (`tvl design`) against the hand-chosen single and multi FAMs.
#
# The design is made from learning logs of tuning worlds only (`tvl world new rooms --seed N`,
# N from 1; the generalization benchmark's test worlds, seeds 1001-1020, are for reporting):
# one log of 15 simulated minutes in each, then `tvl design` over all of them. In the lab, for
# each trial (seed): learn once with the single FAM, train a single, a multi and the designed
# FAM from that one log, and run avoid and wall-left with each: contacts a minute and speed.
# Last, unless --tiny, the generalization benchmark on the test worlds with this run's design
# as "redesigned" beside the shipped configurations (PYTHON, default python, runs it; several
# minutes). At --quick size the design is the shipped `designed` one.
#
#            tuning worlds  their logs  trials  lab learning  runs     generalization
#   --tiny   2              1 min       1       1 min         0.2 min  not run
#   --quick  10             15 min      3       45 min        5 min    --set test --quick
#   --full   20             15 min      5       45 min        5 min    --set test
FIGURE=design_inputs
DESCRIPTION="FAM inputs chosen from tuning worlds' logs by tvl design, against single and multi:
lab avoid and wall-left after 45 minutes of learning, and the generalization benchmark."
# shellcheck source-path=SCRIPTDIR
source "$(dirname "${BASH_SOURCE[0]}")/lib.sh"
parse_options "$@"

TUNING_WORLDS=$(pick 2 10 20)
TUNING_MINUTES=$(pick 1 15 15)
TRIALS=$(pick 1 3 5)
LAB_MINUTES=$(pick 1 45 45)
RUN_MINUTES=$(pick 0.2 5 5)
BEHAVIOURS=(avoid wall-left)
RUN_GENERALIZATION=$(pick no yes yes)
read -r -a GENERALIZATION_SIZE <<<"$(pick "" --quick "")"
DESIGNED=$OUT/work/designed.json
PYTHON=${PYTHON:-python}
mkdir -p "$OUT/work/tuning"

tuning_job() { # WORLD_SEED: the world and a log learnt in it with seed 1, each made once
    local world=$OUT/work/tuning/rooms-s$1.txt log=$OUT/work/tuning/rooms-s$1.h5
    [[ -s $log ]] && return 0
    "$TVL" world new rooms --seed "$1" -o "$world" --force >/dev/null
    rm -f "$log.part"
    if ! "$TVL" learn "$world" --log "$log.part" --minutes "$TUNING_MINUTES" --seed 1 \
        >/dev/null 2>"$log.err"; then
        echo "failed: tvl learn rooms seed $1 (see $log.err)" >&2
        return 1
    fi
    rm -f "$log.err"
    mv "$log.part" "$log"
}

lab_job() { # SEED: train each configuration from the lab log and run each behaviour with it
    local log config fam behaviour
    log=$(log_of lab single "$1")
    for config in single multi designed; do
        fam=$OUT/work/fam-lab-$config-s$1.h5
        if [[ $config == designed ]]; then
            train_fam "$fam" "$log" "$DESIGNED"
        else
            train_fam "$fam" "$log" "$config"
        fi
        for behaviour in "${BEHAVIOURS[@]}"; do
            once "$OUT/runs/$behaviour-lab-$config-s$1.json" \
                "$(params kind tvl world lab seed "$1" config "$config" learn_minutes \
                    "$LAB_MINUTES" behaviour "$behaviour" threshold 0.85 \
                    run_minutes "$RUN_MINUTES" reflexes "$TVL_REFLEX")" \
                "$TVL" run "$fam" "$(world lab)" --behaviour "$behaviour" \
                --minutes "$RUN_MINUTES" --seed "$1" --reflex "$TVL_REFLEX" --json
        done
    done
}

tuning=() learning=() runs=()
for world_seed in $(seq "$TUNING_WORLDS"); do
    tuning+=("tuning_job $world_seed")
done
for seed in $(seq "$TRIALS"); do
    learning+=("learn_job lab single $seed $LAB_MINUTES")
    runs+=("lab_job $seed")
done
pool "${tuning[@]}" "${learning[@]}"
tuning_logs=()
for world_seed in $(seq "$TUNING_WORLDS"); do
    tuning_logs+=("$OUT/work/tuning/rooms-s$world_seed.h5")
done
once "$OUT/runs/design.json" \
    "$(params kind design tuning_worlds "$TUNING_WORLDS" tuning_minutes "$TUNING_MINUTES")" \
    "$TVL" design "${tuning_logs[@]}" -o "$DESIGNED" --seed 1 --force --json
pool "${runs[@]}"

# summary.md: per configuration and behaviour, the lab runs' means over trials.
cat "$OUT"/runs/*.json >"$OUT/results.jsonl"
{
    echo "### Lab, $LAB_MINUTES minutes of learning, $TRIALS trials: designed against single and multi"
    echo
    echo "| config | behaviour | contacts/min | speed m/s |"
    echo "| --- | --- | --- | --- |"
    for config in single multi designed; do
        for behaviour in "${BEHAVIOURS[@]}"; do
            cat "$OUT"/runs/"$behaviour"-lab-"$config"-s*.json |
                grep -o '"contacts_per_min": [-0-9.e]*\|"mean_speed_mps": [-0-9.e]*' |
                awk -v c="$config" -v b="$behaviour" '
                    /contacts/ { contacts += $2; n++ }
                    /speed/ { speed += $2 }
                    END { printf "| %s | %s | %.2f | %.2f |\n", c, b, contacts / n, speed / n }'
        done
    done
} >"$OUT/summary.md"
cat "$OUT/summary.md"

if [[ $RUN_GENERALIZATION == yes ]]; then
    if [[ ! -s $OUT/generalization.txt ]]; then
        "$PYTHON" "$EXPERIMENTS_DIR/../benchmarks/generalization.py" --set test \
            "${GENERALIZATION_SIZE[@]}" --config "redesigned=$DESIGNED" >"$OUT/generalization.txt.part"
        mv "$OUT/generalization.txt.part" "$OUT/generalization.txt"
    fi
    cat "$OUT/generalization.txt"
fi
echo "${0##*/}: design $DESIGNED, lab table $OUT/summary.md ($((SECONDS - STARTED_S)) s)" >&2
