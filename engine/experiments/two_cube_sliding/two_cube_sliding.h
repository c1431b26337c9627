// Experiment 1 of the paper (section 3, Figs. 3-5): two overlapping-sphere cubes face to face, centre
// distance l(1 - eps0), the top one sliding by u along x while the pre-strain is held. Both cubes move
// by prescribed motion (equivalent to the paper's walls, docs/model.md), so the measured forces are the
// contact forces alone. Theory (eq. 1): P = E l^2 eps0 (1 - u/l), T = f P; P0 = E l^2 eps0.
#pragma once

#include <cstdint>
#include <vector>

#include "engine/framework/result_sink.h"
#include "engine/model/model.h"
#include "engine/world/world.h"

namespace granulab {

struct TwoCubeParams {
  GrainGeometry grain{Shape::cube, 0.01, 10, 0.75};
  Material material{3.0e9, 1200, 0.3, 2.0 / 7, 0.05, {}};
  double prestrain = 0.005;       ///< eps0 (-)
  double max_slide = 0.8;         ///< final u / l (-)
  double rate_number = 1e-5;      ///< slide speed / sqrt(E/rho) (-)
  int curve_points = 400;         ///< rows of the curve after u = 0
  double time_step_factor = 0.2;  ///< dt / t0
  double skin_factor = 0.1;       ///< neighbour skin / d
  std::string kernel = "auto";    ///< the contact kernel's instruction set (pair_kernels()); auto: the widest here
};

struct TwoCubeRow {
  double slide_over_size;     ///< u / l (-)
  double normal_over_p0;      ///< P / P0 (-)
  double tangential_over_p0;  ///< T / P0 (-)
  double normal_force;        ///< P, compressive positive (N)
  double tangential_force;    ///< T, positive when it resists the slide (N)

  /// The curve's columns (docs/api.md), in the order of values().
  static const std::vector<CurveColumn>& columns();
  std::vector<double> values() const;
};

struct TwoCubeResult {
  std::vector<TwoCubeRow> curve;
  RunStats run;                   ///< steps, timings and model numbers (d, k_n, N_f)
  double spacing = 0;             ///< sphere spacing s = d(1 - kappa) (m)
  double p0 = 0;                  ///< P0 = E l^2 eps0 (N)
  double slide_speed = 0;         ///< m/s
  double critical_prestrain = 0;  ///< (d - sqrt(d^2 - s^2)) / l (-)
  double contact_end_slide = 0;   ///< theory: u/l where the last sphere pair separates (-)
};

class TwoCubeSliding {
 public:
  explicit TwoCubeSliding(const TwoCubeParams& params);

  World& world() { return world_; }
  const TwoCubeParams& params() const { return params_; }
  double p0() const { return p0_; }

  /// Places the top cube at slide u (m) at rest and evaluates the forces with the current history.
  /// Used to check the exact laws of the model at chosen offsets.
  void place_at(double u);
  /// P (N, compressive positive) and T (N, resisting a +x slide) on the top cube, last evaluation.
  double normal_force() const;
  double tangential_force() const;

  /// Slides from u = 0 to max_slide * l, each curve row to `sink` as it is recorded; the sink may stop
  /// the run (throws Cancelled).
  /// `resume`: a checkpoint this run's sink was given (ResultSink::checkpoint), or empty.
  TwoCubeResult run(ResultSink& sink, const CheckpointSource* resume = nullptr);
  TwoCubeResult run() {
    ResultSink none;
    return run(none);
  }

 private:
  TwoCubeParams params_;
  GrainTemplate grain_;
  World world_;
  BodyId bottom_ = 0, top_ = 0;
  double p0_ = 0, gap_ = 0;
};

}  // namespace granulab
