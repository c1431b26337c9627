// two_cube_sliding as a registered experiment: its spec fields, its run and its summary.
#pragma once

#include <memory>

#include "engine/framework/experiment.h"
#include "engine/experiments/two_cube_sliding/two_cube_sliding.h"

namespace granulab {

class TwoCubeSlidingExperiment : public Experiment {
 public:
  TwoCubeParams params;  ///< the paper's defaults until a spec is read

  void parameters(ParameterVisitor& v) override;
  const std::vector<CurveColumn>& curve_columns() const override { return TwoCubeRow::columns(); }
  Headline headline() const override;
  Workload workload() const override;
  std::unique_ptr<ExperimentResult> run(ResultSink& sink, const CheckpointSource* resume) const override;
};

std::unique_ptr<Experiment> make_two_cube_sliding();

}  // namespace granulab
