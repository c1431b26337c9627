// The confinement phase alone, as an experiment: the crystal sample of every crystal experiment
// (engine/crystal/) confined by the vacuum bag and the servo-controlled platens, with its approach to
// equilibrium recorded at every check. For tuning and checking the confinement (how fast a sample comes
// to rest, whether it does), without paying for a compression.
#pragma once

#include <memory>
#include <vector>

#include "engine/crystal/confinement.h"
#include "engine/framework/experiment.h"

namespace granulab {

struct ConfinementRow {
  double step;                   ///< time steps since the start of confinement (-)
  double stress_top;             ///< top platen stress (Pa)
  double stress_bottom;          ///< bottom platen stress (Pa)
  double lateral_stress_x;       ///< lateral stress the packing carries along x (Pa)
  double lateral_stress_y;       ///< along y (Pa)
  double kinetic_elastic_ratio;  ///< kinetic / elastic energy (-)

  static const std::vector<CurveColumn>& columns();
  std::vector<double> values() const;
};

class CrystalConfinementExperiment : public Experiment {
 public:
  CrystalSampleParams params;  ///< the paper's defaults until a spec is read

  void parameters(ParameterVisitor& v) override;
  const std::vector<CurveColumn>& curve_columns() const override { return ConfinementRow::columns(); }
  Headline headline() const override;
  Workload workload() const override;
  std::unique_ptr<ExperimentResult> run(ResultSink& sink, const CheckpointSource* resume) const override;
};

std::unique_ptr<Experiment> make_crystal_confinement();

}  // namespace granulab
