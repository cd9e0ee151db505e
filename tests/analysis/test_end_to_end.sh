#!/usr/bin/env bash
# analysis/report.py on a hand-made end-to-end CSV: mean ± sd per policy, the paired difference to static with
# its 95% t-interval (t_{0.975,2} = 4.303), the load-balance figure, and REPORT.md with the paper's numbers.
set -euo pipefail
src=$1; work=$2
rm -rf "$work"; mkdir -p "$work/end_to_end"
h=policy,initial,launch,gpus,ranks,cells_start,cells_end,steps,loop_s,compute_s,mean_imbalance,migrated_slices,machine
cat > "$work/end_to_end/load_balance.csv" <<CSV
$h
static,workload,1,0,4,196,500,600,10,8,0.10,0,hostA
gru,workload,1,0,4,196,500,600,9,7,0.02,4,hostA
static,workload,2,0,4,196,500,600,12,9,0.12,0,hostA
gru,workload,2,0,4,196,500,600,10,8,0.03,6,hostA
static,workload,3,0,4,196,500,600,14,10,0.14,0,hostA
gru,workload,3,0,4,196,500,600,14,9,0.04,8,hostA
CSV
"${PYTHON:-/usr/bin/python3}" "$src/analysis/report.py" --results "$work" >/dev/null
t="$work/tables/end_to_end.md"
# static: loop 12 ± 2, imbalance 12.0 ± 2.0 %; gru: loop 11 ± 2.65, differences -1, -2, 0: mean -1, sd 1,
# half-width 4.303 / sqrt(3) = 2.484 -> [-3.48, +1.48] s, over static's mean 12 s: -8.3% [-29.0, +12.4]
grep -qF "| static | workload | 3 | 500 | 12.00 ± 2.00 | 9.00 ± 1.00 | 12.0 ± 2.0 | 0 ± 0 | - | - |" "$t" || { cat "$t"; exit 1; }
grep -qF "| gru | workload | 3 | 500 | 11.00 ± 2.65 | 8.00 ± 1.00 | 3.0 ± 1.0 | 6 ± 2 | -1.00 [-3.48, +1.48] | -8.3% [-29.0, +12.4] |" "$t" \
  || { cat "$t"; exit 1; }
head -c 8 "$work/figures/end_to_end_load_balance.png" | od -An -c | grep -q "P   N   G"
grep -qF "imbalance static 11.3%, reactive 3.8%, RNN 3.5%" "$work/REPORT.md" || { cat "$work/REPORT.md"; exit 1; }
grep -qF "mean imbalance static 11.3%, reactive 3.8%, RNN 3.5%" "$work"/report/*-load_balance.md || { echo "paper line"; exit 1; }
grep -qF "![figures/end_to_end_load_balance.png](figures/end_to_end_load_balance.png)" "$work/REPORT.md"
echo "1 passed, 0 failed"
