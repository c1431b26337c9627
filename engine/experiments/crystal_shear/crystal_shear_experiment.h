// crystal_shear as a registered experiment: its spec fields, its run and its summary.
#pragma once

#include <memory>

#include "engine/experiments/crystal_shear/crystal_shear.h"
#include "engine/framework/experiment.h"

namespace granulab {

class CrystalShearExperiment : public Experiment {
 public:
  ShearParams params;  ///< the defaults until a spec is read

  void parameters(ParameterVisitor& v) override;
  const std::vector<CurveColumn>& curve_columns() const override { return ShearRow::columns(); }
  Headline headline() const override;
  Workload workload() const override;
  std::optional<YieldEstimate> yield_estimate() const override;
  std::unique_ptr<ExperimentResult> run(ResultSink& sink, const CheckpointSource* resume) const override;
};

std::unique_ptr<Experiment> make_crystal_shear();

}  // namespace granulab
