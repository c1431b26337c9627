#include "clients/cli/estimate.h"

#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <sstream>
#include <stdexcept>

#include "api/spec.h"
#include "api/summary_json.h"

namespace granulab::cli {

using nlohmann::json;

std::string human_yield_estimate(const json& e) {
  // The engine's own sentence: the keys are the experiments' (a shear's column names among them).
  return e.is_object() && e.contains("text") && e["text"].is_string() ? e["text"].get<std::string>() + "\n" : "";
}

int run_estimate(int argc, char** argv) {
  std::string path;
  bool json_out = false;
  for (int i = 2; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--json") json_out = true;
    else if (path.empty() && a.rfind("--", 0) != 0) path = a;
    else throw std::invalid_argument("unexpected argument '" + a + "'; usage: granulab estimate SPEC.json [--json]");
  }
  if (path.empty()) throw std::invalid_argument("estimate needs SPEC.json; usage: granulab estimate SPEC.json [--json]");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::invalid_argument("cannot read spec file '" + path + "'");
  std::stringstream text;
  text << in.rdbuf();
  api::Spec spec;
  try {
    spec = api::parse_spec_text(text.str());
  } catch (const api::SpecError& e) {
    throw std::invalid_argument(path + ": " + e.what());
  }
  const Workload w = spec.experiment->workload();
  json phases = json::array();
  for (const WorkPhase& p : w.phases) phases.push_back({{"name", p.name}, {"steps", p.steps}});
  json out = {{"experiment", spec.name()}, {"spheres", std::llround(w.spheres)},  {"grains", std::llround(w.grains)},
              {"steps", w.expected_steps()}, {"phases", phases}, {"max_steps", w.steps}};
  if (const json e = api::yield_estimate_json(*spec.experiment); !e.is_null()) out["yield_estimate"] = e;
  if (json_out) {
    std::cout << out.dump(2) << "\n";
    return 0;
  }
  std::printf("%s: %.4g spheres in %.4g grains, about %.3g steps (at most %.3g)\n", spec.name(), w.spheres, w.grains,
              w.expected_steps(), w.steps);
  std::cout << (out.contains("yield_estimate") ? human_yield_estimate(out["yield_estimate"])
                                                : std::string("no yield estimate for this experiment\n"));
  return 0;
}

}  // namespace granulab::cli
