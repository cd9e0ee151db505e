#!/usr/bin/env bash
# Final states of the shipped scenes from two semlb binaries, compared bit for bit by h5diff (/elements and /cells):
# scenes/epidermis.yaml and scenes/mechanics.yaml on the four backends, scenes/epidermis_development.yaml on the three
# binned/OpenCL ones, double and float, STEPS steps (cell stages included). A refactor that must not change results
# (a plug-in moved out of the core, a loop rewritten) passes with "different 0". Usage: scripts/compare_states.sh OLD_SEMLB NEW_SEMLB [STEPS] [PLATFORM]
# (defaults 100, Portable: PoCL); work files in $TMPDIR/compare_states. OLD_SCENES: the scenes folder OLD reads (default
# this checkout's scenes/), for an OLD built before a change of the scene format (e.g. OLD_SCENES=../main/scenes).
set -u
OLD=$1; NEW=$2; STEPS=${3:-100}; PLATFORM=${4:-Portable}
here=$(cd "$(dirname "$0")/.." && pwd)
OLD_SCENES=${OLD_SCENES:-$here/scenes}
W=${TMPDIR:-/tmp}/compare_states; rm -rf "$W"; mkdir -p "$W"
same=0; different=0
run() {  # SCENE BACKEND PRECISION
  local tag v bin scenes platform=()
  tag="$(basename "$1" .yaml)_$2_$3"
  case $2 in opencl*) platform=(--platform "$PLATFORM");; esac  # the OpenCL backends' setting: the others refuse it
  for v in old new; do
    bin=$OLD scenes=$OLD_SCENES; [ "$v" = new ] && bin=$NEW scenes=$here/scenes
    "$bin" sim --scene "$scenes/$1" --out "$W/$v/$tag" --steps "$STEPS" --backend "$2" --precision "$3" \
      "${platform[@]}" --quiet --set output.snapshot_every=0 --set output.checkpoint_every=0 > "$W/$v.$tag.log" 2>&1 ||
      { echo "$v $tag failed:"; tail -3 "$W/$v.$tag.log"; }
  done
  if h5diff "$W/old/$tag/final.h5" "$W/new/$tag/final.h5" /elements > /dev/null 2>&1 &&
     h5diff "$W/old/$tag/final.h5" "$W/new/$tag/final.h5" /cells > /dev/null 2>&1; then
    same=$((same + 1)); echo "same      $tag"
  else
    different=$((different + 1)); echo "DIFFERENT $tag"
  fi
}
for s in epidermis.yaml mechanics.yaml; do
  for b in serial cpu-binned opencl-allpairs opencl-binned; do for p in double float; do run $s $b $p; done; done
done
for b in cpu-binned opencl-allpairs opencl-binned; do for p in double float; do run epidermis_development.yaml $b $p; done; done
echo "identical $same, different $different"
[ "$different" = 0 ]
