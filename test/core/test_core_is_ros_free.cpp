// The core library must build and run without ROS: no core source or public core header
// may include a ROS or message header (DESIGN.md). Debian installs ROS headers in
// /usr/include, so the compiler alone would not catch one; this test does.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <regex>
#include <string>
#include <vector>

namespace fs = std::filesystem;

namespace {

const std::regex kRosInclude(
    R"(^\s*#\s*include\s*[<"](ros/|sensor_msgs/|geometry_msgs/|std_msgs/|visualization_msgs/|)"
    R"(nav_msgs/|tf2_ros/|tf2_msgs/|pcl_conversions/|pcl_ros/|cv_bridge/|image_transport/|)"
    R"(nodelet/|rosbag/|dynamic_reconfigure/|room_reverb/[A-Z][A-Za-z]*\.h))");

std::vector<std::string> rosIncludesUnder(const fs::path& root, const fs::path& skip) {
  std::vector<std::string> hits;
  for (const auto& entry : fs::recursive_directory_iterator(root)) {
    if (!entry.is_regular_file()) continue;
    if (!skip.empty() && entry.path().string().rfind(skip.string(), 0) == 0) continue;
    std::ifstream in(entry.path());
    std::string line;
    int number = 0;
    while (std::getline(in, line)) {
      ++number;
      if (std::regex_search(line, kRosInclude)) {
        hits.push_back(entry.path().string() + ":" + std::to_string(number) + ": " + line);
      }
    }
  }
  return hits;
}

}  // namespace

TEST(CoreIsRosFree, CoreSourcesIncludeNoRosHeader) {
  const fs::path src = fs::path(ROOM_REVERB_SOURCE_DIR) / "src" / "core";
  ASSERT_TRUE(fs::exists(src));
  const auto hits = rosIncludesUnder(src, {});
  EXPECT_TRUE(hits.empty()) << hits.front();
}

TEST(CoreIsRosFree, CoreHeadersIncludeNoRosHeader) {
  const fs::path include = fs::path(ROOM_REVERB_SOURCE_DIR) / "include" / "room_reverb";
  ASSERT_TRUE(fs::exists(include));
  const auto hits = rosIncludesUnder(include, include / "ros");
  EXPECT_TRUE(hits.empty()) << hits.front();
}

TEST(CoreIsRosFree, PatternCatchesRosIncludes) {
  // The scan is only as good as its pattern: check it on lines it must and must not flag.
  EXPECT_TRUE(std::regex_search("#include <ros/ros.h>", kRosInclude));
  EXPECT_TRUE(std::regex_search("#include <sensor_msgs/Image.h>", kRosInclude));
  EXPECT_TRUE(std::regex_search("  #  include \"room_reverb/ImpulseResponse.h\"", kRosInclude));
  EXPECT_FALSE(std::regex_search("#include \"room_reverb/audio/fft.h\"", kRosInclude));
  EXPECT_FALSE(std::regex_search("#include <vector>", kRosInclude));
}
