#!/usr/bin/env bash
# REPORT.md in two levels and the provenance of committed GPU rows: a stale row is marked with its commit and the
# summary draws no verdict from it (nor from one git cannot date), a current one gets its verdict; on the committed
# results REPORT.md stays within 400 lines and links a detail page per section, each of which exists.
set -euo pipefail
src=$1; work=$2; semlb=$3
PY=${PYTHON:-/usr/bin/python3}
git -C "$src" rev-parse HEAD >/dev/null 2>&1 || { echo "no git history: staleness cannot be tested"; exit 77; }
rm -rf "$work"; mkdir -p "$work"
fail() { echo "FAIL: $*"; exit 1; }

# One section (single device) with this run's CPU rows and a committed H200 CSV whose provenance we choose.
run_with() {  # COMMIT NAME [DEVICE] -> the REPORT.md of a run whose committed gpu/single_device was made with COMMIT
  local c=$1 d="$work/$2" dev=${3:+, \"device\": \"$3\"}
  mkdir -p "$d/results/single_device" "$d/committed/gpu/single_device"
  cp "$src/results/cpu/single_device/single_device.csv" "$src/results/cpu/single_device/single_device.manifest.yaml" \
    "$d/results/single_device/"
  cp "$src/results/gpu/single_device/single_device.csv" "$d/committed/gpu/single_device/"
  printf '{"semlb_commit": "%s", "date": "2026-01-01", "how": "test"%s}\n' "$c" "$dev" > "$d/committed/gpu/single_device/provenance.json"
  "$PY" "$src/analysis/report.py" --results "$d/results" --committed "$d/committed" --semlb "$semlb" > "$d/log" 2>&1 ||
    { cat "$d/log"; fail "report.py on $2"; }
}
row() { grep "^| 1 | \[Single-device" "$work/$1/results/REPORT.md" || fail "$1: no summary row 1"; }

# Stale: the newest commit that provenance.py itself calls stale (a commit before the last change under the kernels'
# and controllers' paths that is more than comments; the commit just before a comment-only change is still current).
old=$(cd "$src/analysis" && "$PY" -c '
import subprocess, sys, provenance
for c in subprocess.run(["git", "-C", sys.argv[1], "log", "--format=%H", "-40", "--", "engine/backends"],
                        capture_output=True, text=True, check=True).stdout.split():
    if provenance.status(c)[0] == provenance.STALE:
        print(c); break' "$src")
[ -n "$old" ] || fail "no stale commit among the last 40 changes to engine/backends"
run_with "$old" stale
r=$(row stale)
[[ "$r" == *"**stale**"* && "$r" == *"${old:0:7}"* ]] || fail "stale row not marked with its commit: $r"
[[ "$r" == *"**no verdict**"* && "$r" != *"| agrees |"* ]] || fail "summary drew a verdict from a stale row: $r"
grep -q "^\*Committed GPU rows: made with \`${old:0:7}\` 2026-01-01; \*\*stale\*\*" "$work/stale/results/REPORT.md" ||
  fail "section does not say its GPU rows are stale"
grep -q "^\*\*Reading (of stale GPU rows" "$work/stale/results/REPORT.md" || fail "reading not flagged as from stale rows"

# Current: HEAD itself (no kernel or controller change after it): the verdict stands.
run_with "$(git -C "$src" rev-parse HEAD)" fresh
r=$(row fresh)
[[ "$r" == *"| agrees |" && "$r" == *"current ("* ]] || fail "current row lost its verdict: $r"
# The card is the record's `device` where it has one (a record without it is from the H200s)
[[ "$r" == *"H200 binned"* ]] || fail "a record without a device is not labelled H200: $r"
run_with "$(git -C "$src" rev-parse HEAD)" card "NVIDIA H100 80GB HBM3, 580.159.04"
r=$(row card)
[[ "$r" == *"H100 binned"* && "$r" != *"H200"* ]] || fail "the summary does not name the record's card: $r"
grep -q "machine: 1 NVIDIA H100 80GB HBM3 (" "$work/card/results/report/01-single_device.md" ||
  fail "the detail page does not name the record's card"

# Unknown: a commit this clone does not hold: no verdict, and it says why.
run_with 0123456789abcdef0123456789abcdef01234567 unknown
r=$(row unknown)
[[ "$r" == *"**unknown**"* && "$r" == *"**no verdict**"* ]] || fail "unknown provenance got a verdict: $r"
grep -q "staleness \*\*unknown\*\* (commit 0123456 is not in this clone)" "$work/unknown/results/REPORT.md" ||
  fail "unknown: no reason given"

# analysis/provenance.py on its own: every committed GPU folder has a record (--check), stale ones named.
"$PY" "$src/analysis/provenance.py" --check > "$work/provenance.txt" || { cat "$work/provenance.txt"; fail "a committed GPU result without provenance.json"; }
grep -q "^gpu/single_device: [0-9a-f]\{7\} 2026-[0-9-]* \(stale\|fresh\)" "$work/provenance.txt" || fail "provenance.py line"
# a result under a folder made with another commit than the folder's gets its own line
grep -q "^gpu/measured/learned_repartition: c3e6807 2026-12-03 \(stale\|fresh\)" "$work/provenance.txt" ||
  fail "provenance.py: no line for a subfolder with its own commit"

# The bottom line of "which controller": a scene's current measured summaries decide its line; a scene with none shows
# its newest stale one, marked stale with its commit; a stale summary of a scene that has a current one is left out.
bottom_of() {  # NAME SCENE=COMMIT...: REPORT.md's bottom line with those measured summaries (provenance COMMIT)
  local d="$work/$1"; shift
  mkdir -p "$d/results/single_device"  # one section of this run, as report.py needs one
  cp "$src/results/cpu/single_device/single_device.csv" "$src/results/cpu/single_device/single_device.manifest.yaml" \
    "$d/results/single_device/"
  for sc in "$@"; do
    mkdir -p "$d/committed/gpu/measured/${sc%%=*}"
    cp "$src/results/gpu/measured/${sc%%=*}/end_to_end_summary.csv" "$d/committed/gpu/measured/${sc%%=*}/"
    printf '{"semlb_commit": "%s", "date": "2026-01-01", "how": "test"}\n' "${sc#*=}" \
      > "$d/committed/gpu/measured/${sc%%=*}/provenance.json"
  done
  "$PY" "$src/analysis/report.py" --results "$d/results" --committed "$d/committed" --semlb "$semlb" > "$d/log" 2>&1 ||
    { cat "$d/log"; fail "report.py on $1"; }
  sed -n '/^\*\*Bottom line\*\*/,/^How to read it/p' "$d/results/REPORT.md"
}
head=$(git -C "$src" rev-parse HEAD)
bottom=$(bottom_of bottom "epidermis_half=$head" "epidermis_development=$old")
half=$(grep "^- the paper's regime" <<< "$bottom") || fail "no paper's-regime line in the bottom line: $bottom"
[[ "$half" == *"P = 8: \`"*"less loop time than static"* && "$half" != *stale* ]] || fail "current scene's line: $half"
[[ "$half" == *"P = 2: \`static\` (the best, \`persistence\`"*"within the spread over launches)"* ]] ||
  fail "a P whose interval reaches zero does not say to run static: $half"
dev=$(grep "^- a proliferative front" <<< "$bottom") || fail "a scene with only a stale summary has no line: $bottom"
[[ "$dev" == *"**stale**, last measured with \`${old:0:7}\`"*"Rerun \`make gpu-results\`"* ]] ||
  fail "the stale-only scene is not marked stale with its commit: $dev"
grep -q "epidermis_development/end_to_end_summary.csv\` (semlb \`${old:0:7}\`, 2026-01-01 · \*\*stale\*\*" \
  "$work/bottom/results/REPORT.md" || fail "the stale summary is not shown as stale"
# The development scene current through the learned controller's summary: its stale summary is left out.
bottom=$(bottom_of bottom2 "epidermis_half=$head" "epidermis_development=$old" "learned_repartition=$head")
dev=$(grep "^- a proliferative front" <<< "$bottom") || fail "bottom2: no development line: $bottom"
[[ "$dev" != *stale* && "$dev" == *"P = 4: \`learned_repartition\`"* && "$dev" != *"P = 2"* ]] ||
  fail "the bottom line drew from a stale summary of a scene that has a current one: $dev"
[[ "$dev" != *"not in the call this line comes from"* ]] || fail "the policies of the stale summary counted beside the current: $dev"

# The committed results (results/cpu as this run, results/gpu committed): length, links, detail pages.
cp -r "$src/results/cpu" "$work/full"
"$PY" "$src/analysis/report.py" --results "$work/full" --semlb "$semlb" > "$work/full.log" 2>&1 || { cat "$work/full.log"; fail "full report"; }
rep="$work/full/REPORT.md"
n=$(wc -l < "$rep"); [ "$n" -le 400 ] || fail "REPORT.md has $n lines (limit 400)"
grep -q "^## Which controller should I run?$" "$rep" || fail "no which-controller section"
grep -q '^\*\*P = 2\*\*: `' "$rep" || fail "which-controller names no policy at P = 2"
links=$(grep -o "(report/[0-9][0-9]-[a-z_]*\.md)" "$rep" | tr -d '()' | sort -u)
[ -n "$links" ] || fail "no detail page linked"
for l in $links; do [ -s "$work/full/$l" ] || fail "linked detail page $l missing"; done
for f in "$work/full"/report/*.md; do grep -q "(report/$(basename "$f"))" "$rep" || fail "detail page $(basename "$f") not linked"; done
# Every section with content has its detail page; no table in REPORT.md longer than the key table's 8 rows.
[ "$(grep -c '^Details (every run' "$rep")" = "$(ls "$work/full/report" | wc -l)" ] || fail "sections and detail pages differ"
awk '/^\|/ {n++; if (n > 10) bad = 1} !/^\|/ {n = 0} END {exit bad}' <(sed -n '/^<a id/,$p' "$rep") ||
  fail "a table of more than 8 rows in REPORT.md outside the summary"
# The 4/8-GPU rows keep their place, labelled with their commit and the engine they predate.
grep -q "before the GPU-resident engine" "$work/full/report/"*load_balance.md || fail "load_balance rows not labelled"
echo "1 passed, 0 failed"
