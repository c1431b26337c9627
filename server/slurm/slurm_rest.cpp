#include "server/slurm/slurm_rest.h"

#include <cctype>
#include <chrono>

#include "server/slurm/jwt.h"

namespace granulab::server::slurm {

using nlohmann::json;

namespace {

constexpr int kTokenLifespan = 600;  // s; renewed after half of it

// Slurm's "no value" for 32-bit fields (NO_VAL and INFINITE), which v0.0.38 prints as plain numbers.
bool no_value(std::int64_t v) { return v >= 4294967294LL || v < 0; }

std::int64_t integer(const json& j, const char* key) {
  if (!j.contains(key)) return -1;
  const json& v = j[key];
  if (v.is_number_integer()) return v.get<std::int64_t>();
  if (v.is_string()) try {
      return std::stoll(v.get<std::string>());
    } catch (const std::exception&) {}
  return -1;
}

std::string text(const json& j, const char* key) {
  return j.contains(key) && j[key].is_string() ? j[key].get<std::string>() : std::string();
}

// "Slurm's errors" of a reply, joined: [{"error": "...", "error_number": N, ...}].
std::string errors_of(const json& reply) {
  std::string out;
  if (!reply.contains("errors") || !reply["errors"].is_array()) return out;
  for (const json& e : reply["errors"]) {
    std::string one = text(e, "error");
    if (one.empty()) one = text(e, "description");
    if (e.contains("error_number")) one += " (error " + e["error_number"].dump() + ")";
    out += (out.empty() ? "" : "; ") + one;
  }
  return out;
}

// Slurm's refusal of a job for what it asks (a partition, a node configuration, a time limit, CPUs) rather
// than for the moment (slurmctld away, a policy limit on queued jobs, a busy controller).
bool about_the_job(const std::string& errors) {
  std::string lower = errors;
  for (char& c : lower) c = char(std::tolower(static_cast<unsigned char>(c)));
  for (const char* word : {"partition", "node configuration", "time limit", "cpu count", "memory specification"})
    if (lower.find(word) != std::string::npos) return true;
  return false;
}

bool unknown_job(const json& reply) {
  // ESLURM_INVALID_JOB_ID (2017): "Invalid job id specified"; also answered for purged jobs.
  if (!reply.contains("errors") || !reply["errors"].is_array()) return false;
  for (const json& e : reply["errors"])
    if (integer(e, "error_number") == 2017 || text(e, "error").find("Invalid job id") != std::string::npos) return true;
  return false;
}

}  // namespace

bool SlurmJob::covers_task(std::int64_t task) const {
  if (array_task_id) return *array_task_id == task;
  // "1-3,5,7-11:2%4": ranges with optional steps, then a limit on running tasks.
  const std::string list = array_task_string.substr(0, array_task_string.find('%'));
  std::size_t at = 0;
  while (at < list.size()) {
    const std::size_t comma = list.find(',', at);
    const std::string part = list.substr(at, comma == std::string::npos ? std::string::npos : comma - at);
    at = comma == std::string::npos ? list.size() : comma + 1;
    try {
      const std::size_t dash = part.find('-'), colon = part.find(':');
      const std::int64_t lo = std::stoll(part);
      const std::int64_t hi = dash == std::string::npos ? lo : std::stoll(part.substr(dash + 1));
      const std::int64_t step =
          colon == std::string::npos ? 1 : std::max<std::int64_t>(1, std::stoll(part.substr(colon + 1)));
      if (task >= lo && task <= hi && (task - lo) % step == 0) return true;
    } catch (const std::exception&) {}
  }
  return false;
}

RestClient::RestClient(RestOptions options)
    : options_(std::move(options)), http_(std::make_unique<http::Client>(options_.url, 5, 30, 30)) {
  if (!http_->valid()) throw std::invalid_argument("cannot use the Slurm REST URL '" + options_.url + "'");
  if (options_.jwt_key.empty() && options_.jwt.empty())
    throw std::invalid_argument("the Slurm executor needs --slurm-jwt-key FILE or SLURM_JWT");
}

RestClient::~RestClient() = default;

std::string RestClient::token() {
  if (options_.jwt_key.empty()) return options_.jwt;
  const auto now = std::chrono::steady_clock::now();
  if (token_.empty() || now >= token_renew_) {
    const std::int64_t unix_now =
        std::chrono::duration_cast<std::chrono::seconds>(std::chrono::system_clock::now().time_since_epoch()).count();
    token_ = slurm_jwt(options_.jwt_key, options_.user, unix_now, kTokenLifespan);
    token_renew_ = now + std::chrono::seconds(kTokenLifespan / 2);
  }
  return token_;
}

json RestClient::call(const std::string& method, const std::string& path, const std::string& body, int& status) {
  std::lock_guard<std::mutex> lock(mutex_);
  const std::string full = std::string("/slurm/") + kDialect + path;
  std::string problem;
  const auto r = http_->send(method, full, {{"X-SLURM-USER-NAME", options_.user}, {"X-SLURM-USER-TOKEN", token()}},
                             body, "application/json", problem);
  if (!r) throw Unreachable("cannot reach slurmrestd at " + options_.url + " (" + problem + ")");
  status = r->status;
  if (r->status == 404 && r->body.find("Unable to find") != std::string::npos)
    throw Refused("slurmrestd at " + options_.url + " does not serve openapi/" + kDialect + " (" + method + " " + full +
                  ": " + r->body.substr(0, 200) + "); granulab speaks only that dialect (Slurm 22.05)");
  if (r->status == 401 || r->status == 403)  // e.g. an expired SLURM_JWT: jobs wait until it is replaced
    throw Unreachable("slurmrestd refused the credentials of user '" + options_.user + "' (HTTP " +
                      std::to_string(r->status) + "): check --slurm-user and the JWT key or SLURM_JWT");
  const json reply = json::parse(r->body, nullptr, false);
  if (!reply.is_object())
    throw Unreachable("slurmrestd answered " + method + " " + full + " with HTTP " + std::to_string(r->status) +
                      " and no JSON: " + r->body.substr(0, 200));
  // The dialect: meta.plugin.type is "openapi/v0.0.38"; a newer slurmrestd answers in its own.
  const json& meta = reply.contains("meta") ? reply["meta"] : json();
  const std::string plugin = meta.contains("plugin") ? text(meta["plugin"], "type") : "";
  if (!plugin.empty() && plugin != std::string("openapi/") + kDialect)
    throw Refused("slurmrestd answers in dialect '" + plugin + "', granulab speaks openapi/" + kDialect +
                  " (Slurm 22.05)");
  return reply;
}

std::string RestClient::check() {
  int status = 0;
  const json reply = call("GET", "/ping", "", status);
  if (status >= 400 || !errors_of(reply).empty())
    throw Refused("slurmrestd ping failed (HTTP " + std::to_string(status) + "): " + errors_of(reply));
  std::string release = "Slurm";
  if (reply.contains("meta") && reply["meta"].contains("Slurm"))
    release += " " + text(reply["meta"]["Slurm"], "release");
  return release + " (openapi/" + kDialect + ")";
}

std::int64_t RestClient::submit(const json& job, const std::string& script) {
  int status = 0;
  const json reply = call("POST", "/job/submit", json{{"job", job}, {"script", script}}.dump(), status);
  if (const std::string errors = errors_of(reply); !errors.empty() || status >= 400) {
    const std::string message =
        "(HTTP " + std::to_string(status) + "): " + (errors.empty() ? reply.dump().substr(0, 200) : errors);
    if (about_the_job(errors)) throw Refused("Slurm refused the job " + message);
    throw Unreachable("Slurm did not take the job now " + message);
  }
  const std::int64_t id = integer(reply, "job_id");
  if (id <= 0) throw Unreachable("slurmrestd's submit answer has no job_id: " + reply.dump().substr(0, 200));
  return id;
}

std::optional<std::vector<SlurmJob>> RestClient::job(const std::string& id) {
  int status = 0;
  const json reply = call("GET", "/job/" + id, "", status);
  if (unknown_job(reply)) return std::nullopt;
  if (const std::string errors = errors_of(reply); !errors.empty() || status >= 400)
    throw Unreachable("slurmrestd could not say how job " + id + " is (HTTP " + std::to_string(status) +
                      "): " + errors);
  std::vector<SlurmJob> out;
  if (!reply.contains("jobs") || !reply["jobs"].is_array()) return out;
  for (const json& j : reply["jobs"]) {
    SlurmJob r;
    r.job_id = integer(j, "job_id");
    const std::int64_t array = integer(j, "array_job_id");
    r.array_job_id = no_value(array) ? 0 : array;
    const std::int64_t task = integer(j, "array_task_id");
    if (r.array_job_id != 0 && !no_value(task)) r.array_task_id = task;
    r.array_task_string = text(j, "array_task_string");
    r.state = text(j, "job_state");
    r.reason = text(j, "state_reason");
    if (r.reason == "None") r.reason.clear();
    r.exit_code = int(std::max<std::int64_t>(0, integer(j, "exit_code")));
    out.push_back(std::move(r));
  }
  return out;
}

void RestClient::cancel(const std::string& id) {
  int status = 0;
  const json reply = call("DELETE", "/job/" + id, "", status);
  if (unknown_job(reply)) return;
  if (const std::string errors = errors_of(reply); !errors.empty() || status >= 400)
    throw Unreachable("Slurm did not cancel job " + id + " (HTTP " + std::to_string(status) + "): " + errors);
}

}  // namespace granulab::server::slurm
