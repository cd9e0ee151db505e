// Replay of engine workloads at any rank count: the time model on a hand-computed case, other rank counts,
// coarsening, noise that policies see but the score does not, and the refusals.
#include <gtest/gtest.h>

#include "common/errors.hpp"
#include "controllers/policy.hpp"
#include "surrogate/workload_replay.hpp"
#include "../workload_fixtures.hpp"

namespace semlb::surrogate {
namespace {

EngineWorkload hand() { return test::hand_workload(); }  // tests/workload_fixtures.hpp

WorkloadReplay exact(int ranks) {
  WorkloadReplay r;
  r.ranks = ranks;
  r.model = {.ghost_weight = 0.5, .speed_spread = 0, .jitter = 0, .migrate_s_per_slice = 0.25, .seconds_per_work = 0.5};
  return r;
}

TEST(WorkloadReplay, TimeModelMatchesAHandComputedCase) {
  // P=2 from the optimal partition [2]: T_r = 0.5 (W_r + 0.5 * 2 * G_r), one ghost element each way.
  // Event 0: W = 8, 8 -> 4.5, 4.5 (I = 0); event 1: W = 12, 4 -> 6.5, 2.5 (I = 4 / 4.5).
  auto policy = make_policy("static");
  const auto r = replay_workload(hand(), exact(2), *policy, "static", "hand.h5");
  ASSERT_EQ(r.events, 2);
  EXPECT_DOUBLE_EQ(r.imbalance[0], 0.0);
  EXPECT_DOUBLE_EQ(r.imbalance[1], 4.0 / 4.5);
  EXPECT_DOUBLE_EQ(r.mean_imbalance, 2.0 / 4.5);
  EXPECT_DOUBLE_EQ(r.compute_s, 4.5 + 6.5);
  EXPECT_DOUBLE_EQ(r.ideal_s, 9.0);
  EXPECT_EQ(r.migration, 0);
  EXPECT_DOUBLE_EQ(r.loop_s, 11.0);
  // persistence repartitions to event 1's W_s at its end ([1]: 8 | 8): one slice, 0.25 s, after the last interval
  auto persistence = make_policy("persistence");
  const auto p = replay_workload(hand(), exact(2), *persistence, "persistence", "hand.h5");
  EXPECT_EQ(p.migration, 1);
  EXPECT_DOUBLE_EQ(p.mean_imbalance, 2.0 / 4.5);
  EXPECT_DOUBLE_EQ(p.loop_s, 11.25);
}

// The hand workload with measured seconds that disagree with W_s: event 0's W_s is even (4, 4, 4, 4) but the device
// took 1, 1, 3, 3 s; event 1's W_s is heavy on the left (8, 4, 2, 2) and so were the seconds (2, 2, 1, 1).
EngineWorkload hand_measured() {
  EngineWorkload w = hand();
  w.cost_regions = 2;
  w.events[0].slice_seconds = {1, 1, 3, 3};
  w.events[1].slice_seconds = {2, 2, 1, 1};
  return w;
}

TEST(WorkloadReplay, MeasuredSecondsAreTheTruthWhenTheFileHasThem) {
  // P=2 from the W_s-optimal partition [2] (what policies see is still W_s): T_r = S_r + 0.5 sigma G_r + 0.25 with
  // sigma = sum of the seconds / 8 elements and one ghost element each way.
  // Event 0: sigma = 1: 2 + 0.5 + 0.25, 6 + 0.5 + 0.25 = 2.75, 6.75; event 1: sigma = 0.75: 4.625, 2.625.
  auto model = exact(2);
  model.model.rank_overhead_s = 0.25;
  auto policy = make_policy("static");
  const auto r = replay_workload(hand_measured(), model, *policy, "static", "hand.h5");
  EXPECT_TRUE(r.measured);
  EXPECT_DOUBLE_EQ(r.imbalance[0], 4.0 / 4.75);
  EXPECT_DOUBLE_EQ(r.imbalance[1], 2.0 / 3.625);
  EXPECT_DOUBLE_EQ(r.compute_s, 6.75 + 4.625);
  EXPECT_DOUBLE_EQ(r.ideal_s, 4.75 + 3.625);
  // truth=work scores the same file on W_s through c_w (the hand-computed case above, plus the overhead)
  model.model.truth = TimeModel::Truth::kWork;
  const auto w = replay_workload(hand_measured(), model, *policy, "static", "hand.h5");
  EXPECT_FALSE(w.measured);
  EXPECT_DOUBLE_EQ(w.compute_s, 4.75 + 6.75);
  EXPECT_DOUBLE_EQ(w.imbalance[0], 0.0);
  // a file without measured seconds under truth=measured is refused naming the field
  model.model.truth = TimeModel::Truth::kMeasured;
  try {
    replay_workload(hand(), model, *policy, "static", "hand.h5");
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("hand.h5: field 'slice_seconds': --time-model truth=measured"),
              std::string::npos)
        << e.what();
  }
}

// hand_measured() as version 3: 0.8 s of event 0's seconds were list builds (0.2 per slice of 2 elements), made at
// the interval's two cell stages by the left half (bits 0-1 of slices 0 and 1) and none by the right; event 1's
// builds (0.4 s) at stage 0 by slices 0 and 3 and at stage 1 by slice 3.
EngineWorkload hand_parts() {
  EngineWorkload w = hand_measured();
  for (auto& e : w.events) e.part_seconds = {0.1, 0, 0.1, e.interval_s - 0.2};
  w.events[0].part_seconds = {0.1, 0.8, 0.05, 0.05};
  w.events[1].part_seconds[1] = 0.4, w.events[1].part_seconds[3] -= 0.4;
  w.events[0].cell_stage_changes = {3, 3, 0, 0};
  w.events[1].cell_stage_changes = {1, 0, 0, 3};
  return w;
}

TEST(WorkloadReplay, ListBuildsGoToTheRanksWhoseSlicesChanged) {
  // P=2 at [2], no ghosts, no overhead. Event 0: the slices keep 0.8, 0.8, 2.8, 2.8; the left rank made both builds
  // of the whole list's 0.8 s over its half of the elements: 1.6 + 0.8 * 4/8 * 2/2 = 2.0, the right 5.6 + 0 = 5.6.
  // Event 1: 1.9, 1.9, 0.9, 0.9; stages 0-1 changed somewhere (k = 2): left k_r = 1 (stage 0), right 2:
  // 3.8 + 0.4 * 1/2 * 1/2 = 3.9, 1.8 + 0.4 * 1/2 * 2/2 = 2.0.
  auto model = exact(2);
  model.model.ghost_weight = 0;
  auto policy = make_policy("static");
  auto w = hand_parts();
  const auto r = replay_workload(w, model, *policy, "static", "hand.h5");
  EXPECT_TRUE(r.measured);
  EXPECT_NEAR(r.compute_s, 5.6 + 3.9, 1e-12);
  EXPECT_NEAR(r.ideal_s, (2.0 + 5.6) / 2 + (3.9 + 2.0) / 2, 1e-12);
  // a version 2 file (no parts) spreads them by elements, as recorded: 2 + 6 and 4 + 2
  const auto v2 = replay_workload(hand_measured(), model, *policy, "static", "hand.h5");
  EXPECT_NEAR(v2.compute_s, 6 + 4, 1e-12);
  // the oracles and foresight see the recorded seconds per slice (additive), as in version 2: the same decisions
  for (const std::string name : {"oracle", "foresight"}) {
    auto a = make_policy(name), b = make_policy(name);
    EXPECT_EQ(replay_workload(w, model, *a, name, "hand.h5").migration,
              replay_workload(hand_measured(), model, *b, name, "hand.h5").migration)
        << name;
  }
}

TEST(WorkloadReplay, ListBuildsByChangedWorkWithAWeightAndAPerElementCost) {
  // list_by=work, list_weight 0.5, element_s 0.1 (4 elements a rank), no ghosts: W_s is 4, 4, 4, 4 then 8, 4, 2, 2.
  // Event 0: the changed slices 0-1 hold 8 of 16: left 1.6 + 0.5 * 0.8 * 8/16 + 0.4 = 2.2, right 5.6 + 0 + 0.4 = 6.0.
  // Event 1: slice 0 (8) changed on the left, slice 3 (2) on the right: 3.8 + 0.5 * 0.4 * 8/16 + 0.4 = 4.3 and
  // 1.8 + 0.5 * 0.4 * 2/16 + 0.4 = 2.225.
  auto model = exact(2);
  model.model.ghost_weight = 0;
  set_time_model(model.model, "list_by", "work", "--time-model ");
  set_time_model(model.model, "list_weight", "0.5", "--time-model ");
  set_time_model(model.model, "element_s", "0.1", "--time-model ");
  auto policy = make_policy("static");
  const auto r = replay_workload(hand_parts(), model, *policy, "static", "hand.h5");
  EXPECT_NEAR(r.compute_s, 6.0 + 4.3, 1e-12);
  EXPECT_NEAR(r.ideal_s, (2.2 + 6.0) / 2 + (4.3 + 2.225) / 2, 1e-12);
  // a version 2 file has no list seconds and no elements per slice, and truth=work replays W_s: the three keys would
  // change nothing there, and are refused (any one of them), naming the file and the key
  for (const char* key : {"list_by", "list_weight", "list_element_weight", "element_s"}) {
    auto one = exact(2);
    set_time_model(one.model, key, std::string(key) == "list_by" ? "work" : "0.5", "--time-model ");
    try {
      replay_workload(hand_measured(), one, *policy, "static", "hand.h5");
      ADD_FAILURE() << key << ": no error on a version 2 file";
    } catch (const InputError& e) {
      EXPECT_NE(
          std::string(e.what()).find("hand.h5: time model " + std::string(key) + ": the file has no list seconds"),
          std::string::npos)
          << e.what();
    }
    set_time_model(one.model, "truth", "work", "--time-model ");
    try {
      replay_workload(hand_parts(), one, *policy, "static", "hand.h5");
      ADD_FAILURE() << key << ": no error under truth=work";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("truth=work replays W_s"), std::string::npos) << e.what();
    }
  }
  auto plain = exact(2);
  plain.model.ghost_weight = 0;
  EXPECT_NEAR(replay_workload(hand_measured(), plain, *policy, "static", "hand.h5").compute_s, 6 + 4, 1e-12);
  try {
    set_time_model(model.model, "list_by", "elements", "--time-model ");
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("--time-model list_by: 'elements' is not one of stages, work, triggers"),
              std::string::npos)
        << e.what();
  }
}

TEST(WorkloadReplay, ListBuildsByTriggersGoToTheRanksThatWouldHaveRebuilt) {
  // list_by=triggers on hand_parts() with list triggers (P=2 at [2], no ghosts; W_s 4, 4, 4, 4 then 8, 4, 2, 2).
  // Event 0: 4 builds; slice 1 triggered build 0 and slice 2 build 2; stages 0-1 changed slices 0-1. Left: 1 trigger
  // + 2 stages = 3 of 4 builds at its W_s share 8/16: 1.6 + 0.8 * 3/4 * 1/2 = 1.9; right: 1 of 4: 5.6 + 0.1 = 5.7.
  // Event 1: 2 builds, no trigger; stage 0 on the left (12/16 of W_s), stages 0-1 on the right (4/16):
  // 3.8 + 0.4 * 1/2 * 12/16 = 3.95 and 1.8 + 0.4 * 2/2 * 4/16 = 1.9.
  auto w = hand_parts();
  w.events[0].list_builds = 4, w.events[0].list_triggers = {0, 1, 4, 0};
  w.events[1].list_builds = 2, w.events[1].list_triggers = {0, 0, 0, 0};
  auto model = exact(2);
  model.model.ghost_weight = 0;
  set_time_model(model.model, "list_by", "triggers", "--time-model ");
  auto policy = make_policy("static");
  const auto r = replay_workload(w, model, *policy, "static", "hand.h5");
  EXPECT_NEAR(r.compute_s, 5.7 + 3.95, 1e-12);
  EXPECT_NEAR(r.ideal_s, (1.9 + 5.7) / 2 + (3.95 + 1.9) / 2, 1e-12);
  // a rank's builds are capped at the one rank's: 1 build, which both a trigger and two stages claim on the left
  w.events[1].list_builds = 1, w.events[1].list_triggers = {1, 0, 0, 0};
  w.events[1].cell_stage_changes = {3, 0, 0, 0};
  const auto capped = replay_workload(w, model, *policy, "static", "hand.h5");
  EXPECT_NEAR(capped.ideal_s, (1.9 + 5.7) / 2 + (3.8 + 0.4 * 12.0 / 16 + 1.8) / 2, 1e-12);
  // list_element_weight 1 adds each rank's element share of the list seconds (4 of 8 elements): 0.4 and 0.2
  w.events[1] = hand_parts().events[1];
  w.events[1].list_builds = 2, w.events[1].list_triggers = {0, 0, 0, 0};
  set_time_model(model.model, "list_element_weight", "1", "--time-model ");
  const auto both = replay_workload(w, model, *policy, "static", "hand.h5");
  EXPECT_NEAR(both.compute_s, 6.1 + 4.15, 1e-12);
  EXPECT_NEAR(both.ideal_s, (2.3 + 6.1) / 2 + (4.15 + 2.1) / 2, 1e-12);
  model.model.list_element_weight = 0;
  // a version 3 file has no triggers: refused, naming the file and the field
  try {
    replay_workload(hand_parts(), model, *policy, "static", "hand.h5");
    ADD_FAILURE() << "no error on a version 3 file";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("hand.h5: time model list_by: triggers, but the file has no list triggers"),
              std::string::npos)
        << e.what();
  }
}

TEST(WorkloadReplay, TheOracleSeesTheNextMeasuredSeconds) {
  // oracle_work is the next event's measured seconds: at event 0 it sees 2, 2, 1, 1 and moves the boundary to 1
  // (2 | 4 -> max 4 at [2] or [1]: the partition of the least maximum, found by chains; either gives T_max 4 + ghosts).
  auto policy = make_policy("oracle");
  const auto m = replay_workload(hand_measured(), exact(2), *policy, "oracle", "hand.h5");
  auto work = exact(2);
  work.model.truth = TimeModel::Truth::kWork;
  const auto w = replay_workload(hand_measured(), work, *policy, "oracle", "hand.h5");
  // under W_s the oracle sees 8, 4, 2, 2 next and moves to [1]; under measured seconds 2, 2, 1, 1 is as good at [2]
  EXPECT_EQ(w.migration, 1);
  EXPECT_LE(m.compute_s, 6.5 + 4.375 + 1e-12);  // static's 6.5 (event 0) + 4.375 (event 1) without the overhead
}

TEST(WorkloadReplay, TruthAndOverheadKeysAreChecked) {
  TimeModel m;
  set_time_model(m, "truth", "measured", "--time-model ");
  EXPECT_EQ(m.truth, TimeModel::Truth::kMeasured);
  set_time_model(m, "rank_overhead_s", "0.002", "--time-model ");
  EXPECT_DOUBLE_EQ(m.rank_overhead_s, 0.002);
  for (const auto& [k, v] : std::vector<std::pair<std::string, std::string>>{
           {"truth", "wall"}, {"rank_overhead_s", "-1"}, {"rank_overhead_s", "1x"}}) {
    try {
      set_time_model(m, k, v, "--time-model ");
      ADD_FAILURE() << k << "=" << v;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("--time-model " + k), std::string::npos) << e.what();
    }
  }
}

TEST(WorkloadReplay, AnotherRankCountAndCoarseningFollowTheModel) {
  // P=4, one slice each: ghosts 1, 2, 2, 1. Event 0: T = 0.5 (4 + G) = 2.5, 3, 3, 2.5 (I = 0.5 / 2.75);
  // event 1: 0.5 (8 + 1), 0.5 (4 + 2), 0.5 (2 + 2), 0.5 (2 + 1) = 4.5, 3, 2, 1.5 (I = 3 / 2.75).
  auto policy = make_policy("static");
  const auto r = replay_workload(hand(), exact(4), *policy, "static", "hand.h5");
  EXPECT_DOUBLE_EQ(r.imbalance[0], 0.5 / 2.75);
  EXPECT_DOUBLE_EQ(r.imbalance[1], 3.0 / 2.75);
  // two slices of two: the coarse edge is the fine edge 2; P=2 sees what it saw on the fine slices
  auto c = exact(2);
  c.coarsen = 2;
  const auto coarse = replay_workload(hand(), c, *policy, "static", "hand.h5");
  EXPECT_DOUBLE_EQ(coarse.imbalance[1], 4.0 / 4.5);
  // a window of the second event alone starts from ITS optimal partition ([1]: 8 | 8)
  auto win = exact(2);
  win.first_event = 1;
  const auto one = replay_workload(hand(), win, *policy, "static", "hand.h5");
  ASSERT_EQ(one.events, 1);
  EXPECT_DOUBLE_EQ(one.imbalance[0], 0.0);  // 0.5 (8 + 1) on both ranks (one ghost element each)
  EXPECT_DOUBLE_EQ(one.compute_s, 4.5);
}

TEST(WorkloadReplay, PoliciesSeeJitterAndSpeedFactorsTheScoreSeesOnlySpeed) {
  auto policy = make_policy("static");
  auto noisy_run = exact(2);
  noisy_run.model.jitter = 0.2;
  noisy_run.seed = 7;
  const auto a = replay_workload(hand(), noisy_run, *policy, "static", "hand.h5");
  EXPECT_DOUBLE_EQ(a.mean_imbalance, 2.0 / 4.5);  // the score uses the true times
  auto slow = exact(2);
  slow.model.speed_spread = 0.1;
  slow.seed = 7;
  const auto s = speed_factors(2, 7, 0.1);
  const auto b = replay_workload(hand(), slow, *policy, "static", "hand.h5");
  const double t0 = 4.5 * s[0], t1 = 4.5 * s[1];
  EXPECT_NE(s[0], s[1]);
  EXPECT_DOUBLE_EQ(b.imbalance[0], std::abs(t0 - t1) / ((t0 + t1) / 2));
  EXPECT_EQ(speed_factors(2, 7, 0.1), s) << "a pure function of the seed";
  // reactive under jitter sees different times for different seeds (its decisions may differ), the same for the same
  auto reactive = make_policy("reactive");
  const auto x = replay_workload(hand(), noisy_run, *reactive, "reactive", "hand.h5");
  auto reactive2 = make_policy("reactive");
  const auto y = replay_workload(hand(), noisy_run, *reactive2, "reactive", "hand.h5");
  EXPECT_EQ(x.imbalance, y.imbalance);
  EXPECT_EQ(x.migration, y.migration);
}

TEST(WorkloadReplay, RefusesRankCountsAndWindowsThatDoNotFit) {
  auto policy = make_policy("static");
  auto too_many = exact(5);
  try {
    replay_workload(hand(), too_many, *policy, "static", "hand.h5");
    FAIL() << "5 ranks on 4 slices";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("hand.h5: --ranks 5: 5 ranks of at least 1 slices do not fit in 4 slices"),
              std::string::npos)
        << e.what();
  }
  auto late = exact(2);
  late.first_event = 2;
  EXPECT_THROW(replay_workload(hand(), late, *policy, "static", "hand.h5"), InputError);
  TimeModel m;
  EXPECT_THROW(set_time_model(m, "ghost_weight", "0.5x", "--time-model "), InputError);
  EXPECT_THROW(set_time_model(m, "jitter", "0.5", "--time-model "), InputError);  // outside [0, 0.3]
  EXPECT_THROW(set_time_model(m, "speed", "0.1", "--time-model "), InputError);
  set_time_model(m, "migrate_s_per_slice", "0.003", "--time-model ");
  EXPECT_EQ(m.migrate_s_per_slice, 0.003);
}

}  // namespace
}  // namespace semlb::surrogate
