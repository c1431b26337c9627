#include "server/admission.h"

#include <algorithm>
#include <cstdio>
#include <vector>

#include <unistd.h>

#include "api/spec.h"
#include "server/http/replies.h"

namespace granulab::server {

using nlohmann::json;

namespace {

std::string gigabytes(double bytes) {
  char text[32];
  std::snprintf(text, sizeof text, "%.2f GB", bytes / 1e9);
  return text;
}

std::string number(double x) {
  char text[32];
  std::snprintf(text, sizeof text, "%.3g", x);
  return text;
}

}  // namespace

Admission::Admission(JobStore& store, const Executor& executor, AdmissionLimits limits)
    : store_(store), executor_(executor), limits_(limits) {
  if (limits_.max_memory_bytes <= 0)
    limits_.max_memory_bytes = 0.5 * double(::sysconf(_SC_PHYS_PAGES)) * double(::sysconf(_SC_PAGESIZE));
}

std::string Admission::budget_problem(const api::Spec& spec) const {
  const Workload w = spec.experiment->workload();
  const std::string size = number(w.spheres) + " spheres in " + number(w.grains) + " grains";
  if (w.peak_bytes() > limits_.max_memory_bytes)
    return "this job would need about " + gigabytes(w.peak_bytes()) + " of memory (" + size +
           "); the server's limit is " + gigabytes(limits_.max_memory_bytes) + " (max_memory)";
  if (w.sphere_steps() > limits_.max_sphere_steps)
    return "this job would take about " + number(w.sphere_steps()) + " sphere-steps (" + size + " x " +
           number(w.steps) + " steps); the server's limit is " + number(limits_.max_sphere_steps) +
           " (max_sphere_steps)";
  return "";
}

bool Admission::within_budget(const api::Spec& spec, http::Response& res) const {
  const std::string problem = budget_problem(spec);
  if (problem.empty()) return true;
  http::error(res, 400, "over_budget", problem);
  return false;
}

bool Admission::within_queue_quota(const User& who, std::size_t more, http::Response& res) const {
  if (limits_.max_queued_per_user <= 0) return true;
  const std::size_t queued = store_.count(JobStatus::queued, who.name);
  if (queued + more <= std::size_t(limits_.max_queued_per_user)) return true;
  http::error(res, 429, "quota",
              (who.name.empty() ? std::string("the server") : "user '" + who.name + "'") + " has " +
                  std::to_string(queued) + " queued jobs and asks for " + std::to_string(more) +
                  " more; the limit is " + std::to_string(limits_.max_queued_per_user) +
                  " (max_queued_per_user): wait for some to start or cancel some");
  return false;
}

json Admission::cost_estimate(const api::Spec& spec) const {
  const Workload w = spec.experiment->workload();
  const std::string experiment = spec.normalized["experiment"].get<std::string>();
  // The speed of this server: the median rate of its recent succeeded jobs of the same experiment (of any,
  // failing that); with none, 5e7 sphere-steps per second per thread, what the crystal runs at here.
  // The workload's step count is an upper bound (confinement until converged, at most its step limit):
  // the same jobs also say what fraction of it runs took (their steps over their own estimate).
  // With no similar run, the bound itself: an upper estimate.
  std::vector<double> same, any, used;
  for (const JobRecord& j : store_.list(JobStatus::succeeded, 50, 0, "")) {
    const json summary = json::parse(j.summary_json, nullptr, false);
    if (!summary.is_object() || !summary.contains("sphere_steps_per_second") ||
        !summary["sphere_steps_per_second"].is_number())
      continue;
    const double rate = summary["sphere_steps_per_second"].get<double>();
    if (!(rate > 0)) continue;
    any.push_back(rate);
    if (j.experiment != experiment) continue;
    same.push_back(rate);
    if (summary.contains("steps") && summary["steps"].is_number()) {
      try {
        // Only runs of a similar length: the fraction depends on the loading (a slow rate spends longer
        // compressing, a small crystal converges sooner), so unlike runs would mislead.
        const double bound = api::parse_spec_text(j.spec_json).experiment->workload().steps;
        if (bound > 0.5 * w.steps && bound < 2 * w.steps)
          used.push_back(std::clamp(summary["steps"].get<double>() / bound, 0.01, 1.0));
      } catch (const std::exception&) {
        // a spec this build no longer accepts says nothing about this one
      }
    }
  }
  double fraction = 1;
  if (!used.empty()) {
    std::nth_element(used.begin(), used.begin() + used.size() / 2, used.end());
    fraction = used[used.size() / 2];
  }
  std::vector<double>& rates = same.empty() ? any : same;
  std::string basis =
      same.empty() ? (any.empty() ? "typical" : "recent jobs of other experiments") : "recent " + experiment + " jobs";
  double rate = 5e7 * executor_.threads_per_job();
  if (!rates.empty()) {
    std::nth_element(rates.begin(), rates.begin() + rates.size() / 2, rates.end());
    rate = rates[rates.size() / 2];
  }
  json out = {{"dry_run", true},
              {"experiment", experiment},
              {"spheres", w.spheres},
              {"grains", w.grains},
              {"steps", w.steps},
              {"sphere_steps", w.sphere_steps()},
              {"memory_bytes", w.peak_bytes()},
              {"sphere_steps_per_second", rate},
              {"rate_basis", basis},
              {"expected_seconds", fraction * w.sphere_steps() / rate},
              {"steps_fraction", fraction},
              {"queued_ahead", store_.count(JobStatus::queued)},
              {"units", {{"memory_bytes", "B"}, {"expected_seconds", "s"}, {"sphere_steps_per_second", "1/s"}}}};
  if (const std::string problem = budget_problem(spec); !problem.empty()) out["over_budget"] = problem;
  return out;
}

}  // namespace granulab::server
