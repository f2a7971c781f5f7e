#include <gtest/gtest.h>

#include "core/common/error.h"
#include "importers/mapping.h"
#include "test_support.h"

using namespace roverlab;
using roverlab::test::TempDir;
using roverlab::test::write_text;

TEST(Mapping, ShippedPathfinderMappingLoads) {
  const std::vector<std::filesystem::path> folders{std::string(ROVERLAB_RESOURCES_DIR) + "/mappings"};
  const io::Mapping m = io::load_mapping(io::find_mapping("wvu_pathfinder", folders));
  EXPECT_EQ(m.name, "wvu_pathfinder");
  ASSERT_GE(m.streams.size(), 2u);
  EXPECT_EQ(m.streams[0].name, "imu");
  EXPECT_EQ(m.streams[0].time_variable, "tTimu");
  EXPECT_EQ(m.streams[1].channels[0].scale, -1.0);  // left wheels count negative forward
  EXPECT_NE(std::find(io::list_mappings(folders).begin(), io::list_mappings(folders).end(), "wvu_pathfinder"),
            io::list_mappings(folders).end());
  EXPECT_THROW(io::find_mapping("no_such_rover", folders), InputError);
  EXPECT_THROW(io::find_mapping("/nowhere/x.json", folders), InputError);
}

TEST(Mapping, RejectsMalformedMappingsNamingTheFile) {
  TempDir dir;
  const std::string head = R"({"format": "roverlab-mapping", "version": 1, "name": "m", "streams": [)";
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"{ not json", "not valid JSON"},
      {R"({"format": "other", "version": 1})", "not a RoverLab mapping"},
      {head + "]}", "non-empty"},
      {head + R"({"name": "imu", "time": {"variable": "t", "unit": "fortnight"}, "channels": []}]})",
       "unknown unit 'fortnight'"},
      {head +
           R"({"name": "imu", "time": {"variable": "t"}, "channels": [{"name": "x", "variable": "X", "unit": "parsec"}]}]})",
       "unknown unit 'parsec'"},
      {head + R"({"name": "imu", "time": {"variable": "t", "unit": "m"}, "channels": []}]})", "not a unit of time"},
      {head + R"({"name": "imu", "time": {"variable": "t"}, "channels": [{"name": "x"}]}]})",
       "field 'streams[0].channels[0].variable': missing, expected a string"},
  };
  for (std::size_t k = 0; k < cases.size(); ++k) {
    const std::string path = dir.file("m" + std::to_string(k) + ".json");
    write_text(path, cases[k].first);
    try {
      io::load_mapping(path);
      ADD_FAILURE() << "accepted case " << k;
    } catch (const InputError& e) {
      EXPECT_EQ(e.file(), path);
      EXPECT_NE(std::string(e.what()).find(cases[k].second), std::string::npos) << "case " << k << ": " << e.what();
      EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos) << "case " << k;
    }
  }
}
