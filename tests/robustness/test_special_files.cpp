// Issue 18, "nothing hangs": every reader opens only a regular file of at most its documented size
// (files/input_file.hpp). A directory, /dev/zero, /dev/urandom, a FIFO and an oversized file named as any input are
// refused at once with an InputError naming the file and what it is; before, /dev/zero or a FIFO hung a reader and a
// directory gave "empty scene" or "missing header". A hang here hits the ctest TIMEOUT.
#include "robustness_support.hpp"

#include "geartopo/core/input_error.hpp"
#include "geartopo/files/input_file.hpp"
#include "geartopo/measurement/any_measurement.hpp"
#include "geartopo/grinding/topology_csv.hpp"
#include "geartopo/machine/error_table.hpp"
#include "geartopo/scene/scene.hpp"
#include "geartopo/surfaces/point_cloud.hpp"

#include <gtest/gtest.h>

#include <fstream>
#include <functional>
#include <sys/stat.h>

using namespace geartopo;
using namespace geartopo::robustness;
namespace fs = std::filesystem;

namespace {

struct Reader {
  std::string name;
  std::function<void(const fs::path&)> read;
  std::uintmax_t max_bytes;
};

std::vector<Reader> readers() {
  const auto& setup = default_scene().setup;
  return {
      {"scene::load_scene", [](const fs::path& p) { (void)scene::load_scene(p); }, input::kMaxSceneBytes},
      {"machine::load_error_tables", [](const fs::path& p) { (void)machine::load_error_tables(p); }, input::kMaxErrorTableBytes},
      {"grinding::read_topology_csv", [](const fs::path& p) { (void)grinding::read_topology_csv(p, 35); }, input::kMaxMeasurementBytes},
      {"grinding::read_traces_csv", [](const fs::path& p) { (void)grinding::read_traces_csv(p, 35); }, input::kMaxMeasurementBytes},
      {"surfaces::read_point_cloud", [](const fs::path& p) { (void)surfaces::read_point_cloud(p); }, input::kMaxMeasurementBytes},
      {"measurement::read_any_measurement", [&setup](const fs::path& p) { (void)measurement::read_any_measurement(p.string(), setup); },
       input::kMaxMeasurementBytes},
  };
}

// The reader's InputError message for `file`; fails the test on anything else.
std::string refusal(const Reader& r, const fs::path& file) {
  try {
    r.read(file);
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), file.string()) << r.name;
    return e.what();
  } catch (const std::exception& e) {
    ADD_FAILURE() << r.name << " on " << file << ": not an InputError: " << e.what();
    return {};
  }
  ADD_FAILURE() << r.name << " accepted " << file;
  return {};
}

} // namespace

TEST(SpecialFiles, ADirectoryIsRefusedByName) {
  const auto dir = temp_path("a_directory");
  fs::create_directories(dir);
  for (const auto& r : readers()) {
    const auto msg = refusal(r, dir);
    EXPECT_NE(msg.find("is a directory, not a"), std::string::npos) << r.name << ": " << msg;
  }
  fs::remove_all(dir);
}

TEST(SpecialFiles, DevicesAreRefusedWithoutReading) {
  for (const fs::path dev : {"/dev/zero", "/dev/urandom", "/dev/null"}) {
    if (!fs::exists(dev)) continue;
    for (const auto& r : readers()) {
      const auto msg = refusal(r, dev);
      EXPECT_NE(msg.find("is a device, not a regular"), std::string::npos) << r.name << ": " << msg;
    }
  }
}

TEST(SpecialFiles, AFifoIsRefusedWithoutOpeningIt) {
  const auto fifo = temp_path("a_fifo");
  fs::remove(fifo);
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  // Opening a FIFO without a writer blocks: a reader that opened it would hang here (ctest TIMEOUT).
  for (const auto& r : readers()) {
    const auto msg = refusal(r, fifo);
    EXPECT_NE(msg.find("is a FIFO"), std::string::npos) << r.name << ": " << msg;
  }
  fs::remove(fifo);
}

TEST(SpecialFiles, AMissingFileIsNamed) {
  const auto missing = temp_path("does_not_exist.csv");
  for (const auto& r : readers()) {
    const auto msg = refusal(r, missing);
    EXPECT_NE(msg.find("does not exist"), std::string::npos) << r.name << ": " << msg;
  }
}

// A sparse file one byte over each bound: refused by its size before a byte is read (the 2 GiB measurement bound
// included, which costs no disk space as a hole).
TEST(SpecialFiles, AFileOverItsSizeBoundIsRefusedBeforeReading) {
  const auto big = temp_path("oversized.csv");
  for (const auto& r : readers()) {
    { std::ofstream(big) << "tooth"; }
    fs::resize_file(big, r.max_bytes + 1);
    const auto msg = refusal(r, big);
    EXPECT_NE(msg.find("more than the " + std::to_string(r.max_bytes) + " bytes"), std::string::npos)
        << r.name << ": " << msg;
    // At the bound itself the size check passes (the content is then refused as whatever it is, not for its size).
    fs::resize_file(big, std::min<std::uintmax_t>(r.max_bytes, 64));
    const auto at = refusal(r, big);
    EXPECT_EQ(at.find("bytes a"), std::string::npos) << r.name << ": " << at;
  }
  fs::remove(big);
}

TEST(SpecialFiles, AnEmptyNameIsRefused) {
  EXPECT_THROW(input::check_regular_file("", input::kMaxSceneBytes, "scene file"), InputError);
}
