// Minimal RAII layer over the HDF5 C API: handles close themselves, every return code is checked.
#pragma once
#include <hdf5.h>

#include <cstdint>
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

 private:
  hid_t id_;
  Closer closer_;
};

class File {
 public:
  static File open_read(const std::string& path);  // throws InputError naming the path
  static File create(const std::string& path);     // truncates
  // A file in memory only (HDF5's core driver, no backing store): nothing touches the disk; image() is its bytes.
  // `name` is for messages. Writers save the image with write_file_atomically, so a full disk is one write
  // error of ours, and HDF5 never holds a half-written file open.
  static File create_in_memory(const std::string& name);
  std::string image() const;                        // the whole file as bytes (flushes first)
  static File open_write(const std::string& path);  // an existing file, read-write (tests, tools)
  const std::string& path() const { return path_; }
  hid_t id() const { return id_.get(); }

  bool has(const std::string& name) const;
  // Names of the links in group `name` (empty if the group does not exist), in name order.
  std::vector<std::string> list(const std::string& name) const;
  // Reads a dataset of any floating type as doubles; dims receives its shape. Missing -> InputError.
  std::vector<double> read(const std::string& name, std::vector<hsize_t>& dims) const;
  void write(const std::string& name, const std::vector<hsize_t>& dims, const std::vector<double>& data);
  // Integer datasets (stored as int64); reading refuses a floating-point dataset.
  std::vector<int64_t> read_ints(const std::string& name, std::vector<hsize_t>& dims) const;
  void write(const std::string& name, const std::vector<hsize_t>& dims, const std::vector<int64_t>& data);
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
