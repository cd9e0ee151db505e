#!/usr/bin/env bash
# Packs what a device call made under a results folder, for a machine whose files come back from one folder with
# limits on their count and size: the files under RESULTS newer than SINCE (a file touched when the call began), less
# what a later call remakes in seconds and is large (measured_time.sh's tissue/final.h5), as one tar.gz cut into
# parts of PART_MB (default 15) MB named NAME.tgz.aa, .ab, ... in DEST; at most MAX_PARTS (default 7) parts, else
# exit 1 saying so and leaving none. Unpack beside RESULTS: `cat DEST/NAME.tgz.* | tar xz -C PARENT_OF_RESULTS`.
# Usage: bash scripts/gpu/pack_results.sh RESULTS SINCE DEST [NAME]
set -euo pipefail
[ $# -ge 3 ] || { echo "usage: pack_results.sh RESULTS SINCE DEST [NAME]" >&2; exit 2; }
results=$1; since=$2; dest=$3; name=${4:-results}
[ -d "$results" ] || { echo "pack_results.sh: $results: not a folder" >&2; exit 2; }
[ -f "$since" ] || { echo "pack_results.sh: $since: no such file (the call's start marker)" >&2; exit 2; }
mkdir -p "$dest"
parent=$(cd "$(dirname "$results")" && pwd); base=$(basename "$results")
list=$(mktemp); trap 'rm -f "$list"' EXIT
(cd "$parent" && find "$base" -type f -newer "$since" ! -path '*/tissue/final.h5' | LC_ALL=C sort) > "$list"
if [ ! -s "$list" ]; then echo "pack_results.sh: nothing under $results is newer than $since"; exit 0; fi
rm -f "$dest/$name.tgz."*
tar czf - -C "$parent" -T "$list" | split -b "${PART_MB:-15}m" - "$dest/$name.tgz."
parts=$(ls "$dest/$name.tgz."* | wc -l)
if [ "$parts" -gt "${MAX_PARTS:-7}" ]; then
  rm -f "$dest/$name.tgz."*
  echo "pack_results.sh: $(wc -l < "$list") files need $parts parts of ${PART_MB:-15} MB, more than ${MAX_PARTS:-7}" >&2
  exit 1
fi
echo "pack_results.sh: $(wc -l < "$list") files in $parts part(s) $dest/$name.tgz.*"
