# shellcheck shell=bash
# Shared by the experiment scripts (source it): options and sizes, resumable runs, a pool of
# parallel jobs, and the last steps (results.jsonl, the figure and its summary table).
#
# Every run keeps its result as one JSON line in OUT/runs/NAME.json: the run's parameters
# followed by what `tvl ... --json` printed. A run whose file exists is never repeated, so an
# interrupted script picks up where it stopped. Learning logs and FAM files live in OUT/work/.

set -euo pipefail

EXPERIMENTS_DIR=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
WORLDS_DIR=${TVL_WORLDS:-$EXPERIMENTS_DIR/../worlds}
TVL=${TVL:-tvl}

# The length of the avoid run that tests competence, as COMPETENCE_RUN_MINUTES in
# tvl_cli/core/competence.py (which holds the test; `tvl figure` applies it): "time to
# competence" is the first learning minute whose snapshot FAM passes it.
COMPETENCE_RUN_MINUTES=5

# The reflexes beyond the paper (`tvl run --reflex`) that TVL runs and baseline runs use; each
# run's JSON line records them. TVL_REFLEX=none runs the paper's choice rule alone.
TVL_REFLEX=${TVL_REFLEX:-all}
BASELINE_REFLEX=${BASELINE_REFLEX:-none}

die() {
    echo "${0##*/}: $*" >&2
    exit 2
}

usage() {
    cat <<EOF
usage: ${0##*/} [--quick | --full | --tiny] [--out DIR] [-j N]

$DESCRIPTION

  --quick    a smaller study that finishes in about a quarter of an hour on 2 cores (default)
  --full     the paper's trial counts and learning times
  --tiny     seconds: checks that the script works, not a result
  --out DIR  where results go (default: results/$FIGURE); running again resumes
  -j N       parallel runs (default: the number of cores)
EOF
}

# parse_options "$@": sets SIZE (tiny|quick|full), OUT and JOBS; needs FIGURE and DESCRIPTION.
parse_options() {
    SIZE=quick
    OUT=results/$FIGURE
    JOBS=$(nproc 2>/dev/null || getconf _NPROCESSORS_ONLN 2>/dev/null || echo 1)
    while (($#)); do
        case $1 in
            --tiny | --quick | --full) SIZE=${1#--} ;;
            --out)
                (($# >= 2)) || die "--out needs a directory"
                OUT=$2
                shift
                ;;
            --out=*) OUT=${1#*=} ;;
            -j | --jobs)
                (($# >= 2)) || die "$1 needs a number"
                JOBS=$2
                shift
                ;;
            --jobs=*) JOBS=${1#*=} ;;
            -j*) JOBS=${1#-j} ;;
            -h | --help)
                usage
                exit 0
                ;;
            *) die "unknown option $1 (see --help)" ;;
        esac
        shift
    done
    [[ $JOBS =~ ^[1-9][0-9]*$ ]] || die "-j $JOBS: expected a positive whole number"
    command -v "$TVL" >/dev/null || die "'$TVL' not found: activate the environment where tvl is installed, or set TVL=/path/to/tvl"
    [[ -d $WORLDS_DIR ]] || die "$WORLDS_DIR: no worlds directory (set TVL_WORLDS)"
    mkdir -p "$OUT/runs" "$OUT/work"
    # Results of different sizes must not mix in one figure.
    if [[ -s $OUT/size ]]; then
        local before
        before=$(<"$OUT/size")
        [[ $before == "$SIZE" ]] || die "$OUT holds a --$before study; use another --out or remove it"
    else
        echo "$SIZE" >"$OUT/size"
    fi
    STARTED_S=$SECONDS
    echo "${0##*/}: --$SIZE, $JOBS parallel runs, results in $OUT" >&2
}

# pick TINY QUICK FULL: the value for this size.
pick() {
    case $SIZE in
        tiny) echo "$1" ;;
        quick) echo "$2" ;;
        full) echo "$3" ;;
    esac
}

competence_run_minutes() {
    pick 0.2 "$COMPETENCE_RUN_MINUTES" "$COMPETENCE_RUN_MINUTES"
}

# world FILE_NAME: the world file of a bundled world name.
world() {
    echo "$WORLDS_DIR/$1.txt"
}

# world_goals NAME: the world's goals, one "X,Y" (metres) a line, from `tvl world show --json`.
world_goals() {
    "$TVL" world show "$(world "$1")" --json |
        grep -o '"goals": \[\(\[[^]]*\],\? \?\)*\]' |
        grep -o '\[[-0-9.e]*, [-0-9.e]*\]' |
        tr -d '[] '
}

# params KEY VALUE ...: one JSON object; values that look like numbers stay numbers.
params() {
    local json="" separator="" key value
    while (($# >= 2)); do
        key=$1 value=$2
        shift 2
        if [[ $value =~ ^-?[0-9]+(\.[0-9]+)?$ ]]; then
            json+="$separator\"$key\": $value"
        else
            value=${value//\\/\\\\}
            json+="$separator\"$key\": \"${value//\"/\\\"}\""
        fi
        separator=", "
    done
    printf '{%s}' "$json"
}

# done_all RESULT...: true when every result file exists.
done_all() {
    local result
    for result in "$@"; do
        [[ -s $result ]] || return 1
    done
}

# once RESULT PARAMS COMMAND...: run COMMAND (a `tvl ... --json` command) unless RESULT exists,
# and keep its JSON object with PARAMS in front as one line in RESULT.
once() {
    local result=$1 parameters=$2 output
    shift 2
    [[ -s $result ]] && return 0
    if ! output=$("$@" 2>"$result.err"); then
        echo "failed: $* (see $result.err)" >&2
        return 1
    fi
    # `tvl --json` indents; one line per run is what JSON-lines readers expect.
    # shellcheck disable=SC2001 # each line's indent, which no ${var//} pattern anchors
    output=$(sed 's/^ *//' <<<"$output" | tr '\n' ' ')
    output=${output% }
    if [[ $output != \{*\} ]]; then
        printf '%s\n' "$output" >>"$result.err"
        echo "failed: $* printed no JSON object (see $result.err)" >&2
        return 1
    fi
    rm -f "$result.err"
    local body=${output#\{}
    body=${body# }
    if [[ $body == "}" ]]; then
        printf '%s\n' "$parameters" >"$result.tmp"
    else
        printf '%s, %s\n' "${parameters%\}}" "$body" >"$result.tmp"
    fi
    mv "$result.tmp" "$result"
    echo "  done ${result##*/}" >&2
}

# learn_log LOG WORLD SEED CONFIG MINUTES: make the learning log once. `tvl learn` appends a
# session to an existing log, so it writes LOG.part first and a half-made one is started again.
learn_log() {
    local log=$1 world_name=$2 seed=$3 config=$4 minutes=$5
    [[ -s $log ]] && return 0
    rm -f "$log.part"
    if ! "$TVL" learn "$(world "$world_name")" --log "$log.part" --minutes "$minutes" \
        --seed "$seed" --config "$config" --json >/dev/null 2>"$log.err"; then
        echo "failed: tvl learn $world_name seed $seed (see $log.err)" >&2
        return 1
    fi
    rm -f "$log.err"
    mv "$log.part" "$log"
}

# train_fam FAM LOG CONFIG [MINUTE]: train FAM from LOG once (a snapshot if MINUTE is given).
train_fam() {
    local fam=$1 log=$2 config=$3 until=()
    [[ -s $fam ]] && return 0
    (($# >= 4)) && until=(--until-minute "$4")
    if ! "$TVL" train "$log" -o "$fam" --config "$config" "${until[@]}" --force \
        >/dev/null 2>"$fam.err"; then
        echo "failed: tvl train $log (see $fam.err)" >&2
        return 1
    fi
    rm -f "$fam.err"
}

# learn_job WORLD CONFIG SEED MINUTES: learn once into log_of WORLD CONFIG SEED, and record its
# per-minute ΔV, episodes and collisions (`tvl replay --json`) as a "learn" run.
learn_job() {
    local log
    log=$(log_of "$1" "$2" "$3")
    learn_log "$log" "$1" "$3" "$2" "$4"
    once "$OUT/runs/learn-$1-$2-s$3.json" \
        "$(params kind learn world "$1" seed "$3" config "$2" learn_minutes "$4")" \
        "$TVL" replay "$log" --json
}

log_of() { # WORLD CONFIG SEED
    echo "$OUT/work/$1-$2-s$3.h5"
}

# snapshot_job WORLD SEED LOG_CONFIG FAM_CONFIG MINUTE BEHAVIOUR...: train a FAM_CONFIG FAM
# from the log learnt with LOG_CONFIG as it stood at MINUTE, and run each behaviour with it for
# a competence run's length. The FAM is deleted once all its runs are kept.
snapshot_job() {
    local world_name=$1 seed=$2 log_config=$3 config=$4 minute=$5 name fam behaviour
    local results=() minutes
    shift 5
    minutes=$(competence_run_minutes)
    name=$world_name-$config-s$seed-m$(printf %02d "$minute")
    fam=$OUT/work/$name.h5
    for behaviour in "$@"; do
        results+=("$OUT/runs/$behaviour-$name.json")
    done
    done_all "${results[@]}" && return 0
    train_fam "$fam" "$(log_of "$world_name" "$log_config" "$seed")" "$config" "$minute"
    for behaviour in "$@"; do
        once "$OUT/runs/$behaviour-$name.json" \
            "$(params kind tvl world "$world_name" seed "$seed" config "$config" \
                learn_config "$log_config" minute "$minute" behaviour "$behaviour" \
                threshold 0.85 run_minutes "$minutes" reflexes "$TVL_REFLEX")" \
            "$TVL" run "$fam" "$(world "$world_name")" --behaviour "$behaviour" \
            --minutes "$minutes" --seed "$seed" --reflex "$TVL_REFLEX" --json
    done
    rm -f "$fam"
}

# dwa_job WORLD SEED: the Dynamic Window Approach's avoid run, as long as a competence run.
dwa_job() {
    local minutes
    minutes=$(competence_run_minutes)
    once "$OUT/runs/dwa-$1-s$2.json" \
        "$(params kind dwa world "$1" seed "$2" behaviour avoid run_minutes "$minutes" \
            reflexes "$BASELINE_REFLEX")" \
        "$TVL" baseline dwa "$(world "$1")" --behaviour avoid --minutes "$minutes" \
        --seed "$2" --reflex "$BASELINE_REFLEX" --json
}

# qlearn_job WORLD SEED LEARN_MINUTES EVERY: tabular Q-learning beside TVL, its competence
# judged every EVERY learning minutes (not at --tiny size: each check is a 5-minute run).
qlearn_job() {
    local minutes checks=() recorded=()
    minutes=$(competence_run_minutes)
    if [[ $SIZE != tiny ]]; then
        checks=(--competence-every "$4")
        recorded=(competence_every "$4")
    fi
    once "$OUT/runs/qlearn-$1-s$2.json" \
        "$(params kind qlearn world "$1" seed "$2" run_minutes "$minutes" "${recorded[@]}" \
            reflexes "$BASELINE_REFLEX")" \
        "$TVL" baseline qlearn "$(world "$1")" --learn-minutes "$3" --minutes "$minutes" \
        --seed "$2" "${checks[@]}" --reflex "$BASELINE_REFLEX" --json
}

# pool JOB...: run each JOB (a command line naming a function of the script) with at most JOBS
# at once; after all have finished, fail if any failed (running the script again retries them).
pool() {
    local job running=0 failed=0
    for job in "$@"; do
        if ((running >= JOBS)); then
            wait -n || failed=1
            running=$((running - 1))
        fi
        (eval "$job") &
        running=$((running + 1))
    done
    while ((running > 0)); do
        wait -n || failed=1
        running=$((running - 1))
    done
    if ((failed)); then
        echo "${0##*/}: some runs failed; run the script again to retry them" >&2
        exit 1
    fi
}

# finish FIGURE_NAME: gather the runs into results.jsonl, draw the figure, write summary.md.
finish() {
    local runs=("$OUT"/runs/*.json)
    [[ -e ${runs[0]} ]] || die "no results in $OUT/runs"
    cat "${runs[@]}" >"$OUT/results.jsonl.tmp"
    if [[ -s $OUT/$FIGURE.png && -s $OUT/summary.md ]] &&
        cmp -s "$OUT/results.jsonl.tmp" "$OUT/results.jsonl"; then
        rm "$OUT/results.jsonl.tmp"
        cat "$OUT/summary.md"
        echo "${0##*/}: nothing new since $OUT/$FIGURE.png was drawn (remove it to redraw)" >&2
        return 0
    fi
    mv "$OUT/results.jsonl.tmp" "$OUT/results.jsonl"
    "$TVL" figure "$1" "$OUT/results.jsonl" -o "$OUT/$FIGURE.png" --table "$OUT/summary.md" \
        --force
    echo "${0##*/}: ${#runs[@]} runs in $OUT/results.jsonl, figure $OUT/$FIGURE.png," \
        "table $OUT/summary.md ($((SECONDS - STARTED_S)) s)" >&2
}
