// The backend registry and the host versions of the backend operations on cells (W_s, migration, removal, fates).
#include "backend.hpp"

#include <numeric>
#include <optional>

#include "common/errors.hpp"

namespace semlb::engine {
BackendConfig backend_settings(const BackendConfig& config) {
  const BackendInfo* chosen = Backends::find(config.name);
  if (!chosen) {  // named where the name was given (the scene's line, --backend, --set backend.name)
    const std::string why = "backend '" + config.name + "' is unknown (known: " + Backends::known() + ")";
    if (config.settings) config.settings->fail("name", why);
    throw InputError(why);
  }
  BackendConfig c = config;
  if (!config.settings) return c;
  const Section top = *config.settings;  // a copy: what it marks read is this call's, whichever backend runs next
  std::optional<Section> chosen_own;
  for (const auto& name : Backends::names()) {
    if (!top.has(name)) continue;
    const Section own = top.child(name);
    BackendConfig checked = c;
    const BackendInfo& info = Backends::at(name);
    if (info.read) info.read(own, name == c.name ? c : checked);
    own.finish("backend '" + name + "' does not use it");
    if (name == c.name)
      chosen_own = own;
    else if (info.check)
      info.check(checked, [&](const std::string& key, const std::string& why) { own.fail(key, why); });
  }
  if (chosen->read) chosen->read(top, c);
  if (chosen_own)  // a flag into the chosen one's map that a key beside it overrides would do nothing
    for (const auto& key : chosen_own->keys())
      if (const auto* beside = top.find(key); beside && !chosen_own->origin(key).flag.empty()) {
        const Origin& o = beside->origin;
        chosen_own->fail(key, "has no effect: " + top.field(key) + " (" +
                                  (o.flag.empty() ? o.file + ":" + std::to_string(o.line) : o.flag) +
                                  ") overrides the backend's map; set that one instead");
      }
  if (chosen->check)  // the keys beside the maps override the chosen one's map: a key set there is blamed there
    chosen->check(c, [&](const std::string& key, const std::string& why) {
      if (chosen_own && !top.has(key) && chosen_own->has(key)) chosen_own->fail(key, why);
      top.fail(key, why);
    });
  for (const auto& key : top.unread()) {
    if (top.find(key)->kind == Settings::Kind::map)
      top.fail(key, "is not a backend (known: " + Backends::known() + ")");
    top.fail(key, "backend '" + c.name + "' does not use it");
  }
  return c;
}

std::unique_ptr<Backend> make_backend(const BackendConfig& config) {
  const BackendConfig c = backend_settings(config);
  return Backends::at(c.name).make(c);
}

std::vector<double> HostCellOps::slice_work(State& host, const SliceMap& map, const Grid& g,
                                            const CountReduce& reduce) {
  download(host);
  auto counts = bin_counts(host, g);
  if (reduce) reduce(counts);
  return cell_work(host, g, counts, map);
}

void HostCellOps::take_leavers(State& host, const SliceMap& map, const std::vector<int>& boundaries, int rank,
                               State& leavers, std::vector<int>& owner) {
  download(host);
  owner.clear();
  State stay;
  split_by_owner(host, map, boundaries, rank, stay, &leavers, &owner);
  if (leavers.cells() == 0) return;  // the backend holds exactly these cells
  host = std::move(stay);
  upload(host);
}

long HostCellOps::remove_cells(State& host, const RemovalCall& r) {
  const RemovalEvaluator removes = evaluator_of(r.removes, "removal rule", r.rule);
  const std::vector<double>& params = r.params;
  download(host);
  std::vector<long> spared;
  for (long c = 0; c < host.cells(); ++c) {
    const auto ctr = centroid(host, c);
    if (!removes(ctr[0], ctr[1], ctr[2], host.cell_type[c], host.cell_count[c], params.data())) spared.push_back(c);
  }
  const long removed = host.cells() - static_cast<long>(spared.size());
  if (removed == 0) return 0;  // the backend holds exactly these cells
  State kept = empty_like(host);
  copy_cells(host, spared, kept);
  kept.reindex();
  host = std::move(kept);
  upload(host);
  return removed;
}

void HostCellOps::cell_fate(State& host, const FateCall& r, int field, double elapsed_h) {
  const FateEvaluator decides = evaluator_of(r.decides, "fate rule", r.rule);
  const std::vector<double>& params = r.params;
  download(host);
  std::vector<double>* column = host.cell_field_at(field);
  for (long c = 0; c < host.cells(); ++c) {
    const auto ctr = centroid(host, c);
    double f = column ? (*column)[c] : 0.0;
    decides(ctr[0], ctr[1], ctr[2], host.cell_count[c], elapsed_h, params.data(), &host.cell_type[c], &f);
    if (column) (*column)[c] = f;
  }
  upload(host);
}

void HostCellOps::append_cells(State& host, const State& arrivals) {
  download(host);
  std::vector<long> all(static_cast<size_t>(arrivals.cells()));
  std::iota(all.begin(), all.end(), 0L);
  copy_cells(arrivals, all, host);
  host.reindex();
  upload(host);
}

}  // namespace semlb::engine
