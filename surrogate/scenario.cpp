// Scenario generation and workload evolution; every draw is keyed by (seed, stream, event, index).
#include "scenario.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "common/errors.hpp"
#include "common/text_io.hpp"
#include "rng.hpp"

namespace semlb::surrogate {
namespace {

enum Stream : uint64_t { kSetup = 1, kHotspot, kDrift, kGrowth, kBurst, kTimeNoise, kWorkNoise, kTexture, kBias };
using rng::clipped_normal;

}  // namespace

const std::vector<std::string>& scenario_keys() {
  static const std::vector<std::string> k = {"slices",        "min_width",       "baseline",          "growth_rate",
                                             "growth_period", "growth_offset",   "burst_probability", "burst_size",
                                             "time_jitter",   "work_noise",      "drift_speed",       "drift_walk",
                                             "drift_max",     "front_amplitude", "front_speed",       "front_start"};
  return k;
}

Scenario make_scenario(uint64_t seed, int ranks, const ScenarioSet& set) {
  for (const auto& [k, v] : set)
    if (std::find(scenario_keys().begin(), scenario_keys().end(), k) == scenario_keys().end()) {
      std::string known;
      for (const auto& name : scenario_keys()) known += (known.empty() ? "" : ", ") + name;
      throw InputError("scenario." + k + ": unknown scenario key (one of " + known + ")");
    }
  // The override of `key` if given (parsed strictly, in [lo, hi]), else the drawn value.
  auto real = [&](const char* key, double drawn, double lo, double hi) {
    const auto it = set.find(key);
    return it == set.end() ? drawn : parse_real(it->second, std::string("scenario.") + key + ": ", lo, hi);
  };
  auto integer = [&](const char* key, int drawn, long lo, long hi) {
    const auto it = set.find(key);
    return it == set.end() ? drawn
                           : static_cast<int>(parse_integer(it->second, std::string("scenario.") + key + ": ", lo, hi));
  };
  Scenario s;
  s.seed = seed;
  s.ranks = ranks;
  auto u = [&](double lo, double hi, uint64_t k) { return rng::uniform(lo, hi, seed, kSetup, 0, k); };
  s.slices = integer("slices", static_cast<int>(u(256, 1025, 0)), 1, 1 << 20);
  if (ranks < 1 || ranks > s.slices)
    throw InputError("ranks = " + std::to_string(ranks) + " must be in [1, " + std::to_string(s.slices) + "]");
  s.min_width = integer("min_width", std::max(1, std::min(static_cast<int>(u(2, 7, 1)), s.slices / (2 * ranks))), 1,
                        s.slices / ranks);
  s.baseline = real("baseline", u(0.2, 0.6, 2), 0.0, 1e6);
  s.growth_rate = real("growth_rate", u(0.0, 0.001, 3), -0.5, 1.0);
  s.growth_period = integer("growth_period", static_cast<int>(u(8, 31, 4)), 1, 1 << 20);
  s.growth_offset = integer("growth_offset", static_cast<int>(u(0, s.growth_period, 5)), 0, s.growth_period - 1);
  s.burst_probability = real("burst_probability", u(0.02, 0.10, 6), 0.0, 1.0);
  s.burst_size = real("burst_size", 1.0, 0.0, 1e6);
  s.time_jitter = real("time_jitter", u(0.005, 0.03, 7), 0.0, 1.0);
  s.work_noise = real("work_noise", u(0.05, 0.20, 8), 0.0, 1.0);
  s.drift_speed = real("drift_speed", s.drift_speed, 0.0, 1.0);
  s.drift_walk = real("drift_walk", s.drift_walk, 0.0, 1.0);
  s.drift_max = real("drift_max", s.drift_max, 0.0, 1.0);
  s.front_amplitude = real("front_amplitude", s.front_amplitude, 0.0, 1e6);
  s.front_speed = real("front_speed", s.front_speed, -1.0, 1.0);
  s.front_start = real("front_start", s.front_start, -1.0, 2.0);
  const int n = static_cast<int>(u(2, 7, 9));
  for (int h = 0; h < n; ++h) {
    auto hu = [&](double lo, double hi, uint64_t k) { return rng::uniform(lo, hi, seed, kHotspot, h, k); };
    s.hotspots.push_back({hu(0.05, 0.95, 0),
                          std::clamp(s.drift_speed * clipped_normal(seed, kHotspot, h, 7), -s.drift_max, s.drift_max),
                          hu(0.5, 2.0, 2), hu(0.05, 0.25, 3)});
  }
  for (int k = 0; k < 3; ++k) {
    auto bu = [&](double lo, double hi, uint64_t i) { return rng::uniform(lo, hi, seed, kBias, k, i); };
    s.proxy_bias.push_back(
        {bu(0.02, 0.10, 0), bu(1.0, 4.0, 1), bu(0.0, 2.0 * std::numbers::pi, 2), bu(-0.02, 0.02, 3)});
  }
  s.texture.resize(s.slices);
  for (int i = 0; i < s.slices; ++i)
    s.texture[i] = std::clamp(1.0 + 0.15 * clipped_normal(seed, kTexture, 0, i), 0.5, 1.5);
  return s;
}

Workload::Workload(const Scenario& s) : s_(s), hotspots_(s.hotspots), work_(s.slices) { evaluate(); }

double Workload::growth_phase() const {
  const int p = s_.growth_period;
  return static_cast<double>(((event_ - s_.growth_offset) % p + p) % p) / p;
}

void Workload::advance() {
  ++event_;
  const uint64_t seed = s_.seed, t = static_cast<uint64_t>(event_);
  growth_event_ = (event_ - s_.growth_offset) % s_.growth_period == 0;
  for (size_t h = 0; h < hotspots_.size(); ++h) {
    Hotspot& hs = hotspots_[h];
    hs.velocity =
        std::clamp(hs.velocity + s_.drift_walk * clipped_normal(seed, kDrift, t, h), -s_.drift_max, s_.drift_max);
    hs.centre += hs.velocity;
    if (hs.centre < 0.02 || hs.centre > 0.98) {  // reflect at the tissue edge
      hs.velocity = -hs.velocity;
      hs.centre = std::clamp(hs.centre, 0.02, 0.98);
    }
    hs.amplitude *= 1.0 + s_.growth_rate;
    if (growth_event_ && rng::uniform(seed, kGrowth, t, 3 * h) < 0.5) {  // a division wave in this region
      hs.amplitude *= 1.0 + rng::uniform(0.01, 0.05, seed, kGrowth, t, 3 * h + 1);
      hs.width = std::min(0.3, hs.width * (1.0 + rng::uniform(0.0, 0.03, seed, kGrowth, t, 3 * h + 2)));
    }
  }
  std::erase_if(bursts_, [&](const Burst& b) { return std::exp(-(event_ - b.start) / b.decay) < 1e-3; });
  if (rng::uniform(seed, kBurst, t, 0) < s_.burst_probability)
    bursts_.push_back({rng::uniform(0.02, 0.98, seed, kBurst, t, 1), rng::uniform(0.005, 0.03, seed, kBurst, t, 2),
                       s_.burst_size * rng::uniform(0.1, 0.6, seed, kBurst, t, 3), event_,
                       rng::uniform(1.0, 5.0, seed, kBurst, t, 4)});
  evaluate();
}

namespace {
// amplitude * exp(-z^2/2), z = (x - centre)/width; exactly 0 beyond 9 widths (below 3e-18 of the peak).
double gaussian(double x, double centre, double width, double amplitude) {
  const double z = (x - centre) / width;
  return z * z > 81.0 ? 0.0 : amplitude * std::exp(-0.5 * z * z);
}
}  // namespace

void Workload::evaluate() {
  for (int i = 0; i < s_.slices; ++i) {
    const double x = (i + 0.5) / s_.slices;
    double d = s_.baseline;
    for (const auto& h : hotspots_) d += gaussian(x, h.centre, h.width, h.amplitude);
    for (const auto& b : bursts_)
      d += gaussian(x, b.centre, b.width, b.amplitude * std::exp(-(event_ - b.start) / b.decay));
    if (s_.front_amplitude > 0) {  // the ramp behind the front: 0 at the front, front_amplitude 0.2 behind it
      const double behind = s_.front_start + s_.front_speed * event_ - x;
      d += s_.front_amplitude * std::clamp(behind / 0.2, 0.0, 1.0);
    }
    work_[i] = d * s_.texture[i] / s_.slices;
  }
}

std::vector<double> noisy(const std::vector<double>& v, double sigma, uint64_t seed, uint64_t stream, int event) {
  std::vector<double> out(v.size());
  for (size_t i = 0; i < v.size(); ++i)
    out[i] = std::max(0.0, v[i] * (1.0 + sigma * clipped_normal(seed, stream, event, i)));
  return out;
}

std::vector<double> measured_times(const Scenario& s, int event, const std::vector<double>& t) {
  return noisy(t, s.time_jitter, s.seed, kTimeNoise, event);
}

std::vector<double> observed_work(const Scenario& s, int event, const std::vector<double>& w) {
  auto out = noisy(w, s.work_noise, s.seed, kWorkNoise, event);
  for (size_t i = 0; i < out.size(); ++i) {
    const double x = (i + 0.5) / out.size();
    double g = 0.0;
    for (const auto& m : s.proxy_bias)
      g += m.amplitude * std::sin(2.0 * std::numbers::pi * m.wavenumber * x + m.phase + m.speed * event);
    out[i] *= std::exp(g);
  }
  return out;
}

}  // namespace semlb::surrogate
