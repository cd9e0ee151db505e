// The HDF5 layer reads text attributes however a writer stored them (h5py's variable-length UTF-8 included) and
// names the file and the object in its errors.
#include <gtest/gtest.h>

#include "../run_command.hpp"

#include <unistd.h>

#include <filesystem>
#include <functional>
#include <vector>

#include "common/errors.hpp"
#include "common/h5.hpp"

using namespace semlb;

namespace {

// A file with one scalar string attribute `format` = `value` of the given kind, written with the C API as h5py
// (variable length, UTF-8) or numpy / other tools (fixed length, any padding and character set) write it.
std::string file_with_text(const std::string& name, const std::string& stored, bool variable, H5T_cset_t cset,
                           H5T_str_t pad) {
  const std::string path = test::fresh_dir("h5_text") + "/" + name + ".h5";
  h5::File f = h5::File::create(path);
  h5::Id type(H5Tcopy(H5T_C_S1), H5Tclose, "type");
  H5Tset_cset(type.get(), cset);
  H5Tset_size(type.get(), variable ? H5T_VARIABLE : stored.size());
  if (!variable) H5Tset_strpad(type.get(), pad);
  h5::Id space(H5Screate(H5S_SCALAR), H5Sclose, "space");
  h5::Id a(H5Acreate2(f.id(), "format", type.get(), space.get(), H5P_DEFAULT, H5P_DEFAULT), H5Aclose, "attribute");
  if (variable) {
    const char* p = stored.c_str();
    H5Awrite(a.get(), type.get(), &p);
  } else {
    H5Awrite(a.get(), type.get(), stored.data());
  }
  return path;
}

}  // namespace

TEST(H5, TextAttributesReadWhateverWayTheirWriterStoredThem) {
  const std::string want = "semlb-workload";
  struct Kind {
    const char* name;
    std::string stored;
    bool variable;
    H5T_cset_t cset;
    H5T_str_t pad;
  };
  const Kind kinds[] = {
      {"vlen_utf8", want, true, H5T_CSET_UTF8, H5T_STR_NULLTERM},  // h5py: f.attrs["format"] = "semlb-workload"
      {"vlen_ascii", want, true, H5T_CSET_ASCII, H5T_STR_NULLTERM},
      {"fixed_nullterm", want + std::string(1, '\0'), false, H5T_CSET_ASCII, H5T_STR_NULLTERM},  // semlb's own
      {"fixed_nullpad", want + std::string(3, '\0'), false, H5T_CSET_ASCII, H5T_STR_NULLPAD},    // numpy bytes_
      {"fixed_exact", want, false, H5T_CSET_ASCII, H5T_STR_NULLPAD},
      {"fixed_spacepad", want + "   ", false, H5T_CSET_ASCII, H5T_STR_SPACEPAD},  // Fortran style
      {"fixed_utf8", want + std::string(1, '\0'), false, H5T_CSET_UTF8, H5T_STR_NULLTERM},
  };
  for (const Kind& k : kinds) {
    const std::string path = file_with_text(k.name, k.stored, k.variable, k.cset, k.pad);
    EXPECT_EQ(h5::File::open_read(path).read_text_attr("format"), want) << k.name;
  }
}

TEST(H5, ErrorsNameTheFileAndTheObject) {
  const std::string path = file_with_text("named", "x", true, H5T_CSET_UTF8, H5T_STR_NULLTERM);
  {
    h5::File f = h5::File::open_write(path);
    f.write_attr("steps", 5L);
  }
  const h5::File f = h5::File::open_read(path);
  const auto message = [&](const std::function<void()>& read) -> std::string {
    try {
      read();
    } catch (const InputError& e) {
      return e.what();
    }
    return "no InputError";
  };
  EXPECT_EQ(message([&] { f.read_text_attr("steps"); }), path + ": attribute 'steps' is not text");
  EXPECT_EQ(message([&] { f.read_int_attr("format"); }), path + ": attribute 'format' must be one integer value");
  EXPECT_EQ(message([&] { f.read_text_attr("nope"); }), path + ": attribute 'nope' is missing");
}

// A file that cannot be written for want of space names the file and the cause once, and leaves nothing of its own
// behind, whether its create fails (a full tmpfs) or a later write (64 KiB free for 512 KiB of data).
TEST(H5, AFullDiskNamesTheFileAndItsCauseOnce) {
  if (::geteuid() != 0) GTEST_SKIP() << "needs root to mount a small tmpfs";
  const std::string mnt = test::fresh_dir("h5_full") + "/mnt";
  std::filesystem::create_directories(mnt);
  const std::vector<double> big(1 << 16, 1.0);  // 512 KiB
  for (const bool full : {true, false}) {
    SCOPED_TRACE(full ? "the create fails" : "a write fails");
    const auto m = test::run("mount -t tmpfs -o size=64k tmpfs " + mnt);
    if (m.rc != 0) GTEST_SKIP() << "cannot mount a tmpfs here: " << m.out;
    if (full) test::run("dd if=/dev/zero of=" + mnt + "/filler bs=4k count=100");  // stops when the tmpfs is full
    std::string message = "no error";
    try {
      h5::File::write_atomically(mnt + "/state.h5", [&](h5::File& f) { f.write("x", {big.size()}, big); });
    } catch (const std::runtime_error& e) {
      message = e.what();
    }
    const std::string why = "No space left on device";
    EXPECT_EQ(message.rfind(mnt + "/state.h5", 0), 0u) << message;
    EXPECT_NE(message.find(why), std::string::npos) << message;
    EXPECT_EQ(message.find(why), message.rfind(why)) << message;
    EXPECT_FALSE(std::filesystem::exists(mnt + "/state.h5")) << message;
    EXPECT_FALSE(std::filesystem::exists(mnt + "/state.h5.tmp")) << message;
    test::run("umount " + mnt);
  }
}
