#include "api/results.h"

#include <cstdio>

namespace granulab::api {

const char* engine_version() { return "0.1.0"; }

namespace {

// The contract's summary keys, which every experiment's result provides under the same names.
template <class Result>
nlohmann::json run_fields(const Result& r, const char* experiment, const nlohmann::json& spec, std::size_t grains) {
  const double sphere_steps = double(r.spheres) * double(r.steps);
  nlohmann::json s;
  s["experiment"] = experiment;
  s["engine_version"] = engine_version();
  s["spec"] = spec;
  s["grains"] = grains;
  s["spheres"] = r.spheres;
  s["steps"] = r.steps;
  s["time_step"] = r.time_step;
  s["wall_seconds"] = r.wall_seconds;
  s["threads"] = r.threads;
  s["sphere_steps_per_second"] = r.wall_seconds > 0 ? sphere_steps / r.wall_seconds : 0.0;
  s["seconds_per_step"] = r.steps > 0 ? r.wall_seconds / double(r.steps) : 0.0;
  s["sphere_diameter"] = r.sphere_diameter;
  s["normal_stiffness"] = r.normal_stiffness;
  s["spheres_per_face"] = r.spheres_per_face;
  s["neighbor_rebuilds"] = r.rebuilds;
  s["stage_seconds"] = {{"integrate", r.stage_times.integrate},
                        {"sphere_positions", r.stage_times.spheres},
                        {"neighbor_rebuild", r.stage_times.rebuild},
                        {"contact_forces", r.stage_times.contacts},
                        {"wall_forces", r.stage_times.walls}};
  return s;
}

}  // namespace

nlohmann::json summary_json(const TwoCubeResult& r, const nlohmann::json& spec) {
  nlohmann::json s = run_fields(r, "two_cube_sliding", spec, 2);
  s["sphere_spacing"] = r.spacing;
  s["p0"] = r.p0;
  s["slide_speed"] = r.slide_speed;
  s["critical_prestrain"] = r.critical_prestrain;
  s["contact_end_slide_over_size"] = r.contact_end_slide;
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


nlohmann::json summary_json(const CrystalResult& r, const nlohmann::json& spec) {
  const double p0 = spec["loading"]["confining_pressure"].get<double>();
  const auto [yield_strain, yield_deviator] = first_yield_peak(r.curve, p0);
  double peak = 0, peak_strain = 0;
  for (const CrystalRow& row : r.curve)
    if (row.deviator > peak) peak = row.deviator, peak_strain = row.strain;
  nlohmann::json s = run_fields(r, "crystal_compression", spec, r.grains);
  s["knocked_out"] = r.knocked_out;
  s["compression_steps"] = r.compression_steps;
  s["prestrain"] = r.prestrain;
  s["strain_rate"] = r.strain_rate;
  s["initial_length"] = r.initial_length;
  s["cross_section"] = r.cross_section;
  s["confinement"] = {{"steps", r.confinement.steps},
                      {"converged", r.confinement.converged},
                      {"stress_top", r.confinement.stress_top},
                      {"stress_bottom", r.confinement.stress_bottom},
                      {"lateral_stress_x", r.confinement.lateral_stress_x},
                      {"lateral_stress_y", r.confinement.lateral_stress_y},
                      {"kinetic_elastic_ratio", r.confinement.kinetic_elastic_ratio}};
  // The paper does not say whether its sigma_y ~ 7 p0 is the total axial stress or the deviator: both.
  s["first_yield"] = {{"strain", yield_strain},
                      {"deviator", yield_deviator},
                      {"deviator_over_p0", p0 > 0 ? yield_deviator / p0 : 0.0},
                      {"axial_over_p0", p0 > 0 ? (yield_deviator + p0) / p0 : 0.0}};
  s["peak"] = {{"strain", peak_strain}, {"deviator", peak}, {"deviator_over_p0", p0 > 0 ? peak / p0 : 0.0},
               {"axial_over_p0", p0 > 0 ? (peak + p0) / p0 : 0.0}};
  nlohmann::json snaps = nlohmann::json::array();
  for (std::size_t k = 0; k < r.snapshots.size(); ++k)
    snaps.push_back({{"index", k}, {"strain", r.snapshots[k].strain}, {"step", r.snapshots[k].step}});
  s["snapshots"] = snaps;
  return s;
}

std::string crystal_curve_header() {
  return "strain,stress_top,stress_bottom,deviator,lateral_strain_x,lateral_strain_y,lateral_stress,"
         "kinetic_elastic_ratio,contacts,sliding_contacts\n";
}

std::string crystal_curve_row(const CrystalRow& row) {
  char line[512];
  std::snprintf(line, sizeof line, "%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.6g,%zu,%zu\n", row.strain, row.stress_top,
                row.stress_bottom, row.deviator, row.lateral_strain_x, row.lateral_strain_y, row.lateral_stress,
                row.kinetic_elastic_ratio, row.contacts, row.sliding_contacts);
  return line;
}

std::string curve_csv(const CrystalResult& r) {
  std::string out = crystal_curve_header();
  for (const CrystalRow& row : r.curve) out += crystal_curve_row(row);
  return out;
}

std::pair<double, double> first_yield_peak(const std::vector<CrystalRow>& curve, double p0, double drop) {
  double best = 0, at = 0;
  for (const CrystalRow& row : curve) {
    if (best < 0.1 * p0 && row.deviator < 0.1 * p0) continue;  // still in the noise around zero
    if (row.deviator > best) best = row.deviator, at = row.strain;
    else if (row.deviator < best - drop * best) break;
  }
  return {at, best};
}

}  // namespace granulab::api
