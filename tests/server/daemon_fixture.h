// The test fixture of the daemon's HTTP tests: a real SQLite file in a temporary folder, a worker pool,
// the routes on 127.0.0.1 (any free port) and cpp-httplib's client.
#pragma once

#include <gtest/gtest.h>

#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <memory>
#include <string>
#include <thread>

#include <nlohmann/json.hpp>

#include "server/http_server.h"
#include "server/worker_pool.h"

// After the project headers: <resolv.h>, pulled in by httplib, defines a macro `_res` that breaks Eigen.
#include <httplib.h>

namespace granulab::server {

/// Every route group, as granulabd (server/main.cpp) mounts them.
inline void mount_every_route(HttpServer& server) {
  for (auto group : {mount_meta_routes, mount_job_routes, mount_sweep_routes, mount_picture_routes, mount_export_routes,
                     mount_web_routes, mount_worker_routes})
    server.mount(group);
}

class Daemon : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = std::filesystem::temp_directory_path() / ("granulab_http_" + std::to_string(::getpid()) + "_" +
                                                     ::testing::UnitTest::GetInstance()->current_test_info()->name());
    std::filesystem::create_directories(dir_);
    store_ = std::make_unique<JobStore>((dir_ / "jobs.db").string());
    pool_ = std::make_unique<WorkerPool>(*store_, 1, 1, 0.05);
    http_ = std::make_unique<HttpServer>(*store_, *pool_, HttpOptions{64 * 1024, 4, {}});
    mount_every_route(*http_);
    port_ = http_->bind("127.0.0.1", 0);
    ASSERT_GT(port_, 0);
    serving_ = std::thread([this] { http_->serve(); });
    client_ = std::make_unique<httplib::Client>("127.0.0.1", port_);
    for (int k = 0; k < 100 && !client_->Get("/v1/health"); ++k)
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  // A new HTTP front on the same store and pool, with other options (tokens, limits).
  void restart(const HttpOptions& options) {
    http_->stop();
    serving_.join();
    http_ = std::make_unique<HttpServer>(*store_, *pool_, options);
    mount_every_route(*http_);
    port_ = http_->bind("127.0.0.1", 0);
    ASSERT_GT(port_, 0);
    serving_ = std::thread([this] { http_->serve(); });
    client_ = std::make_unique<httplib::Client>("127.0.0.1", port_);
    for (int k = 0; k < 100 && !client_->Get("/v1/health"); ++k)
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  void TearDown() override {
    http_->stop();
    serving_.join();
    pool_->stop();
    client_.reset();
    http_.reset();
    pool_.reset();
    store_.reset();
    std::filesystem::remove_all(dir_);
  }

  nlohmann::json post(const std::string& path, const std::string& body, int expect) {
    auto r = client_->Post(path.c_str(), body, "application/json");
    EXPECT_TRUE(r) << path;
    if (!r) return {};
    EXPECT_EQ(r->status, expect) << path << ": " << r->body;
    EXPECT_TRUE(r->has_header("X-Request-Id"));
    return nlohmann::json::parse(r->body);
  }
  nlohmann::json get(const std::string& path, int expect = 200) {
    auto r = client_->Get(path.c_str());
    EXPECT_TRUE(r) << path;
    if (!r) return {};
    EXPECT_EQ(r->status, expect) << path << ": " << r->body;
    return nlohmann::json::parse(r->body);
  }
  // Polls a job until it leaves queued/running (at most `seconds`).
  nlohmann::json wait(std::int64_t id, double seconds = 60) {
    const auto until = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
    nlohmann::json j;
    while (std::chrono::steady_clock::now() < until) {
      j = get("/v1/jobs/" + std::to_string(id));
      const std::string s = j.value("status", "");
      if (s != "queued" && s != "running") return j;
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    ADD_FAILURE() << "job " << id << " did not finish: " << j.dump();
    return j;
  }

  std::filesystem::path dir_;
  std::unique_ptr<JobStore> store_;
  std::unique_ptr<WorkerPool> pool_;
  std::unique_ptr<HttpServer> http_;
  std::unique_ptr<httplib::Client> client_;
  std::thread serving_;
  int port_ = 0;
};

}  // namespace granulab::server
