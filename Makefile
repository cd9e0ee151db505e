# Entry points: deps, build, test, experiments, bench (see README.md).
PYTHON  ?= /usr/bin/python3
BUILD   ?= build
JOBS    ?= 2
PROFILE ?= small
RESULTS ?= results
SEMLB   := $(BUILD)/cli/semlb
MANIFESTS := $(wildcard experiments/*.yaml)

export OMPI_ALLOW_RUN_AS_ROOT=1
export OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1

.PHONY: deps build test experiments gpu-measured gpu-results epidermis development analysis bench train train-fronts train-synthetic train-v1 fit clean surrogate-fit

deps:
	bash scripts/install-deps.sh

build: deps
	cmake -S . -B $(BUILD) -DCMAKE_BUILD_TYPE=Release
	cmake --build $(BUILD) -j$(JOBS)

test: build
	ctest --test-dir $(BUILD) --output-on-failure -j$(JOBS)

# Engine experiments whose runs (trace.jsonl, rank_times.csv, run.csv, scene.yaml) stay under RESULTS/<name>/runs/;
# replay_score then scores every policy on every trace.jsonl under RESULTS (docs/controllers.md "Replay").
KEEP_RUNS := load_balance rank_balance

experiments: build
	@set -e; for m in $(filter-out experiments/replay_score.yaml,$(MANIFESTS)); do \
	  keep=; case " $(KEEP_RUNS) " in *" $$(basename $$m .yaml) "*) keep=--keep-runs;; esac; \
	  $(SEMLB) sweep $$m --profile $(PROFILE) --results $(RESULTS) $$keep; \
	done
	$(SEMLB) sweep experiments/replay_score.yaml --profile $(PROFILE) --results $(RESULTS) --set traces=$(abspath $(RESULTS))
	$(PYTHON) analysis/trace_model.py --results $(RESULTS) --out $(RESULTS)/trace_model/trace_model.csv
	$(MAKE) --no-print-directory epidermis development analysis

# The paper's use case: a small epidermis run rendered like the paper's epidermal figure.
epidermis: build
	$(SEMLB) sim --scene scenes/epidermis.yaml --out $(RESULTS)/epidermis --steps 3000
	$(PYTHON) analysis/render.py $(RESULTS)/epidermis/final.h5 $(RESULTS)/figures/epidermis.png --semlb $(SEMLB)

# Day 0-5 of the developing epidermis, one process, at the small profile's step (experiments/end_to_end.yaml):
# six snapshots, Day 0 to Day 5, rendered as panels of ellipsoids seen from the side (analysis/render.py), with a
# ParaView state of the same snapshots and a CSV of cells per type and thickness per day beside the figure.
DEV := $(RESULTS)/development
development: build
	$(SEMLB) sim --quiet --scene scenes/epidermis_development.yaml --out $(DEV) --set time.dt=0.1 --set time.steps=1200 \
	  --set time.cell_update_every=5 --set output.snapshot_every=240 --set output.checkpoint_every=0
	$(PYTHON) analysis/render.py $(DEV)/snapshots/step_000000000.h5 $(DEV)/snapshots/step_000000240.h5 \
	  $(DEV)/snapshots/step_000000480.h5 $(DEV)/snapshots/step_000000720.h5 $(DEV)/snapshots/step_000000960.h5 \
	  $(DEV)/snapshots/step_000001200.h5 $(RESULTS)/figures/development.png --semlb $(SEMLB) \
	  --paraview $(RESULTS)/figures/development_paraview.py --summary $(RESULTS)/figures/development.csv

analysis:
	$(PYTHON) analysis/report.py --results $(RESULTS) --semlb $(SEMLB)

# The surrogate fitted to every engine trace under results/ and the policies' ranks on both (docs/controllers.md
# "Surrogate fitted to engine traces"); several minutes on 2 cores, so not part of `make experiments`.
surrogate-fit: build
	$(PYTHON) analysis/fit_surrogate.py --semlb $(SEMLB) --results results --csv results/surrogate/surrogate_fit.csv \
	  --params-csv results/surrogate/surrogate_fit_params.csv --table results/surrogate/surrogate_fit.md

# Regenerates the shipped GRU weights from the mixed family (engine workloads + synthetic scenarios, features
# boundary-v2; docs/train.md "Engine workloads"), and its synthetic-only ablation; each resumes after an interruption.
# learned_repartition's parameters (surrogate/fit/learned_repartition.yaml: about 3 minutes on 2 cores; docs/train.md)
fit: build
	$(SEMLB) fit --config surrogate/fit/learned_repartition.yaml --out controllers/weights/learned_repartition/default.h5
train: build
	$(SEMLB) train --config surrogate/train/engine_mixed.yaml --out controllers/weights/gru_default.h5
train-fronts: build
	$(SEMLB) train --config surrogate/train/engine_mixed_fronts.yaml --out controllers/weights/gru_mixed_fronts.h5
train-synthetic: build
	$(SEMLB) train --config surrogate/train/engine_synthetic.yaml --out controllers/weights/gru_synthetic.h5
# The synthetic-only recipe (synthetic scenarios, boundary-v1 features) of gru_v1_migration_penalty_2.h5, the first shipped weights.
train-v1: build
	$(SEMLB) train --config surrogate/train/default.yaml --out controllers/weights/gru_v1_migration_penalty_2.h5

# Every committed single-GPU result (single device, effect costs, accuracy against time, Day 0-5, peer ratio, the
# measured end-to-end, the workload library and its replays), on a machine with one NVIDIA GPU, in stages of a few
# minutes that resume across calls: rerun until it exits 0 (scripts/gpu/results.sh). GPU_OUT: where (results/gpu).
GPU_OUT ?= results/gpu
gpu-results:
	bash scripts/gpu/results.sh $(GPU_OUT)

# The engine workload library (results/gpu/workloads/README.md) needs an OpenCL GPU: bash scripts/gpu/workload_library.sh.
# The controller evaluation on it: experiments/controller_eval_engine.yaml (part of `make experiments`), tables by
# analysis/engine_eval.py.

# Measured GPU time (docs/measured_time.md) on an OpenCL GPU: the paper's regime scene and a Day 2-3 window of the
# development scene, P = 2, 4, 8 ranks taking turns on one device, every policy, three launches; resumable (a stage's
# finished runs are kept under GPU_RUNS). The tables go to results/gpu/measured/.
GPU_RUNS ?= $(BUILD)/measured
gpu-measured: build
	bash scripts/gpu/measured_all.sh $(SEMLB) $(GPU_RUNS)

bench: build
	$(SEMLB) bench policies --ranks 16
	$(SEMLB) bench engine --backends serial,cpu-binned,opencl-allpairs,opencl-binned --cells 200 --steps 50
	$(SEMLB) bench cells --backends cpu-binned,opencl-binned --cells 2000,20000 --steps 10

clean:
	rm -rf $(BUILD)
