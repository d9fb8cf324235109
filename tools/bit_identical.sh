#!/bin/bash
# Renders the default scene and the seed scenes with two spar binaries and
# checks that every image is identical pixel for pixel and in its metadata
# (all but spar:version, which names the git revision).
#   tools/bit_identical.sh OLD_SPAR NEW_SPAR [WORKDIR]
# Used for refactors that must not change a single output bit (issue 14).
set -euo pipefail
old=$1 new=$2 dir=${3:-$(mktemp -d)}
here=${SPAR_ROOT:-$(cd "$(dirname "$0")/.." && pwd)}
cases=(
  "default||-m color,dop,ellipticity,azimuth,stokes"
  "default-rust||-m color,dop --accel rust"
  "default-draft||-m color --quality draft --resolution 96x96"
  "default-block||-m color --samples 1..3/4 --resolution 64x64|exr"
  "calcite-polarized|scenes/calcite-polarized.toml|-m color,dop,ellipticity,stokes --resolution 128x128"
  "calcite-unpolarized|scenes/calcite-unpolarized.toml|-m color,dop --resolution 128x128"
  "glass-polarized|scenes/glass-polarized.toml|-m color,dop,stokes --resolution 128x128"
  "glass-unpolarized|scenes/glass-unpolarized.toml|-m color,azimuth --resolution 128x128 --spectral hero:3 --samples 4"
)
fail=0
for c in "${cases[@]}"; do
  IFS='|' read -r name scene flags ext <<<"$c"
  for which in old new; do
    bin=${!which}
    mkdir -p "$dir/$which"
    # shellcheck disable=SC2086
    (cd "$here" && "$bin" render ${scene:+"$scene"} $flags -o "$dir/$which/$name.${ext:-png}" >/dev/null 2>"$dir/$which/$name.log") || {
      echo "FAIL $name: $which binary failed (see $dir/$which/$name.log)"; fail=1; }
  done
done
for f in "$dir"/old/*.png "$dir"/old/*.exr; do
  [ -e "$f" ] || continue
  g=$dir/new/$(basename "$f")
  if [ ! -e "$g" ]; then echo "FAIL $(basename "$f"): missing in new"; fail=1; continue; fi
  if ! idiff -fail 0 -failpercent 0 -warn 0 "$f" "$g" >/dev/null 2>&1; then
    echo "FAIL $(basename "$f"): pixels differ"; fail=1; continue
  fi
  if ! diff <(iinfo -v "$f" | grep -v -e spar:version -e DateTime -e "^$f") <(iinfo -v "$g" | grep -v -e spar:version -e DateTime -e "^$g") >/dev/null; then
    echo "FAIL $(basename "$f"): metadata differs"; fail=1; continue
  fi
  echo "same $(basename "$f")"
done
for f in "$dir"/new/*.png "$dir"/new/*.exr; do
  [ -e "$dir/old/$(basename "$f")" ] || { echo "FAIL $(basename "$f"): only in new"; fail=1; }
done
[ $fail = 0 ] && echo "bit-identical: all images equal" || echo "bit-identical: DIFFERENCES"
exit $fail
