// Minimal RAII layer over the HDF5 C API: handles close themselves, every return code is checked.
#pragma once
#include <hdf5.h>

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace semlb::h5 {

// One owned HDF5 identifier, closed with the matching H5?close on destruction.
class Id {
 public:
  using Closer = herr_t (*)(hid_t);
  Id(hid_t id, Closer closer, const std::string& what);  // throws if id < 0
  Id(Id&& o) noexcept : id_(o.id_), closer_(o.closer_) { o.id_ = H5I_INVALID_HID; }
  Id(const Id&) = delete;
  Id& operator=(const Id&) = delete;
  Id& operator=(Id&&) = delete;
  ~Id();
  hid_t get() const { return id_; }
  // Gives the identifier up (the caller closes it, checking the result).
  hid_t release() {
    const hid_t id = id_;
    id_ = H5I_INVALID_HID;
    return id;
  }

 private:
  hid_t id_;
  Closer closer_;
};

class File {
 public:
  static File open_read(const std::string& path);  // throws InputError naming the path
  static File create(const std::string& path);     // truncates
  // Writes PATH whole or not at all: FILL(file) writes into PATH.tmp (HDF5's default driver: each dataset goes from
  // the caller's buffer to the file, no copy of the file in memory), which is then closed (checked) and renamed over
  // PATH. Any error (a full disk, a throw in FILL) removes PATH.tmp, leaves PATH as it was and is rethrown; the
  // writer's errors are std::runtime_error naming PATH ("PATH: HDF5: write /elements/position failed").
  static void write_atomically(const std::string& path, const std::function<void(File&)>& fill);
  static File open_write(const std::string& path);  // an existing file, read-write (tests, tools)
  const std::string& path() const { return path_; }
  hid_t id() const { return id_.get(); }

  bool has(const std::string& name) const;
  // Names of the links in group `name` (empty if the group does not exist), in name order.
  std::vector<std::string> list(const std::string& name) const;
  // Reads a dataset of any floating type as doubles; dims receives its shape. Missing -> InputError.
  std::vector<double> read(const std::string& name, std::vector<hsize_t>& dims) const;
  void write(const std::string& name, const std::vector<hsize_t>& dims, const std::vector<double>& data);
  // Integer datasets, read as int64 whatever integer type they were stored as; reading refuses a floating-point
  // dataset. Written as int64, or as int32 from int32 data.
  std::vector<int64_t> read_ints(const std::string& name, std::vector<hsize_t>& dims) const;
  void write(const std::string& name, const std::vector<hsize_t>& dims, const std::vector<int64_t>& data);
  void write(const std::string& name, const std::vector<hsize_t>& dims, const std::vector<int32_t>& data);
  std::string read_text_attr(const std::string& name) const;  // attribute on the root group
  long read_int_attr(const std::string& name) const;
  double read_real_attr(const std::string& name) const;
  // Datasets written from now on are chunked, shuffled and deflate-compressed at `level` (1-9; 0: contiguous,
  // the default). Readers need nothing: HDF5 decompresses transparently.
  void set_deflate(int level) { deflate_ = level; }
  void write_attr(const std::string& name, const std::string& value);
  void write_attr(const std::string& name, long value);
  void write_attr(const std::string& name, double value);

 private:
  Id open_dataset(const std::string& name, H5T_class_t expected, std::vector<hsize_t>& dims) const;
  void write_raw(const std::string& name, const std::vector<hsize_t>& dims, hid_t file_type, hid_t mem_type,
                 const void* data);
  File(Id id, std::string path) : id_(std::move(id)), path_(std::move(path)) {}
  Id attr(const std::string& name) const;
  Id id_;
  std::string path_;
  int deflate_ = 0;
};

}  // namespace semlb::h5
