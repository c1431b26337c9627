#include "api/spec.h"

#include "api/bounded_json.h"
#include "api/spec_reader.h"

namespace granulab::api {

void visit_job_fields(ParameterVisitor& v, JobFields& f) {
  std::vector<std::string> names;
  for (const ExperimentType& t : experiment_types()) names.push_back(t.name);
  if (f.experiment.empty()) f.experiment = names.front();
  v.section("");
  v.choice("experiment", f.experiment, names, "which experiment (docs/spec.md lists each one's fields)");
  v.text("label", f.label, 200, "free text");
  v.section("run");
  v.integer("threads", f.threads, 0, 256, "OpenMP threads, 0 = all cores (on a daemon: at most its threads per job)");
}

Spec parse_spec(const nlohmann::json& document) {
  if (!document.is_object())
    throw SpecError("wrong_type", "", "the spec must be a JSON object, got " + std::string(document.type_name()));
  SpecReader reader(document);
  JobFields fields;
  visit_job_fields(reader, fields);
  Spec spec;
  spec.type = find_experiment_type(fields.experiment);
  spec.label = fields.label;
  spec.threads = fields.threads;
  std::unique_ptr<Experiment> experiment = spec.type->make();
  experiment->parameters(reader);
  spec.normalized = reader.finish();
  spec.experiment = std::move(experiment);
  return spec;
}

Spec parse_spec_text(const std::string& text) { return parse_spec(parse_bounded_json(text)); }

}  // namespace granulab::api
