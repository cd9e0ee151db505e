// Helpers for the engine tests: small scenes from text, random tissues, backend lists and the rank-count harness.
#pragma once
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "common/errors.hpp"
#include "engine/backends/backend.hpp"
#include "engine/backends/opencl.hpp"
#include "engine/effects/cell_fields.hpp"
#include "engine/effects/effect.hpp"
#include "engine/model/scene.hpp"
#include "engine/model/state.hpp"
#include "engine/pairs/pair_term.hpp"
#include "engine/io/io.hpp"
#include "engine/simulation/simulation.hpp"
#include "../run_command.hpp"

namespace semlb::engine::testing {

// A scene from YAML text; effects default to mechanics only.
inline Scene scene_from(const std::string& yaml, const std::vector<std::string>& overrides = {}) {
  return parse_scene(yaml, "test.yaml", overrides);
}

inline const char* kMechanicsYaml = R"(
name: t
cutoff: 8.75
tissue: {cells: 40, layers: 2}
time: {dt: 0.01, steps: 20}
backend: {name: serial}
effects:
  mechanics: {}
)";

// The cell stage's rules of the cell effects `yaml` lists (lines under kMechanicsYaml's `effects:`), their fields
// prepared on and declared in `s`.
inline CellRules rules_of(const std::string& yaml, State& s) {
  auto scene = scene_from(std::string(kMechanicsYaml) + yaml);
  const auto effects = make_effects(scene);
  std::vector<std::string> listed;
  for (auto& e : effects) {
    e->prepare(s);
    listed.push_back(e->name());
  }
  declare_cell_fields(s, listed);
  return cell_rules_of(effects, s, false);
}

// Cells of `per_cell` elements scattered uniformly in a box (types cycle through the three).
inline State random_state(long cells, int per_cell, double side, uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0, side);
  State s;
  for (long c = 0; c < cells; ++c) {
    s.cell_id.push_back(static_cast<uint64_t>(c) * 7 + 3);
    s.cell_type.push_back(static_cast<int>(c % 3));
    s.cell_count.push_back(per_cell);
    for (int e = 0; e < 3 * per_cell; ++e) s.position.push_back(u(rng));
  }
  s.reindex();
  return s;
}

// Backends this machine can run: the C++ ones always, the OpenCL ones when a platform exists.
inline std::vector<std::string> available_backends() {
  std::vector<std::string> b = {"serial", "cpu-binned"};
  if (!cl::list_devices().empty()) {
    b.push_back("opencl-allpairs");
    b.push_back("opencl-binned");
  }
  return b;
}

// Every backend this machine runs (available_backends) in both precisions, as (name, precision) pairs.
inline std::vector<std::pair<std::string, std::string>> backend_precisions() {
  std::vector<std::pair<std::string, std::string>> out;
  for (const auto& b : available_backends())
    for (const char* p : {"double", "float"}) out.emplace_back(b, p);
  return out;
}
// A backend by name and precision, the other settings at their defaults.
inline std::unique_ptr<Backend> backend(const std::string& name, const std::string& precision) {
  BackendConfig c;
  c.name = name;
  c.precision = precision;
  return make_backend(c);
}
// `call(backend, host)` on every backend and precision this machine runs, each holding `s` (host: a copy of it) must
// throw std::logic_error: a call made by hand for a plug-in that is not registered (device/backend.hpp).
template <class Call>
void expect_logic_error_on_every_backend(const State& s, const Call& call) {
  for (const auto& [name, precision] : backend_precisions()) {
    auto b = backend(name, precision);
    b->upload(s);
    State host = s;
    EXPECT_THROW(call(*b, host), std::logic_error) << name << " " << precision;
  }
}
// What `read` (a plug-in's ElementTerm::read or RemovalRule::read) derives from the YAML map `yaml` read as the
// section effects.NAME; every key must have been read (Section::finish).
template <class Read>
std::vector<double> section_params(const std::string& name, const std::string& yaml, const Read& read) {
  const Section s(YAML::Load(yaml), "effects." + name, "test.yaml", nullptr);
  auto p = read(s);
  s.finish();
  return p;
}
// The forces of the registered pair term `name` with the YAML map `yaml` read as its section effects.NAME (every key
// read), at `cutoff` um.
inline PairForces pair_forces(const std::string& name, const std::string& yaml, double cutoff) {
  return pair_forces_of(
      name, section_params(name, yaml, [&](const Section& s) { return PairTerms::at(name).read(s, cutoff); }), cutoff);
}
// The force (force units) of pair term f.term on element i (info_i) from element j (info_j) at distance r um along
// +x (double), its fixed-point sum read back: its x component (the others must be 0).
inline double pair_force_x(const PairForces& f, double r, int info_i, int info_j) {
  int64_t acc[4] = {0, 0, 0, 0};
  PairTerms::at(f.term).f64(r, 0, 0, info_i, info_j, 1, 2, f.params.data(), f.cutoff * f.cutoff, acc);
  EXPECT_EQ(acc[1], 0);
  EXPECT_EQ(acc[2], 0);
  return static_cast<double>(acc[0]) * SEMLB_FIXED_INV;
}
// The force on element i (key key_i) from element j (key key_j) of the same cell at the same place: the added
// fixed-point components (pairs/pair_force.h's coincident kick) in `out` and their length (force units) returned.
template <class Real>
double coincident_kick(PairEvaluator<Real> law, const std::vector<Real>& p, Real cutoff2, int info, uint64_t key_i,
                       uint64_t key_j, int64_t* out) {
  out[0] = out[1] = out[2] = out[3] = 0;
  law(0, 0, 0, info, info, key_i, key_j, p.data(), cutoff2, out);
  double norm = 0;
  for (int c = 0; c < 3; ++c) norm += std::pow(static_cast<double>(out[c]) * SEMLB_FIXED_INV, 2);
  return std::sqrt(norm);
}
// mechanics with inter-cell sets that differ per type pair (V0 0.3 + 0.1 (ta + tb)): type-dependent tables.
inline const char* kTypedMorse =
    "{pairs: {basal-basal: {V0: 0.3}, basal-spinous: {V0: 0.4}, basal-granular: {V0: 0.5}, "
    "spinous-spinous: {V0: 0.5}, spinous-granular: {V0: 0.6}, granular-granular: {V0: 0.7}}}";
// The InputError message of kMechanicsYaml with `overrides`, constructed as a Simulation does (the effects' sections
// read), or "no error".
inline std::string scene_error(const std::vector<std::string>& overrides) {
  try {
    auto scene = scene_from(kMechanicsYaml, overrides);
    Simulation sim(scene, random_state(2, 2, 5.0, 1));
  } catch (const InputError& e) {
    return e.what();
  }
  return "no error";
}
// Each {--set override of kMechanicsYaml, field}: the scene is refused with a message naming the field.
inline void expect_errors_name_fields(const std::vector<std::pair<std::string, std::string>>& cases) {
  for (const auto& [set, field] : cases) {
    const std::string message = scene_error({set});
    EXPECT_NE(message.find(field), std::string::npos) << set << ": " << message;
  }
}

// `semlb sim` under mpirun on `ranks` ranks, bounded by `seconds` (a hang fails the test); `env` holds VAR=VALUE
// assignments for every rank.
inline std::string mpirun_sim(int ranks, const std::string& env = "", int seconds = 300) {
  return "OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 " + env + " " + test::within(seconds) +
         SEMLB_MPIEXEC + " --oversubscribe -np " + std::to_string(ranks) + " " + test::semlb_bin() + " sim";
}

// The rank-count harness: `semlb sim ARGS` on one device into DIR/single, then under mpirun on each of `ranks` into
// DIR/npR; every final state must equal the single device's bit for bit (State::hash). Returns the single device's
// final state. `args` starts with a space and names the scene, steps and settings, not --out.
inline State expect_same_state_on_ranks(const std::string& args, const std::string& dir,
                                        const std::vector<int>& ranks = {1, 2, 4}) {
  auto r = test::run(test::within(300) + test::semlb_bin() + " sim" + args + " --out " + dir + "/single");
  EXPECT_EQ(r.rc, 0) << r.out;
  if (r.rc != 0) return {};
  const State single = read_state(dir + "/single/final.h5");
  for (int n : ranks) {
    const std::string out = dir + "/np" + std::to_string(n);
    r = test::run(mpirun_sim(n) + args + " --out " + out);
    EXPECT_EQ(r.rc, 0) << n << " ranks: " << r.out;
    if (r.rc == 0) {
      EXPECT_EQ(read_state(out + "/final.h5").hash(), single.hash()) << n << " ranks";
    }
  }
  return single;
}

}  // namespace semlb::engine::testing
