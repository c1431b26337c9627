#include "clients/cli/job_watch.h"

#include "api/job_status.h"

#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <map>
#include <thread>

namespace granulab::cli {

namespace {

using nlohmann::json;

std::atomic<bool> interrupted{false};

extern "C" void on_interrupt(int) { interrupted = true; }

}  // namespace

std::string duration(double s) {
  char text[48];
  if (s < 10) std::snprintf(text, sizeof text, "%.2g s", s);
  else if (s < 90) std::snprintf(text, sizeof text, "%.0f s", s);
  else if (s < 5400) std::snprintf(text, sizeof text, "%.0f min", s / 60);
  else std::snprintf(text, sizeof text, "%.1f h", s / 3600);
  return text;
}

namespace {

// A number at `key`, or `fallback` when it is missing or not a number (a NaN cell arrives as null).
double number(const json& j, const char* key, double fallback = 0) {
  return j.is_object() && j.contains(key) && j[key].is_number() ? j[key].get<double>() : fallback;
}

}  // namespace

std::string job_line(const json& job, int bar_width) {
  const std::string status = job.contains("status") && job["status"].is_string() ? job["status"].get<std::string>() : "?";
  const double progress = std::clamp(number(job, "progress"), 0.0, 1.0);
  const int filled = int(progress * bar_width + 0.5);
  char head[160];
  std::snprintf(head, sizeof head, "job %-5lld %-9s [%s%s] %5.1f %%", (long long)number(job, "id"), status.c_str(),
                std::string(std::size_t(filled), '#').c_str(), std::string(std::size_t(bar_width - filled), '.').c_str(),
                100 * progress);
  std::string line = head;
  if (status == api::status_name(api::JobStatus::running) && job.contains("eta_seconds")) line += "  ETA " + duration(number(job, "eta_seconds"));
  // On a cluster, while it waits there: Slurm's word on why (e.g. "Slurm 123: PENDING (Resources)").
  if (status == api::status_name(api::JobStatus::queued) && job.contains("slurm_state") && job["slurm_state"].is_string())
    line += "  Slurm " + job.value("slurm_job_id", std::string("?")) + ": " + job["slurm_state"].get<std::string>();
  // The latest strain and stress of a running job, the first yield of a finished crystal.
  if (job.contains("latest") && job["latest"].is_object()) {
    const json& l = job["latest"];
    char text[96];
    if (l.contains("strain")) std::snprintf(text, sizeof text, "  strain %.3g %%", 100 * number(l, "strain")), line += text;
    if (l.contains("deviator")) std::snprintf(text, sizeof text, "  deviator %.4g kPa", number(l, "deviator") / 1e3), line += text;
    if (l.contains("tangential_over_p0"))
      std::snprintf(text, sizeof text, "  u/l %.3g  T/P0 %.3g", number(l, "slide_over_size"), number(l, "tangential_over_p0")),
          line += text;
  }
  if (job.contains("summary") && job["summary"].contains("first_yield")) {
    const json& y = job["summary"]["first_yield"];
    char text[96];
    std::snprintf(text, sizeof text, "  first yield %.3g p0 at %.3g %%", number(y, "deviator_over_p0"), 100 * number(y, "strain"));
    line += text;
  }
  if (job.contains("error") && job["error"].is_string()) line += "  " + job["error"].get<std::string>();
  if (job.contains("warnings") && job["warnings"].is_array() && !job["warnings"].empty())
    line += "  (" + std::to_string(job["warnings"].size()) + " warning" + (job["warnings"].size() > 1 ? "s" : "") + ")";
  return line;
}

int watch_jobs(const JsonGetter& get, const std::vector<std::string>& ids) {
  interrupted = false;
  struct sigaction action {}, previous {};
  action.sa_handler = on_interrupt;
  sigemptyset(&action.sa_mask);
  sigaction(SIGINT, &action, &previous);
  const bool tty = isatty(STDERR_FILENO);
  std::map<std::string, std::string> shown;  // id -> the last line printed (logs print changes only)
  std::map<std::string, json> last;
  std::size_t drawn = 0;
  auto last_log = std::chrono::steady_clock::now();
  int result = 0;
  for (;;) {
    bool all_done = true;
    std::vector<std::string> lines;
    for (const std::string& id : ids) {
      if (!last.count(id) || !api::is_finished(last[id].value("status", ""))) last[id] = get("/v1/jobs/" + id);
      all_done = all_done && api::is_finished(last[id].value("status", ""));
      lines.push_back(job_line(last[id]));
    }
    if (tty) {
      // Redraw in place: up over the previous block, each line cleared.
      if (drawn) std::fprintf(stderr, "\033[%zuA", drawn);
      for (const std::string& l : lines) std::fprintf(stderr, "\r\033[K%s\n", l.c_str());
      drawn = lines.size();
    } else {
      // A log: a job's line when its status changes, and every job's every 60 s.
      const bool periodic = std::chrono::steady_clock::now() - last_log > std::chrono::seconds(60);
      for (std::size_t k = 0; k < ids.size(); ++k) {
        const std::string status = last[ids[k]].value("status", "");
        if (shown[ids[k]] != status || periodic) std::fprintf(stderr, "%s\n", lines[k].c_str()), shown[ids[k]] = status;
      }
      if (periodic) last_log = std::chrono::steady_clock::now();
    }
    if (all_done) break;
    for (int i = 0; i < 20 && !interrupted; ++i) std::this_thread::sleep_for(std::chrono::milliseconds(100));
    if (interrupted) {
      std::string running;
      for (const std::string& id : ids)
        if (!api::is_finished(last[id].value("status", ""))) running += (running.empty() ? "" : ", ") + id;
      std::fprintf(stderr, "\nstopped waiting; on the server, job%s %s go%s on (granulab cancel ID stops one)\n",
                   running.find(',') != std::string::npos ? "s" : "", running.c_str(),
                   running.find(',') != std::string::npos ? "" : "es");
      sigaction(SIGINT, &previous, nullptr);
      return 130;
    }
  }
  sigaction(SIGINT, &previous, nullptr);
  for (const std::string& id : ids) {
    const json& j = last[id];
    if (j.value("status", "") != api::status_name(api::JobStatus::succeeded)) result = 1;
    if (j.contains("warnings") && j["warnings"].is_array())
      for (const json& w : j["warnings"])
        if (w.is_string()) std::fprintf(stderr, "job %s warning: %s\n", id.c_str(), w.get<std::string>().c_str());
  }
  return result;
}

}  // namespace granulab::cli
