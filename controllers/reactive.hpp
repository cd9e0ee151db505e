// The paper's reactive boundary rule (Sec. IV-B, eqs. 2-4), shared by the reactive and gru policies.
#pragma once
#include <vector>

#include "observation.hpp"

namespace semlb {

struct ReactiveParams {
  double tau = 0.02;   // imbalance threshold (paper: 0.02)
  double alpha = 0.5;  // adjustment coefficient (paper: 0.5)
};

// The proposal at one boundary, computed from the observation before any boundary moves.
struct BoundaryProposal {
  double local_imbalance = 0.0;  // I_t = (T+ - T-) / ((T+ + T-)/2); 0 when both times are 0
  int direction = 0;             // +1: right rank slower (boundary moves right), -1: left slower, 0: equal
  int n_slow = 0;                // width of the slower rank before the sweep (left rank's when equal)
  double magnitude = 0.0;        // |Δs_r| = α N_slow |T+ - T-| / (2 T_slow) if |I_t| > τ, else 0
};

std::vector<BoundaryProposal> reactive_proposals(const Observation& obs, const ReactiveParams& p);

// Signed integer step of a proposal: direction * lround(magnitude) (half away from zero).
long integer_step(int direction, double magnitude);

}  // namespace semlb
