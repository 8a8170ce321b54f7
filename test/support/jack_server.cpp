#include "jack_server.h"

#include <gtest/gtest.h>
#include <jack/jack.h>
#include <fcntl.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <thread>

#include "test_files.h"

namespace room_reverb::test {
namespace {

void quiet(const char*) {}

jack_client_t* openClient(const std::string& server, const std::string& name) {
  jack_set_error_function(quiet);
  jack_set_info_function(quiet);
  jack_status_t status{};
  return jack_client_open(name.c_str(), static_cast<jack_options_t>(JackNoStartServer | JackServerName), &status,
                          server.c_str());
}

}  // namespace

DummyJackServer::DummyJackServer(double rate_hz, std::size_t period_frames, const std::string& name)
    : name_(name.empty() ? "room_reverb_test_" + std::to_string(::getpid()) : name) {
  const std::string log = tempPath("jackd_" + name_ + ".log").string();
  const std::string rate = std::to_string(static_cast<long>(rate_hz));
  const std::string period = std::to_string(period_frames);
  std::vector<std::string> args = {"jackd", "--port-max", "32", "-n", name_, "-d", "dummy", "-r", rate, "-p", period};
  std::vector<char*> argv;
  for (auto& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  ::setenv("JACK_NO_AUDIO_RESERVATION", "1", 1);
  pid_ = fork();
  if (pid_ == 0) {
    // The server stops with the test process, even when a failed test kills that. SIGTERM,
    // not SIGKILL: a killed jackd leaves its entry in JACK's shared registry, which holds
    // only a few servers, and later servers are refused.
    prctl(PR_SET_PDEATHSIG, SIGTERM);
    const int fd = open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    if (fd >= 0) {
      dup2(fd, 1);
      dup2(fd, 2);
    }
    execvp("jackd", argv.data());
    _exit(127);
  }
  if (pid_ < 0) {
    ADD_FAILURE() << "could not fork for jackd";
    return;
  }
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(10);
  while (std::chrono::steady_clock::now() < deadline) {
    if (waitpid(pid_, nullptr, WNOHANG) == pid_) {  // jackd gave up (not installed, or refused)
      pid_ = -1;
      break;
    }
    if (jack_client_t* probe = openClient(name_, "probe")) {
      jack_client_close(probe);
      ok_ = true;
      return;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  std::ifstream in(log);
  std::stringstream text;
  text << in.rdbuf();
  ADD_FAILURE() << "the dummy JACK server " << name_ << " did not come up (jackd stopped, or 10 s passed):\n" << text.str();
}

DummyJackServer::~DummyJackServer() {
  stop();
  // A client still connected when its server stops leaves its semaphore behind.
  std::error_code ec;
  for (const auto& entry : std::filesystem::directory_iterator("/dev/shm", ec)) {
    const std::string file = entry.path().filename().string();
    if (file.rfind("jack_sem.", 0) == 0 && file.find("_" + name_ + "_") != std::string::npos) {
      std::filesystem::remove(entry.path(), ec);
    }
  }
}

void DummyJackServer::stop() {
  if (pid_ <= 0) return;
  ::kill(pid_, SIGTERM);
  for (int i = 0; i < 250; ++i) {
    if (waitpid(pid_, nullptr, WNOHANG) == pid_) {
      pid_ = -1;
      return;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  ::kill(pid_, SIGKILL);  // hung: its registry entry is lost
  waitpid(pid_, nullptr, 0);
  pid_ = -1;
}

JackRecorder::JackRecorder(const std::string& server_name, const std::string& client_name, std::size_t capacity_frames) {
  samples_[0].assign(capacity_frames, 0.0f);
  samples_[1].assign(capacity_frames, 0.0f);
  auto* client = openClient(server_name, client_name);
  if (client == nullptr) return;
  const char* names[2] = {"in_left", "in_right"};
  for (int c = 0; c < 2; ++c) ports_[c] = jack_port_register(client, names[c], JACK_DEFAULT_AUDIO_TYPE, JackPortIsInput, 0);
  jack_set_process_callback(client, &JackRecorder::process, this);
  jack_set_xrun_callback(client, &JackRecorder::onXrun, this);
  if (jack_activate(client) != 0) {
    jack_client_close(client);
    return;
  }
  client_ = client;
}

JackRecorder::~JackRecorder() {
  if (client_ != nullptr) {
    jack_deactivate(static_cast<jack_client_t*>(client_));
    jack_client_close(static_cast<jack_client_t*>(client_));
  }
}

int JackRecorder::process(unsigned frames, void* self) {
  auto* me = static_cast<JackRecorder*>(self);
  if (!me->recording_.load()) return 0;
  const std::size_t at = me->recorded_.load();
  const std::size_t keep = std::min<std::size_t>(frames, me->samples_[0].size() - at);
  for (int c = 0; c < 2; ++c) {
    const auto* in = static_cast<const float*>(jack_port_get_buffer(static_cast<jack_port_t*>(me->ports_[c]), frames));
    std::copy(in, in + keep, me->samples_[c].begin() + static_cast<std::ptrdiff_t>(at));
  }
  me->recorded_.store(at + keep);
  return 0;
}

int JackRecorder::onXrun(void* self) {
  auto* me = static_cast<JackRecorder*>(self);
  if (me->recording_.load()) me->xruns_.fetch_add(1);
  return 0;
}

bool JackRecorder::connectFrom(const std::string& source_port, int channel) {
  if (client_ == nullptr) return false;
  auto* client = static_cast<jack_client_t*>(client_);
  return jack_connect(client, source_port.c_str(), jack_port_name(static_cast<jack_port_t*>(ports_[channel]))) == 0;
}

std::vector<float> JackRecorder::channel(int c) const {
  const std::size_t n = recorded_.load();
  return std::vector<float>(samples_[c].begin(), samples_[c].begin() + static_cast<std::ptrdiff_t>(n));
}

std::vector<std::string> JackRecorder::connectionsOf(const std::string& port) const {
  std::vector<std::string> names;
  if (client_ == nullptr) return names;
  auto* client = static_cast<jack_client_t*>(client_);
  jack_port_t* p = jack_port_by_name(client, port.c_str());
  if (p == nullptr) return names;
  if (const char** connections = jack_port_get_all_connections(client, p)) {
    for (int i = 0; connections[i] != nullptr; ++i) names.emplace_back(connections[i]);
    jack_free(connections);
  }
  return names;
}

long findExact(const std::vector<float>& haystack, const std::vector<float>& needle) {
  for (std::size_t start = 0; start + needle.size() <= haystack.size(); ++start) {
    if (std::equal(needle.begin(), needle.end(), haystack.begin() + static_cast<std::ptrdiff_t>(start))) {
      return static_cast<long>(start);
    }
  }
  return -1;
}

}  // namespace room_reverb::test
