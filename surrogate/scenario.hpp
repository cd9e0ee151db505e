// Randomised load-balancing scenarios (paper Sec. IV-E): slice count, min width, and a per-slice workload
// that evolves by drifting hotspots, periodic growth events and transient bursts. Ranges: docs/surrogate.md.
#pragma once
#include <cstdint>
#include <map>
#include <string>
#include <vector>

namespace semlb::surrogate {

// Disjoint seed ranges (inclusive). Training code must only draw from kTrainSeeds.
struct SeedRange {
  uint64_t first, last;
  bool contains(uint64_t s) const { return s >= first && s <= last; }
};
inline constexpr SeedRange kTrainSeeds{0, 7999};
inline constexpr SeedRange kValidationSeeds{8000, 8999};
inline constexpr SeedRange kEvaluationSeeds{9000, 9999};

struct Hotspot {
  double centre, velocity, amplitude, width;  // domain units: the axis is [0, 1]
};

struct Burst {
  double centre, width, amplitude;
  int start;
  double decay;  // events (e-folding time)
};

// One mode of the smooth bias between the per-slice workload proxy and true cost:
// log(observed/true) += amplitude * sin(2 pi wavenumber x + phase + speed * t).
struct BiasMode {
  double amplitude, wavenumber, phase, speed;
};

struct Scenario {
  uint64_t seed = 0;
  int ranks = 2, slices = 256, min_width = 2;
  double baseline = 0.2;                      // tissue density floor
  double growth_rate = 0.0;                   // steady amplitude growth per event
  int growth_period = 16, growth_offset = 0;  // growth events at t = offset (mod period), t > 0
  double burst_probability = 0.05;            // per event
  double burst_size = 1.0;                    // scale of the burst amplitudes (each drawn in 0.1-0.6)
  double drift_speed = 0.0002;                // std of a hotspot's initial velocity, domain lengths per event
  double drift_walk = 0.00003;                // std of its per-event velocity change (random walk)
  double drift_max = 0.0005;                  // cap on |velocity|
  // A proliferative front (off unless front_amplitude > 0; never drawn, only set by overrides): behind the front at
  // front_start + front_speed * t (domain lengths per event) the density rises linearly over 0.2 domain lengths to
  // front_amplitude, as the stratifying epidermis behind a growth front does (docs/surrogate.md).
  double front_amplitude = 0.0, front_speed = 0.005, front_start = 0.0;
  double time_jitter = 0.01;         // relative std of measured times
  double work_noise = 0.05;          // relative std of the observed per-slice work
  std::vector<Hotspot> hotspots;     // at event 0
  std::vector<double> texture;       // fixed per-slice heterogeneity (mean ~1)
  std::vector<BiasMode> proxy_bias;  // systematic error of the observed per-slice work
};

// Scenario overrides KEY -> VALUE text (`semlb surrogate --scenario KEY=VALUE`, sweep key scenario.KEY): each
// replaces the seed's draw of that quantity before anything that depends on it is drawn (slices before the
// texture, drift_speed before the hotspot velocities, growth_period before growth_offset). Keys: see
// scenario_keys(); everything not overridden is drawn exactly as without overrides.
using ScenarioSet = std::map<std::string, std::string>;
const std::vector<std::string>& scenario_keys();

// Draws a scenario from its seed; only min_width depends on ranks (reduced so that 2*P*min_width <= slices).
// Throws InputError if ranks < 1 or ranks > slices, or on an unknown key or a value that is not a number in
// its range ("scenario.KEY: 'TEXT' is not a number" / "... outside [a, b]"; min_width must keep P*min_width
// <= slices; an overridden growth_offset must be < growth_period).
Scenario make_scenario(uint64_t seed, int ranks, const ScenarioSet& set = {});

// The noise-free per-slice workload of event t, advanced one event at a time (independent of any policy).
class Workload {
 public:
  explicit Workload(const Scenario& s);
  void advance();
  int event() const { return event_; }
  const std::vector<double>& work() const { return work_; }
  double growth_phase() const;
  bool growth_event() const { return growth_event_; }

 private:
  void evaluate();
  const Scenario& s_;
  int event_ = 0;
  bool growth_event_ = false;
  std::vector<Hotspot> hotspots_;
  std::vector<Burst> bursts_;
  std::vector<double> work_;
};

// v[i] (1 + sigma z_i), z_i standard normal clipped at 3 sigma, drawn from (seed, stream, event, i); never negative.
std::vector<double> noisy(const std::vector<double>& v, double sigma, uint64_t seed, uint64_t stream, int event);

// Measurement noise of event t: multiplicative, clipped at 3 sigma, never negative. Observed work also
// carries the scenario's smooth proxy bias (the engine's W_s is a proxy of cost, not a measurement).
std::vector<double> measured_times(const Scenario& s, int event, const std::vector<double>& true_times);
std::vector<double> observed_work(const Scenario& s, int event, const std::vector<double>& true_work);

}  // namespace semlb::surrogate
