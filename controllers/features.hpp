// GRU input features per boundary (paper Sec. IV-C): dimensionless, clamped; one implementation for
// the Eigen controller and the trainer. The list and formulas are documented in docs/controllers.md.
#pragma once
#include <array>
#include <map>
#include <string>
#include <vector>

namespace semlb {

inline constexpr int kFeatureCount = 12;
// Two sets of the same 12 inputs (docs/controllers.md "Features"): boundary-v1 clamps the imbalance, its change and
// the last move to [-1, 1] (the global imbalance to [0, 2]), which saturates on engine workloads (|I_t| ~ 1);
// boundary-v2 maps them through x / (1 + |x|) instead (equal to x to first order, never flat). Weights files name their
// set.
enum class FeatureSet { v1, v2 };
inline constexpr const char* kFeatureSet = "boundary-v1";    // the name of FeatureSet::v1
inline constexpr const char* kFeatureSetV2 = "boundary-v2";  // the name of FeatureSet::v2
const char* feature_set_name(FeatureSet set);
// InputError "WHERE'NAME' is not a feature set (boundary-v1, boundary-v2)".
FeatureSet parse_feature_set(const std::string& name, const std::string& where);

// Everything one boundary's features are computed from. Real-valued so that a soft (relaxed) rollout
// can use the same code.
struct BoundaryState {
  double local_imbalance = 0;              // I_t at this boundary
  double prev_local_imbalance = 0;         // I_{t-1} (equal to I_t at the first event)
  double global_imbalance = 0;             // (T_max - T_min) / T_mean
  double width_left = 0, width_right = 0;  // slices of the two adjacent ranks
  double min_width = 1, mean_width = 1;    // min_width and slices / P
  double last_move = 0;                    // signed slices this boundary moved at the previous event
  double growth_phase = 0;                 // [0, 1)
  bool growth_event = false;
  double proposal = 0;  // signed reactive proposal Δs_r (slices, + = right)
  double ds_max = 1;    // bound of one event's move at this boundary (slices)
};

using FeatureVector = std::array<double, kFeatureCount>;
FeatureVector boundary_features(const BoundaryState& s, FeatureSet set = FeatureSet::v1);

struct Observation;
struct ReactiveParams;

// What the GRU needs at one boundary for one event: its features and the reactive pieces of eq. 6.
struct BoundaryInputs {
  FeatureVector features;
  int direction = 0;              // toward the slower rank (+1 right, -1 left, 0 none)
  double reactive_magnitude = 0;  // |Δs_r| (slices)
  double ds_max = 0;              // ds_max_frac * N_slow (slices)
};

// Keeps the per-boundary history the features need (previous local imbalance, previously observed
// boundaries). Used by the gru policy and by the trainer, so both compute identical inputs.
class FeatureTracker {
 public:
  explicit FeatureTracker(double ds_max_frac, FeatureSet set = FeatureSet::v1) : ds_max_frac_(ds_max_frac), set_(set) {}
  // Throws InputError if the number of boundaries differs from the first observation's.
  std::vector<BoundaryInputs> observe(const Observation& obs, const ReactiveParams& p);
  // History under "tracker.*" keys (checkpoints); load_state throws InputError for a malformed state.
  void save_state(std::map<std::string, std::vector<double>>& out) const;
  void load_state(const std::map<std::string, std::vector<double>>& in);

 private:
  double ds_max_frac_;
  FeatureSet set_;
  bool started_ = false;
  std::vector<double> prev_imbalance_;
  std::vector<int> prev_boundaries_;
};

// Names in order, e.g. "local_imbalance"; joined with commas in the weights file's metadata.
const std::array<std::string, kFeatureCount>& feature_names();
std::string feature_list();

}  // namespace semlb
