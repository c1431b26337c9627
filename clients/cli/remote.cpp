#include "clients/cli/remote.h"

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include <nlohmann/json.hpp>

#include "api/int_option.h"

// After the project headers: <resolv.h>, pulled in by httplib, defines a macro `_res` that breaks Eigen.
#include <httplib.h>

namespace granulab::cli {

namespace {

namespace fs = std::filesystem;
using nlohmann::json;

struct Args {
  std::string command, server, target, out, status, owner;
  bool reuse = false, priority_given = false;
  int priority = 0, limit = 20;
};

Args parse(int argc, char** argv) {
  Args a;
  a.command = argv[1];
  const char* env = std::getenv("GRANULAB_SERVER");
  a.server = env ? env : "http://127.0.0.1:8080";
  for (int i = 2; i < argc; ++i) {
    const std::string s = argv[i];
    auto value = [&]() -> std::string {
      if (i + 1 >= argc) throw std::invalid_argument("'" + s + "' needs a value");
      return argv[++i];
    };
    if (s == "--server") a.server = value();
    else if (s == "--out") a.out = value();
    else if (s == "--status") a.status = value();
    else if (s == "--reuse") a.reuse = true;
    else if (s == "--priority") a.priority = api::parse_int_option(s, value(), -100, 100), a.priority_given = true;
    else if (s == "--owner") a.owner = value();
    else if (s == "--limit") a.limit = api::parse_int_option(s, value(), 1, 1000);
    else if (a.target.empty() && s.rfind("--", 0) != 0) a.target = s;
    else throw std::invalid_argument("unexpected argument '" + s + "'");
  }
  return a;
}

// One request; a transport failure or an error status becomes an exception with the server's message.
std::string call(httplib::Client& http, const std::string& server, const std::string& method, const std::string& path,
                 const std::string& body = "") {
  const httplib::Result r = method == "POST"     ? http.Post(path.c_str(), body, "application/json")
                           : method == "DELETE" ? http.Delete(path.c_str())
                                                : http.Get(path.c_str());
  if (!r) throw std::runtime_error("cannot reach the server at " + server + " (" + httplib::to_string(r.error()) + ")");
  if (r->status >= 400) {
    std::string message = r->body;
    try {
      const json e = json::parse(r->body);
      message = e["error"]["message"].get<std::string>();
    } catch (const std::exception&) {
    }
    throw std::runtime_error("HTTP " + std::to_string(r->status) + ": " + message);
  }
  return r->body;
}

std::string need_id(const Args& a) {
  if (a.target.empty() || a.target.find_first_not_of("0123456789") != std::string::npos)
    throw std::invalid_argument("'" + a.command + "' needs a job id (a number)");
  return a.target;
}

void save(const fs::path& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary);
  out << text;
  if (!out) throw std::runtime_error("cannot write '" + path.string() + "'");
}

}  // namespace

int run_remote(int argc, char** argv) {
  const Args a = parse(argc, argv);
  httplib::Client http(a.server);
  http.set_read_timeout(60, 0);
  if (const char* token = std::getenv("GRANULAB_TOKEN")) http.set_bearer_token_auth(token);
  if (a.command == "submit") {
    if (a.target.empty()) throw std::invalid_argument("'submit' needs a spec file");
    std::ifstream in(a.target, std::ios::binary);
    if (!in) throw std::invalid_argument("cannot read spec file '" + a.target + "'");
    std::stringstream spec;
    spec << in.rdbuf();
    std::string path = "/v1/jobs?priority=" + std::to_string(a.priority);
    if (a.reuse) path += "&reuse=true";
    std::cout << call(http, a.server, "POST", path, spec.str());
    return 0;
  }
  if (a.command == "status") {
    std::cout << json::parse(call(http, a.server, "GET", "/v1/jobs/" + need_id(a))).dump(2) << "\n";
    return 0;
  }
  if (a.command == "cancel") {
    std::cout << call(http, a.server, "POST", "/v1/jobs/" + need_id(a) + "/cancel");
    return 0;
  }
  if (a.command == "delete") {
    std::cout << call(http, a.server, "DELETE", "/v1/jobs/" + need_id(a));
    return 0;
  }
  if (a.command == "priority") {
    if (!a.priority_given) throw std::invalid_argument("'priority' needs --priority N");
    std::cout << call(http, a.server, "POST", "/v1/jobs/" + need_id(a) + "/priority?value=" + std::to_string(a.priority));
    return 0;
  }
  if (a.command == "list") {
    std::string path = "/v1/jobs?limit=" + std::to_string(a.limit);
    if (!a.status.empty()) path += "&status=" + httplib::detail::encode_query_param(a.status);
    if (!a.owner.empty()) path += "&owner=" + httplib::detail::encode_query_param(a.owner);
    const json list = json::parse(call(http, a.server, "GET", path));  // named: a temporary would dangle
    for (const json& j : list["jobs"])
      std::printf("%6lld  %-10s %5.1f %%  %-20s %s\n", j["id"].get<long long>(), j["status"].get<std::string>().c_str(),
                  100 * j["progress"].get<double>(), j["experiment"].get<std::string>().c_str(),
                  j["label"].get<std::string>().c_str());
    return 0;
  }
  if (a.command == "wait") {
    const std::string id = need_id(a);
    for (;;) {
      const json j = json::parse(call(http, a.server, "GET", "/v1/jobs/" + id));
      const std::string status = j["status"];
      if (status == "succeeded") {
        std::fprintf(stderr, "job %s succeeded\n", id.c_str());
        return 0;
      }
      if (status == "failed" || status == "cancelled") {
        std::fprintf(stderr, "job %s %s%s\n", id.c_str(), status.c_str(),
                     j.contains("error") ? (": " + j["error"].get<std::string>()).c_str() : "");
        return 1;
      }
      std::fprintf(stderr, "job %s %s %5.1f %%%s\n", id.c_str(), status.c_str(), 100 * j["progress"].get<double>(),
                   j.contains("eta_seconds") ? (", ETA " + std::to_string(int(j["eta_seconds"].get<double>())) + " s").c_str() : "");
      std::this_thread::sleep_for(std::chrono::seconds(2));
    }
  }
  if (a.command == "results") {
    const std::string id = need_id(a);
    if (a.out.empty()) throw std::invalid_argument("'results' needs --out DIR");
    const fs::path out(a.out);
    fs::create_directories(out / "snapshots");
    const json job = json::parse(call(http, a.server, "GET", "/v1/jobs/" + id));
    save(out / "curve.csv", call(http, a.server, "GET", "/v1/jobs/" + id + "/curve?format=csv"));
    // A job that has not succeeded has no summary: its rows and snapshots so far are still worth having.
    const bool finished = job.contains("summary");
    if (finished) save(out / "summary.json", job["summary"].dump(2) + "\n");
    const json snapshots = json::parse(call(http, a.server, "GET", "/v1/jobs/" + id + "/snapshots"));
    for (const json& s : snapshots["snapshots"]) {
      const std::string k = std::to_string(s["index"].get<int>());
      save(out / "snapshots" / ("snapshot_" + k + ".json"), call(http, a.server, "GET", "/v1/jobs/" + id + "/snapshots/" + k));
    }
    if (!finished) {
      std::fprintf(stderr, "job %s is %s: its results so far are in %s (no summary.json)\n", id.c_str(),
                   job.value("status", "").c_str(), a.out.c_str());
      return 1;
    }
    std::fprintf(stderr, "results of job %s in %s\n", id.c_str(), a.out.c_str());
    return 0;
  }
  throw std::invalid_argument("unknown command '" + a.command + "'");
}

}  // namespace granulab::cli
