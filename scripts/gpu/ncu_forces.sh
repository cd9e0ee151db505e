#!/usr/bin/env bash
# Profiles opencl-binned's force kernel under Nsight Compute, which cannot profile OpenCL: captures the first
# forces_binned launch of `semlb bench engine` (SEMLB_OPENCL_CAPTURE), replays it through the CUDA driver
# (ncu_replay.cpp: checks the replay reproduces the OpenCL launch bit for bit, times it), and writes ncu's full
# report, its details page and its per-SASS-instruction source page, for float and double.
# Usage: scripts/gpu/ncu_forces.sh SEMLB OUT [CELLS] [PRECISIONS]   (an NVIDIA GPU, nvcc and ncu on the PATH)
# KERNEL=nl_forces SKIN=0.5 profiles the neighbour list's force kernel instead. LAUNCH=N captures the
# N-th launch (default 10: past the first steps, where the list's kmax is still growing and slots over it take the
# stencil). The replay's median is printed beside OpenCL's own ms/step of the kernel in the same bench: a replay
# that differs by more than 10% is not the launch the bench timed, and the script says so. SETS: extra flags of the
# bench (e.g. "--set backend.opencl-binned.newton=true"), SETS_float and SETS_double those of one precision (e.g.
# SETS_double="--set backend.pair_exp=ranged"); OUT/sets.txt records them.
set -euo pipefail
semlb=$1; out=$2; cells=${3:-435661}; precisions=${4:-"float double"}
here=$(cd "$(dirname "$0")" && pwd)
k=${KERNEL:-forces_binned}; skin=${SKIN:-0}; launch=${LAUNCH:-10}
scratch=$(mktemp -d)
trap 'rm -rf "$scratch"' EXIT
mkdir -p "$out"
printf 'SETS=%s\nSETS_float=%s\nSETS_double=%s\n' "${SETS:-}" "${SETS_float:-}" "${SETS_double:-}" > "$out/sets.txt"
nvcc -O2 -std=c++17 "$here/ncu_replay.cpp" -lcuda -o "$scratch/ncu_replay"
for p in $precisions; do
  cap="$scratch/capture_$p"; own="SETS_$p"
  # shellcheck disable=SC2086
  SEMLB_OPENCL_PROFILE=1 SEMLB_OPENCL_CAPTURE="$k@$launch:$cap" "$semlb" bench engine --platform NVIDIA \
    --backends opencl-binned --cells "$cells" --steps 20 --warmup 1 --precision "$p" --set backend.skin="$skin" \
    ${SETS:-} ${!own:-} > "$out/bench_$p.txt" 2>&1
  rc=0; "$scratch/ncu_replay" "$cap" 20 > "$out/replay_$p.txt" 2>&1 || rc=$?
  if [ "$rc" != 0 ] && grep -q "did not load" "$out/replay_$p.txt"; then  # JIT refused it: ptxas's cubin instead
    ptxas -arch=sm_90 "$cap/patched.ptx" -o "$cap/patched.cubin"
    rc=0; "$scratch/ncu_replay" "$cap" 20 > "$out/replay_$p.txt" 2>&1 || rc=$?
  fi
  replay_ms=$(sed -n 's/.*median \([0-9.]*\) ms.*/\1/p' "$out/replay_$p.txt")
  opencl_ms=$(awk -v k="$k" '$1 == "kernel" && $2 == k {print $3; exit}' "$out/bench_$p.txt")
  awk -v r="$replay_ms" -v o="$opencl_ms" -v k="$k" -v p="$p" 'BEGIN {
    if (r == "" || o == "") { print k " " p ": replay or OpenCL time missing"; exit }
    printf "%s %s: replay %.3f ms, OpenCL %.3f ms/step, ratio %.3f%s\n", k, p, r, o, r / o,
      (r / o > 1.1 || r / o < 0.9) ? " (NOT representative: more than 10% apart)" : "" }' | tee "$out/agreement_$p.txt"
  cp "$cap/program.bin" "$out/${k}_$p.ptx"
  ptxas -arch=sm_90 -v "$cap/patched.ptx" -o /dev/null > "$out/ptxas_$p.txt" 2>&1 || true
  [ "$rc" = 0 ] || { cat "$out/replay_$p.txt" "$out/ptxas_$p.txt"; exit 1; }
  ncu --clock-control none --set full -k "regex:$k" -c 1 -f -o "$out/${k}_$p" \
    "$scratch/ncu_replay" "$cap" 1 > "$out/ncu_run_$p.log" 2>&1
  ncu --import "$out/${k}_$p.ncu-rep" --page details --print-details all > "$out/ncu_details_$p.txt" 2>&1 ||
    ncu --import "$out/${k}_$p.ncu-rep" --page details > "$out/ncu_details_$p.txt" 2>&1
  ncu --import "$out/${k}_$p.ncu-rep" --page source --csv --print-source sass > "$out/ncu_source_$p.csv" 2>&1 || true
  rm -rf "$cap"
done
