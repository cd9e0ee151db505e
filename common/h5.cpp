// RAII HDF5 handles and typed dataset/attribute helpers; errors name the file and the object.
#include "h5.hpp"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <filesystem>

#include "errors.hpp"
#include "text_io.hpp"

namespace semlb::h5 {
namespace {

// HDF5 prints its own error stack unless told not to; we report errors ourselves. Nor does it flush at exit what a
// failed close left open (a file whose last writes met a full disk: File::write_atomically has removed it, and a
// second flush at exit would crash): every file of ours is closed by its owner.
struct SilenceHdf5 {
  SilenceHdf5() {
    H5dont_atexit();
    H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  }
};
const SilenceHdf5 silence;

// A failed HDF5 call on file `path`: "PATH: HDF5: WHAT failed", WHAT naming the object (std::runtime_error: the
// writers' and the library's errors).
void check(herr_t status, const std::string& path, const std::string& what) {
  if (status < 0) throw std::runtime_error(path + ": HDF5: " + what + " failed");
}
// A failed read of an object of an input file: InputError (exit 2) "PATH: OBJECT: HDF5 could not read it".
void check_read(herr_t status, const std::string& path, const std::string& object) {
  if (status < 0) throw InputError(path + ": " + object + ": HDF5 could not read it (a damaged or truncated file?)");
}

}  // namespace

Id::Id(hid_t id, Closer closer, const std::string& what) : id_(id), closer_(closer) {
  if (id < 0) throw InputError(what);
}

Id::~Id() {
  if (id_ >= 0) closer_(id_);
}

File File::open_read(const std::string& path) {
  if (!std::filesystem::exists(path)) throw InputError(path + ": no such file");
  return File(Id(H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose, path + ": not an HDF5 file"), path);
}

File File::open_write(const std::string& path) {
  if (!std::filesystem::exists(path)) throw InputError(path + ": no such file");
  return File(
      Id(H5Fopen(path.c_str(), H5F_ACC_RDWR, H5P_DEFAULT), H5Fclose, path + ": cannot open HDF5 file for writing"),
      path);
}

File File::create(const std::string& path) {
  return File(Id(H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT), H5Fclose,
                 path + ": cannot create HDF5 file"),
              path);
}

void File::write_atomically(const std::string& path, const std::function<void(File&)>& fill) {
  PendingFile pending(path);  // removed on every way out but the rename (and by a signal's cleanup)
  const std::string& tmp = pending.tmp();
  errno = 0;
  try {
    const hid_t id = H5Fcreate(tmp.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
    if (id < 0) throw std::runtime_error(path + ": cannot create " + tmp + ": " + std::strerror(errno));
    File f(Id(id, H5Fclose, path), path);
    fill(f);
    check(H5Fclose(f.id_.release()), path, "closing the file (its last writes)");
  } catch (const InputError&) {
    throw;  // the caller's refusal of its data, as it was
  } catch (const std::runtime_error& e) {
    const int err = errno;  // HDF5 does not say why a write failed; the system call's cause, when it is one of these
    const std::string what = e.what(), why = std::strerror(err);
    if ((err == ENOSPC || err == EIO || err == EDQUOT || err == EFBIG || err == EROFS) && !what.ends_with(why))
      throw std::runtime_error(what + ": " + why);  // once: a failed create has named it already
    throw;
  }
  pending.commit();
}

std::vector<std::string> File::list(const std::string& name) const {
  std::vector<std::string> out;
  if (!has(name)) return out;
  Id group(H5Gopen2(id(), name.c_str(), H5P_DEFAULT), H5Gclose, path_ + ": group " + name);
  H5G_info_t info;
  check_read(H5Gget_info(group.get(), &info), path_, "group " + name);
  for (hsize_t i = 0; i < info.nlinks; ++i) {
    const ssize_t n = H5Lget_name_by_idx(group.get(), ".", H5_INDEX_NAME, H5_ITER_INC, i, nullptr, 0, H5P_DEFAULT);
    check_read(n < 0 ? -1 : 0, path_, "group " + name);
    std::string link(static_cast<size_t>(n) + 1, '\0');
    check_read(
        H5Lget_name_by_idx(group.get(), ".", H5_INDEX_NAME, H5_ITER_INC, i, link.data(), link.size(), H5P_DEFAULT) < 0
            ? -1
            : 0,
        path_, "group " + name);
    link.resize(static_cast<size_t>(n));
    out.push_back(link);
  }
  return out;
}

bool File::has(const std::string& name) const {
  // Walk the path one link at a time: H5Lexists fails on a missing intermediate group.
  std::string prefix;
  size_t pos = 0;
  while (pos != std::string::npos) {
    const size_t next = name.find('/', pos + 1);
    prefix = name.substr(0, next);
    if (prefix != "/" && H5Lexists(id(), prefix.c_str(), H5P_DEFAULT) <= 0) return false;
    pos = next;
  }
  return true;
}

Id File::open_dataset(const std::string& name, H5T_class_t expected, std::vector<hsize_t>& dims) const {
  if (!has(name)) throw InputError(path_ + ": dataset " + name + " is missing");
  Id set(H5Dopen2(id(), name.c_str(), H5P_DEFAULT), H5Dclose, path_ + ": cannot open dataset " + name);
  Id space(H5Dget_space(set.get()), H5Sclose, path_ + ": no dataspace for " + name);
  const int rank = H5Sget_simple_extent_ndims(space.get());
  dims.assign(std::max(rank, 0), 0);
  if (rank < 0 || (rank > 0 && H5Sget_simple_extent_dims(space.get(), dims.data(), nullptr) < 0))
    check_read(-1, path_, "the shape of dataset " + name);
  Id type(H5Dget_type(set.get()), H5Tclose, path_ + ": no datatype for " + name);
  if (H5Tget_class(type.get()) != expected)
    throw InputError(path_ + ": dataset " + name + " is not " + (expected == H5T_FLOAT ? "floating-point" : "integer"));
  return set;
}

namespace {
hsize_t count_of(const std::vector<hsize_t>& dims) {
  hsize_t n = 1;
  for (auto d : dims) n *= d;
  return n;
}
}  // namespace

std::vector<double> File::read(const std::string& name, std::vector<hsize_t>& dims) const {
  Id set = open_dataset(name, H5T_FLOAT, dims);
  std::vector<double> data(count_of(dims));
  if (!data.empty())
    check_read(H5Dread(set.get(), H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, data.data()), path_,
               "dataset " + name);
  return data;
}

std::vector<int64_t> File::read_ints(const std::string& name, std::vector<hsize_t>& dims) const {
  Id set = open_dataset(name, H5T_INTEGER, dims);
  std::vector<int64_t> data(count_of(dims));
  if (!data.empty())
    check_read(H5Dread(set.get(), H5T_NATIVE_INT64, H5S_ALL, H5S_ALL, H5P_DEFAULT, data.data()), path_,
               "dataset " + name);
  return data;
}

void File::write_raw(const std::string& name, const std::vector<hsize_t>& dims, hid_t file_type, hid_t mem_type,
                     const void* data) {
  Id lcpl(H5Pcreate(H5P_LINK_CREATE), H5Pclose, path_ + ": H5Pcreate for " + name);
  check(H5Pset_create_intermediate_group(lcpl.get(), 1), path_, "intermediate groups of " + name);
  Id space(H5Screate_simple(static_cast<int>(dims.size()), dims.data(), nullptr), H5Sclose,
           path_ + ": dataspace " + name);
  Id dcpl(H5Pcreate(H5P_DATASET_CREATE), H5Pclose, path_ + ": H5Pcreate for " + name);
  if (deflate_ > 0 && !dims.empty() && count_of(dims) > 0) {  // chunks of whole rows, up to 2^20 values each
    std::vector<hsize_t> chunk = dims;
    const hsize_t row = count_of(dims) / dims[0];
    chunk[0] = std::max<hsize_t>(1, std::min<hsize_t>(dims[0], (hsize_t{1} << 20) / std::max<hsize_t>(row, 1)));
    check(H5Pset_chunk(dcpl.get(), static_cast<int>(chunk.size()), chunk.data()), path_, "chunk " + name);
    check(H5Pset_shuffle(dcpl.get()), path_, "shuffle " + name);
    check(H5Pset_deflate(dcpl.get(), static_cast<unsigned>(deflate_)), path_, "deflate " + name);
  }
  Id set(H5Dcreate2(id(), name.c_str(), file_type, space.get(), lcpl.get(), dcpl.get(), H5P_DEFAULT), H5Dclose,
         path_ + ": cannot create dataset " + name);
  if (count_of(dims) > 0)
    check(H5Dwrite(set.get(), mem_type, H5S_ALL, H5S_ALL, H5P_DEFAULT, data), path_, "write " + name);
}

void File::write(const std::string& name, const std::vector<hsize_t>& dims, const std::vector<double>& data) {
  write_raw(name, dims, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, data.data());
}

void File::write(const std::string& name, const std::vector<hsize_t>& dims, const std::vector<int64_t>& data) {
  write_raw(name, dims, H5T_STD_I64LE, H5T_NATIVE_INT64, data.data());
}

void File::write(const std::string& name, const std::vector<hsize_t>& dims, const std::vector<int32_t>& data) {
  write_raw(name, dims, H5T_STD_I32LE, H5T_NATIVE_INT32, data.data());
}

Id File::attr(const std::string& name) const {
  if (H5Aexists(id(), name.c_str()) <= 0) throw InputError(path_ + ": attribute '" + name + "' is missing");
  return Id(H5Aopen(id(), name.c_str(), H5P_DEFAULT), H5Aclose, path_ + ": cannot open attribute " + name);
}

// A text attribute however its writer stored it: fixed length (null-terminated, null- or space-padded) or variable
// length (h5py's default for a Python str), ASCII or UTF-8, one value (a scalar or a one-element array).
std::string File::read_text_attr(const std::string& name) const {
  Id a = attr(name);
  const std::string object = "attribute '" + name + "'";
  Id type(H5Aget_type(a.get()), H5Tclose, path_ + ": " + object + ": no datatype");
  Id space(H5Aget_space(a.get()), H5Sclose, path_ + ": " + object + ": no dataspace");
  if (H5Tget_class(type.get()) != H5T_STRING) throw InputError(path_ + ": " + object + " is not text");
  if (H5Sget_simple_extent_npoints(space.get()) != 1) throw InputError(path_ + ": " + object + " must be one string");
  // The memory type in the file's character set: HDF5 converts no string between ASCII and UTF-8.
  Id mem(H5Tcopy(H5T_C_S1), H5Tclose, path_ + ": " + object + ": string type");
  check(H5Tset_cset(mem.get(), H5Tget_cset(type.get())), path_, object + " character set");
  if (H5Tis_variable_str(type.get()) > 0) {
    check(H5Tset_size(mem.get(), H5T_VARIABLE), path_, object + " string size");
    char* raw = nullptr;
    check_read(H5Aread(a.get(), mem.get(), &raw), path_, object);
    std::string s = raw ? raw : "";
    H5free_memory(raw);
    return s;
  }
  const size_t size = H5Tget_size(type.get());
  if (size == 0) check_read(-1, path_, object);
  const H5T_str_t pad = H5Tget_strpad(type.get());
  check(H5Tset_size(mem.get(), size), path_, object + " string size");
  check(H5Tset_strpad(mem.get(), pad == H5T_STR_ERROR ? H5T_STR_NULLPAD : pad), path_, object + " padding");
  std::string s(size, '\0');
  check_read(H5Aread(a.get(), mem.get(), s.data()), path_, object);
  s = s.substr(0, s.find('\0'));
  if (pad == H5T_STR_SPACEPAD) s.erase(s.find_last_not_of(' ') + 1);
  return s;
}

namespace {
// A numeric attribute of the expected class holding one value (a float is not silently truncated to an
// integer, a list is not read as its first value).
void check_scalar(hid_t a, H5T_class_t expected, const std::string& path, const std::string& name) {
  Id type(H5Aget_type(a), H5Tclose, path + ": attribute '" + name + "': no datatype");
  Id space(H5Aget_space(a), H5Sclose, path + ": attribute '" + name + "': no dataspace");
  if (H5Tget_class(type.get()) != expected || H5Sget_simple_extent_npoints(space.get()) != 1)
    throw InputError(path + ": attribute '" + name + "' must be one " +
                     (expected == H5T_FLOAT ? "floating-point" : "integer") + " value");
}
}  // namespace

long File::read_int_attr(const std::string& name) const {
  long v = 0;
  Id a = attr(name);
  check_scalar(a.get(), H5T_INTEGER, path_, name);
  check_read(H5Aread(a.get(), H5T_NATIVE_LONG, &v), path_, "attribute '" + name + "'");
  return v;
}

double File::read_real_attr(const std::string& name) const {
  double v = 0;
  Id a = attr(name);
  check_scalar(a.get(), H5T_FLOAT, path_, name);
  check_read(H5Aread(a.get(), H5T_NATIVE_DOUBLE, &v), path_, "attribute '" + name + "'");
  if (!std::isfinite(v)) throw InputError(path_ + ": attribute '" + name + "' is not finite");
  return v;
}

namespace {
void write_scalar_attr(hid_t file, const std::string& path, const std::string& name, hid_t file_type, hid_t mem_type,
                       const void* value) {
  Id space(H5Screate(H5S_SCALAR), H5Sclose, path + ": scalar dataspace for attribute " + name);
  Id a(H5Acreate2(file, name.c_str(), file_type, space.get(), H5P_DEFAULT, H5P_DEFAULT), H5Aclose,
       path + ": cannot create attribute " + name);
  check(H5Awrite(a.get(), mem_type, value), path, "write attribute " + name);
}
}  // namespace

void File::write_attr(const std::string& name, const std::string& value) {
  Id type(H5Tcopy(H5T_C_S1), H5Tclose, path_ + ": string type for attribute " + name);
  check(H5Tset_size(type.get(), value.size() + 1), path_, "string size of attribute " + name);
  write_scalar_attr(id(), path_, name, type.get(), type.get(), value.c_str());
}

void File::write_attr(const std::string& name, long value) {
  write_scalar_attr(id(), path_, name, H5T_STD_I64LE, H5T_NATIVE_LONG, &value);
}

void File::write_attr(const std::string& name, double value) {
  write_scalar_attr(id(), path_, name, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, &value);
}

}  // namespace semlb::h5
