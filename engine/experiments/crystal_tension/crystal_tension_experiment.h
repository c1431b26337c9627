// crystal_tension as a registered experiment: its spec fields, its run and its summary.
#pragma once

#include <memory>

#include "engine/experiments/crystal_tension/crystal_tension.h"
#include "engine/framework/experiment.h"

namespace granulab {

class CrystalTensionExperiment : public Experiment {
 public:
  TensionParams params;  ///< the defaults until a spec is read

  void parameters(ParameterVisitor& v) override;
  const std::vector<CurveColumn>& curve_columns() const override { return TensionRow::columns(); }
  Headline headline() const override;
  Workload workload() const override;
  std::unique_ptr<ExperimentResult> run(ResultSink& sink, const CheckpointSource* resume) const override;
};

std::unique_ptr<Experiment> make_crystal_tension();

}  // namespace granulab
