// "division": a cell of a listed type with at least at_elements elements splits through its centroid,
// perpendicular to the long axis of its gyration tensor; the daughter on the +axis side gets the id
// daughter_id(mother, depth) (state.hpp), the same on any number of ranks.
#include <Eigen/Dense>

#include "effect.hpp"
#include "cell_types.hpp"

namespace semlb::engine {
namespace {

class Division final : public Effect {
 public:
  explicit Division(const Section& s)
      : at_(static_cast<int>(s.integer("at_elements", 20, 2, kMaxSlots - 1))), types_(read_types(s, "types", {"basal"})) {}
  std::string name() const override { return "division"; }
  bool changes_cells() const override { return true; }
  void prepare(State& s) override { s.cell_fields["division.depth"].resize(s.cell_id.size(), 0.0); }

  bool update_cells(CellContext& ctx) override {
    State& s = ctx.state;
    const long before = s.cells();
    bool any = false;
    for (long c = 0; c < before && !any; ++c) any = types_[s.cell_type[c]] && s.cell_count[c] >= at_;
    if (!any) return false;
    std::vector<long> halves_of(before, -1);  // mother -> index into halves; daughter before + i
    std::vector<std::pair<Positions, Positions>> halves;
    for (long c = 0; c < before; ++c) {  // cells in stored order
      if (!types_[s.cell_type[c]] || s.cell_count[c] < at_) continue;
      auto& depth = s.cell_fields["division.depth"];
      const int d = static_cast<int>(depth[c]);
      if (d >= kMaxDivisionDepth)
        throw std::runtime_error("cell " + std::to_string(s.cell_id[c]) + " divided " + std::to_string(d) + " times: cell ids are exhausted");
      halves_of[c] = static_cast<long>(halves.size());
      halves.push_back(split(elements_of(s, c)));
      s.cell_id.push_back(daughter_id(s.cell_id[c], d));
      s.cell_type.push_back(s.cell_type[c]);
      s.cell_count.push_back(0);
      depth[c] = d + 1;
      for (auto& [name, field] : s.cell_fields) field.push_back(field[c]);  // daughters inherit (depth too)
    }
    const auto append = [](const Positions& e, std::vector<double>& out) {
      for (const auto& p : e) out.insert(out.end(), p.begin(), p.end());
    };
    rewrite_elements(s, [&](long c, std::vector<double>& out) {
      if (c >= before) append(halves[c - before].second, out);          // a daughter: the +axis half
      else if (halves_of[c] >= 0) append(halves[halves_of[c]].first, out);  // a mother keeps the rest
      else copy_elements(s, c, out);
    }, 0);
    return true;
  }

  // Splits by the sign of (y - c) . a, a the gyration tensor's long axis; a degenerate cell (all
  // elements on one side, e.g. coincident) is split in half by projection order.
  static std::pair<Positions, Positions> split(const Positions& e) {
    Eigen::Vector3d c = Eigen::Vector3d::Zero();
    for (const auto& p : e) c += Eigen::Vector3d(p[0], p[1], p[2]);
    c /= static_cast<double>(e.size());
    Eigen::Matrix3d g = Eigen::Matrix3d::Zero();
    for (const auto& p : e) {
      const Eigen::Vector3d d = Eigen::Vector3d(p[0], p[1], p[2]) - c;
      g += d * d.transpose();
    }
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(g / static_cast<double>(e.size()));
    Eigen::Vector3d axis = eig.eigenvectors().col(2);  // largest eigenvalue
    int big = 0;
    axis.cwiseAbs().maxCoeff(&big);
    if (axis[big] < 0) axis = -axis;  // eigenvector sign is arbitrary: fix it
    std::vector<std::pair<double, int>> proj;
    for (size_t k = 0; k < e.size(); ++k) proj.push_back({(Eigen::Vector3d(e[k][0], e[k][1], e[k][2]) - c).dot(axis), static_cast<int>(k)});
    Positions stay, leave;
    for (const auto& [p, k] : proj) (p > 0 ? leave : stay).push_back(e[k]);
    if (stay.empty() || leave.empty()) {
      std::stable_sort(proj.begin(), proj.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
      stay.clear();
      leave.clear();
      for (size_t r = 0; r < proj.size(); ++r) (r < proj.size() / 2 ? stay : leave).push_back(e[proj[r].second]);
    }
    return {stay, leave};
  }

 private:
  int at_;
  std::array<bool, kCellTypes> types_;
};

const EffectRegistrar registrar("division", {50, [](const Section& s, const Scene&) { return std::make_unique<Division>(s); }});

}  // namespace
}  // namespace semlb::engine
