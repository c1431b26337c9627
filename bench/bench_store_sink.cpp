// What the server's live results cost the engine: the same spec run through the one runner into memory
// (MemorySink) and into a real SQLite store (StoreSink, rows and snapshots flushed in batches), one after
// the other, alternating, so machine noise hits both. Reports wall time per run, the time the StoreSink spent
// writing (which the engine's loop waits for) and how many batches it wrote.
// Usage: bench_store_sink SPEC.json [--repeat N] [--flush-seconds S] [--threads T]
#include <omp.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <unistd.h>

#include "api/runner.h"
#include "server/store_sink.h"

using namespace granulab;
namespace fs = std::filesystem;

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: bench_store_sink SPEC.json [--repeat N] [--flush-seconds S] [--threads T]\n");
    return 2;
  }
  int repeat = 2, threads = 1;
  double flush_seconds = 1.0;
  for (int i = 2; i + 1 < argc; i += 2) {
    const std::string a = argv[i];
    if (a == "--repeat") repeat = std::max(1, std::atoi(argv[i + 1]));
    else if (a == "--flush-seconds") flush_seconds = std::atof(argv[i + 1]);
    else if (a == "--threads") threads = std::max(1, std::atoi(argv[i + 1]));
  }
  omp_set_num_threads(threads);
  std::ifstream in(argv[1]);
  std::stringstream text;
  text << in.rdbuf();
  const api::Spec spec = api::parse_spec_text(text.str());
  const fs::path db = fs::temp_directory_path() / ("bench_store_sink_" + std::to_string(::getpid()) + ".db");
  server::JobStore store(db.string());
  std::atomic<bool> stopping{false};
  auto seconds_of = [](auto f) {
    const auto t = std::chrono::steady_clock::now();
    f();
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
  };
  std::printf("%-6s %-8s %10s %10s %8s %12s %8s\n", "run", "sink", "wall (s)", "steps", "rows", "writes (s)",
              "batches");
  for (int k = 0; k < repeat; ++k) {
    api::MemorySink memory;
    nlohmann::json summary;
    const double t_memory = seconds_of([&] { summary = api::run(spec, memory); });
    std::printf("%-6d %-8s %10.2f %10.0f %8zu %12s %8s\n", k, "memory", t_memory, summary["steps"].get<double>(),
                std::size_t(std::count(memory.curve_csv_.begin(), memory.curve_csv_.end(), '\n') - 1), "-", "-");
    const std::int64_t id = store.submit(spec.normalized.dump(), spec.name(), spec.label, "", "", "", 0);
    store.claim_next();
    server::StoreSink sink(store, id, stopping, flush_seconds);
    const double t_store = seconds_of([&] { summary = api::run(spec, sink); });
    const std::string csv = store.live_curve_csv(id).value_or("\n");
    std::printf("%-6d %-8s %10.2f %10.0f %8zu %12.4f %8zu\n", k, "store", t_store, summary["steps"].get<double>(),
                std::size_t(std::count(csv.begin(), csv.end(), '\n') - 1), sink.flush_seconds_total(), sink.flushes());
  }
  fs::remove(db);
  fs::remove(db.string() + "-wal");
  fs::remove(db.string() + "-shm");
  return 0;
}
