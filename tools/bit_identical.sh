#!/bin/bash
# Renders the default scene and the seed scenes with two spar binaries and
# checks that every image is identical pixel for pixel and in its metadata
# (all but spar:version, which names the git revision).
#   [NEW_FLAGS="..."] tools/bit_identical.sh OLD_SPAR NEW_SPAR [WORKDIR]
# NEW_FLAGS (default empty): extra flags appended to the NEW binary's render
# command line only, e.g. NEW_FLAGS="--coherence incoherent" to check that a
# newer spar run with an option reproduces an older spar's images.
# The metadata comparison ignores the " coherence=<model>" suffix that a spar
# with coherent light (issue 12) appends to the new image's spar:settings,
# spar:scene_hash when both images carry one and they differ, and the
# spar:wavelengths_nm attribute when only the new image has it (see below).
# A Stokes EXR is in the JCGT 2021 layout since issue 16 (channels S0.580nm,
# an RGB preview, three layout attributes): when the old one is not, the new
# one's channels are compared under the old names (S0_580nm, or S0 for one
# wavelength) and the preview and layout attributes are left out.
# Used for refactors that must not change a single output bit (issue 14).
set -euo pipefail
old=$1 new=$2 dir=${3:-$(mktemp -d)}
new_flags=${NEW_FLAGS:-}
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
    extra=; [ $which = new ] && extra=$new_flags
    mkdir -p "$dir/$which"
    # shellcheck disable=SC2086
    (cd "$here" && "$bin" render ${scene:+"$scene"} $flags $extra -o "$dir/$which/$name.${ext:-png}" >/dev/null 2>"$dir/$which/$name.log") || {
      echo "FAIL $name: $which binary failed (see $dir/$which/$name.log)"; fail=1; }
  done
done
# The metadata of image $1 as compared; $2 = new strips the coherence suffix.
meta() {
  { iinfo -v "$1" || echo "iinfo failed"; } |
    { grep -v -e spar:version -e DateTime -e "^$1" || true; } |
    if [ "$2" = new ]; then sed '/^ *spar:settings: /s/ coherence=[a-z]*"$/"/'; else cat; fi
}
for f in "$dir"/old/*.png "$dir"/old/*.exr; do
  [ -e "$f" ] || continue
  g=$dir/new/$(basename "$f")
  if [ ! -e "$g" ]; then echo "FAIL $(basename "$f"): missing in new"; fail=1; continue; fi
  if [[ $f == *.exr ]] && iinfo -v "$g" | grep -q spectralLayoutVersion && ! iinfo -v "$f" | grep -q spectralLayoutVersion; then
    # Old names from the old file: S<c>_<λ>nm -> S<c>.<λ>nm, S<c> -> S<c>.<λ>nm.
    nm=$(iinfo -v "$g" | sed -n 's/^ *spar:wavelengths_nm: "\(.*\)"$/\1/p')
    spec=$(iinfo -v "$f" | sed -n 's/^ *channel list: //p' | tr -d ' ' | tr ',' '\n' |
      while read -r ch; do
        case $ch in
          S[0-3]_*nm) new=${ch%%_*}.${ch#*_}; new=${new/./@}; new=${new//./,}; new=${new/@/.} ;;
          S[0-3]) new=$ch.${nm//./,}nm ;;
          *) new=$ch ;;
        esac
        printf '%s=%s\n' "$ch" "$new"
      done | paste -sd, -)
    oiiotool "$g" --ch "$spec" -o "$g.old-names.exr" >/dev/null 2>&1 &&
      mv "$g.old-names.exr" "$g" || { echo "FAIL $(basename "$f"): cannot rename the new channels"; fail=1; continue; }
  fi
  if ! idiff -fail 0 -failpercent 0 -warn 0 "$f" "$g" >/dev/null 2>&1; then
    echo "FAIL $(basename "$f"): pixels differ"; fail=1; continue
  fi
  mo=$(meta "$f" old) mn=$(meta "$g" new)
  if [[ $f == *.exr ]] && grep -q spectralLayoutVersion <<<"$mn" && ! grep -q spectralLayoutVersion <<<"$mo"; then
    # The layout's attributes, and what oiiotool's renaming added.
    mn=$(grep -v -e spectralLayoutVersion -e emissiveUnits -e polarisationHandedness -e '^ *Software: "OpenImageIO' -e 'Exif:ImageHistory' <<<"$mn" || true)
  fi
  # spar:scene_hash now also hashes lights at infinity and the scene unit
  # (issue 12), so it legitimately changed for the same scene: when both
  # images carry one and they differ, leave it out (a missing one still fails).
  ho=$(grep '^ *spar:scene_hash: ' <<<"$mo" || true) hn=$(grep '^ *spar:scene_hash: ' <<<"$mn" || true)
  if [ -n "$ho" ] && [ -n "$hn" ] && [ "$ho" != "$hn" ]; then
    mo=$(grep -v '^ *spar:scene_hash: ' <<<"$mo" || true) mn=$(grep -v '^ *spar:scene_hash: ' <<<"$mn" || true)
    note=" (spar:scene_hash differs, ignored)"
  else
    note=
  fi
  # A Stokes EXR names its wavelengths in spar:wavelengths_nm since issue 16
  # (item 5): a new attribute, left out when only the new image has it.
  if ! grep -q '^ *spar:wavelengths_nm: ' <<<"$mo"; then
    mn=$(grep -v '^ *spar:wavelengths_nm: ' <<<"$mn" || true)
  fi
  if ! diff <(echo "$mo") <(echo "$mn") >/dev/null; then
    echo "FAIL $(basename "$f"): metadata differs"; fail=1; continue
  fi
  echo "same $(basename "$f")$note"
done
for f in "$dir"/new/*.png "$dir"/new/*.exr; do
  [ -e "$dir/old/$(basename "$f")" ] || { echo "FAIL $(basename "$f"): only in new"; fail=1; }
done
[ $fail = 0 ] && echo "bit-identical: all images equal" || echo "bit-identical: DIFFERENCES"
exit $fail
