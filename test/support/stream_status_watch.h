#pragma once
// A rostest's view of a binaural_renderer's ~status: the latest StreamStatus, and waiting
// (spinning) until it says something. Header-only: only ROS tests include it.
#include <ros/ros.h>
#include <room_reverb/StreamStatus.h>

#include <functional>
#include <mutex>
#include <string>

namespace room_reverb::test {

class StreamStatusWatch {
 public:
  StreamStatusWatch(ros::NodeHandle& nh, const std::string& topic)
      : sub_(nh.subscribe(topic, 10, &StreamStatusWatch::onStatus, this)) {}

  room_reverb::StreamStatus latest() {
    std::lock_guard<std::mutex> lock(mutex_);
    return status_;
  }
  // True as soon as `done` holds for a status received, false after `timeout_s` of wall time.
  bool waitFor(const std::function<bool(const room_reverb::StreamStatus&)>& done, double timeout_s) {
    const ros::WallTime end = ros::WallTime::now() + ros::WallDuration(timeout_s);
    while (ros::WallTime::now() < end) {
      ros::spinOnce();
      {
        std::lock_guard<std::mutex> lock(mutex_);
        if (received_ && done(status_)) return true;
      }
      ros::WallDuration(0.01).sleep();
    }
    return false;
  }

 private:
  void onStatus(const room_reverb::StreamStatus::ConstPtr& m) {
    std::lock_guard<std::mutex> lock(mutex_);
    status_ = *m;
    received_ = true;
  }
  std::mutex mutex_;
  room_reverb::StreamStatus status_;
  bool received_ = false;
  ros::Subscriber sub_;
};

}  // namespace room_reverb::test
