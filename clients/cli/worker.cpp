// `granulab worker`: one job of a granulabd that runs its jobs on a Slurm cluster (server/slurm/), run on
// the node Slurm chose. It fetches the spec (and the checkpoint to resume from) from the daemon, runs it
// through the one runner into a RemoteSink, and reports how it ended; the daemon decides what follows.
#include "clients/cli/worker.h"

#include <omp.h>

#include <atomic>
#include <csignal>
#include <cstdlib>
#include <optional>

#include <spdlog/spdlog.h>

#include "api/engine_version.h"
#include "api/int_option.h"
#include "api/runner.h"
#include "api/spec.h"
#include "clients/cli/remote_sink.h"
#include "engine/core/checkpoint.h"

// After the project headers: <resolv.h>, pulled in by httplib, defines a macro `_res` that breaks Eigen.
#include <httplib.h>

namespace granulab::cli {

using nlohmann::json;

namespace {

std::atomic<int> g_stop_signal{0};

extern "C" void on_stop_signal(int sig) { g_stop_signal = sig; }

const char* kWorkerUsage =
    "usage: granulab worker --server URL --job ID [--patience S]\n"
    "  runs job ID of the granulabd at URL here (what its Slurm jobs run); the job's secret comes in\n"
    "  GRANULAB_WORKER_TOKEN. --patience: how long to keep retrying an unreachable daemon (default 900 s)\n";

// The Slurm job this process belongs to, as granulabd names it: "123", or "123_4" for task 4 of array 123.
std::string slurm_job_id() {
  const char* array = std::getenv("SLURM_ARRAY_JOB_ID");
  const char* task = std::getenv("SLURM_ARRAY_TASK_ID");
  if (array && task && *array && *task) return std::string(array) + "_" + task;
  const char* job = std::getenv("SLURM_JOB_ID");
  return job ? job : "";
}

// The daemon's refusals that mean "this run is no longer wanted" (cancelled, finished, requeued, not this
// worker's): the worker stops without reporting. Any other refusal (a limit, a malformed request) is a
// failure it reports, with the daemon's message.
bool ends_quietly(const Refused& e) {
  return e.code == "wrong_state" || e.code == "stale_worker" || e.code == "forbidden";
}

// Tells the daemon how the run ended; an answer it refuses (the job was cancelled meanwhile) is logged.
void report_end(DaemonLink& link, const json& body) {
  try {
    link.post_json("/end", body);
  } catch (const std::exception& e) {
    spdlog::error("job {}: could not report its end ({}): {}", link.job(), body.value("outcome", ""), e.what());
  }
}

}  // namespace

int run_worker(int argc, char** argv) {
  std::string server;
  std::int64_t job = 0;
  double patience = 900;
  for (int i = 2; i < argc; ++i) {
    const std::string a = argv[i];
    if (i + 1 >= argc) throw std::invalid_argument("'" + a + "' needs a value\n" + kWorkerUsage);
    const std::string v = argv[++i];
    if (a == "--server") server = v;
    else if (a == "--job") job = api::parse_int_option(a, v, 1, 2000000000);
    else if (a == "--patience") patience = api::parse_int_option(a, v, 0, 86400);
    else throw std::invalid_argument("unexpected argument '" + a + "'\n" + kWorkerUsage);
  }
  const char* token = std::getenv("GRANULAB_WORKER_TOKEN");
  if (server.empty() || job == 0 || !token || !*token)
    throw std::invalid_argument(std::string("worker needs --server, --job and GRANULAB_WORKER_TOKEN\n") + kWorkerUsage);

  // First of all: Slurm's warning may come at once, and USR1's default action would kill the process.
  struct sigaction action {};
  action.sa_handler = on_stop_signal;
  sigemptyset(&action.sa_mask);
  ::sigaction(SIGUSR1, &action, nullptr);
  ::sigaction(SIGTERM, &action, nullptr);

  DaemonLink link(server, job, token, slurm_job_id(), patience);
  const std::string version = api::engine_version();
  json start;
  try {
    start = json::parse(link.get("?engine_version=" + httplib::detail::encode_query_param(version)));
  } catch (const Refused& e) {
    spdlog::warn("job {} does not start: {}", job, e.what());  // cancelled or finished meanwhile
    return 0;
  }
  api::Spec spec;
  std::optional<api::Resume> resume;
  try {
    spec = api::parse_spec_text(start["spec"].dump());
    if (start.value("resume", false)) {
      try {
        resume = remote_checkpoint(link);  // the daemon checked it before it said resume; the reader does again
      } catch (const CheckpointError& e) {
        spdlog::warn("job {}: unusable checkpoint ({}); it starts afresh", job, e.what());
      }
    }
  } catch (const Refused& e) {
    if (ends_quietly(e)) return 0;
    report_end(link, {{"outcome", "failed"}, {"error", e.what()}});
    return 1;
  } catch (const std::exception& e) {  // a spec this build cannot read (another version of granulab?)
    report_end(link, {{"outcome", "failed"}, {"error", std::string("the worker cannot run this job: ") + e.what()}});
    return 1;
  }
  const char* cpus = std::getenv("SLURM_CPUS_PER_TASK");
  const int threads = cpus && std::atoi(cpus) > 0 ? std::atoi(cpus) : spec.threads;
  if (threads > 0) omp_set_num_threads(threads);
  spdlog::info("job {} ({}) on {} thread(s){}", job, spec.name(), omp_get_max_threads(),
               resume ? ", resuming after " + std::to_string(resume->rows) + " curve rows" : "");

  for (;;) {
    RemoteSink sink(link, g_stop_signal, start.value("progress_seconds", 1.0), start.value("checkpoint_seconds", 60.0),
                    version);
    try {
      api::run(spec, sink, resume ? &*resume : nullptr);
      spdlog::info("job {} succeeded", job);
      return 0;
    } catch (const CheckpointError& e) {
      if (resume) {  // the checkpoint does not fit: once more, afresh
        spdlog::warn("job {}: cannot resume ({}); it starts afresh", job, e.what());
        resume.reset();
        continue;
      }
      report_end(link, {{"outcome", "failed"}, {"error", e.what()}});
      return 1;
    } catch (const Interrupted& e) {
      spdlog::warn("job {} interrupted ({}); the daemon requeues it", job, e.what());
      report_end(link, {{"outcome", "interrupted"}, {"reason", e.what()}});
      return 0;
    } catch (const Cancelled&) {
      try {
        sink.flush();  // what it computed since the last batch
      } catch (const std::exception&) {}
      report_end(link, {{"outcome", "cancelled"}});
      spdlog::info("job {} cancelled", job);
      return 0;
    } catch (const Refused& e) {
      if (ends_quietly(e)) {
        spdlog::warn("job {} stops: {}", job, e.what());  // e.g. cancelled and already marked so
        return 0;
      }
      report_end(link, {{"outcome", "failed"}, {"error", e.what()}});  // e.g. a limit of the daemon's, named
      spdlog::error("job {} failed: {}", job, e.what());
      return 1;
    } catch (const std::exception& e) {
      try {
        sink.flush();
      } catch (const std::exception&) {}
      report_end(link, {{"outcome", "failed"}, {"error", e.what()}});
      spdlog::error("job {} failed: {}", job, e.what());
      return 1;
    }
  }
}

}  // namespace granulab::cli
