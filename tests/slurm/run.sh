#!/bin/bash
# spar's render-farm path on a real Slurm (issue 8), run by .ci/run after the
# README's test command. Starts munge, slurmctld and slurmd by hand on
# 127.0.0.1 (throwaway config and munge key, as root, no cgroups), then:
#
#  1. submits the `spar plan --slurm` script for a small scene (a tile array
#     and the dependent merge), waits by polling squeue, checks every job's
#     state and exit code, and compares the merged raw EXR and the developed
#     PNG with a one-machine render, pixel by pixel (no tolerance);
#  2. makes one tile fail (its output path is a directory), checks that the
#     merge was cancelled and nothing merged, resubmits only that tile
#     (`bash job.sh 2`), and compares again;
#  3. stops the daemons by their PID files.
#
# Needs root, slurm-wlm, munge and oiiotool/idiff (openimageio-tools).
# SPAR=path/to/spar overrides the binary (default: target/release/spar).
set -euo pipefail
cd "$(dirname "$0")/../.."
for tool in slurmctld slurmd munged sbatch squeue idiff; do
    if ! command -v "$tool" >/dev/null; then
        echo "tests/slurm/run.sh: FAILED: $tool is not installed (apt-get install slurm-wlm munge openimageio-tools)" >&2
        exit 1
    fi
done
if [ "$(id -u)" != 0 ]; then
    echo "tests/slurm/run.sh: FAILED: the test cluster runs as root" >&2
    exit 1
fi
TARGET_DIR=${CARGO_TARGET_DIR:-target}
case $TARGET_DIR in /*) ;; *) TARGET_DIR=$PWD/$TARGET_DIR ;; esac
SPAR=${SPAR:-$TARGET_DIR/release/spar}
[ -x "$SPAR" ] || cargo build --release
W=$(mktemp -d /tmp/spar-slurm.XXXXXX)
source tests/slurm/cluster.sh
cleanup() {
    local rc=$?
    slurm_stop
    if [ "$rc" != 0 ]; then
        echo "--- slurm test failed; logs from $W:" >&2
        tail -n 20 "$W"/cluster/*.log "$W"/job/logs/*.log >&2 2>/dev/null || true
    fi
    rm -rf "$W"
    exit "$rc"
}
trap cleanup EXIT
fail() {
    echo "tests/slurm/run.sh: FAILED: $*" >&2
    exit 1
}

slurm_start "$W/cluster"
echo "slurm: $(sinfo -h -o '%P %D %c %T') (slurm $(sinfo -V | cut -d' ' -f2))"

SCENE=$PWD/scenes/glass-unpolarized.toml
ARGS=(--resolution 96x64 --samples 3)
TILES=4
"$SPAR" render "$SCENE" "${ARGS[@]}" --raw -o "$W/ref.exr" -q
"$SPAR" render "$SCENE" "${ARGS[@]}" --mode color -o "$W/ref.png" -q
"$SPAR" plan "$SCENE" --tiles $TILES --slurm --out-dir "$W/job" "${ARGS[@]}" >"$W/job.sh"

# Submits job.sh (with its arguments); sets ARRAY and MERGE to the job ids.
submit() {
    local out
    out=$(bash "$W/job.sh" "$@")
    echo "$out"
    ARRAY=$(sed -nE 's/.* as job ([0-9]+) and .*/\1/p' <<<"$out")
    MERGE=$(sed -nE 's/.*merge as job ([0-9]+).*/\1/p' <<<"$out")
    [ -n "$ARRAY" ] && [ -n "$MERGE" ] || fail "cannot read the job ids from: $out"
    slurm_wait "$ARRAY,$MERGE" 600
}

# Expects `slurm_states JOB` to print exactly $2 (lines joined by "; ").
expect_states() {
    local got
    got=$(slurm_states "$1" | paste -sd ';' | sed 's/;/; /g')
    [ "$got" = "$2" ] || fail "job $1: expected states '$2', got '$got'"
    echo "job $1: $got"
}

same_pixels() {
    idiff -fail 0 -warn 0 "$1" "$2" >"$W/idiff.txt" 2>&1 ||
        { cat "$W/idiff.txt" >&2; fail "$2 differs from the one-machine render $1"; }
    echo "identical pixels: $(basename "$1") and $2"
}

echo "== 1. the whole job"
submit
expect_states "$ARRAY" "0 COMPLETED 0:0; 1 COMPLETED 0:0; 2 COMPLETED 0:0; 3 COMPLETED 0:0"
expect_states "$MERGE" "- COMPLETED 0:0"
same_pixels "$W/ref.exr" "$W/job/merged.exr"
same_pixels "$W/ref.png" "$W/job/image.png"
grep -qE '^spar: progress ([0-9]+)/\1 tiles 100.0%' "$W/job/logs/tile-3.log" ||
    fail "no progress lines in the tile log"

echo "== 2. one failing tile, resubmitted alone"
rm -rf "$W/job"
mkdir -p "$W/job/parts/tile-2.exr" # tile 2 cannot write its part
submit
expect_states "$ARRAY" "0 COMPLETED 0:0; 1 COMPLETED 0:0; 2 FAILED 2:0; 3 COMPLETED 0:0"
state=$(slurm_states "$MERGE")
[ "$state" = "- CANCELLED 0:0" ] || fail "the merge should be cancelled, is '$state'"
echo "job $MERGE: $state"
[ ! -e "$W/job/merged.exr" ] || fail "a merge ran although a tile failed"
grep -q 'is a directory' "$W/job/logs/tile-2.log" || fail "tile 2's log does not say why"
rmdir "$W/job/parts/tile-2.exr"
submit 2
expect_states "$ARRAY" "2 COMPLETED 0:0"
expect_states "$MERGE" "- COMPLETED 0:0"
same_pixels "$W/ref.exr" "$W/job/merged.exr"
same_pixels "$W/ref.png" "$W/job/image.png"

echo "tests/slurm/run.sh: PASS"
