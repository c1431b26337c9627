#include "clients/cli/job_watch.h"

#include "api/headline_json.h"
#include "api/job_status.h"

#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
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

// The same at a dotted path ("first_yield.strain").
double number_at(const json& j, const std::string& dotted, double fallback = 0) {
  return api::number_at_path(j, dotted).value_or(fallback);
}

}  // namespace

std::string job_line(const json& job, const json& headline, int bar_width) {
  const std::string status =
      job.contains("status") && job["status"].is_string() ? job["status"].get<std::string>() : "?";
  const double progress = std::clamp(number(job, "progress"), 0.0, 1.0);
  const int filled = int(progress * bar_width + 0.5);
  char head[160];
  std::snprintf(head, sizeof head, "job %-5lld %-9s [%s%s] %5.1f %%", (long long)number(job, "id"), status.c_str(),
                std::string(std::size_t(filled), '#').c_str(),
                std::string(std::size_t(bar_width - filled), '.').c_str(), 100 * progress);
  std::string line = head;
  if (status == api::status_name(api::JobStatus::running) && job.contains("eta_seconds"))
    line += "  ETA " + duration(number(job, "eta_seconds"));
  // On a cluster, while it waits there: Slurm's word on why (e.g. "Slurm 123: PENDING (Resources)").
  if (status == api::status_name(api::JobStatus::queued) && job.contains("slurm_state") &&
      job["slurm_state"].is_string())
    line += "  Slurm " + job.value("slurm_job_id", std::string("?")) + ": " + job["slurm_state"].get<std::string>();
  // The latest x and first series of a running job, the key values of a finished one, in natural units.
  if (headline.is_object()) {
    const json spec = job.value("spec", json::object());
    char text[160];
    const auto reading = [&](const json& axis, double value) {
      const json scale = axis.value("natural", json::object());
      double v = value * scale.value("factor", 1.0);
      if (scale.contains("per_field") && scale["per_field"].is_string()) {
        const double per = number_at(spec, scale["per_field"].get<std::string>());
        if (!(per > 0)) return std::string();
        v /= per;
      }
      std::snprintf(text, sizeof text, "%.3g %s", v, scale.value("unit", std::string()).c_str());
      return std::string(text);
    };
    const json x = headline.value("x", json::object()), y = headline.value("y", json::object());
    const json series = headline.value("series", json::array());
    if (job.contains("latest") && job["latest"].is_object()) {
      const json& l = job["latest"];
      const std::string xc = x.value("column", std::string());
      if (l.contains(xc) && l[xc].is_number())
        line += "  " + x.value("label", xc) + " " + reading(x, l[xc].get<double>());
      if (!series.empty()) {
        const std::string yc = series[0].value("column", std::string());
        if (l.contains(yc) && l[yc].is_number())
          line += "  " + series[0].value("label", yc) + " " + reading(y, l[yc].get<double>());
      }
    }
    const json summary = job.value("summary", json());
    for (const json& v : headline.value("values", json::array())) {
      if (v.contains("status") && v["status"].is_string())
        if (const auto reason = api::missing_reason(summary, v["status"].get<std::string>())) {
          line += "  " + v.value("label", std::string()) + ": " + *reason;
          continue;
        }
      const double value = number_at(summary, v.value("key", std::string()), NAN);
      if (!std::isfinite(value)) continue;
      const std::string unit = v.value("unit", std::string());
      std::snprintf(text, sizeof text, "  %s %.3g%s", v.value("label", std::string()).c_str(), value,
                    unit == "-" ? "" : (" " + unit).c_str());
      line += text;
      if (v.contains("at_x") && v["at_x"].is_string()) {
        const double at = number_at(summary, v["at_x"].get<std::string>(), NAN);
        if (std::isfinite(at)) line += " at " + reading(x, at);
      }
    }
  }
  if (job.contains("error") && job["error"].is_string()) line += "  " + job["error"].get<std::string>();
  if (job.contains("warnings") && job["warnings"].is_array() && !job["warnings"].empty())
    line += "  (" + std::to_string(job["warnings"].size()) + " warning" + (job["warnings"].size() > 1 ? "s" : "") + ")";
  return line;
}

json headlines(const JsonGetter& get) {
  json out = json::object();
  const json described = get("/v1/experiments");
  for (const json& e : described.value("experiments", json::array()))
    if (e.contains("name") && e["name"].is_string() && e.contains("headline"))
      out[e["name"].get<std::string>()] = e["headline"];
  return out;
}

int watch_jobs(const JsonGetter& get, const std::vector<std::string>& ids) {
  interrupted = false;
  const json known = headlines(get);
  struct sigaction action {
  }, previous{};
  action.sa_handler = on_interrupt;
  sigemptyset(&action.sa_mask);
  sigaction(SIGINT, &action, &previous);
  const bool tty = isatty(STDERR_FILENO);
  std::map<std::string, std::string> shown;  // id -> status and tenths of progress last printed (logs)
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
      const std::string experiment = last[id].value("experiment", std::string());
      lines.push_back(job_line(last[id], known.contains(experiment) ? known[experiment] : json()));
    }
    if (tty) {
      // Redraw in place: up over the previous block, each line cleared.
      if (drawn) std::fprintf(stderr, "\033[%zuA", drawn);
      for (const std::string& l : lines) std::fprintf(stderr, "\r\033[K%s\n", l.c_str());
      drawn = lines.size();
    } else {
      // A log (a file, a pipe, a batch system's output): a job's line when its status changes or its progress
      // passes another tenth, and every job's every 30 s; each line flushed as it is written, so that
      // `tail -f` follows the run rather than what a buffer let through.
      const bool periodic = std::chrono::steady_clock::now() - last_log > std::chrono::seconds(30);
      for (std::size_t k = 0; k < ids.size(); ++k) {
        const json& j = last[ids[k]];
        const std::string mark = j.value("status", "") + " " +
                                 std::to_string(int(10 * (j.contains("progress") && j["progress"].is_number()
                                                              ? j["progress"].get<double>()
                                                              : 0.0)));
        if (shown[ids[k]] != mark || periodic) {
          std::fprintf(stderr, "%s\n", lines[k].c_str());
          shown[ids[k]] = mark;
        }
      }
      std::fflush(stderr);
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
