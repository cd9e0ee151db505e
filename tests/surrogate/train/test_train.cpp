// Trainer: config errors, training seeds only, soft times -> hard times, untrained export == reactive,
// parity of exported weights, determinism, and kill + resume == uninterrupted.
#include <gtest/gtest.h>

#include <filesystem>

#include "../../run_command.hpp"
#include "../../workload_fixtures.hpp"
#include "common/errors.hpp"
#include "controllers/features.hpp"
#include "controllers/gru.hpp"
#include "common/h5.hpp"
#include "controllers/partition.hpp"
#include "common/text_io.hpp"
#include "surrogate/train/config.hpp"
#include "surrogate/train/episodes.hpp"
#include "surrogate/train/soft_rollout.hpp"
#include "surrogate/train/trainer.hpp"

using namespace semlb;
using namespace semlb::train;
namespace fs = std::filesystem;

namespace {
TrainConfig tiny(long steps) {
  return load_train_config(
      "", {"steps=" + std::to_string(steps), "batch=4", "events=6", "validate_every=0", "validation_seeds=8000-8001",
           "validation_ranks=2,5", "validation_events=20", "checkpoint_every=2"});
}
std::string train_to(const TrainConfig& c, const std::string& name) {
  const auto dir = test::fresh_dir("train_" + name);
  TrainOptions o;
  o.out = dir + "/w.h5";
  o.progress = false;
  run_training(c, o);
  return o.out;
}
void expect_same_weights(const std::string& a, const std::string& b) {
  const auto wa = load_gru_weights(a), wb = load_gru_weights(b);
  EXPECT_EQ(wa.w_ih, wb.w_ih);
  EXPECT_EQ(wa.w_hh, wb.w_hh);
  EXPECT_EQ(wa.b_hh, wb.b_hh);
  EXPECT_EQ(wa.head_w, wb.head_w);
  EXPECT_EQ(wa.head_b, wb.head_b);
}
}  // namespace

TEST(TrainConfig, DefaultsFileAndErrors) {
  const auto c = load_train_config(test::source("surrogate/train/default.yaml"), {});
  EXPECT_EQ(c.steps, 6000);
  EXPECT_EQ(c.batch, 32);
  EXPECT_DOUBLE_EQ(c.migration_penalty, 2.0);
  EXPECT_EQ(c.migration_norm, "reactive");
  const auto dir = test::fresh_dir("train_cfg");
  test::write(dir + "/bad.yaml", "steps: 10\nbatchsize: 3\n");
  try {
    load_train_config(dir + "/bad.yaml", {});
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("bad.yaml:2: field 'batchsize': unknown training setting"), std::string::npos)
        << e.what();
  }
  EXPECT_THROW(load_train_config("", {"lr=fast"}), InputError);
  EXPECT_THROW(load_train_config("", {"validation_seeds=9000-9001"}), InputError);  // evaluation seeds refused
  EXPECT_THROW(load_train_config("", {"ranks_min=1"}), InputError);
  auto message = [](const std::string& path, const std::vector<std::string>& sets) {
    try {
      load_train_config(path, sets);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  // Ranges, flags and unknown keys read like a scene's (common/settings.hpp): the line or the flag, then the field.
  test::write(dir + "/range.yaml", "steps: 10\nbatch: 0\n");
  EXPECT_EQ(message(dir + "/range.yaml", {}).rfind(dir + "/range.yaml:2: field 'batch': '0' is outside [1, ", 0), 0u);
  EXPECT_EQ(message("", {"ranks_min=1"}), "--set ranks_min: '1' is outside [2, 64]");
  EXPECT_EQ(message("", {"lr=0"}).rfind("--set lr: '0' is outside (0, ", 0), 0u);
  EXPECT_EQ(message("", {"batchsize=3"}), "--set batchsize: unknown training setting");
  EXPECT_EQ(message(dir + "/range.yaml", {"batch=2", "ranks_min=8", "ranks_max=4"}),
            "--set ranks_max: must be >= ranks_min (8)");
}

TEST(Episodes, UseTrainingSeedsOnlyAndAreReproducible) {
  const auto c = tiny(1);
  for (long step = 0; step < 50; ++step)
    for (int i = 0; i < 4; ++i) {
      const auto e = make_episode(c, step, i);
      ASSERT_TRUE(surrogate::kTrainSeeds.contains(e.scenario.seed));
      ASSERT_GE(e.scenario.ranks, 2);
      ASSERT_LE(e.scenario.ranks, 16);
      ASSERT_EQ(e.work.size(), 7u);
      ASSERT_GE(e.difficulty, c.difficulty_floor);
    }
  EXPECT_EQ(make_episode(c, 7, 1).work, make_episode(c, 7, 1).work);
  auto two = c;
  two.threads = 2;
  const auto a = make_batch(c, 3), b = make_batch(two, 3);
  for (size_t i = 0; i < a.size(); ++i) EXPECT_EQ(a[i].work, b[i].work);
}

TEST(SoftRollout, SoftTimesApproachHardTimesAndCarryGradients) {
  std::vector<double> work(40);
  for (size_t s = 0; s < work.size(); ++s) work[s] = 1.0 + (s % 7);
  const std::vector<int> hard{9, 23, 31};
  const auto exact = rank_sums(work, hard);
  auto b = torch::tensor({9.f, 23.f, 31.f}).requires_grad_();
  const auto cold = soft_rank_times(work, b, 0.02);
  for (int r = 0; r < 4; ++r) EXPECT_NEAR(cold[r].item<double>(), exact[r], 1e-3 * exact[r]);
  const auto warm = soft_rank_times(work, b, 1.0);
  EXPECT_NEAR(warm.sum().item<double>(), exact[0] + exact[1] + exact[2] + exact[3], 1e-3);  // work is conserved
  warm[0].backward();
  EXPECT_GT(b.grad()[0].item<double>(), 0.0);  // moving boundary 0 right adds work to rank 0
}

TEST(Trainer, UntrainedExportReproducesReactive) {
  const auto path = train_to(tiny(0), "zero");
  EXPECT_DOUBLE_EQ(gru_parity_error(path), 0.0);
  const auto w = load_gru_weights(path);
  EXPECT_TRUE(w.head_w.isZero());
  EXPECT_EQ(w.head_b, 0.0);
  EXPECT_EQ(w.parameter_count(), 2761);
  const auto r = test::run(test::semlb_bin() + " surrogate --policies reactive,gru --weights " + path +
                           " --ranks 3,16 --seeds 9000-9002 --events 60 --no-timing --quiet --out " +
                           fs::path(path).parent_path().string());
  ASSERT_EQ(r.rc, 0) << r.out;
  std::istringstream csv(test::slurp(fs::path(path).parent_path().string() + "/controller_eval.csv"));
  std::string line;
  std::vector<std::string> reactive, gru;
  std::getline(csv, line);
  while (std::getline(csv, line))
    (line.rfind("reactive,", 0) == 0 ? reactive : gru).push_back(line.substr(line.find(',')));
  ASSERT_EQ(reactive.size(), 6u);
  EXPECT_EQ(reactive, gru);
}

TEST(Trainer, TrainedWeightsPassParityAndRunsRepeat) {
  const auto c = tiny(3);
  const auto a = train_to(c, "a"), b = train_to(c, "b");
  expect_same_weights(a, b);
  EXPECT_FALSE(load_gru_weights(a).head_w.isZero());  // it learned something
  EXPECT_LT(gru_parity_error(a), 1e-5);
  std::vector<hsize_t> dims;
  const auto residuals = h5::File::open_read(a).read("/parity/residuals", dims);
  double largest = 0;
  for (double r : residuals) largest = std::max(largest, std::fabs(r));
  EXPECT_GT(largest, 1e-4);  // the parity record is not trivially zero
  EXPECT_EQ(h5::File::open_read(a).read_int_attr("steps"), 3);
  EXPECT_FALSE(fs::exists(a + ".ckpt"));  // removed once the weights are written
}

TEST(Trainer, KilledRunResumesToTheSameWeights) {
  // Validation every step, so that the log shows which steps each run trained.
  const std::vector<std::string> sets = {"batch=4",
                                         "events=6",
                                         "validate_every=1",
                                         "validation_seeds=8000-8001",
                                         "validation_ranks=2,5",
                                         "validation_events=20",
                                         "checkpoint_every=2"};
  const auto ref = train_to(load_train_config("",
                                              [&] {
                                                auto s = sets;
                                                s.push_back("steps=4");
                                                return s;
                                              }()),
                            "ref");
  const auto dir = test::fresh_dir("train_kill");
  std::string cmd = test::semlb_bin() + " train --steps 4 --out " + dir + "/w.h5";
  for (const auto& s : sets) cmd += " --set " + s;
  const auto killed = test::run("SEMLB_TRAIN_KILL_AFTER=2 " + cmd + " --quiet");
  EXPECT_EQ(killed.rc, 128 + 9) << killed.out;
  EXPECT_FALSE(fs::exists(dir + "/w.h5"));
  EXPECT_TRUE(fs::exists(dir + "/w.h5.ckpt"));
  // The killed run logged steps 1 and 2; mark their wall_seconds: a resume keeps them, a fresh start would not.
  auto rows = split(test::slurp(dir + "/w.log.csv"), '\n');
  ASSERT_EQ(rows.size(), 4u) << test::slurp(dir + "/w.log.csv");  // header, steps 1 and 2, ""
  std::string marked = rows[0] + "\n";
  for (int i : {1, 2}) {
    auto cells = split(rows[i], ',');
    ASSERT_EQ(cells[0], std::to_string(i));
    cells[1] = "-" + std::to_string(i);
    for (size_t c = 0; c < cells.size(); ++c) marked += (c ? "," : "") + cells[c];
    marked += "\n";
  }
  test::write(dir + "/w.log.csv", marked);
  const auto resumed = test::run(cmd);  // with the progress lines
  ASSERT_EQ(resumed.rc, 0) << resumed.out;
  expect_same_weights(ref, dir + "/w.h5");
  EXPECT_NE(resumed.out.find("resuming from " + dir + "/w.h5.ckpt at step 2"), std::string::npos) << resumed.out;
  for (const char* trained : {"step 3 validation", "step 4 validation"})
    EXPECT_NE(resumed.out.find(trained), std::string::npos) << resumed.out;
  for (const char* not_again : {"step 1 validation", "step 2 validation"})
    EXPECT_EQ(resumed.out.find(not_again), std::string::npos) << resumed.out;
  // One row per step, in order, no duplicates; the killed run's rows kept as they were.
  const auto log = split(test::slurp(dir + "/w.log.csv"), '\n');
  ASSERT_EQ(log.size(), 6u) << test::slurp(dir + "/w.log.csv");
  EXPECT_EQ(log[0] + "\n" + log[1] + "\n" + log[2] + "\n", marked);
  for (int i : {3, 4}) {
    EXPECT_EQ(split(log[i], ',')[0], std::to_string(i));
    EXPECT_GE(std::stod(split(log[i], ',')[1]), 0.0) << log[i];
  }
  // Each row's temperature is the one its step trained with: temp_start at step 1 down to temp_end at the last.
  const auto c = load_train_config("", {"steps=4"});
  for (int i = 1; i <= 4; ++i)
    EXPECT_NEAR(std::stod(split(log[i], ',')[4]), c.temp_start + (c.temp_end - c.temp_start) * (i - 1) / 3.0, 1e-12)
        << log[i];
}

TEST(SoftRollout, TruncatedBpttKeepsTheForwardPassAndShortensGradients) {
  auto c = tiny(1);
  c.events = 8;
  const auto batch = make_batch(c, 0);
  auto grads = [&](long bptt) {
    c.bptt = bptt;
    torch::manual_seed(3);
    Controller model(kFeatureCount, 24);
    {
      torch::NoGradGuard g;
      model->head->weight.fill_(0.05);
    }
    auto loss = soft_rollout_loss(model, batch, c, 1.0);
    loss.backward();
    return std::pair{loss.item<double>(), model->cell->weight_hh.grad().clone()};
  };
  const auto [full_loss, full_grad] = grads(0);
  const auto [cut_loss, cut_grad] = grads(2);
  EXPECT_DOUBLE_EQ(full_loss, cut_loss);
  EXPECT_FALSE(torch::allclose(full_grad, cut_grad));
  EXPECT_THROW(load_train_config("", {"bptt=-1"}), InputError);
}

// Trace-driven episodes: windows of a recorded workload at a rank count that fits, from a file the config names, and
// the mixed family's three sources in the proportions asked for.
TEST(Episodes, TraceDrivenEpisodesReplayWindowsOfAWorkloadFile) {
  EngineWorkload w = test::workload_shape(64, 2, 10);
  for (int t = 0; t < 30; ++t) {
    WorkloadEvent e;
    e.step = 10 * (t + 1);
    e.elements = 64;
    e.cells = 8;
    e.interval_s = 1;
    e.growth_event = t % 5 == 0;
    for (int s = 0; s < 64; ++s) {
      e.slice_work.push_back(s < 2 * t + 2 ? 50 : 1);  // a front moving right by 2 slices per event
      e.slice_elements.push_back(1);
    }
    e.band_below.assign(63, 1);
    e.band_above.assign(63, 1);
    w.events.push_back(e);
  }
  const auto dir = test::fresh_dir("train_trace_episodes");
  write_workload(dir + "/w.h5", w);
  auto c = load_train_config("", {"batch=4", "events=6", "validation_seeds=8000-8001", "trace_fraction=0.5",
                                  "front_fraction=0.5", "workloads=" + dir + "/w.h5", "trace_coarsen_max=2"});
  const auto loaded = load_training_workloads(c);
  ASSERT_EQ(loaded.size(), 1u);
  int traces = 0, fronts = 0, plain = 0;
  for (long step = 0; step < 100; ++step) {
    const auto e = make_episode(c, step, 0, loaded);
    if (e.source == "workload:0") {
      ++traces;
      ASSERT_EQ(e.work.size(), 7u);
      ASSERT_TRUE(e.scenario.slices == 64 || e.scenario.slices == 32) << e.scenario.slices;
      ASSERT_GE(e.scenario.ranks, 2);
      ASSERT_LE(static_cast<long>(e.scenario.ranks) * e.scenario.min_width, e.scenario.slices);
      double first = 0, total = 0;  // the front: the work of the window's first event is a step of 50s then 1s
      for (double x : e.work[0]) first += x > 1.5 * e.work[0].back(), total += 1;
      ASSERT_GT(first, 0);
      ASSERT_LT(first, total);
    } else {
      (e.source == "front" ? fronts : plain) += 1;
      ASSERT_TRUE(surrogate::kTrainSeeds.contains(e.scenario.seed));
    }
  }
  EXPECT_GT(traces, 35);
  EXPECT_LT(traces, 65);
  EXPECT_GT(fronts, 10);
  EXPECT_GT(plain, 10);
  EXPECT_EQ(make_episode(c, 3, 1, loaded).work, make_episode(c, 3, 1, loaded).work);
  EXPECT_THROW(load_train_config("", {"trace_fraction=0.5"}), InputError);  // no workloads named
  EXPECT_THROW(load_train_config("", {"features=boundary-v9"}), InputError);
  // The trace episodes' jitter is drawn in [0.005, trace_jitter_max] (the default 0.03: a synthetic scenario's range).
  auto jitters = [&](const TrainConfig& cfg) {
    double lo = 1, hi = 0;
    for (long step = 0; step < 100; ++step) {
      const auto e = make_episode(cfg, step, 0, loaded);
      if (e.source != "workload:0") continue;
      lo = std::min(lo, e.scenario.time_jitter), hi = std::max(hi, e.scenario.time_jitter);
    }
    return std::pair{lo, hi};
  };
  const auto [lo3, hi3] = jitters(c);
  EXPECT_GE(lo3, 0.005);
  EXPECT_LE(hi3, 0.03);
  auto wide = c;
  wide.trace_jitter_max = 0.08;
  const auto [lo8, hi8] = jitters(wide);
  EXPECT_GE(lo8, 0.005);
  EXPECT_GT(hi8, 0.05);
  EXPECT_LE(hi8, 0.08);
  EXPECT_THROW(load_train_config("", {"validation_ranks=2,100000"}), InputError);
  EXPECT_THROW(load_train_config("", {"validation_events=-1"}), InputError);
  EXPECT_THROW(load_train_config("", {"trace_jitter_max=0.001"}), InputError);
  EXPECT_THROW(load_train_config("", {"trace_jitter_max=0.5"}), InputError);
  c.workloads = dir + "/absent.h5";
  EXPECT_THROW(load_training_workloads(c), InputError);
}
