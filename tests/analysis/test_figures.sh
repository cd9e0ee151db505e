#!/usr/bin/env bash
# analysis/report.py on the small committed CSVs (results/cpu, results/surrogate; results/gpu through --committed):
# every figure is written and is a non-empty PNG, REPORT.md has a section for every paper figure in the paper's order,
# every section names its profile and machine, and the Day 0-5 figure (render.py on a short sim's snapshots) gets
# its section with the cell types the binary lists. Usage: test_figures.sh REPO_ROOT WORK_DIR SEMLB
set -euo pipefail
src=$1; work=$2; semlb=$3
py=${PYTHON:-/usr/bin/python3}
rm -rf "$work"; r=$work/r; mkdir -p "$r"
for d in load_balance rank_balance single_device strong_scaling effects_cost; do
  mkdir -p "$r/$d"; cp "$src/results/cpu/$d/$d.csv" "$src/results/cpu/$d/$d.manifest.yaml" "$r/$d/"
done
mkdir -p "$r/controller_eval" "$r/accuracy_vs_time" "$r/end_to_end"
cp "$src/results/surrogate/controller_eval.csv" "$r/controller_eval/"
cp "$src/results/cpu/accuracy_vs_time/development.csv" "$r/accuracy_vs_time/"
# experiments/accuracy_pair_exp.yaml's CSV: its table in the accuracy section, without accuracy_vs_time's CSV
a=pair_exp,precision,dt,cutoff,steps,wall_s,rms_error_um,max_error_um,reference
printf '%s\n' "$a" builtin,double,0.0025,8.75,800,2.0,0,0,ref ranged,double,0.0025,8.75,800,1.6,1e-12,4e-12,ref \
  native,double,0.0025,8.75,800,1.2,3e-8,2e-7,ref builtin,double,0.01,8.75,200,0.5,0.007,0.02,ref \
  ranged,double,0.01,8.75,200,0.45,0.007,0.02,ref native,double,0.01,8.75,200,0.3,0.007,0.02,ref \
  > "$r/accuracy_vs_time/pair_exp.csv"
h=policy,initial,launch,gpus,ranks,cells_start,cells_end,steps,loop_s,compute_s,mean_imbalance,migrated_slices,machine
printf '%s\n' "$h" static,workload,1,0,2,196,500,1200,10,8,0.10,0,hostA gru,workload,1,0,2,196,500,1200,9,7,0.02,4,hostA \
  reactive,workload,1,0,2,196,500,1200,9.5,7,0.03,9,hostA static,workload,2,0,2,196,500,1200,12,9,0.12,0,hostA \
  gru,workload,2,0,2,196,500,1200,10,8,0.03,6,hostA reactive,workload,2,0,2,196,500,1200,11,8,0.04,12,hostA \
  > "$r/end_to_end/load_balance.csv"
# The Day 0-5 figure from a short run's snapshots (the Makefile's `development` on 2 snapshots).
"$semlb" sim --quiet --scene "$src/scenes/epidermis_development.yaml" --out "$work/dev" --set tissue.cells=36 \
  --set time.dt=0.1 --set time.steps=40 --set output.snapshot_every=20 --set output.checkpoint_every=0
"$py" "$src/analysis/render.py" "$work/dev/snapshots/step_000000000.h5" "$work/dev/snapshots/step_000000040.h5" \
  "$r/figures/development.png" --semlb "$semlb" --paraview "$r/figures/development_paraview.py" \
  --summary "$r/figures/development.csv" >/dev/null
head -1 "$r/figures/development.csv" | grep -qx "time_h,step,cells,elements,basal,spinous,granular,thickness_um" \
  || { echo "summary header"; cat "$r/figures/development.csv"; exit 1; }
grep -q "XDMFReader" "$r/figures/development_paraview.py"
grep -qF "$work/dev/snapshots.xmf" "$r/figures/development_paraview.py"
"$py" "$src/analysis/report.py" --results "$r" --semlb "$semlb" >/dev/null
for f in single_device strong_scaling rank_balance rank_balance_gpu_4ranks rank_balance_gpu_8ranks load_balance \
         end_to_end_load_balance load_balance_gpu_4 load_balance_gpu_8 controller_eval development effects_cost \
         effects_cost_gpu accuracy_development controller_eval_engine_paper_dev_v24.8_s1 \
         controller_eval_engine_paper_epidermis_s1 controller_eval_engine_paper_epidermis_half_s1; do
  png=$r/figures/$f.png
  [ -s "$png" ] || { echo "missing or empty: $png"; exit 1; }
  head -c 8 "$png" | od -An -c | grep -q "P   N   G" || { echo "not a PNG: $png"; exit 1; }
  [ "$(stat -c %s "$png")" -gt 10000 ] || { echo "suspiciously small: $png"; exit 1; }
  grep -qF "![figures/$f.png](figures/$f.png)" "$r/REPORT.md" || grep -qF "![figures/$f.png](../figures/$f.png)" "$r"/report/*.md ||
    { echo "neither REPORT.md nor a detail page shows $f"; exit 1; }
done
rep=$r/REPORT.md
grep -qF "| ranged | double | 8.75 | 0.0025 | 800 | 1.6 | 0.800 | 1e-12 | 4e-12 |" "$rep" "$r"/report/*.md || { echo "the pair exp rows"; exit 1; }
# One section per paper figure, in the paper's order, before any section beyond the paper.
want="fig:single_gpu fig:scaling fig:rank_balance fig:load_balance fig:rnn_prediction fig:epidermal_visualization"
got=$(grep -o '^\*Paper: Fig\. `fig:[a-z_]*`' "$rep" | grep -o 'fig:[a-z_]*' | uniq | tr '\n' ' ' | sed 's/ $//')
[ "$got" = "$want" ] || { echo "paper sections: '$got'"; exit 1; }
first_extra=$(grep -n "^\*Beyond the paper" "$rep" | head -1 | cut -d: -f1)
last_paper=$(grep -n '^\*Paper: Fig' "$rep" | tail -1 | cut -d: -f1)
[ "$last_paper" -lt "$first_extra" ] || { echo "a section beyond the paper comes before a paper figure"; exit 1; }
# Every section (with its detail page) names its profile and machine, and every paper section the paper's numbers and
# a reading.
"$py" - "$rep" <<'PY' || exit 1
import os, re, sys
text = open(sys.argv[1]).read()
sections = re.split(r"(?m)^(?=## \d+\. )", text)[1:]
assert len(sections) >= 9, f"only {len(sections)} sections"
for sec in sections:
    title = sec.splitlines()[0]
    link = re.search(r"\]\((report/\d\d-[a-z_]+\.md)\)", sec)
    if link:
        sec += open(os.path.join(os.path.dirname(sys.argv[1]), link.group(1))).read()
    assert "profile **" in sec, f"no profile in: {title}"
    assert "machine: " in sec, f"no machine in: {title}"
    if sec.count("*Paper: Fig.") == 1:
        assert re.search(r"(?m)^\*\*Paper\.\*\* ", sec), f"no paper numbers in: {title}"
        assert re.search(r"(?m)^\*\*Reading", sec), f"no reading in: {title}"
        for word in ("ranks: ", "cores: ", "launches: ", "intervals: "):
            assert word in sec, f"no '{word}' in: {title}"
PY
# Numbers that must come from the data: H200 E_8 at 435,661 cells (6.319 / 0.933 / 8 = 85%), the paper's beside.
grep -qF "E_8 85% (435K, paper 45%)" "$rep" || { echo "strong-scaling comparison"; grep -n "E_8" "$rep"; exit 1; }
grep -qF "4xH200: static 11.6%, reactive 8.9% / 347 slices, gru 8.4% / 82 slices" "$rep" || { echo "load balance"; exit 1; }
# The Day 0-5 section reads its per-day table.
grep -q "^| 0.0 | 36 | " "$rep" || { echo "Day 0 row"; grep -n "^| 0" "$rep"; exit 1; }
# The effects table and figure share one ms per step: seconds / steps x 1000, two decimals.
ms=$("$py" -c "import csv,sys; r=list(csv.DictReader(open('$r/effects_cost/effects_cost.csv')))[0]; print(f\"{1000*float(r['seconds'])/int(r['steps']):.2f}\")")
grep -q "^| mechanics | [0-9]* | $ms |" "$r/tables/effects_cost.md" || { echo "ms/step $ms"; cat "$r/tables/effects_cost.md"; exit 1; }
# The state file loads in ParaView and draws the tissue: pvbatch on a virtual display, the last snapshot saved as a PNG
# that must show more than the background (a state whose reader or glyphs failed leaves a uniform image).
cat > "$work/shot.py" <<'PY'
import sys
exec(open(sys.argv[1]).read())
scene = GetAnimationScene()
scene.AnimationTime = reader.TimestepValues[-1]
SaveScreenshot(sys.argv[2], view, ImageResolution=[640, 480])
PY
# pvbatch draws on an Xvfb of its own: -displayfd makes the server take a free display number itself (xvfb-run -a
# picks one from the lock files before starting, a race another X server can win, and pvbatch then aborts with "bad X
# server connection"). Three tries, each with its own logs; a failure prints what pvbatch and Xvfb said.
on_xvfb() {  # on_xvfb LOG_PREFIX COMMAND...: run COMMAND with DISPLAY on a fresh Xvfb; the server's log in LOG_PREFIX.xvfb
  local log=$1 n="" pid rc; shift
  : > "$log.display"
  Xvfb -displayfd 3 -screen 0 1280x1024x24 -nolisten tcp 3>"$log.display" 2>"$log.xvfb" & pid=$!
  for _ in $(seq 100); do n=$(tr -dc 0-9 < "$log.display"); [ -n "$n" ] && break; kill -0 $pid 2>/dev/null || break; sleep 0.1; done
  if [ -z "$n" ]; then kill $pid 2>/dev/null; wait $pid 2>/dev/null; echo "Xvfb gave no display" >> "$log.xvfb"; return 1; fi
  rc=0; DISPLAY=:$n timeout 300 "$@" || rc=$?
  kill $pid 2>/dev/null; wait $pid 2>/dev/null || true
  return $rc
}
shoot() { on_xvfb "$work/try$1" pvbatch "$work/shot.py" "$r/figures/development_paraview.py" "$work/paraview.png" \
            >"$work/try$1.pvbatch" 2>&1; }
# When pvbatch cannot draw even a sphere on this machine, the test is skipped (exit 77) with what it said, since the
# state file is then not what fails; when the sphere draws and the state does not, the state file is wrong.
if ! { shoot 1 || shoot 2 || shoot 3; }; then
  printf 'from paraview.simple import *\nShow(Sphere())\nSaveScreenshot("%s", GetActiveViewOrCreate("RenderView"))\n' \
    "$work/sphere.png" > "$work/sphere.py"
  if ! on_xvfb "$work/sphere" pvbatch "$work/sphere.py" >"$work/sphere.log" 2>&1; then
    echo "SKIPPED (the figures and the report passed): pvbatch on Xvfb cannot draw a sphere on this machine:"; tail -n 40 "$work/sphere.log" "$work/sphere.xvfb"
    exit 77
  fi
  echo "pvbatch could not render development_paraview.py (three tries):"
  for t in 1 2 3; do tail -n 15 "$work/try$t.pvbatch" "$work/try$t.xvfb"; done
  exit 1
fi
"$py" - "$work/paraview.png" <<'PY'
import sys
import matplotlib.image as mpimg
img = mpimg.imread(sys.argv[1])[..., :3]
background = img[0, 0]
drawn = (abs(img - background).sum(axis=2) > 0.05).mean()
assert 0.01 < drawn < 0.9, f"ParaView drew {drawn:.1%} of the image"
PY
echo "1 passed, 0 failed"
