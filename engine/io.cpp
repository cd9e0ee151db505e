// HDF5 state files and the XDMF index.
#include "io.hpp"

#include <cmath>
#include <filesystem>
#include <sstream>

#include "controllers/errors.hpp"
#include "controllers/h5.hpp"
#include "controllers/text_io.hpp"

namespace semlb::engine {

void write_state(const std::string& path, const State& state, const std::map<std::string, std::string>& attributes) {
  const std::string tmp = path + ".tmp";
  {
    auto f = h5::File::create(tmp);
    const State s = state.canonical();  // cells by id: files do not depend on storage order or rank count
    const hsize_t n = static_cast<hsize_t>(s.elements()), c = static_cast<hsize_t>(s.cells());
    f.write("/elements/position", {n, 3}, s.position);
    std::vector<int64_t> cell(n), type(n);
    for (long k = 0; k < s.cells(); ++k)
      for (int e = 0; e < s.cell_count[k]; ++e) {
        cell[s.cell_first[k] + e] = static_cast<int64_t>(s.cell_id[k]);
        type[s.cell_first[k] + e] = s.cell_type[k];
      }
    f.write("/elements/cell", {n}, cell);
    f.write("/elements/type", {n}, type);
    f.write("/cells/id", {c}, std::vector<int64_t>(s.cell_id.begin(), s.cell_id.end()));
    f.write("/cells/type", {c}, std::vector<int64_t>(s.cell_type.begin(), s.cell_type.end()));
    f.write("/cells/count", {c}, std::vector<int64_t>(s.cell_count.begin(), s.cell_count.end()));
    for (const auto& [name, field] : s.cell_fields) f.write("/cells/fields/" + name, {c}, field);
    f.write_attr("step", s.step);
    f.write_attr("time", s.time);
    f.write_attr("format", std::string("semlb-state-v1"));
    for (const auto& [k, v] : attributes) f.write_attr(k, v);
  }
  std::filesystem::rename(tmp, path);
}

State read_state(const std::string& path) {
  const auto f = h5::File::open_read(path);
  std::vector<hsize_t> dims;
  State s;
  s.position = f.read("/elements/position", dims);
  if (dims.size() != 2 || dims[1] != 3) throw InputError(path + ": dataset /elements/position must be n x 3");
  const auto ids = f.read_ints("/cells/id", dims);
  const auto types = f.read_ints("/cells/type", dims);
  const auto counts = f.read_ints("/cells/count", dims);
  if (types.size() != ids.size() || counts.size() != ids.size())
    throw InputError(path + ": datasets /cells/id, /cells/type and /cells/count differ in length");
  long total = 0;
  for (size_t c = 0; c < ids.size(); ++c) {
    if (types[c] < 0 || types[c] >= kCellTypes) throw InputError(path + ": dataset /cells/type: value " + std::to_string(types[c]) + " at " + std::to_string(c) + " is not a type");
    if (counts[c] < 1 || counts[c] >= kMaxSlots) throw InputError(path + ": dataset /cells/count: value at " + std::to_string(c) + " outside 1.." + std::to_string(kMaxSlots - 1));
    total += counts[c];
  }
  if (total * 3 != static_cast<long>(s.position.size()))
    throw InputError(path + ": dataset /cells/count sums to " + std::to_string(total) + " elements but /elements/position has " + std::to_string(s.position.size() / 3));
  for (double v : s.position)
    if (!std::isfinite(v)) throw InputError(path + ": dataset /elements/position holds a non-finite value");
  s.cell_id.assign(ids.begin(), ids.end());
  s.cell_type.assign(types.begin(), types.end());
  s.cell_count.assign(counts.begin(), counts.end());
  s.step = H5Aexists(f.id(), "step") > 0 ? f.read_int_attr("step") : 0;
  s.time = H5Aexists(f.id(), "time") > 0 ? f.read_real_attr("time") : 0.0;
  for (const char* name : {"growth.clock", "differentiation.age", "division.depth"})
    if (f.has(std::string("/cells/fields/") + name)) {
      s.cell_fields[name] = f.read(std::string("/cells/fields/") + name, dims);
      if (s.cell_fields[name].size() != ids.size()) throw InputError(path + ": dataset /cells/fields/" + name + " has the wrong length");
    }
  s.reindex();
  return s;
}

void write_xdmf(const std::string& path, const std::vector<Snapshot>& snapshots) {
  std::ostringstream x;
  x << "<?xml version=\"1.0\" ?>\n<Xdmf Version=\"3.0\">\n <Domain>\n  <Grid Name=\"tissue\" GridType=\"Collection\" CollectionType=\"Temporal\">\n";
  for (const auto& s : snapshots) {
    x << "   <Grid Name=\"step_" << s.step << "\" GridType=\"Uniform\">\n    <Time Value=\"" << s.time << "\"/>\n"
      << "    <Topology TopologyType=\"Polyvertex\" NumberOfElements=\"" << s.elements << "\" NodesPerElement=\"1\"/>\n"
      << "    <Geometry GeometryType=\"XYZ\">\n     <DataItem Dimensions=\"" << s.elements << " 3\" NumberType=\"Float\" Precision=\"8\" Format=\"HDF\">"
      << s.file << ":/elements/position</DataItem>\n    </Geometry>\n";
    for (const char* a : {"cell", "type"})
      x << "    <Attribute Name=\"" << a << "\" AttributeType=\"Scalar\" Center=\"Node\">\n     <DataItem Dimensions=\"" << s.elements
        << "\" NumberType=\"Int\" Precision=\"8\" Format=\"HDF\">" << s.file << ":/elements/" << a << "</DataItem>\n    </Attribute>\n";
    x << "   </Grid>\n";
  }
  x << "  </Grid>\n </Domain>\n</Xdmf>\n";
  write_file_atomically(path, x.str());
}

}  // namespace semlb::engine
