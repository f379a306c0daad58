#!/usr/bin/env bash
# The ablation of the reflexes: how much of each behaviour the robot learnt, and how much each
# rule beyond the paper adds. In the square, the lab and a generated lab (seed 7) nobody tuned
# on: for each trial (seed), learn with our defaults and train a single and a multi FAM, then
# avoid and follow the left wall with no reflex, each reflex alone, and all of them; and learn,
# train and run by the paper's method (`--method paper`: core.method.PAPER).
#
#            trials  learning minutes  runs
#   --tiny   1       1 (square only)   0.2 min, avoid only
#   --quick  3       15                5 min
#   --full   5       15                10 min
FIGURE=ablation
DESCRIPTION="Reflex ablation: contacts, speed and spins of avoid and wall-left with each reflex
alone, all, none, and the paper's method, in square, lab and a generated lab."
# shellcheck source-path=SCRIPTDIR
source "$(dirname "${BASH_SOURCE[0]}")/lib.sh"
parse_options "$@"

read -r -a WORLD_NAMES <<<"$(pick square "square lab lab-s7" "square lab lab-s7")"
TRIALS=$(pick 1 3 5)
LEARN_MINUTES=$(pick 1 15 15)
RUN_MINUTES=$(pick 0.2 5 10)
read -r -a BEHAVIOURS <<<"$(pick avoid "avoid wall-left" "avoid wall-left")"
CONFIGS=(single multi)
SETTINGS=(none blocked-ways near-miss bump tie wall-start all)

# Generated worlds live beside the work files; the shipped ones in worlds/.
GENERATED=$OUT/work/worlds
mkdir -p "$GENERATED"
[[ -s $GENERATED/lab-s7.txt ]] || "$TVL" world new lab --seed 7 -o "$GENERATED/lab-s7.txt" --force
world() {
    if [[ -s $GENERATED/$1.txt ]]; then echo "$GENERATED/$1.txt"; else echo "$WORLDS_DIR/$1.txt"; fi
}

fam_job() { # WORLD SEED LEARNING (ours|paper)
    local log=$OUT/work/$1-$3-s$2.h5 method=(--method default)
    [[ $3 == paper ]] && method=(--method paper)
    if [[ ! -s $log ]]; then
        rm -f "$log.part"
        "$TVL" learn "$(world "$1")" --log "$log.part" --minutes "$LEARN_MINUTES" --seed "$2" \
            "${method[@]}" --json >/dev/null 2>"$log.err" || {
            echo "failed: tvl learn $1 seed $2 $3 (see $log.err)" >&2
            return 1
        }
        rm -f "$log.err"
        mv "$log.part" "$log"
    fi
    for config in "${CONFIGS[@]}"; do
        local fam=$OUT/work/$1-$3-$config-s$2-fam.h5
        [[ -s $fam ]] && continue
        "$TVL" train "$log" -o "$fam" --config "$config" "${method[@]}" --force >/dev/null ||
            return 1
    done
}

run_job() { # WORLD SEED CONFIG BEHAVIOUR SETTING
    local learning=ours method=(--reflex "$5")
    if [[ $5 == paper ]]; then
        learning=paper method=(--method paper)
    fi
    once "$OUT/runs/$4-$1-$3-s$2-$5.json" \
        "$(params kind tvl world "$1" seed "$2" config "$3" learning "$learning" \
            learn_minutes "$LEARN_MINUTES" behaviour "$4" threshold 0.85 \
            run_minutes "$RUN_MINUTES" reflexes "$5")" \
        "$TVL" run "$OUT/work/$1-$learning-$3-s$2-fam.h5" "$(world "$1")" --behaviour "$4" \
        --minutes "$RUN_MINUTES" --seed "$2" "${method[@]}" --json
}

fams=() runs=()
for world_name in "${WORLD_NAMES[@]}"; do
    for seed in $(seq "$TRIALS"); do
        fams+=("fam_job $world_name $seed ours" "fam_job $world_name $seed paper")
        for config in "${CONFIGS[@]}"; do
            for behaviour in "${BEHAVIOURS[@]}"; do
                for setting in "${SETTINGS[@]}" paper; do
                    runs+=("run_job $world_name $seed $config $behaviour $setting")
                done
            done
        done
    done
done
pool "${fams[@]}"
pool "${runs[@]}"
finish ablation
