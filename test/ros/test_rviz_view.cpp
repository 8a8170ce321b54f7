// rostest: rviz/room_reverb.rviz in rviz under Xvfb, on the sample bag replayed through
// replay.launch (test/ros/rviz_view.test). The test node starts its own Xvfb (a free display
// found by Xvfb itself, the size of the .rviz file's window) and rviz --fullscreen on it, so
// that the 3D view is the whole screen; it waits for the room model's latched markers (the
// room model is built from the cloud, so the cloud has been published by then), then takes
// screenshots (xwd | xwdtopnm) every two seconds until the view shows what it must or a
// deadline passes, and checks the last one against the room model's CUBE markers projected
// with the .rviz file's orbit camera:
//  - the 3D view is not just the background colour;
//  - every opaque room-model cuboid in view (the floor, the objects) covers its whole
//    visible area (no background pixel inside), in a colour of its material's hue. A cloud
//    alone cannot pass: seen from another point than the rig's it has holes (the rig's
//    blind spot, the objects' shadows);
//  - the point cloud is drawn: outside the cuboids the view is speckled with points, not
//    the flat translucent walls and grid that the markers alone give.
// On the sample bag: cuboids 0.0005 background at most, hues 0.97..1, speckle 0.93. With
// rviz on a wrong marker topic the cuboids show 0.2..0.4 background; on a wrong cloud topic
// the speckle is 0.02 (and the desk's hue fails: without the cloud's depth, rviz draws the
// translucent floor over the translucent objects that stand on it).
// The screenshot and a picture of the regions judged are kept (RecordProperty
// "screenshot", "regions"); ~rviz_config picks another .rviz file, ~screenshot_dir where
// the pictures go (default $ROS_HOME/test_results/room_reverb).
#include <fcntl.h>
#include <gtest/gtest.h>
#include <poll.h>
#include <ros/ros.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>
#include <visualization_msgs/MarkerArray.h>
#include <yaml-cpp/yaml.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <limits>
#include <mutex>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <sstream>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;

constexpr double kPi = 3.14159265358979323846;
// rviz's camera: Ogre's default vertical field of view (rviz 1.14 has no setting for it).
constexpr double kFovY = kPi / 4.0;

// ---------------------------------------------------------------------------------------
// What the .rviz file says about the view.
// ---------------------------------------------------------------------------------------

struct RvizView {
  std::string fixed_frame;
  cv::Vec3b background;  // BGR, as OpenCV reads images
  Eigen::Vector3d focal_point = Eigen::Vector3d::Zero();
  double distance = 0.0, yaw = 0.0, pitch = 0.0;
  cv::Size window{1200, 800};  // Window Geometry
};

RvizView loadRvizView(const std::string& path) {
  const YAML::Node root = YAML::LoadFile(path);
  const YAML::Node manager = root["Visualization Manager"];
  const YAML::Node options = manager["Global Options"];
  const YAML::Node current = manager["Views"]["Current"];
  if (current["Class"].as<std::string>() != "rviz/Orbit") throw std::runtime_error("the test knows rviz/Orbit views only");
  if (current["Target Frame"] && current["Target Frame"].as<std::string>() != options["Fixed Frame"].as<std::string>()) {
    throw std::runtime_error("the test expects the orbit view's target frame to be the fixed frame");
  }
  RvizView view;
  view.fixed_frame = options["Fixed Frame"].as<std::string>();
  int r = 48, g = 48, b = 48;  // rviz's default background
  if (options["Background Color"]) {
    std::string text = options["Background Color"].as<std::string>();
    std::replace(text.begin(), text.end(), ';', ' ');
    std::istringstream(text) >> r >> g >> b;
  }
  view.background = cv::Vec3b(static_cast<uchar>(b), static_cast<uchar>(g), static_cast<uchar>(r));
  view.focal_point = Eigen::Vector3d(current["Focal Point"]["X"].as<double>(), current["Focal Point"]["Y"].as<double>(),
                                     current["Focal Point"]["Z"].as<double>());
  view.distance = current["Distance"].as<double>();
  view.yaw = current["Yaw"].as<double>();
  view.pitch = current["Pitch"].as<double>();
  const YAML::Node window = root["Window Geometry"];
  if (window["Width"] && window["Height"]) view.window = cv::Size(window["Width"].as<int>(), window["Height"].as<int>());
  return view;
}

// rviz's orbit camera (OrbitViewController::updateCamera): on a sphere about the focal
// point, looking at it, z up; Ogre's perspective projection over the whole render panel.
struct Camera {
  Camera(const RvizView& v, int w, int h) : width(w), height(h) {
    eye = v.focal_point + v.distance * Eigen::Vector3d(std::cos(v.yaw) * std::cos(v.pitch),
                                                       std::sin(v.yaw) * std::cos(v.pitch), std::sin(v.pitch));
    forward = (v.focal_point - eye).normalized();
    right = forward.cross(Eigen::Vector3d::UnitZ()).normalized();
    up = right.cross(forward);
  }
  Eigen::Vector3d ray(int u, int v) const {
    const double t = std::tan(0.5 * kFovY);
    const double x = (2.0 * (u + 0.5) / width - 1.0) * t * width / height;
    const double y = (1.0 - 2.0 * (v + 0.5) / height) * t;
    return (forward + x * right + y * up).normalized();
  }
  int width, height;
  Eigen::Vector3d eye, forward, right, up;
};

// A CUBE marker in the fixed frame.
struct Cuboid {
  std::string name;  // ns/id
  Eigen::Vector3d centre, half_size;
  Eigen::Matrix3d rotation;  // box axes in the fixed frame
  cv::Vec3f color;           // RGB, 0..1
  float alpha = 1.0f;
};

// Distance along the ray to the box, or infinity.
double hitDistance(const Cuboid& box, const Eigen::Vector3d& origin, const Eigen::Vector3d& dir) {
  const Eigen::Vector3d o = box.rotation.transpose() * (origin - box.centre);
  const Eigen::Vector3d d = box.rotation.transpose() * dir;
  double t0 = 0.0, t1 = std::numeric_limits<double>::infinity();
  for (int k = 0; k < 3; ++k) {
    if (std::abs(d[k]) < 1e-12) {
      if (std::abs(o[k]) > box.half_size[k]) return std::numeric_limits<double>::infinity();
      continue;
    }
    double ta = (-box.half_size[k] - o[k]) / d[k], tb = (box.half_size[k] - o[k]) / d[k];
    if (ta > tb) std::swap(ta, tb);
    t0 = std::max(t0, ta);
    t1 = std::min(t1, tb);
    if (t0 > t1) return std::numeric_limits<double>::infinity();
  }
  return t0;
}

std::vector<Cuboid> cuboidsOf(const visualization_msgs::MarkerArray& array, const std::string& fixed_frame) {
  std::vector<Cuboid> boxes;
  for (const auto& m : array.markers) {
    if (m.action != visualization_msgs::Marker::ADD || m.type != visualization_msgs::Marker::CUBE) continue;
    if (m.header.frame_id != fixed_frame) continue;
    Cuboid box;
    box.name = m.ns + "/" + std::to_string(m.id);
    box.centre = Eigen::Vector3d(m.pose.position.x, m.pose.position.y, m.pose.position.z);
    box.half_size = 0.5 * Eigen::Vector3d(m.scale.x, m.scale.y, m.scale.z);
    box.rotation = Eigen::Quaterniond(m.pose.orientation.w, m.pose.orientation.x, m.pose.orientation.y,
                                      m.pose.orientation.z)
                       .normalized()
                       .toRotationMatrix();
    box.color = cv::Vec3f(m.color.r, m.color.g, m.color.b);
    box.alpha = m.color.a;
    boxes.push_back(box);
  }
  return boxes;
}

// ---------------------------------------------------------------------------------------
// The screenshot's analysis.
// ---------------------------------------------------------------------------------------

// Markers at least this opaque hide what is behind them (the floor 0.9, objects 0.85; the
// walls 0.35 and the ceiling 0.15 are see-through).
constexpr float kOpaqueAlpha = 0.8f;
// A pixel within this of the background colour (each channel) counts as background.
constexpr int kBackgroundTolerance = 10;
// A cuboid's area must be this big (pixels, after trimming its edges) to be judged.
constexpr int kMinCuboidArea = 1500;

struct CuboidCheck {
  std::string name;
  int area = 0;                   // pixels where it is the nearest opaque cuboid (edges trimmed)
  double background_fraction = 0;  // of those, pixels of the background colour
  double hue_agreement = 0;       // cosine between its chroma and its material's (1: same hue)
  bool hue_checked = false;       // false for greys, whose hue says nothing
};

struct ViewAnalysis {
  double non_background_fraction = 0;  // of the whole view
  std::vector<CuboidCheck> cuboids;
  double speckle_fraction = 0;  // of the view outside the opaque cuboids: pixels in a point texture
  int speckle_area = 0;
  cv::Mat regions;  // BGR picture of the regions judged, for the record
};

bool isBackground(const cv::Vec3b& p, const cv::Vec3b& bg) {
  for (int c = 0; c < 3; ++c) {
    if (std::abs(int(p[c]) - int(bg[c])) > kBackgroundTolerance) return false;
  }
  return true;
}

// Chroma (r, g, b) / (r + g + b) minus the neutral third: the direction of a colour's hue.
Eigen::Vector3d chroma(double r, double g, double b) {
  const double sum = std::max(r + g + b, 1e-9);
  return Eigen::Vector3d(r / sum - 1.0 / 3.0, g / sum - 1.0 / 3.0, b / sum - 1.0 / 3.0);
}

// panel: the render panel's size; the image is its top-left part (all of it in the test).
ViewAnalysis analyse(const cv::Mat& image, const RvizView& view, const std::vector<Cuboid>& boxes, cv::Size panel) {
  ViewAnalysis out;
  const Camera camera(view, panel.width, panel.height);
  const cv::Vec3b bg = view.background;

  int non_bg = 0;
  for (int v = 0; v < image.rows; ++v) {
    for (int u = 0; u < image.cols; ++u) non_bg += isBackground(image.at<cv::Vec3b>(v, u), bg) ? 0 : 1;
  }
  out.non_background_fraction = double(non_bg) / (image.rows * image.cols);

  // Which opaque cuboid each pixel sees first.
  std::vector<int> opaque;
  for (std::size_t i = 0; i < boxes.size(); ++i) {
    if (boxes[i].alpha >= kOpaqueAlpha) opaque.push_back(int(i));
  }
  cv::Mat owner(image.size(), CV_32S, cv::Scalar(-1));
  for (int v = 0; v < image.rows; ++v) {
    for (int u = 0; u < image.cols; ++u) {
      const Eigen::Vector3d dir = camera.ray(u, v);
      double nearest = std::numeric_limits<double>::infinity();
      for (int i : opaque) {
        const double t = hitDistance(boxes[std::size_t(i)], camera.eye, dir);
        if (t < nearest) {
          nearest = t;
          owner.at<int>(v, u) = i;
        }
      }
    }
  }

  out.regions = image.clone();
  const cv::Mat kernel = cv::getStructuringElement(cv::MORPH_RECT, cv::Size(3, 3));
  for (int i : opaque) {
    const Cuboid& box = boxes[std::size_t(i)];
    // Colours too close to the background (an opening, foam) cannot show coverage.
    const cv::Vec3f c = box.color * 255.0f;
    if (std::max({std::abs(c[0] - bg[2]), std::abs(c[1] - bg[1]), std::abs(c[2] - bg[0])}) < 40.0f) continue;
    cv::Mat mask = owner == i;
    cv::erode(mask, mask, kernel, cv::Point(-1, -1), 4);  // off the anti-aliased edges
    CuboidCheck check;
    check.name = box.name;
    check.area = cv::countNonZero(mask);
    if (check.area < kMinCuboidArea) continue;
    int bg_pixels = 0;
    std::vector<int> channel[3];
    for (int v = 0; v < image.rows; ++v) {
      for (int u = 0; u < image.cols; ++u) {
        if (!mask.at<uchar>(v, u)) continue;
        const cv::Vec3b p = image.at<cv::Vec3b>(v, u);
        if (isBackground(p, bg)) {
          ++bg_pixels;
          out.regions.at<cv::Vec3b>(v, u) = cv::Vec3b(255, 0, 255);
        }
        for (int k = 0; k < 3; ++k) channel[k].push_back(p[k]);
      }
    }
    check.background_fraction = double(bg_pixels) / check.area;
    double median[3];
    for (int k = 0; k < 3; ++k) {
      auto mid = channel[k].begin() + long(channel[k].size() / 2);
      std::nth_element(channel[k].begin(), mid, channel[k].end());
      median[k] = *mid;
    }
    // The material's hue; the rendering shades and blends it, which keeps its direction.
    const Eigen::Vector3d want = chroma(box.color[0], box.color[1], box.color[2]);
    const Eigen::Vector3d got = chroma(median[2], median[1], median[0]);
    check.hue_checked = want.norm() > 0.04;
    check.hue_agreement = got.norm() > 1e-6 ? want.dot(got) / (want.norm() * got.norm()) : 0.0;
    std::vector<std::vector<cv::Point>> outline;
    cv::findContours(mask, outline, cv::RETR_EXTERNAL, cv::CHAIN_APPROX_SIMPLE);
    cv::drawContours(out.regions, outline, -1, cv::Scalar(0, 255, 255), 1);
    out.cuboids.push_back(check);
  }

  // Outside the opaque cuboids (and off their edges): a cloud drawn as points leaves a
  // speckle of strong local contrast; translucent walls, the grid and labels do not.
  cv::Mat grey, hi, lo;
  cv::cvtColor(image, grey, cv::COLOR_BGR2GRAY);
  cv::dilate(grey, hi, kernel);
  cv::erode(grey, lo, kernel);
  cv::Mat outside = owner < 0;
  cv::erode(outside, outside, kernel, cv::Point(-1, -1), 4);
  int speckle = 0;
  for (int v = 0; v < image.rows; ++v) {
    for (int u = 0; u < image.cols; ++u) {
      if (!outside.at<uchar>(v, u)) continue;
      ++out.speckle_area;
      if (int(hi.at<uchar>(v, u)) - int(lo.at<uchar>(v, u)) >= 40) ++speckle;
    }
  }
  out.speckle_fraction = out.speckle_area > 0 ? double(speckle) / out.speckle_area : 0.0;
  return out;
}

// What the test asks of a screenshot (the numbers on the sample bag: the header comment).
constexpr double kMinNonBackground = 0.5;    // of the view
constexpr double kMaxCuboidBackground = 0.01;  // of a cuboid's area
constexpr double kMinHueAgreement = 0.8;
constexpr int kMinCuboidsJudged = 3;          // the floor and two objects at least
constexpr double kMinSpeckle = 0.25;          // of the view outside the cuboids

bool cuboidsDrawn(const ViewAnalysis& a) {
  if (int(a.cuboids.size()) < kMinCuboidsJudged) return false;
  for (const CuboidCheck& c : a.cuboids) {
    if (c.background_fraction > kMaxCuboidBackground) return false;
    if (c.hue_checked && c.hue_agreement < kMinHueAgreement) return false;
  }
  return true;
}

bool looksRight(const ViewAnalysis& a) {
  return a.non_background_fraction >= kMinNonBackground && cuboidsDrawn(a) && a.speckle_fraction >= kMinSpeckle;
}

// ---------------------------------------------------------------------------------------
// Xvfb and rviz: children of the test node, killed when it dies.
// ---------------------------------------------------------------------------------------

extern "C" char** environ;

pid_t spawn(const std::vector<std::string>& args, const std::vector<std::string>& extra_env, const std::string& log) {
  // Everything exec needs is made before fork: the node has threads running.
  std::vector<std::string> env_strings;
  for (char** e = environ; *e != nullptr; ++e) {
    const std::string entry(*e);
    const std::string key = entry.substr(0, entry.find('=') + 1);
    bool replaced = false;
    for (const std::string& x : extra_env) replaced = replaced || x.compare(0, key.size(), key) == 0;
    if (!replaced) env_strings.push_back(entry);
  }
  env_strings.insert(env_strings.end(), extra_env.begin(), extra_env.end());
  std::vector<char*> argv, envp;
  for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  for (const std::string& e : env_strings) envp.push_back(const_cast<char*>(e.c_str()));
  envp.push_back(nullptr);
  const pid_t parent = getpid();
  const pid_t pid = fork();
  if (pid != 0) return pid;
  prctl(PR_SET_PDEATHSIG, SIGKILL);
  if (getppid() != parent) _exit(1);
  const int fd = open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd >= 0) {
    dup2(fd, STDOUT_FILENO);
    dup2(fd, STDERR_FILENO);
  }
  execvpe(argv[0], argv.data(), envp.data());
  _exit(127);
}

bool running(pid_t pid) { return pid > 0 && waitpid(pid, nullptr, WNOHANG) == 0; }

void stop(pid_t& pid, int signal, double timeout_s) {
  if (pid <= 0) return;
  kill(pid, signal);
  const ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(timeout_s);
  while (ros::WallTime::now() < deadline) {
    if (waitpid(pid, nullptr, WNOHANG) != 0) {
      pid = -1;
      return;
    }
    ros::WallDuration(0.05).sleep();
  }
  kill(pid, SIGKILL);
  waitpid(pid, nullptr, 0);
  pid = -1;
}

// Xvfb on a free display it picks itself (-displayfd); returns ":N", or "" on failure.
std::string startXvfb(cv::Size size, const std::string& log, pid_t& pid) {
  int fds[2];
  if (pipe(fds) != 0) return "";
  pid = spawn({"Xvfb", "-displayfd", std::to_string(fds[1]), "-screen", "0",
               std::to_string(size.width) + "x" + std::to_string(size.height) + "x24", "-nolisten", "tcp", "-br"},
              {}, log);
  close(fds[1]);
  std::string number;
  pollfd p{fds[0], POLLIN, 0};
  const ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(20.0);
  while (ros::WallTime::now() < deadline) {
    if (poll(&p, 1, 100) <= 0) continue;
    char c = 0;
    if (read(fds[0], &c, 1) != 1 || c == '\n') break;
    number += c;
  }
  close(fds[0]);
  return number.empty() ? "" : ":" + number;
}

cv::Mat screenshot(const std::string& display, const fs::path& dir) {
  const std::string xwd = (dir / "screen.xwd").string(), ppm = (dir / "screen.ppm").string();
  const std::string command = "xwd -display " + display + " -root -silent -out '" + xwd + "' && xwdtopnm '" + xwd +
                              "' > '" + ppm + "' 2>/dev/null";
  if (std::system(command.c_str()) != 0) return cv::Mat();
  return cv::imread(ppm, cv::IMREAD_COLOR);
}

std::string tail(const std::string& path, std::size_t chars) {
  FILE* f = std::fopen(path.c_str(), "rb");
  if (f == nullptr) return "";
  std::string text;
  char buffer[4096];
  std::size_t n = 0;
  while ((n = std::fread(buffer, 1, sizeof buffer, f)) > 0) text.append(buffer, n);
  std::fclose(f);
  return text.size() > chars ? text.substr(text.size() - chars) : text;
}

// ---------------------------------------------------------------------------------------
// The run: Xvfb, rviz, the markers, the screenshots.
// ---------------------------------------------------------------------------------------

struct ViewRun {
  std::string error;  // why there is no screenshot to judge
  std::string screenshot_file, regions_file, rviz_log;
  RvizView view;
  std::vector<Cuboid> boxes;
  cv::Mat image;
  ViewAnalysis analysis;
  double markers_after_s = 0;  // wall seconds from the start
  double seconds = 0;          // to the screenshot judged
  int screenshots = 0;
};

fs::path resultsDir() {
  std::string dir;
  if (ros::NodeHandle("~").getParam("screenshot_dir", dir) && !dir.empty()) return dir;
  const char* ros_home = std::getenv("ROS_HOME");
  const char* home = std::getenv("HOME");
  const fs::path base = ros_home != nullptr ? fs::path(ros_home) : fs::path(home != nullptr ? home : "/tmp") / ".ros";
  return base / "test_results" / "room_reverb";
}

void execute(ViewRun& run) {
  const ros::WallTime start = ros::WallTime::now();
  ros::NodeHandle pnh("~");
  std::string config;
  pnh.param<std::string>("rviz_config", config, std::string(ROOM_REVERB_SOURCE_DIR) + "/rviz/room_reverb.rviz");
  double markers_timeout_s = 75.0, render_timeout_s = 30.0;
  pnh.param("markers_timeout_s", markers_timeout_s, markers_timeout_s);
  pnh.param("render_timeout_s", render_timeout_s, render_timeout_s);
  try {
    run.view = loadRvizView(config);
  } catch (const std::exception& e) {
    run.error = "cannot read the view from " + config + ": " + e.what();
    return;
  }

  const fs::path out_dir = resultsDir();
  fs::create_directories(out_dir);
  run.screenshot_file = (out_dir / "rviz_view.png").string();
  run.regions_file = (out_dir / "rviz_view_regions.png").string();
  run.rviz_log = (out_dir / "rviz_view_rviz.log").string();
  fs::remove(run.screenshot_file);
  fs::remove(run.regions_file);
  char scratch_template[] = "/tmp/room_reverb_rviz_view.XXXXXX";
  if (mkdtemp(scratch_template) == nullptr) {
    run.error = "mkdtemp failed";
    return;
  }
  const fs::path scratch(scratch_template);
  fs::create_directories(scratch / "home");

  std::mutex mutex;
  visualization_msgs::MarkerArray markers;
  bool have_markers = false;
  ros::NodeHandle nh;
  const ros::Subscriber sub = nh.subscribe<visualization_msgs::MarkerArray>(
      "/rig/room_model/markers", 1, [&](const visualization_msgs::MarkerArrayConstPtr& m) {
        std::lock_guard<std::mutex> lock(mutex);
        markers = *m;
        have_markers = true;
      });

  pid_t xvfb = -1, rviz = -1;
  const std::string display = startXvfb(run.view.window, (scratch / "xvfb.log").string(), xvfb);
  if (display.empty()) {
    run.error = "Xvfb did not start: " + tail((scratch / "xvfb.log").string(), 1000);
  } else {
    // Full screen hides the menus, tool bar and docks: the 3D view fills the window, which
    // is the screen's size (the .rviz file's Window Geometry). Its own HOME keeps rviz's
    // persistent settings out of the user's.
    rviz = spawn({"rviz", "-d", config, "--fullscreen"},
                 {"DISPLAY=" + display, "LIBGL_ALWAYS_SOFTWARE=1", "HOME=" + (scratch / "home").string(),
                  "XDG_RUNTIME_DIR=" + (scratch / "home").string()},
                 run.rviz_log);
    fs::permissions(scratch / "home", fs::perms::owner_all, fs::perm_options::replace);
  }

  auto seconds = [&] { return (ros::WallTime::now() - start).toSec(); };
  while (run.error.empty() && seconds() < markers_timeout_s) {
    {
      std::lock_guard<std::mutex> lock(mutex);
      if (have_markers) break;
    }
    if (!running(rviz)) run.error = "rviz exited: " + tail(run.rviz_log, 2000);
    ros::WallDuration(0.1).sleep();
  }
  if (run.error.empty()) {
    std::lock_guard<std::mutex> lock(mutex);
    if (!have_markers) run.error = "no room model markers on /rig/room_model/markers";
    run.boxes = cuboidsOf(markers, run.view.fixed_frame);
    run.markers_after_s = seconds();
  }
  // rviz draws the cloud (1.7 M points) and the markers a little after they arrive: look
  // every two seconds until the view is right, or the deadline.
  const double render_deadline = seconds() + render_timeout_s;
  while (run.error.empty()) {
    ros::WallDuration(2.0).sleep();
    if (!running(rviz)) {
      run.error = "rviz exited: " + tail(run.rviz_log, 2000);
      break;
    }
    cv::Mat shot = screenshot(display, scratch);
    ++run.screenshots;
    if (shot.empty()) {
      run.error = "the screenshot failed (xwd | xwdtopnm on " + display + ")";
      break;
    }
    run.image = shot;
    run.seconds = seconds();
    run.analysis = analyse(shot, run.view, run.boxes, shot.size());
    if (looksRight(run.analysis) || seconds() > render_deadline) break;
  }
  if (!run.image.empty()) {
    cv::imwrite(run.screenshot_file, run.image);
    cv::imwrite(run.regions_file, run.analysis.regions);
  }
  stop(rviz, SIGINT, 5.0);
  stop(xvfb, SIGTERM, 5.0);
  std::error_code ignored;
  fs::remove_all(scratch, ignored);
}

ViewRun& theRun() {
  static ViewRun run;
  static bool done = false;
  if (!done) {
    done = true;
    execute(run);
  }
  return run;
}

std::string describe(const ViewAnalysis& a) {
  std::ostringstream s;
  s.precision(3);
  s << "non-background " << a.non_background_fraction << ", speckle " << a.speckle_fraction << " of "
    << a.speckle_area << " px";
  for (const CuboidCheck& c : a.cuboids) {
    s << "; " << c.name << ": " << c.area << " px, background " << c.background_fraction << ", hue "
      << c.hue_agreement << (c.hue_checked ? "" : " (grey, not judged)");
  }
  return s.str();
}

TEST(RvizView, RvizShowsTheReplayedBagFullScreen) {
  const ViewRun& run = theRun();
  ::testing::Test::RecordProperty("screenshot", run.screenshot_file);
  ::testing::Test::RecordProperty("regions", run.regions_file);
  ::testing::Test::RecordProperty("rviz_log", run.rviz_log);
  ASSERT_TRUE(run.error.empty()) << run.error;
  ASSERT_FALSE(run.image.empty());
  ::testing::Test::RecordProperty("markers_after_s", std::to_string(run.markers_after_s));
  ::testing::Test::RecordProperty("screenshot_after_s", std::to_string(run.seconds));
  ::testing::Test::RecordProperty("screenshots", run.screenshots);
  ::testing::Test::RecordProperty("analysis", describe(run.analysis));
  EXPECT_EQ(run.image.cols, run.view.window.width);
  EXPECT_EQ(run.image.rows, run.view.window.height);
  // The window fills the screen: Xvfb's black root shows nowhere on its last row/column.
  int black = 0, edge = 0;
  const cv::Vec3b root(0, 0, 0);
  for (int u = 0; u < run.image.cols; ++u, ++edge) black += run.image.at<cv::Vec3b>(run.image.rows - 1, u) == root;
  for (int v = 0; v < run.image.rows; ++v, ++edge) black += run.image.at<cv::Vec3b>(v, run.image.cols - 1) == root;
  EXPECT_LT(black, edge / 4) << "rviz's window does not fill the screen; see " << run.screenshot_file;
}

TEST(RvizView, ViewIsNotJustTheBackground) {
  const ViewRun& run = theRun();
  ASSERT_FALSE(run.image.empty()) << run.error;
  ::testing::Test::RecordProperty("non_background_fraction", std::to_string(run.analysis.non_background_fraction));
  EXPECT_GE(run.analysis.non_background_fraction, kMinNonBackground) << run.screenshot_file;
}

TEST(RvizView, RoomModelCuboidsAreDrawnInTheirMaterialColours) {
  const ViewRun& run = theRun();
  ASSERT_FALSE(run.image.empty()) << run.error;
  const ViewAnalysis& a = run.analysis;
  ::testing::Test::RecordProperty("cuboids_judged", int(a.cuboids.size()));
  EXPECT_GE(int(a.cuboids.size()), kMinCuboidsJudged)
      << "too few room-model cuboids in view (" << run.boxes.size() << " CUBE markers)";
  double worst_background = 0, worst_hue = 1;
  for (const CuboidCheck& c : a.cuboids) {
    EXPECT_LE(c.background_fraction, kMaxCuboidBackground)
        << c.name << ": background shows inside it (magenta in " << run.regions_file << ")";
    if (c.hue_checked) {
      EXPECT_GE(c.hue_agreement, kMinHueAgreement) << c.name << ": not its material's colour";
    }
    worst_background = std::max(worst_background, c.background_fraction);
    if (c.hue_checked) worst_hue = std::min(worst_hue, c.hue_agreement);
  }
  ::testing::Test::RecordProperty("worst_cuboid_background_fraction", std::to_string(worst_background));
  ::testing::Test::RecordProperty("worst_cuboid_hue_agreement", std::to_string(worst_hue));
}

TEST(RvizView, PointCloudIsDrawn) {
  const ViewRun& run = theRun();
  ASSERT_FALSE(run.image.empty()) << run.error;
  ::testing::Test::RecordProperty("speckle_fraction", std::to_string(run.analysis.speckle_fraction));
  EXPECT_GE(run.analysis.speckle_fraction, kMinSpeckle)
      << "no point texture outside the cuboids (" << run.analysis.speckle_area << " px judged); "
      << run.screenshot_file;
}

}  // namespace

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_rviz_view");
  ros::AsyncSpinner spinner(1);
  spinner.start();
  return RUN_ALL_TESTS();
}
