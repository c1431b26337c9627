#include "server/routes.h"


#include <atomic>
#include <cstdint>
#include <optional>
#include <chrono>
#include <fstream>
#include <sstream>

#include <nlohmann/json.hpp>
#include <spdlog/spdlog.h>

#include "api/curve_format.h"
#include "api/engine_version.h"
#include "api/runner.h"
#include "api/spec.h"
#include "api/spec_docs.h"

// After the project headers: <resolv.h>, pulled in by httplib, defines a macro `_res` that breaks Eigen.
#include <httplib.h>

namespace granulab::server {

namespace {

using nlohmann::json;

void reply(httplib::Response& res, int status, const json& body) {
  res.status = status;
  // Messages may quote what a request sent: invalid UTF-8 is replaced, never thrown on.
  res.set_content(body.dump(-1, ' ', false, json::error_handler_t::replace) + "\n", "application/json");
}

// A path id of 1 to 18 digits (the route's regex has already checked they are digits); anything longer
// cannot be a job, snapshot or row number, so it is simply not found. No exception either way.
std::optional<std::int64_t> path_id(const std::string& digits) {
  if (digits.empty() || digits.size() > 18) return std::nullopt;
  std::int64_t v = 0;
  for (char c : digits) {
    if (c < '0' || c > '9') return std::nullopt;
    v = 10 * v + (c - '0');
  }
  return v;
}

void error(httplib::Response& res, int status, const std::string& code, const std::string& message,
           const std::string& field = "") {
  reply(res, status, {{"error", {{"code", code}, {"message", message}, {"field", field}}}});
}

json job_json(const JobRecord& j, bool full) {
  json out = {{"id", j.id},
              {"status", j.status},
              {"label", j.label},
              {"experiment", j.experiment},
              {"progress", j.progress},
              {"created_ms", j.created_ms},
              {"started_ms", j.started_ms},
              {"finished_ms", j.finished_ms},
              {"priority", j.priority}};
  if (j.eta_seconds >= 0 && j.status == "running") out["eta_seconds"] = j.eta_seconds;
  if (!j.error.empty()) out["error"] = j.error;
  if (!j.owner.empty()) out["owner"] = j.owner;
  if (full) {
    out["spec"] = json::parse(j.spec_json);
    out["spec_hash"] = j.spec_hash;
    out["engine_version"] = j.engine_version;
    if (!j.summary_json.empty()) out["summary"] = json::parse(j.summary_json);
  }
  return out;
}

// Query integers with a range; a bad value is a 400 that names the parameter.
bool query_int(const httplib::Request& req, httplib::Response& res, const char* name, long lo, long hi, long& value) {
  if (!req.has_param(name)) return true;
  const std::string text = req.get_param_value(name);
  const bool negative = !text.empty() && text[0] == '-';
  if (const auto v = path_id(negative ? text.substr(1) : text)) {
    value = negative ? -*v : *v;
    if (value >= lo && value <= hi) return true;
  }
  error(res, 400, "out_of_range",
        std::string("'") + name + "' must be an integer in [" + std::to_string(lo) + ", " + std::to_string(hi) +
            "], got '" + text + "'",
        name);
  return false;
}

}  // namespace

std::map<std::string, std::string> read_token_file(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::invalid_argument("cannot read token file '" + path + "'");
  std::map<std::string, std::string> tokens;
  std::string line;
  for (int number = 1; std::getline(in, line); ++number) {
    std::istringstream fields(line);
    std::string user, token, extra;
    if (!(fields >> user) || user[0] == '#') continue;
    if (!(fields >> token) || (fields >> extra))
      throw std::invalid_argument(path + ":" + std::to_string(number) + ": expected '<user> <token>'");
    tokens[token] = user;
  }
  if (tokens.empty()) throw std::invalid_argument("token file '" + path + "' holds no token");
  return tokens;
}

std::string HttpServer::user_of(const std::string& authorization) const {
  const std::string prefix = "Bearer ";
  if (authorization.rfind(prefix, 0) != 0) return "";
  const auto it = options_.tokens.find(authorization.substr(prefix.size()));
  return it == options_.tokens.end() ? "" : it->second;
}

HttpServer::HttpServer(JobStore& store, WorkerPool& pool, const HttpOptions& options)
    : store_(store), pool_(pool), options_(options), http_(std::make_unique<httplib::Server>()) {
  http_->set_payload_max_length(options_.max_body_bytes);
  // Answers go out at once: with Nagle's algorithm a kept-alive connection waited for the client's delayed
  // ACK on every request (26 ms each, 38 requests/s, against 4,000/s on fresh connections).
  http_->set_tcp_nodelay(true);
  const int n = options_.handler_threads;
  http_->new_task_queue = [n] { return new httplib::ThreadPool(std::size_t(n)); };
  // Every response carries a request id; one access-log line per request.
  // With tokens, every route but health needs a known bearer token.
  http_->set_pre_routing_handler([this](const httplib::Request& req, httplib::Response& res) {
    if (options_.tokens.empty() || req.path == "/v1/health") return httplib::Server::HandlerResponse::Unhandled;
    if (!user_of(req.get_header_value("Authorization")).empty()) return httplib::Server::HandlerResponse::Unhandled;
    error(res, 401, "unauthorized",
          req.has_header("Authorization") ? "unknown access token" : "this server needs 'Authorization: Bearer <token>'");
    return httplib::Server::HandlerResponse::Handled;
  });
  http_->set_post_routing_handler([](const httplib::Request&, httplib::Response& res) {
    static std::atomic<std::uint64_t> next{1};
    res.set_header("X-Request-Id", std::to_string(next++));
  });
  // Nothing a handler throws reaches the framework or the client: a JSON 500 with the request id, and the
  // exception text only in the daemon's log.
  http_->set_exception_handler([](const httplib::Request& req, httplib::Response& res, std::exception_ptr ep) {
    std::string what = "unknown exception";
    try {
      if (ep) std::rethrow_exception(ep);
    } catch (const std::exception& e) {
      what = e.what();
    } catch (...) {
    }
    static std::atomic<std::uint64_t> next_error{1};
    const std::string id = "e" + std::to_string(next_error++);
    spdlog::error("{} {} -> 500 ({}): {}", req.method, req.path, id, what);
    res.set_header("X-Request-Id", id);
    error(res, 500, "internal", "internal error; the server's log has it under request id " + id);
  });
  http_->set_logger([](const httplib::Request& req, const httplib::Response& res) {
    spdlog::info("{} {} {} -> {} ({} bytes) id={}", req.remote_addr, req.method, req.path, res.status, res.body.size(),
                 res.get_header_value("X-Request-Id"));
  });
  http_->set_error_handler([](const httplib::Request&, httplib::Response& res) {
    if (!res.body.empty()) return;
    if (res.status == 413) error(res, 413, "too_large", "request body too large");
    else if (res.status == 404) error(res, 404, "not_found", "no such route");
    // cpp-httplib rejects a POST without Content-Length before routing (e.g. `curl -X POST` with no -d).
    else if (res.status == 400) error(res, 400, "bad_request", "malformed request: a POST needs a body or Content-Length: 0");
    else error(res, res.status, "http_error", "request failed with HTTP " + std::to_string(res.status));
  });
  routes();
}

HttpServer::~HttpServer() { stop(); }

int HttpServer::bind(const std::string& host, int port) {
  if (port == 0) return http_->bind_to_any_port(host);
  return http_->bind_to_port(host, port) ? port : -1;
}

void HttpServer::serve() { http_->listen_after_bind(); }

void HttpServer::stop() {
  if (http_->is_running()) http_->stop();
}

void HttpServer::routes() {
  http_->Get("/v1/health", [this](const httplib::Request&, httplib::Response& res) {
    reply(res, 200,
          {{"status", "ok"},
           {"engine_version", api::engine_version()},
           {"queued", store_.count("queued")},
           {"running", store_.count("running")},
           {"workers", pool_.workers()},
           {"threads_per_job", pool_.threads_per_job()}});
  });

  // Every registered experiment: its spec fields (default, range, unit, meaning) and curve columns.
  http_->Get("/v1/experiments", [](const httplib::Request&, httplib::Response& res) {
    static const json description = api::experiments_json();  // the registry does not change at run time
    reply(res, 200, description);
  });

  http_->Post("/v1/jobs", [this](const httplib::Request& req, httplib::Response& res) {
    api::Spec spec;
    try {
      spec = api::parse_spec_text(req.body);
    } catch (const api::SpecError& e) {
      return error(res, 400, e.code, e.what(), e.field);
    }
    const std::string hash = api::spec_hash(spec.normalized);
    const std::string experiment = spec.normalized["experiment"].get<std::string>();
    if (req.has_param("reuse") && req.get_param_value("reuse") == "true") {
      if (const auto id = store_.find_succeeded(hash, api::engine_version()))
        return reply(res, 200, {{"id", *id}, {"status", "succeeded"}, {"reused", true}});
    }
    long priority = 0;
    if (!query_int(req, res, "priority", -100, 100, priority)) return;
    const std::int64_t id = store_.submit(spec.normalized.dump(), experiment, spec.label, hash, api::engine_version(),
                                          user_of(req.get_header_value("Authorization")), int(priority));
    pool_.notify();
    reply(res, 201, {{"id", id}, {"status", "queued"}});
  });

  http_->Get("/v1/jobs", [this](const httplib::Request& req, httplib::Response& res) {
    long limit = 50, offset = 0;
    if (!query_int(req, res, "limit", 1, 1000, limit) || !query_int(req, res, "offset", 0, 1L << 40, offset)) return;
    const std::string status = req.has_param("status") ? req.get_param_value("status") : "";
    if (!status.empty() && status != "queued" && status != "running" && status != "succeeded" && status != "failed" &&
        status != "cancelled")
      return error(res, 400, "invalid_value",
                   "'status' must be one of: queued, running, succeeded, failed, cancelled, got '" + status + "'",
                   "status");
    json jobs = json::array();
    for (const JobRecord& j : store_.list(status, int(limit), int(offset))) jobs.push_back(job_json(j, false));
    reply(res, 200, {{"jobs", jobs}, {"limit", limit}, {"offset", offset}});
  });

  http_->Get(R"(/v1/jobs/(\d+))", [this](const httplib::Request& req, httplib::Response& res) {
    const auto id = path_id(req.matches[1]);
    const auto job = id ? store_.get(*id) : std::nullopt;
    if (!job) return error(res, 404, "not_found", "no job " + std::string(req.matches[1]));
    reply(res, 200, job_json(*job, true));
  });

  http_->Post(R"(/v1/jobs/(\d+)/cancel)", [this](const httplib::Request& req, httplib::Response& res) {
    const std::int64_t id = path_id(req.matches[1]).value_or(0);  // 0: no job has it
    switch (store_.request_cancel(id)) {
      case JobStore::CancelResult::cancelled_queued:
        return reply(res, 200, {{"id", id}, {"status", "cancelled"}});
      case JobStore::CancelResult::requested_running:
        return reply(res, 202, {{"id", id}, {"status", "running"}, {"cancel_requested", true}});
      case JobStore::CancelResult::not_found:
        return error(res, 404, "not_found", "no job " + std::string(req.matches[1]));
      case JobStore::CancelResult::wrong_state:
        return error(res, 409, "wrong_state", "job " + std::to_string(id) + " has already finished");
    }
  });

  http_->Get(R"(/v1/jobs/(\d+)/curve)", [this](const httplib::Request& req, httplib::Response& res) {
    const std::int64_t id = path_id(req.matches[1]).value_or(0);  // 0: no job has it
    const auto job = store_.get(id);
    if (!job) return error(res, 404, "not_found", "no job " + std::string(req.matches[1]));
    // A finished job's stored curve; a running job's rows so far; what a cancelled or failed one computed.
    const bool csv = req.has_param("format") && req.get_param_value("format") == "csv";
    if (job->status == "succeeded" && !csv)
      if (const auto json_text = store_.curve_json(id)) return res.set_content(*json_text, "application/json");
    const auto text = store_.live_curve_csv(id);
    if (!text)
      return error(res, 409, "wrong_state", "job " + std::to_string(id) + " is " + job->status + " and has no curve yet");
    if (csv) return res.set_content(*text, "text/csv");
    res.set_content(api::curve_csv_to_json(*text).dump(), "application/json");
  });

  http_->Get(R"(/v1/jobs/(\d+)/snapshots)", [this](const httplib::Request& req, httplib::Response& res) {
    const std::int64_t id = path_id(req.matches[1]).value_or(0);  // 0: no job has it
    if (!store_.get(id)) return error(res, 404, "not_found", "no job " + std::string(req.matches[1]));
    json list = json::array();
    for (const auto& s : store_.snapshots(id)) list.push_back({{"index", s.index}, {"strain", s.strain}, {"bytes", s.bytes}});
    reply(res, 200, {{"snapshots", list}});
  });

  http_->Get(R"(/v1/jobs/(\d+)/snapshots/(\d+))", [this](const httplib::Request& req, httplib::Response& res) {
    const auto id = path_id(req.matches[1]), index = path_id(req.matches[2]);
    const auto blob = id && index && *index <= INT32_MAX ? store_.snapshot(*id, int(*index)) : std::nullopt;
    if (!blob) return error(res, 404, "not_found", "no snapshot " + std::string(req.matches[2]) + " of job " + std::string(req.matches[1]));
    res.set_content(std::string(blob->begin(), blob->end()), "application/json");
  });
}

}  // namespace granulab::server
