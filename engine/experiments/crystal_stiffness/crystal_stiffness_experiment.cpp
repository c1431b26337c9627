#include "engine/experiments/crystal_stiffness/crystal_stiffness_experiment.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "engine/crystal/sample_parameters.h"

namespace granulab {

namespace {

// The directions Young's modulus is reported along, in the lattice's own indices: the cube's three for the cubic
// lattices; a1, the in-plane normal to it and c for HCP.
std::vector<Indices> modulus_directions(LatticeType lattice) {
  if (lattice == LatticeType::hcp) return {{1, 0, 0}, {1, 2, 0}, {0, 0, 1}, {1, 0, 1}};
  return {{1, 0, 0}, {1, 1, 0}, {1, 1, 1}};
}

std::string indices_text(const Indices& d) {
  return "[" + std::to_string(d[0]) + " " + std::to_string(d[1]) + " " + std::to_string(d[2]) + "]";
}

void write_matrix(SummaryWriter& w, const char* key, const Voigt& c) {
  w.begin_list(key);
  for (int i = 0; i < 6; ++i) {
    w.begin_list(nullptr);
    for (int j = 0; j < 6; ++j) w.number(nullptr, c(i, j), "Pa");
    w.end_list();
  }
  w.end_list();
}

void write_pair(SummaryWriter& w, const char* key, double relaxed, double affine, const char* unit) {
  w.begin_group(key);
  w.number("relaxed", relaxed, unit);
  w.number("affine", affine, unit);
  w.end_group();
}

struct StiffnessSummary : ExperimentResult {
  StiffnessResult r;
  StiffnessParams params;
  Quat orientation;  ///< crystal axes -> lab

  void write_summary(SummaryWriter& w) const override {
    write_run_stats(w, r.run);
    w.count("stiffness_steps", r.stiffness_steps);
    write_confinement(w, r.confinement);
    w.number("strain_amplitude", r.amplitude, "-");
    w.count("interior_grains", r.interior_grains);
    w.count("boundary_grains", r.boundary_grains);
    w.number("interior_volume", r.interior_volume, "m^3");
    const bool cubic = params.lattice != LatticeType::hcp;
    w.text("frame", cubic ? "the crystal's cubic axes x, y, z" : "the crystal's a1 along x, c along z");
    const Mat3 to_crystal = orientation.toRotationMatrix().transpose();
    const Voigt relaxed_lab = stiffness_of(r.curve, 1, r.amplitude), affine_lab = stiffness_of(r.curve, 0, r.amplitude);
    const Voigt relaxed = rotate_stiffness(relaxed_lab, to_crystal), affine = rotate_stiffness(affine_lab, to_crystal);
    const Voigt predicted = affine_prediction(params);
    write_matrix(w, "stiffness", relaxed);
    write_matrix(w, "affine_stiffness", affine);
    write_matrix(w, "affine_prediction", predicted);
    w.begin_group("lab_frame");
    w.text("frame", "the sample's: z the loading axis, x the lateral direction");
    write_matrix(w, "stiffness", relaxed_lab);
    write_matrix(w, "affine_stiffness", affine_lab);
    w.end_group();
    w.number("affine_prediction_error", (affine - predicted).cwiseAbs().maxCoeff() / predicted.cwiseAbs().maxCoeff(),
             "-");
    // The confined state the tensor is the tangent of.
    w.begin_group("reference_stress");
    const double p_relaxed = -(r.reference_stress[1][0] + r.reference_stress[1][1] + r.reference_stress[1][2]) / 3;
    w.number("pressure", p_relaxed, "Pa");
    w.number("pressure_over_p0", p_relaxed / params.confining_pressure, "-");
    w.end_group();
    write_pair(w, "symmetry_error", symmetry_error(relaxed), symmetry_error(affine), "-");
    write_pair(w, "nonlinearity", stiffness_nonlinearity(r.curve, 1), stiffness_nonlinearity(r.curve, 0), "-");
    write_pair(w, "hysteresis", stiffness_hysteresis(r.curve, 1), stiffness_hysteresis(r.curve, 0), "-");
    if (cubic) {
      write_pair(w, "cubic_spread", cubic_spread(relaxed), cubic_spread(affine), "-");
      write_pair(w, "cubic_off_pattern", cubic_off_pattern(relaxed), cubic_off_pattern(affine), "-");
      write_pair(w, "zener_ratio", zener_ratio(relaxed), zener_ratio(affine), "-");
    }
    const auto bulk = [](const Voigt& c) { return (c.block<3, 3>(0, 0).sum()) / 9; };
    write_pair(w, "bulk_modulus", bulk(relaxed), bulk(affine), "Pa");
    const double p0 = params.confining_pressure;
    const Vec3 axis = direction_vector(params.lattice, params.axis, 1).normalized();
    const double e_relaxed = directional_modulus(relaxed, axis), e_affine = directional_modulus(affine, axis);
    w.begin_group("along_axis");
    w.text("axis", indices_text(params.axis));
    w.number("relaxed", e_relaxed, "Pa");
    w.number("affine", e_affine, "Pa");
    w.number("prediction", directional_modulus(predicted, axis), "Pa");
    w.number("relaxed_over_p0", e_relaxed / p0, "-");
    w.number("relaxed_over_affine", e_affine > 0 ? e_relaxed / e_affine : 0.0, "-");
    w.end_group();
    w.begin_list("moduli");
    for (const Indices& d : modulus_directions(params.lattice)) {
      const Vec3 n = direction_vector(params.lattice, d, 1).normalized();
      w.begin_group(nullptr);
      w.text("direction", indices_text(d));
      w.number("relaxed", directional_modulus(relaxed, n), "Pa");
      w.number("affine", directional_modulus(affine, n), "Pa");
      w.number("prediction", directional_modulus(predicted, n), "Pa");
      w.number("relaxed_over_p0", directional_modulus(relaxed, n) / p0, "-");
      w.end_group();
    }
    w.end_list();
    std::size_t unconverged = 0;
    double held = 0;
    for (const StiffnessRow& row : r.curve) unconverged += !row.converged, held = std::max(held, row.relax_steps);
    w.count("states_not_converged", unconverged);
    w.number("longest_hold", held, "-");
    w.begin_list("warnings");
    write_confinement_warning(w, r.confinement);
    if (unconverged > 0)
      w.text(nullptr, std::to_string(unconverged) + " relaxed state(s) still changed by more than loading.relax_tolerance " +
                          "when loading.max_relax_transits cut their hold: the relaxed tensor is not at equilibrium");
    const double nonlinear = std::max(stiffness_nonlinearity(r.curve, 1), stiffness_nonlinearity(r.curve, 0));
    if (nonlinear > 0.02)
      w.text(nullptr, "the responses to +delta and -delta differ by " + std::to_string(100 * nonlinear) +
                          " %: faces open or slide at loading.strain_amplitude; a smaller one measures the tangent");
    w.end_list();
  }
};

}  // namespace

void CrystalStiffnessExperiment::parameters(ParameterVisitor& v) {
  StiffnessParams& p = params;
  visit_crystal_sample(v, p);
  // The summary's affine prediction sums face springs of constant stiffness (docs/model.md, "Crystal stiffness").
  v.require(p.material.contact.normal == NormalModel::hooke && p.material.contact.tangential == TangentialModel::linear_history,
            "contact.normal",
            "crystal_stiffness compares with the face-spring prediction of hooke and linear_history contacts: leave "
            "'contact.normal' and 'contact.tangential' at their defaults");
  v.section("loading");
  if (!(p.strain_amplitude > 0)) p.strain_amplitude = default_strain_amplitude(p);
  v.number("strain_amplitude", p.strain_amplitude, {0, 1e-3, true}, "-",
           "delta: each strain component is imposed at +delta and -delta (default: eps0 / 4, a quarter of the "
           "confinement's pre-strain, so that no face opens or slides; at most 1e-3)");
  v.number("ramp_transits", p.ramp_transits, {0, 1000, true}, "-",
           "each relaxed state is reached over this many wave transits L / c of the sample's largest size");
  v.integer("affine_ramp_steps", p.affine_ramp_steps, 1, 100000,
            "each affine state is reached over this many steps (every grain prescribed: no inertia)");
  v.number("relax_tolerance", p.relax_tolerance, {0, 1, true}, "-",
           "a relaxed state is measured once the interior's stress changes by at most this times the largest affine "
           "response C_kk delta (lab frame) between checks four transits apart");
  v.integer("relax_checks", p.relax_checks, 1, 1000, "consecutive checks meeting loading.relax_tolerance");
  v.number("max_relax_transits", p.max_relax_transits, {1, 1e5}, "-",
           "a relaxed state's hold is cut at the first check after this many transits, reported as not converged");
  // The interior must not be empty: found from the lattice now rather than after a confinement.
  std::size_t interior = 1;
  try {
    const std::vector<std::uint8_t> inside = interior_sites(p, sample_lattice(p));
    interior = std::size_t(std::count(inside.begin(), inside.end(), 1));
  } catch (const std::exception&) {
    // a sample that cannot be cut: visit_crystal_sample named its field
  }
  v.require(interior > 0, "crystal.grains_x",
            "the box 'crystal.grains_x' x 'crystal.layers_y' x 'crystal.rows_z' has no grain with a neighbour across "
            "every face: crystal_stiffness measures the stress of such interior grains; make the box larger");
}

Headline CrystalStiffnessExperiment::headline() const {
  return {"imposed_strain",
          {"imposed strain", {1e6, "1e-6"}, {1e6, "1e-6"}},
          {"stress change", {1, "p0", "loading.confining_pressure"}, {1e-3, "kPa"}},
          {{"interior stress change, imposed component", "response"}},
          {{"along_axis.relaxed_over_p0", "Young's modulus along the axis (relaxed)", "p0"},
           {"along_axis.relaxed_over_affine", "relaxed / affine along the axis", "-"},
           {"affine_prediction_error", "affine tensor against the face springs", "-"}},
          {{"moduli", "Young's modulus along the crystal's directions"}},
          {},
          "each state's response against its imposed strain: the slopes are C11 ... C66, affine set then relaxed",
          {}};
}

Workload CrystalStiffnessExperiment::workload() const {
  Workload w = confinement_workload(params);
  const StiffnessSchedule s = stiffness_schedule(params);
  w.steps += s.max_steps;
  const double affine = 2 * kStiffnessStates * double(params.affine_ramp_steps + 1);
  w.phases.push_back({"conditioning and affine states", affine});
  w.phases.push_back({"relaxed states", s.expected_steps - affine});
  w.curve_rows = 2 * (kStiffnessStates + 1);
  w.snapshots = 0;
  return w;
}

std::unique_ptr<ExperimentResult> CrystalStiffnessExperiment::run(ResultSink& sink, const CheckpointSource* resume) const {
  auto out = std::make_unique<StiffnessSummary>();
  CrystalStiffness experiment(params);
  out->r = experiment.run(sink, resume);
  out->params = params;
  out->orientation = experiment.sample().lattice().orientation;
  return out;
}

std::unique_ptr<Experiment> make_crystal_stiffness() { return std::make_unique<CrystalStiffnessExperiment>(); }

}  // namespace granulab
