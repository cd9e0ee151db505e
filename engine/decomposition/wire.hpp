// The wire formats of the decomposed run: whole cells (migration, gather) and ghost bands (exchange),
// as byte buffers that MPI moves between ranks.
#pragma once
#include <cstring>
#include <vector>

#include "backends/backend.hpp"
#include "model/state.hpp"

namespace semlb::engine {

// Byte buffers for whole cells: id, type, count, per-cell fields (map order), positions.
class Writer {
 public:
  template <class T>
  void put(const T& v) {
    const char* p = reinterpret_cast<const char*>(&v);
    bytes.insert(bytes.end(), p, p + sizeof(T));
  }
  void put(const double* v, size_t n) {
    const char* p = reinterpret_cast<const char*>(v);
    bytes.insert(bytes.end(), p, p + n * sizeof(double));
  }
  std::vector<char> bytes;
};

class Reader {
 public:
  explicit Reader(const std::vector<char>& b) : b_(b) {}
  template <class T>
  T get() {
    T v;
    std::memcpy(&v, b_.data() + at_, sizeof(T));
    at_ += sizeof(T);
    return v;
  }
  // `n` values of type T appended to `to` (one copy).
  template <class T>
  void get(std::vector<T>& to, size_t n) {
    const size_t at = to.size();
    to.resize(at + n);
    std::memcpy(to.data() + at, b_.data() + at_, n * sizeof(T));
    at_ += n * sizeof(T);
  }
  bool done() const { return at_ >= b_.size(); }

 private:
  const std::vector<char>& b_;
  size_t at_ = 0;
};

// One cell (id, type, count, per-cell fields in map order, positions) appended to `w`.
void pack_cell(Writer& w, const State& s, long c);
// Appends the cells in `bytes` to `s`; call s.reindex() afterwards.
void unpack_cells(const std::vector<char>& bytes, State& s);
// A ghost band on the wire: count, positions, keys, info.
std::vector<char> pack_band(const Ghosts& g);
void unpack_band(const std::vector<char>& bytes, Ghosts& g);  // appends

}  // namespace semlb::engine
