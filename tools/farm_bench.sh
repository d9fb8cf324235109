#!/bin/bash
# The cost of cutting a render into farm parts (issue 8's benchmark), on
# one machine. Renders SCENE
#
#   one        in one go, straight to a PNG (the one-machine baseline)
#   raw        in one go as a raw EXR, then `spar develop`
#   tiles-N    as N tiles (`--tile I/N --raw`) run one after another,
#              then `spar merge` and `spar develop`
#   blocks-K   (with --blocks) as K sample blocks `--samples k0..k1/S`
#              run one after another, then merge and develop
#   slurm-N    (with --slurm, as root) the `spar plan --slurm` job of N
#              tiles on a throwaway local Slurm (tests/slurm/cluster.sh),
#              one CPU per tile: wall time from submission to the merged
#              and developed image
#
# and prints a table: wall and CPU (user + sys of every spar process)
# seconds per configuration, each split into render / merge / develop, and
# the ratio to the one-go render. Every merged raw file must equal the
# one-go raw render, and every developed PNG the one-go PNG, pixel for
# pixel (idiff, no tolerance); the script fails otherwise.
#
#   tools/farm_bench.sh [--samples S] [--threads T] [--tiles "4 16"]
#                       [--blocks "4"] [--slurm] [SCENE]
#
# Defaults: scenes/glass-unpolarized.toml (512x512), its own samples (1),
# all cores, tiles "4 16", no blocks, no Slurm. SPAR=path picks the spar
# binary (default: target/release/spar, or $CARGO_TARGET_DIR's). Needs
# idiff (openimageio-tools) and GNU time (/usr/bin/time).
set -euo pipefail
cd "$(dirname "$0")/.."
TARGET_DIR=${CARGO_TARGET_DIR:-target}
case $TARGET_DIR in /*) ;; *) TARGET_DIR=$PWD/$TARGET_DIR ;; esac
SPAR=${SPAR:-$TARGET_DIR/release/spar}
SCENE=scenes/glass-unpolarized.toml
SAMPLES=
THREADS=$(nproc)
TILES="4 16"
BLOCKS=
SLURM=0
while [ $# -gt 0 ]; do
    case $1 in
    --samples) SAMPLES=$2; shift 2 ;;
    --threads) THREADS=$2; shift 2 ;;
    --tiles) TILES=$2; shift 2 ;;
    --blocks) BLOCKS=$2; shift 2 ;;
    --slurm) SLURM=1; shift ;;
    -h | --help) sed -n '2,/^set -euo/p' "$0" | sed '$d; s/^# \{0,1\}//'; exit 0 ;;
    -*) echo "farm_bench.sh: unknown option $1" >&2; exit 2 ;;
    *) SCENE=$1; shift ;;
    esac
done
for tool in idiff /usr/bin/time; do
    command -v "$tool" >/dev/null || { echo "farm_bench.sh: needs $tool" >&2; exit 1; }
done
[ -x "$SPAR" ] || { echo "farm_bench.sh: no spar at $SPAR (cargo build --release)" >&2; exit 1; }
SCENE=$(realpath "$SCENE")
W=$(mktemp -d /tmp/spar-farm-bench.XXXXXX)
trap 'rm -rf "$W"' EXIT
if [ -n "$SAMPLES" ]; then
    SPP=$SAMPLES
else
    SPP=$(sed -nE 's/^samples *= *([0-9]+).*/\1/p' "$SCENE" | head -n1)
fi
BASE=(--threads "$THREADS" -q)
ARGS=("${BASE[@]}" --samples "$SPP")

# `timed LOG cmd…` runs cmd and appends "wall user sys" to LOG.
timed() {
    local log=$1
    shift
    /usr/bin/time -a -o "$log" -f "%e %U %S" "$@"
}
# `sum LOG`: "wall cpu" summed over LOG's lines.
sum() {
    awk '{w += $1; c += $2 + $3} END {printf "%.2f %.2f", w, c}' "$1"
}
same() {
    idiff -fail 0 -warn 0 "$1" "$2" >"$W/idiff.txt" 2>&1 ||
        { cat "$W/idiff.txt" >&2; echo "farm_bench.sh: $2 differs from $1" >&2; exit 1; }
}

ROWS=()
# `row NAME DIR`: one line of the table from DIR/{render,merge,develop}.t.
row() {
    local name=$1 dir=$2 r m d
    r=$(sum "$dir/render.t")
    m=$( [ -s "$dir/merge.t" ] && sum "$dir/merge.t" || echo "0 0")
    d=$( [ -s "$dir/develop.t" ] && sum "$dir/develop.t" || echo "0 0")
    ROWS+=("$name $r $m $d")
}

echo "farm_bench: $(basename "$SCENE") --samples $SPP --threads $THREADS, spar $("$SPAR" --version | cut -d' ' -f2), $(nproc) cores" >&2

echo "== one go" >&2
mkdir -p "$W/one" "$W/raw"
timed "$W/one/render.t" "$SPAR" render "$SCENE" "${ARGS[@]}" -o "$W/one.png"
row one "$W/one"
timed "$W/raw/render.t" "$SPAR" render "$SCENE" "${ARGS[@]}" --raw -o "$W/one.exr"
timed "$W/raw/develop.t" "$SPAR" develop "$W/one.exr" -q -o "$W/raw.png"
same "$W/one.png" "$W/raw.png"
row raw "$W/raw"

for n in $TILES; do
    echo "== $n tiles, one after another" >&2
    d=$W/tiles-$n
    mkdir -p "$d"
    parts=()
    for ((i = 0; i < n; i++)); do
        timed "$d/render.t" "$SPAR" render "$SCENE" "${ARGS[@]}" --tile "$i/$n" -o "$d/tile-$i.exr"
        parts+=("$d/tile-$i.exr")
    done
    timed "$d/merge.t" "$SPAR" merge "${parts[@]}" -q -o "$d/merged.exr"
    timed "$d/develop.t" "$SPAR" develop "$d/merged.exr" -q -o "$d/image.png"
    same "$W/one.exr" "$d/merged.exr"
    same "$W/one.png" "$d/image.png"
    row "tiles-$n" "$d"
done

for k in $BLOCKS; do
    echo "== $k sample blocks of $SPP, one after another" >&2
    [ "$k" -le "$SPP" ] || { echo "farm_bench.sh: $k blocks need at least $k samples" >&2; exit 2; }
    d=$W/blocks-$k
    mkdir -p "$d"
    parts=()
    for ((i = 0; i < k; i++)); do
        k0=$((i * SPP / k))
        k1=$(((i + 1) * SPP / k))
        timed "$d/render.t" "$SPAR" render "$SCENE" "${BASE[@]}" --samples "$k0..$k1/$SPP" \
            -o "$d/block-$i.exr"
        parts+=("$d/block-$i.exr")
    done
    timed "$d/merge.t" "$SPAR" merge "${parts[@]}" -q -o "$d/merged.exr"
    timed "$d/develop.t" "$SPAR" develop "$d/merged.exr" -q -o "$d/image.png"
    same "$W/one.exr" "$d/merged.exr"
    same "$W/one.png" "$d/image.png"
    row "blocks-$k" "$d"
done

if [ "$SLURM" = 1 ]; then
    source tests/slurm/cluster.sh
    trap 'slurm_stop; rm -rf "$W"' EXIT
    slurm_start "$W/cluster"
    for n in $TILES; do
        echo "== $n tiles on the local Slurm, 1 CPU each" >&2
        d=$W/slurm-$n
        mkdir -p "$d"
        "$SPAR" plan "$SCENE" --tiles "$n" --slurm --threads 1 --samples "$SPP" --out-dir "$d/job" >"$d/job.sh"
        t0=$(date +%s.%N)
        out=$(bash "$d/job.sh")
        array=$(sed -nE 's/.* as job ([0-9]+) and .*/\1/p' <<<"$out")
        merge=$(sed -nE 's/.*merge as job ([0-9]+).*/\1/p' <<<"$out")
        slurm_wait "$array,$merge" 3600
        t1=$(date +%s.%N)
        bad=$({ slurm_states "$array"; slurm_states "$merge"; } | grep -v ' COMPLETED 0:0$' || true)
        [ -z "$bad" ] || { echo "farm_bench.sh: failed jobs: $bad" >&2; exit 1; }
        same "$W/one.exr" "$d/job/merged.exr"
        same "$W/one.png" "$d/job/image.png"
        # Slurm knows no CPU time here (no accounting): wall only.
        ROWS+=("slurm-$n $(awk -v a="$t0" -v b="$t1" 'BEGIN {printf "%.2f", b - a}') - 0 - 0 -")
    done
fi

# The table: configuration, wall and CPU seconds (total, then render /
# merge / develop), ratios to the one-go render.
base=(${ROWS[0]})
printf '| configuration | wall s | CPU s | render wall / CPU | merge wall / CPU | develop wall / CPU | wall ÷ one | CPU ÷ one |\n'
printf '|---|---:|---:|---:|---:|---:|---:|---:|\n'
for r in "${ROWS[@]}"; do
    awk -v bw="${base[1]}" -v bc="${base[2]}" '{
        cpu = ($3 == "-") ? "-" : sprintf("%.1f", $3 + $5 + $7)
        wall = $2 + $4 + $6
        if ($3 == "-") {
            printf "| %s | %.1f | - | %.1f / - | in the job | in the job | %.2f | - |\n", $1, wall, $2, wall / bw
        } else {
            printf "| %s | %.1f | %s | %.1f / %.1f | %.2f / %.2f | %.2f / %.2f | %.2f | %.2f |\n",
                $1, wall, cpu, $2, $3, $4, $5, $6, $7, wall / bw, cpu / bc
        }
    }' <<<"$r"
done
echo "farm_bench: every merged and developed image equals the one-go render, pixel for pixel" >&2
