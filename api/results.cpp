#include "api/results.h"

#include <cstdio>

namespace granulab::api {

const char* engine_version() { return "0.1.0"; }

nlohmann::json summary_json(const TwoCubeResult& r, const nlohmann::json& spec) {
  const double sphere_steps = double(r.spheres) * double(r.steps);
  nlohmann::json s;
  s["experiment"] = "two_cube_sliding";
  s["engine_version"] = engine_version();
  s["spec"] = spec;
  s["grains"] = 2;
  s["spheres"] = r.spheres;
  s["steps"] = r.steps;
  s["time_step"] = r.time_step;
  s["wall_seconds"] = r.wall_seconds;
  s["threads"] = r.threads;
  s["sphere_steps_per_second"] = r.wall_seconds > 0 ? sphere_steps / r.wall_seconds : 0.0;
  s["sphere_diameter"] = r.sphere_diameter;
  s["sphere_spacing"] = r.spacing;
  s["normal_stiffness"] = r.normal_stiffness;
  s["spheres_per_face"] = r.spheres_per_face;
  s["p0"] = r.p0;
  s["slide_speed"] = r.slide_speed;
  s["critical_prestrain"] = r.critical_prestrain;
  s["contact_end_slide_over_size"] = r.contact_end_slide;
  s["neighbor_rebuilds"] = r.rebuilds;
  s["stage_seconds"] = {{"integrate", r.stage_times.integrate},
                        {"sphere_positions", r.stage_times.spheres},
                        {"neighbor_rebuild", r.stage_times.rebuild},
                        {"contact_forces", r.stage_times.contacts},
                        {"wall_forces", r.stage_times.walls}};
  return s;
}

std::string curve_csv(const TwoCubeResult& r) {
  std::string out = "slide_over_size,normal_over_p0,tangential_over_p0,normal_force,tangential_force\n";
  char line[256];
  for (const TwoCubeRow& row : r.curve) {
    std::snprintf(line, sizeof line, "%.9g,%.9g,%.9g,%.9g,%.9g\n", row.slide_over_size, row.normal_over_p0,
                  row.tangential_over_p0, row.normal_force, row.tangential_force);
    out += line;
  }
  return out;
}

}  // namespace granulab::api
