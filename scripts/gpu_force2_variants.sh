#!/bin/bash
# Issue 14 round 2: one device run measuring the force-kernel variants (float on GPU 0, double on GPU 1).
cd gpu_force2
L=$OUT/log.txt
nvidia-smi --query-gpu=name,clocks.sm,clocks.max.sm,driver_version --format=csv > $L 2>&1
t0=$(date +%s)
cmake -S . -B /tmp/b -DCMAKE_BUILD_TYPE=Release -DSEMLB_WITH_TORCH=OFF -DSEMLB_BUILD_TESTS=OFF > /tmp/cm.log 2>&1 \
  && cmake --build /tmp/b -j32 --target semlb > /tmp/bd.log 2>&1 || { tail -40 /tmp/cm.log /tmp/bd.log >> $L; exit 1; }
echo "build $(( $(date +%s) - t0 )) s" >> $L
B="/tmp/b/cli/semlb bench engine --platform NVIDIA --device 0 --backends opencl-binned --cells 11000,435661"
FF="cut,cut+trim,fine,fine+notrim,cut+native,fine+native,fine+bitfix,fine+native+bitfix"
FD="cut,cut+trim,fine,fine+notrim,fine+bitfix"
( CUDA_VISIBLE_DEVICES=0 SEMLB_OPENCL_PROFILE=1 SEMLB_FORCE_VARIANTS=$FF $B --steps 200 --precision float > $OUT/prof_float.txt 2>&1
  for k in cut fine fine+native fine+native+bitfix; do echo "## SEMLB_FORCE_KERNEL=$k t=$(( $(date +%s) - t0 ))"; CUDA_VISIBLE_DEVICES=0 SEMLB_FORCE_KERNEL=$k $B --steps 200 --precision float 2>&1; done > $OUT/wall_float.txt ) &
( CUDA_VISIBLE_DEVICES=1 SEMLB_OPENCL_PROFILE=1 SEMLB_FORCE_VARIANTS=$FD $B --steps 200 --precision double > $OUT/prof_double.txt 2>&1
  for k in cut fine fine+bitfix; do echo "## SEMLB_FORCE_KERNEL=$k t=$(( $(date +%s) - t0 ))"; CUDA_VISIBLE_DEVICES=1 SEMLB_FORCE_KERNEL=$k $B --steps 200 --precision double 2>&1; done > $OUT/wall_double.txt ) &
wait
echo "done $(( $(date +%s) - t0 )) s" >> $L
