// Decomposition settings, the per-slice workload W_s (paper eqs. 2-3) and slab ownership.
#include "decomposition.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <sstream>

#include "backends/backend.hpp"
#include "common/errors.hpp"
#include "effects/effect.hpp"
#include "model/tissue.hpp"

namespace semlb::engine {

Decomposition Decomposition::from_scene(const Scene& scene, int ranks) {
  Decomposition d;
  const Section& s = *scene.decomposition;
  const double extent = scene.box_hi[0] - scene.box_lo[0];
  const double slice_um = s.real("slice_width", scene.cutoff / 4, 1e-6, 1e9);
  const double min_um = s.real("min_width", 3 * scene.cutoff, 0, 1e9);
  d.slices = std::max(1, static_cast<int>(std::ceil(extent / slice_um)));
  d.x0 = scene.box_lo[0];
  d.width = extent / d.slices;
  d.min_width = std::max(1, static_cast<int>(std::ceil(min_um / d.width)));
  d.policy = s.text("policy", d.policy);
  d.initial = s.text("initial", d.initial);
  if (d.initial != "workload" && d.initial != "uniform") s.fail("initial", "must be workload or uniform");
  d.rebalance_every = s.integer("rebalance_every", d.rebalance_every, 1, 1L << 40);
  d.timing = s.text("timing", d.timing);
  if (d.timing != "measured" && d.timing != "modelled" && d.timing != "device")
    s.fail("timing", "must be measured, modelled or device");
  const bool opencl = scene.backend.name.rfind("opencl", 0) == 0;
  if (d.timing == "device" && !opencl)
    s.fail("timing",
           "device timers need an OpenCL backend (profiling events); backend.name is '" + scene.backend.name + "'");
  d.device_sharing = s.text("device_sharing", d.device_sharing);
  if (d.device_sharing != "none" && d.device_sharing != "turns") s.fail("device_sharing", "must be none or turns");
  if (d.device_sharing == "turns" && !opencl)
    s.fail("device_sharing", "turns share an OpenCL device; backend.name is '" + scene.backend.name + "'");
  // Under turns a rank's bands travel before its forces: a rank waiting for its neighbour's bands inside its turn
  // would keep the device from the neighbour that has to send them.
  if (d.device_sharing == "turns") {
    if (s.has("overlap") && s.boolean("overlap", false))
      s.fail("overlap", "true cannot be combined with device_sharing: turns (the bands travel before the forces)");
    d.overlap = false;
  }
  d.overlap = s.boolean("overlap", d.overlap);
  const Section p = s.child("params");
  for (const auto& k : p.keys()) {
    std::string v = p.text(k, "");
    // A policy's weights file relative to the scene file's folder, when it is there (else as given: the working
    // directory, then the shipped weights folder, controllers/gru.hpp resolve_gru_weights).
    if (const auto beside = std::filesystem::path(scene.path).parent_path() / v;
        k == "weights" && !v.empty() && std::filesystem::path(v).is_relative() &&
        std::filesystem::is_regular_file(beside))
      v = beside.string();
    d.params.set(k, v);
  }
  p.finish();
  s.finish();
  // On 3 or more ranks the ghost exchange, which reaches the neighbouring ranks only, needs slabs at least as
  // wide as the cutoff plus a cell's reach (taken as one cutoff) on either side. start_exchange() still
  // checks the elements at every step and stops the run if a cell reaches further.
  const int ghost_slices = static_cast<int>(std::ceil(3 * scene.cutoff / d.width));
  if (ranks >= 3 && d.min_width < ghost_slices) {
    std::ostringstream m;
    m << min_um << " um is " << d.min_width << " slices of " << d.width << " um, narrower than the ghost region on "
      << ranks << " ranks: the cutoff plus a cell's reach of one cutoff on either side, 3 x " << scene.cutoff
      << " um = " << ghost_slices << " slices (the default); use at most 2 ranks or a wider min_width";
    s.fail("min_width", m.str());
  }
  if (ranks >= 2 && d.slices < ranks * d.min_width)  // one rank holds the whole domain, however narrow
    s.fail("min_width", std::to_string(ranks) + " ranks need " + std::to_string(ranks * d.min_width) + " slices of " +
                            std::to_string(d.width) + " um but the domain has " + std::to_string(d.slices) +
                            ": use fewer ranks or a larger tissue");
  try {
    check_engine_policy(d.policy);
    make_policy(d.policy, d.params);
  } catch (const InputError& e) {
    s.fail("policy", e.what());
  }
  return d;
}

void check_engine_policy(const std::string& policy) {
  if (policy_needs(policy)
          .true_work)  // the engine measures times and W_s (slice_work); only the surrogate knows the future
    throw InputError("'" + policy +
                     "' needs the true work of the next interval, which a simulation cannot know "
                     "(a surrogate baseline: use it with semlb surrogate)");
}

}  // namespace semlb::engine
