#!/usr/bin/env bash
# Packs what a device call made under a results folder, for a machine whose files come back from one folder with
# limits on their count and size: the files under RESULTS newer than SINCE (a file touched when the call began), less
# what a later call remakes in seconds and is large (measured_time.sh's tissue/final.h5) and partial writes (*.tmp files and
# folders, as a run stopped mid-write leaves), as one tar.gz cut into parts of PART_MB (default 15) MB named NAME.tgz.aa, .ab,
# ... in DEST; at most MAX_PARTS (default 7) parts: when they would be more, the largest files are left out one by
# one until the rest fits, each named on stderr, and the exit status is 1 (what fits still comes back).
# Unpack beside RESULTS: `cat DEST/NAME.tgz.* | tar xz -C PARENT_OF_RESULTS`.
# Usage: bash scripts/gpu/pack_results.sh RESULTS SINCE DEST [NAME]
set -euo pipefail
[ $# -ge 3 ] || { echo "usage: pack_results.sh RESULTS SINCE DEST [NAME]" >&2; exit 2; }
results=$1; since=$2; dest=$3; name=${4:-results}
[ -d "$results" ] || { echo "pack_results.sh: $results: not a folder" >&2; exit 2; }
[ -f "$since" ] || { echo "pack_results.sh: $since: no such file (the call's start marker)" >&2; exit 2; }
mkdir -p "$dest"
parent=$(cd "$(dirname "$results")" && pwd); base=$(basename "$results")
list=$(mktemp); trap 'rm -f "$list" "$list.next"' EXIT
(cd "$parent" && find "$base" -type f -newer "$since" ! -path '*/tissue/final.h5' ! -name '*.tmp' ! -path '*.tmp/*' |
  LC_ALL=C sort) > "$list"
if [ ! -s "$list" ]; then echo "pack_results.sh: nothing under $results is newer than $since"; exit 0; fi
left=0
while :; do
  rm -f "$dest/$name.tgz."*
  [ -s "$list" ] || break
  tar czf - -C "$parent" -T "$list" | split -b "${PART_MB:-15}m" - "$dest/$name.tgz."
  parts=$(ls "$dest/$name.tgz."* | wc -l)
  [ "$parts" -gt "${MAX_PARTS:-7}" ] || break
  # the largest file left out, and the rest packed again
  big=$(cd "$parent" && tr '\n' '\0' < "$list" | xargs -0 stat -c '%s %n' | sort -n | tail -1 | cut -d' ' -f2-)
  echo "pack_results.sh: left out $big ($(du -h "$parent/$big" | cut -f1)): $parts parts of ${PART_MB:-15} MB," \
    "more than ${MAX_PARTS:-7}" >&2
  grep -vxF -- "$big" "$list" > "$list.next" || true
  mv "$list.next" "$list"; left=$((left + 1))
done
echo "pack_results.sh: $(wc -l < "$list") files in $(ls "$dest/$name.tgz."* 2>/dev/null | wc -l) part(s) $dest/$name.tgz.*"
[ "$left" = 0 ] || { echo "pack_results.sh: $left file(s) left out (above)" >&2; exit 1; }
