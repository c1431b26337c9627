#include "clients/cli/remote.h"

#include "api/headline_json.h"
#include "api/job_status.h"

#include <chrono>
#include <algorithm>
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
#include "clients/cli/estimate.h"
#include "clients/cli/job_watch.h"
#include "clients/cli/vary_option.h"

// After the project headers: <resolv.h>, pulled in by httplib, defines a macro `_res` that breaks Eigen.
#include <httplib.h>

namespace granulab::cli {

namespace {

namespace fs = std::filesystem;
using nlohmann::json;

struct Args {
  std::string command, server, target, out, status, owner, label, ca_file;
  std::vector<std::string> targets;  // every positional argument (wait takes several ids)
  std::vector<std::string> vary;     // sweep: KEY=V1,V2,... (vary_option.h)
  bool reuse = false, priority_given = false, json_out = false, dry_run = false, zip = false;
  int priority = 0, limit = 20;
};

Args parse(int argc, char** argv) {
  Args a;
  a.command = argv[1];
  const char* env = std::getenv("GRANULAB_SERVER");
  a.server = env ? env : "http://127.0.0.1:8080";
  if (const char* ca = std::getenv("GRANULAB_CA_FILE")) a.ca_file = ca;
  for (int i = 2; i < argc; ++i) {
    const std::string s = argv[i];
    auto value = [&]() -> std::string {
      if (i + 1 >= argc) throw std::invalid_argument("'" + s + "' needs a value");
      return argv[++i];
    };
    if (s == "--server") a.server = value();
    else if (s == "--ca-file") a.ca_file = value();
    else if (s == "--out") a.out = value();
    else if (s == "--status") a.status = value();
    else if (s == "--reuse") a.reuse = true;
    else if (s == "--priority") a.priority = api::parse_int_option(s, value(), -100, 100), a.priority_given = true;
    else if (s == "--owner") a.owner = value();
    else if (s == "--limit") a.limit = api::parse_int_option(s, value(), 1, 1000);
    else if (s == "--json") a.json_out = true;
    else if (s == "--dry-run") a.dry_run = true;
    else if (s == "--vary") a.vary.push_back(value());
    else if (s == "--zip") a.zip = true;
    else if (s == "--label") a.label = value();
    else if (s.rfind("--", 0) != 0 && (a.targets.empty() || a.command == "wait")) a.targets.push_back(s);
    else throw std::invalid_argument("unexpected argument '" + s + "'");
  }
  if (!a.targets.empty()) a.target = a.targets.front();
  // http://host:8080/ is the same server as http://host:8080 (cpp-httplib takes no path in its address).
  while (a.server.size() > 1 && a.server.back() == '/') a.server.pop_back();
  return a;
}

// One request; a transport failure or an error status becomes an exception with the server's message.
std::string call(httplib::Client& http, const std::string& server, const std::string& method, const std::string& path,
                 const std::string& body = "") {
  const httplib::Result r = method == "POST"     ? http.Post(path.c_str(), body, "application/json")
                            : method == "DELETE" ? http.Delete(path.c_str())
                                                 : http.Get(path.c_str());
  if (!r) {
    const bool tls = r.error() == httplib::Error::SSLServerVerification || r.error() == httplib::Error::SSLConnection;
    throw std::runtime_error("cannot reach the server at " + server + " (" + httplib::to_string(r.error()) + ")" +
                             (tls ? "; for a certificate of the lab's own, give --ca-file FILE or GRANULAB_CA_FILE" : ""));
  }
  if (r->status >= 400) {
    std::string message = r->body;
    try {
      const json e = json::parse(r->body);
      message = e["error"]["message"].get<std::string>();
    } catch (const std::exception&) {}
    throw std::runtime_error("HTTP " + std::to_string(r->status) + ": " + message);
  }
  return r->body;
}

std::string need_id(const Args& a) {
  if (a.target.empty() || a.target.find_first_not_of("0123456789") != std::string::npos)
    throw std::invalid_argument("'" + a.command + "' needs a job id (a number)");
  return a.target;
}

// A spec file, or standard input for "-" (`... | granulab submit -`).
std::string read_spec(const std::string& file, const char* command) {
  if (file.empty()) throw std::invalid_argument(std::string("'") + command + "' needs a spec file (or - for stdin)");
  std::stringstream spec;
  if (file == "-") {
    spec << std::cin.rdbuf();
    return spec.str();
  }
  std::ifstream in(file, std::ios::binary);
  if (!in) throw std::invalid_argument("cannot read spec file '" + file + "'");
  spec << in.rdbuf();
  return spec.str();
}

// One job as a person reads it: `granulab status ID` without --json.
std::string human_status(const json& j) {
  const auto text = [&](const char* key) { return j.contains(key) && j[key].is_string() ? j[key].get<std::string>() : ""; };
  char line[400];
  std::snprintf(line, sizeof line, "job %lld  %s  %.1f %%  %s%s%s\n", j.value("id", 0LL), text("status").c_str(),
                100 * j.value("progress", 0.0), text("experiment").c_str(), text("label").empty() ? "" : "  ",
                text("label").c_str());
  std::string out = line;
  if (!text("owner").empty()) out += "  owner: " + text("owner") + "\n";
  if (!text("error").empty()) out += "  error: " + text("error") + "\n";
  if (j.contains("summary") && j["summary"].is_object()) {
    const json& s = j["summary"];
    std::snprintf(line, sizeof line, "  %.0f steps in %.1f s\n", s.value("steps", 0.0), s.value("wall_seconds", 0.0));
    out += line;
  }
  for (const json& w : j.value("warnings", json::array()))
    if (w.is_string()) out += "  warning: " + w.get<std::string>() + "\n";
  return out;
}

// A sweep.csv cell: a varied value as its JSON text (a string as itself), in quotes when it holds a comma or a
// quote (a list such as [1,1,0]), as RFC 4180 has it.
std::string csv_cell(const json& value) {
  const std::string text = value.is_string() ? value.get<std::string>() : value.dump();
  if (text.find_first_of(",\"\r\n") == std::string::npos) return text;
  std::string quoted = "\"";
  for (const char c : text) quoted += c == '"' ? std::string("\"\"") : std::string(1, c);
  return quoted + "\"";
}

std::string human_cost(const json& c) {
  char text[600];
  std::string phases;
  for (const json& p : c.value("phases", json::array()))
    if (p.is_object() && p.contains("steps") && p["steps"].is_number()) {
      char one[120];
      std::snprintf(one, sizeof one, "%s%s %.3g", phases.empty() ? "" : ", ", p.value("name", "").c_str(),
                    p["steps"].get<double>());
      phases += one;
    }
  std::snprintf(text, sizeof text,
                "%s: %.4g spheres in %.4g grains, about %.3g steps (%s; at most %.3g); peak memory about %.0f MB; "
                "about %s once started on %d thread(s) (at %.3g sphere-steps/s: %s); %lld jobs queued ahead\n",
                c.value("experiment", "").c_str(), c.value("spheres", 0.0), c.value("grains", 0.0),
                c.value("steps", 0.0), phases.c_str(), c.value("max_steps", 0.0), c.value("memory_bytes", 0.0) / 1e6,
                duration(c.value("expected_seconds", 0.0)).c_str(), c.value("threads", 0),
                c.value("sphere_steps_per_second", 0.0), c.value("rate_basis", "").c_str(),
                c.value("queued_ahead", 0LL));
  std::string out = text;
  if (c.contains("yield_estimate")) out += human_yield_estimate(c["yield_estimate"]);
  if (c.contains("over_budget")) out += "this server would refuse it: " + c["over_budget"].get<std::string>() + "\n";
  return out;
}

void save(const fs::path& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary);
  out << text;
  if (!out) throw std::runtime_error("cannot write '" + path.string() + "'");
}

// granulab sweep SPEC --vary KEY=V1,V2 [--vary ...] [--zip] [--label L] --out DIR: one server sweep, watched
// live; then DIR/sweep.csv (a row per job) and each job's curve and summary under DIR/<id>/.
int run_sweep(httplib::Client& http, const Args& a) {
  if (a.vary.empty()) throw std::invalid_argument(std::string("'sweep' needs at least one --vary\n") + vary_syntax());
  if (a.out.empty()) throw std::invalid_argument("'sweep' needs --out DIR");
  const json vary = parse_vary(a.vary, a.zip);
  json spec = json::parse(read_spec(a.target, "sweep"), nullptr, false);
  if (spec.is_discarded()) throw std::invalid_argument("spec file '" + a.target + "' is not JSON");
  // The output folder first: an unwritable one is an error before any job runs, not after all have.
  const fs::path out(a.out);
  fs::create_directories(out);
  json body = {{"spec", spec}, {"vary", vary}, {"mode", a.zip ? "zip" : "product"}};
  if (!a.label.empty()) body["label"] = a.label;
  const json created =
      json::parse(call(http, a.server, "POST", "/v1/sweeps?priority=" + std::to_string(a.priority), body.dump()));
  const std::string sweep = std::to_string(created["id"].get<long long>());
  std::vector<std::string> ids;
  for (const json& id : created["jobs"]) ids.push_back(std::to_string(id.get<long long>()));
  std::fprintf(stderr, "sweep %s: %zu jobs (%s/v1/sweeps/%s; the page: %s/#/sweeps/%s)\n", sweep.c_str(), ids.size(),
               a.server.c_str(), sweep.c_str(), a.server.c_str(), sweep.c_str());
  const int waited =
      watch_jobs([&](const std::string& path) { return json::parse(call(http, a.server, "GET", path)); }, ids);
  if (waited == 130) return waited;
  // The table: one row per job, its varied values, status and its experiment's key values (the headline's,
  // with where on the curve they are), each column named by its dotted summary path with '_' for '.'.
  const json table = json::parse(call(http, a.server, "GET", "/v1/sweeps/" + sweep));
  const json known = headlines([&](const std::string& path) { return json::parse(call(http, a.server, "GET", path)); });
  const std::string experiment =  // every point of a sweep is of the base spec's experiment
      ids.empty() ? ""
                  : json::parse(call(http, a.server, "GET", "/v1/jobs/" + ids[0])).value("experiment", std::string());
  // Each path once: where a value lies on the curve may be another key value (a strength at a strain that is
  // itself a key value, the strength again as its y), and a table's columns are unique.
  std::vector<std::string> paths;
  if (known.contains(experiment))
    for (const json& v : known[experiment].value("values", json::array()))
      for (const char* k : {"key", "at_x", "at_y"})
        if (v.contains(k) && v[k].is_string() &&
            std::find(paths.begin(), paths.end(), v[k].get<std::string>()) == paths.end())
          paths.push_back(v[k].get<std::string>());
  // A key value that may not exist (a first yield of a crystal that never yields) has its group's verdict beside it:
  // <group>_found true or false and, when false, <group>_reason ("none to 1 % strain: ..."); its cells stay empty.
  std::vector<std::string> statuses;
  if (known.contains(experiment))
    for (const json& v : known[experiment].value("values", json::array()))
      if (v.contains("status") && v["status"].is_string() &&
          std::find(statuses.begin(), statuses.end(), v["status"].get<std::string>()) == statuses.end())
        statuses.push_back(v["status"].get<std::string>());
  std::string csv = "id";
  for (const auto& [key, values] : vary.items()) csv += "," + key;
  csv += ",status";
  for (std::string p : paths) csv += "," + (std::replace(p.begin(), p.end(), '.', '_'), p);
  for (std::string s : statuses) {
    std::replace(s.begin(), s.end(), '.', '_');
    csv += "," + s + "_found," + s + "_reason";
  }
  csv += ",warnings\n";
  for (const json& j : table["jobs"]) {
    csv += std::to_string(j["id"].get<long long>());
    for (const auto& [key, values] : vary.items())
      csv += "," + (j["values"].contains(key) ? csv_cell(j["values"][key]) : "");
    csv += "," + j["status"].get<std::string>();
    for (const std::string& p : paths) {
      char text[40] = "";
      if (const auto v = api::number_at_path(j, p)) std::snprintf(text, sizeof text, "%.9g", *v);
      csv += std::string(",") + text;
    }
    for (const std::string& s : statuses) {
      const json* group = api::value_at_path(j, s);
      const bool judged = group && group->is_object() && group->contains("found") && (*group)["found"].is_boolean();
      const auto reason = api::missing_reason(j, s);
      csv += std::string(",") + (judged ? ((*group)["found"].get<bool>() ? "true" : "false") : "") + "," +
             (reason ? csv_cell(json(*reason)) : "");
    }
    csv += "," + std::to_string(j.value("warnings", json::array()).size()) + "\n";
    const std::string id = std::to_string(j["id"].get<long long>());
    fs::create_directories(out / id);
    if (api::is_finished(j.value("status", ""))) {
      const httplib::Result r = http.Get(("/v1/jobs/" + id + "/curve?format=csv").c_str());
      if (r && r->status == 200) save(out / id / "curve.csv", r->body);
    }
    const json job = json::parse(call(http, a.server, "GET", "/v1/jobs/" + id));
    if (job.contains("summary")) save(out / id / "summary.json", job["summary"].dump(2) + "\n");
  }
  save(out / "sweep.csv", csv);
  std::fprintf(stderr, "sweep %s: %s/sweep.csv and one folder per job\n", sweep.c_str(), a.out.c_str());
  return waited;
}

}  // namespace

int run_remote(int argc, char** argv) {
  const Args a = parse(argc, argv);
  httplib::Client http(a.server);
  // An https server's certificate is checked against the system's authorities, or this file's (a lab's own
  // certificate, self-signed).
  if (!a.ca_file.empty()) http.set_ca_cert_path(a.ca_file);
  http.set_read_timeout(60, 0);
  if (const char* token = std::getenv("GRANULAB_TOKEN")) http.set_bearer_token_auth(token);
  if (a.command == "submit") {
    const std::string spec = read_spec(a.target, "submit");
    std::string path = "/v1/jobs?priority=" + std::to_string(a.priority);
    if (a.reuse) path += "&reuse=true";
    if (a.dry_run) path += "&dry_run=true";
    const std::string reply = call(http, a.server, "POST", path, spec);
    // The id alone, for scripts (ID=$(granulab submit spec.json)); --json for the whole reply.
    if (a.json_out) std::cout << reply;
    else if (a.dry_run) std::cout << human_cost(json::parse(reply));
    else std::cout << json::parse(reply)["id"].get<long long>() << "\n";
    return 0;
  }
  if (a.command == "sweep") return run_sweep(http, a);
  // Each prints a line for a person, or with --json the server's answer as it is, for scripts.
  if (a.command == "status") {
    const json job = json::parse(call(http, a.server, "GET", "/v1/jobs/" + need_id(a)));
    std::cout << (a.json_out ? job.dump(2) + "\n" : human_status(job));
    return 0;
  }
  if (a.command == "cancel" || a.command == "delete" || a.command == "priority") {
    const std::string id = need_id(a);
    if (a.command == "priority" && !a.priority_given) throw std::invalid_argument("'priority' needs --priority N");
    const std::string reply =
        a.command == "cancel"   ? call(http, a.server, "POST", "/v1/jobs/" + id + "/cancel")
        : a.command == "delete" ? call(http, a.server, "DELETE", "/v1/jobs/" + id)
                                : call(http, a.server, "POST",
                                       "/v1/jobs/" + id + "/priority?value=" + std::to_string(a.priority));
    if (a.json_out) {
      std::cout << reply << (reply.empty() || reply.back() != '\n' ? "\n" : "");
      return 0;
    }
    const json answer = json::parse(reply, nullptr, false);
    const std::string status = answer.is_object() && answer.contains("status") && answer["status"].is_string()
                                   ? answer["status"].get<std::string>()
                                   : "";
    if (a.command == "cancel") std::cout << "job " << id << ": " << (status.empty() ? "cancel asked" : status) << "\n";
    else if (a.command == "delete") std::cout << "job " << id << " deleted\n";
    else std::cout << "job " << id << ": priority " << a.priority << "\n";
    return 0;
  }
  if (a.command == "list") {
    std::string path = "/v1/jobs?limit=" + std::to_string(a.limit);
    if (!a.status.empty()) path += "&status=" + httplib::detail::encode_query_param(a.status);
    if (!a.owner.empty()) path += "&owner=" + httplib::detail::encode_query_param(a.owner);
    const json list = json::parse(call(http, a.server, "GET", path));  // named: a temporary would dangle
    if (a.json_out) {
      std::cout << list.dump(2) << "\n";
      return 0;
    }
    for (const json& j : list["jobs"]) {
      const std::string owner = j.contains("owner") && j["owner"].is_string() ? j["owner"].get<std::string>() : "";
      std::printf("%6lld  %-10s %5.1f %%  %-12s %-20s %s%s\n", j["id"].get<long long>(),
                  j["status"].get<std::string>().c_str(), 100 * j["progress"].get<double>(),
                  owner.empty() ? "-" : owner.c_str(), j["experiment"].get<std::string>().c_str(),
                  j["label"].get<std::string>().c_str(),
                  j.contains("warnings") ? ("  (" + std::to_string(j["warnings"].size()) + " warnings)").c_str() : "");
    }
    return 0;
  }
  if (a.command == "wait") {
    if (a.targets.empty()) throw std::invalid_argument("'wait' needs one or more job ids");
    for (const std::string& id : a.targets)
      if (id.find_first_not_of("0123456789") != std::string::npos)
        throw std::invalid_argument("'" + id + "' is not a job id");
    return watch_jobs([&](const std::string& path) { return json::parse(call(http, a.server, "GET", path)); },
                      a.targets);
  }
  if (a.command == "results") {
    const std::string id = need_id(a);
    if (a.out.empty()) throw std::invalid_argument("'results' needs --out DIR");
    const fs::path out(a.out);
    // The job first: an unknown id or a refused read leaves no empty folder behind.
    const json job = json::parse(call(http, a.server, "GET", "/v1/jobs/" + id));
    fs::create_directories(out / "snapshots");
    save(out / "curve.csv", call(http, a.server, "GET", "/v1/jobs/" + id + "/curve?format=csv"));
    // A job that has not succeeded has no summary: its rows and snapshots so far are still worth having.
    const bool finished = job.contains("summary");
    if (finished) save(out / "summary.json", job["summary"].dump(2) + "\n");
    save(out / "spec.json", job["spec"].dump(2) + "\n");
    if (const httplib::Result svg = http.Get(("/v1/jobs/" + id + "/curve.svg").c_str()); svg && svg->status == 200)
      save(out / "curve.svg", svg->body);
    // Every snapshot in every format, named as `granulab run` names them.
    const json snapshots = json::parse(call(http, a.server, "GET", "/v1/jobs/" + id + "/snapshots"));
    for (const json& s : snapshots["snapshots"]) {
      const std::string k = std::to_string(s["index"].get<int>()), base = "/v1/jobs/" + id + "/snapshots/" + k;
      const fs::path stem = out / "snapshots" / ("snapshot_" + k);
      save(stem.string() + ".json", call(http, a.server, "GET", base));
      save(stem.string() + ".dump", call(http, a.server, "GET", base + "?format=dump"));
      save(stem.string() + "_grains.vtk", call(http, a.server, "GET", base + "?format=vtk"));
      save(stem.string() + "_interfaces.vtk", call(http, a.server, "GET", base + "?format=vtk_interfaces"));
      save(stem.string() + "_contacts.vtk", call(http, a.server, "GET", base + "?format=contacts_vtk"));
      save(stem.string() + "_contacts.dump", call(http, a.server, "GET", base + "?format=contacts_dump"));
      save(stem.string() + "_meshes.vtk", call(http, a.server, "GET", base + "?format=mesh_vtk"));
      // The DIC-like map when the server can make one (an older server, or an old snapshot, may not).
      for (const auto& [suffix, format] : {std::pair<const char*, const char*>{"_dic.csv", "dic_csv"}, {"_dic.vtk", "dic_vtk"}})
        if (const httplib::Result r = http.Get((base + "?format=" + format).c_str()); r && r->status == 200)
          save(stem.string() + suffix, r->body);
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
