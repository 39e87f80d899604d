#pragma once
// The fixture of the service tests: `hlodr serve` in-process on an ephemeral loopback port over
// a small city built once, and HTTP clients whose answers a test can dereference safely (a
// request that got no answer fails the test instead of crashing it).
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <future>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>
#include <httplib.h>
#include <nlohmann/json.hpp>

#include "../gl/CachedStore.h"
#include "hlod/builder/HlodBuilder.h"
#include "hlod/city/City.h"
#include "hlod/import/Import.h"
#include "service/Server.h"

namespace svctest {

namespace fs = std::filesystem;
using nlohmann::json;

// A folder of this process's own in the temporary folder.
inline fs::path processDir(const std::string& kind) {
  return fs::temp_directory_path() / ("hlodr_server_" + kind + "_" + std::to_string(::getpid()));
}

inline fs::path dataDir() {
  static const fs::path dir = processDir("test");
  return dir;
}

// A jobs folder of the running test's own (a server restarted on it finds its jobs again).
inline fs::path jobsFolder() {
  return dataDir() /
         ("jobs_" + std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
}

inline fs::path webDir() {
  static const fs::path dir = processDir("web");
  return dir;
}

// A small city (2 blocks) built once for all tests.
inline void makeScene() {
  static bool made = false;
  if (made) return;
  made = true;
  fs::remove_all(dataDir());
  fs::create_directories(dataDir());
  // Built once for all the test processes (CachedStore.h), copied: tests write beside it.
  const fs::path built = gltest::cachedStore("city", [](const fs::path& dir) {
    hlod::CityOptions c;
    c.blocks = 2;
    c.textureSize = 128;
    return hlod::writeCity(dir / "src", c, {}).ok() &&
           hlod::buildStoreFromCity(dir / "src", dir / "city.hlod", hlod::BuildOptions{}, {}).ok();
  });
  ASSERT_FALSE(built.empty()) << "the test city did not build";
  fs::copy(built / "city.hlod", dataDir() / "city.hlod", fs::copy_options::recursive);
  // Not a store: a folder the scene scan must ignore, and a broken store it must skip.
  fs::create_directories(dataDir() / "notes.hlod");
  fs::create_directories(dataDir() / "broken.hlod");
  std::ofstream(dataDir() / "broken.hlod" / "skeleton.bin") << "garbage";
}

// An answer, or none: `->` on none fails the test (with httplib's reason) and reads as a
// response of status -1 with an empty body, so the test goes on to fail its own checks.
class Reply {
 public:
  Reply(httplib::Result r, std::string what) : r_(std::move(r)), what_(std::move(what)) {}
  explicit operator bool() const { return bool(r_); }
  const httplib::Response* operator->() const {
    if (r_) return &r_.value();
    ADD_FAILURE() << what_ << ": no answer (" << httplib::to_string(r_.error()) << ")";
    static const httplib::Response none = [] {
      httplib::Response n;
      n.status = -1;
      return n;
    }();
    return &none;
  }
  const httplib::Response& operator*() const { return *operator->(); }

 private:
  httplib::Result r_;
  std::string what_;
};

// httplib::Client with Reply answers.
class TestClient {
 public:
  explicit TestClient(int port) : c_("127.0.0.1", port) { c_.set_read_timeout(120, 0); }
  Reply Get(const std::string& path) { return {c_.Get(path.c_str()), "GET " + path}; }
  Reply Get(const std::string& path, httplib::ContentReceiver receiver) {
    return {c_.Get(path.c_str(), std::move(receiver)), "GET " + path};
  }
  Reply Post(const std::string& path, const std::string& body, const std::string& type) {
    return {c_.Post(path.c_str(), body, type.c_str()), "POST " + path};
  }
  Reply Delete(const std::string& path) { return {c_.Delete(path.c_str()), "DELETE " + path}; }
  httplib::Client& raw() { return c_; }

 private:
  httplib::Client c_;
};

class ServerTest : public ::testing::Test {
 protected:
  void start(service::ServerOptions o = {}) {
    makeScene();
    o.dataDir = dataDir();
    o.port = 0;
    o.workers = o.workers > 0 ? o.workers : 2;
    o.accessLog = false;
    if (o.jobsDir.empty())
      o.jobsDir =
          dataDir() /
          ("jobs_" + std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
    auto s = service::Server::create(o, [this](const std::string& line) {
      std::lock_guard lock(logMutex);
      log += line + "\n";
    });
    ASSERT_TRUE(s.ok()) << s.message();
    server = std::move(*s);
    auto p = server->bind();
    ASSERT_TRUE(p.ok()) << p.message();
    port = *p;
    thread = std::thread([this] { server->run(); });
  }
  // Starts with a page of its own (an index.html with the title hlodr) served at the root.
  void startWithPage(service::ServerOptions o = {}) {
    const fs::path web = webDir();
    fs::create_directories(web);
    std::ofstream(web / "index.html") << "<!doctype html><title>hlodr</title>";
    o.webDir = web;
    start(o);
  }
  void stop() {
    if (server) server->stop();
    if (thread.joinable()) thread.join();
    server.reset();
  }
  void TearDown() override { stop(); }
  TestClient client() const { return TestClient(port); }
  Reply post(const std::string& path, const json& body) const {
    return client().Post(path, body.dump(), "application/json");
  }
  static json parse(const Reply& r) { return json::parse(r->body, nullptr, false); }
  static std::string errorCode(const Reply& r) {
    const json j = parse(r);
    return j.is_object() && j.contains("error") ? j["error"]["code"].get<std::string>() : "";
  }
  static std::string errorMessage(const Reply& r) {
    const json j = parse(r);
    return j.is_object() && j.contains("error") ? j["error"]["message"].get<std::string>() : "";
  }
  std::string newSession(json extra = json::object()) {
    json body = {{"scene", "city"}, {"width", 160}, {"height", 120}};
    body.update(extra);
    auto r = post("/api/sessions", body);
    EXPECT_EQ(r->status, 201) << r->body;
    return r->status == 201 ? parse(r)["id"].get<std::string>() : "";
  }
  std::string newJob(json extra = json::object()) {
    json body = {{"scene", "city"}, {"path", {{"kind", "orbit"}}},
                 {"fps", 10},       {"frames", 12},
                 {"width", 160},    {"height", 120}};
    body.update(extra);
    auto r = post("/api/jobs", body);
    EXPECT_EQ(r->status, 202) << r->body;
    return r->status == 202 ? parse(r)["id"].get<std::string>() : "";
  }
  // Polls the job until it is finished (a job runs on its own thread: there is nothing to wait
  // on but its state).
  json waitForJob(const std::string& id, const std::string& collection = "jobs") {
    for (int i = 0; i < 1200; ++i) {
      auto r = client().Get("/api/" + collection + "/" + id);
      if (r && r->status == 200 && parse(r)["finished"].get<bool>()) return parse(r);
      std::this_thread::sleep_for(std::chrono::milliseconds(100));
    }
    ADD_FAILURE() << "job " << id << " did not finish";
    return {};
  }
  // Polls until the job has rendered more than n frames.
  void waitForFrames(const std::string& id, int n) {
    for (int i = 0; i < 1200; ++i) {
      const json j = parse(client().Get("/api/jobs/" + id));
      if (j.is_object() && j.value("framesDone", 0) > n) return;
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
    ADD_FAILURE() << "job " << id << " did not render " << n << " frames";
  }

  std::unique_ptr<service::Server> server;
  std::thread thread;
  int port = 0;
  std::mutex logMutex;
  std::string log;
};

inline bool isJpeg(const std::string& b) {
  return b.size() > 3 && (unsigned char)b[0] == 0xff && (unsigned char)b[1] == 0xd8;
}
inline bool isPng(const std::string& b) {
  return b.size() > 8 && b.compare(1, 3, "PNG") == 0;
}

}  // namespace svctest
