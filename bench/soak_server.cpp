// Soak benchmark of the lab server (not part of `make test`; loopback only, bounded): an in-process
// granulabd (real SQLite file, 1 worker running small two-cube jobs back to back) while C client threads
// poll job status and list jobs for S seconds. Reports requests/s and the p50/p99/max latency.
// Usage: soak_server [--clients C] [--seconds S] (S <= 120)
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include <unistd.h>

#include "server/http_server.h"
#include "server/worker_pool.h"

// After the project headers: <resolv.h>, pulled in by httplib, defines a macro `_res` that breaks Eigen.
#include <httplib.h>

using namespace granulab::server;
namespace fs = std::filesystem;

int main(int argc, char** argv) {
  int clients = 4, seconds = 20;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string a = argv[i];
    if (a == "--clients") clients = std::max(1, std::atoi(argv[i + 1]));
    else if (a == "--seconds") seconds = std::clamp(std::atoi(argv[i + 1]), 1, 120);
  }
  const fs::path dir = fs::temp_directory_path() / ("granulab_soak_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  {
    JobStore store((dir / "jobs.db").string());
    WorkerPool pool(store, 1, 1);
    HttpServer http(store, pool, HttpOptions{1 << 20, 8, {}});
    for (auto group : {mount_meta_routes, mount_job_routes, mount_sweep_routes, mount_picture_routes,
                       mount_export_routes, mount_web_routes, mount_worker_routes})
      http.mount(group);
    const int port = http.bind("127.0.0.1", 0);
    std::thread serving([&] { http.serve(); });
    pool.start();
    httplib::Client submit("127.0.0.1", port);
    const char* spec =
        R"({"grain": {"edge_spheres": 4}, "loading": {"rate_number": 1e-4}, "output": {"curve_points": 20}})";
    for (int k = 0; k < 200; ++k) submit.Post("/v1/jobs", spec, "application/json");  // more than the soak can run

    std::atomic<bool> running{true};
    std::mutex mutex;
    std::vector<double> latencies;  // ms
    std::atomic<long> errors{0};
    std::vector<std::thread> threads;
    for (int c = 0; c < clients; ++c)
      threads.emplace_back([&, c] {
        httplib::Client client("127.0.0.1", port);
        std::vector<double> mine;
        for (long k = 0; running; ++k) {
          const std::string path = k % 4 == 3 ? "/v1/jobs?limit=20" : "/v1/jobs/" + std::to_string(1 + (k + c) % 200);
          const auto t0 = std::chrono::steady_clock::now();
          const auto r = client.Get(path.c_str());
          mine.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
          if (!r || r->status != 200) ++errors;
        }
        std::lock_guard<std::mutex> lock(mutex);
        latencies.insert(latencies.end(), mine.begin(), mine.end());
      });
    std::this_thread::sleep_for(std::chrono::seconds(seconds));
    running = false;
    for (std::thread& t : threads) t.join();
    const std::size_t done = store.count(JobStatus::succeeded);
    http.stop();
    serving.join();
    pool.stop();
    std::sort(latencies.begin(), latencies.end());
    auto pct = [&](double p) { return latencies.empty() ? 0.0 : latencies[std::size_t(p * (latencies.size() - 1))]; };
    std::printf(
        "%d clients, %d s: %zu requests, %.0f requests/s, latency p50 %.2f ms, p99 %.2f ms, max %.2f ms, "
        "%ld errors; %zu jobs finished meanwhile\n",
        clients, seconds, latencies.size(), latencies.size() / double(seconds), pct(0.5), pct(0.99),
        latencies.empty() ? 0.0 : latencies.back(), errors.load(), done);
  }
  fs::remove_all(dir);
  return 0;
}
