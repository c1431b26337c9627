#include "api/runner.h"

#include <cstdio>
#include <sstream>

#include "api/results.h"
#include "api/snapshot_files.h"

namespace granulab::api {

RunOutput run_spec(const Spec& spec, const ProgressFn& progress) {
  RunOutput out;
  if (spec.experiment == Experiment::two_cube_sliding) {
    TwoCubeSliding experiment(spec.two_cube);
    const TwoCubeResult r = experiment.run(progress);
    out.summary = summary_json(r, spec.normalized);
    out.curve_csv = curve_csv(r);
  } else {
    CrystalCompression experiment(spec.crystal);
    const CrystalResult r = experiment.run(progress);
    out.summary = summary_json(r, spec.normalized);
    out.curve_csv = curve_csv(r);
    for (const CrystalSnapshot& s : r.snapshots) out.snapshots.emplace_back(s.strain, snapshot_json(s));
  }
  return out;
}

nlohmann::json curve_csv_to_json(const std::string& csv) {
  std::istringstream in(csv);
  std::string line;
  std::vector<std::string> names;
  nlohmann::json out = nlohmann::json::object();
  if (std::getline(in, line)) {
    std::istringstream header(line);
    for (std::string name; std::getline(header, name, ',');) {
      names.push_back(name);
      out[name] = nlohmann::json::array();
    }
  }
  while (std::getline(in, line)) {
    std::istringstream row(line);
    std::size_t k = 0;
    for (std::string cell; std::getline(row, cell, ',') && k < names.size(); ++k) out[names[k]].push_back(std::stod(cell));
  }
  out["columns"] = names;
  return out;
}

std::string spec_hash(const nlohmann::json& normalized_spec) {
  std::uint64_t h = 1469598103934665603ull;  // FNV-1a over the canonical dump (keys sorted by nlohmann)
  for (unsigned char c : normalized_spec.dump()) h = (h ^ c) * 1099511628211ull;
  char buf[17];
  std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(h));
  return buf;
}

}  // namespace granulab::api
