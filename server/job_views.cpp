#include "server/job_views.h"

#include <algorithm>

#include "api/curve_format.h"
#include "api/snapshot_files.h"
#include "api/pictures/curve_pictures.h"
#include "server/http/replies.h"

namespace granulab::server {

using nlohmann::json;

json job_json(const JobRecord& j, bool full) {
  json out = {{"id", j.id},
              {"status", api::status_name(j.status)},
              {"label", j.label},
              {"experiment", j.experiment},
              {"progress", j.progress},
              {"created_ms", j.created_ms},
              {"started_ms", j.started_ms},
              {"finished_ms", j.finished_ms},
              {"priority", j.priority}};
  if (j.eta_seconds >= 0 && j.status == JobStatus::running) out["eta_seconds"] = j.eta_seconds;
  if (!j.error.empty()) out["error"] = j.error;
  if (json warnings = warnings_of(j); !warnings.empty()) out["warnings"] = std::move(warnings);
  if (!j.owner.empty()) out["owner"] = j.owner;
  if (!j.slurm_job_id.empty()) out["slurm_job_id"] = j.slurm_job_id;
  if (!j.slurm_state.empty()) out["slurm_state"] = j.slurm_state;  // e.g. "PENDING (Resources)"
  if (j.sweep_id != 0) {
    out["sweep_id"] = j.sweep_id;
    out["sweep_values"] = json::parse(j.sweep_values, nullptr, false);
  }
  if (full) {
    out["spec"] = json::parse(j.spec_json);
    out["spec_hash"] = j.spec_hash;
    out["engine_version"] = j.engine_version;
    if (!j.summary_json.empty()) out["summary"] = json::parse(j.summary_json);
  }
  return out;
}

json parsed_or_null(const std::string& text) {
  json j = json::parse(text, nullptr, false);
  return j.is_discarded() ? json() : j;
}

json latest_values(JobStore& store, const JobRecord& job) {
  if (job.status != JobStatus::running) return nullptr;
  const auto row = store.latest_row(job.id);
  if (!row) return nullptr;
  const json columns = api::curve_rows_to_json(row->first, {row->second});
  json out = json::object();
  for (const auto& name : columns["columns"])
    if (!columns[name.get<std::string>()].empty()) out[name.get<std::string>()] = columns[name.get<std::string>()][0];
  return out;
}

json warnings_of(const JobRecord& job) {
  if (job.summary_json.empty()) return json::array();
  const json summary = json::parse(job.summary_json, nullptr, false);
  if (!summary.is_object() || !summary.contains("warnings") || !summary["warnings"].is_array()) return json::array();
  json out = json::array();
  for (const json& w : summary["warnings"])
    if (w.is_string()) out.push_back(w);
  return out;
}

std::optional<json> curve_columns(JobStore& store, const JobRecord& job) {
  if (job.status == JobStatus::succeeded)
    if (const auto text = store.curve_json(job.id)) {
      json curve = json::parse(*text, nullptr, false);
      if (!curve.is_discarded()) return curve;
    }
  const auto rows = store.live_rows(job.id);
  if (!rows) return std::nullopt;
  return api::curve_rows_to_json(rows->first, rows->second);
}

std::optional<std::string> job_curve_svg(JobStore& store, const JobRecord& job, const pictures::CurveChoice& choice) {
  const auto curve = curve_columns(store, job);
  if (!curve) return std::nullopt;
  pictures::LinePlot plot =
      pictures::job_curve_plot(parsed_or_null(job.spec_json), *curve, parsed_or_null(job.summary_json), choice);
  plot.title = job.label.empty() ? "job " + std::to_string(job.id) : job.label;
  if (job.status != JobStatus::succeeded) plot.title += std::string(" (") + api::status_name(job.status) + ")";
  return pictures::line_plot_svg(plot);
}

bool curve_choice(const http::Request& req, http::Response& res, const json& spec, pictures::CurveChoice& choice) {
  const std::string units = req.has_param("units") ? req.get_param_value("units") : "natural";
  if (units != "natural" && units != "si") {
    http::error(res, 400, "invalid_value", "'units' must be natural or si, got '" + units + "'", "units");
    return false;
  }
  choice.units = units == "si" ? pictures::Units::si : pictures::Units::natural;
  if (!req.has_param("y")) return true;
  choice.y = req.get_param_value("y");
  const std::vector<std::string> names = pictures::curve_column_names(spec);
  if (std::find(names.begin(), names.end(), choice.y) != names.end()) return true;
  std::string list;
  for (const std::string& n : names) list += (list.empty() ? "" : ", ") + n;
  http::error(res, 400, "invalid_value",
              "'y' must be a curve column of this experiment (" + list + "), got '" + choice.y + "'", "y");
  return false;
}

std::optional<GrainSnapshot> stored_snapshot(JobStore& store, const JobRecord& job, const std::string& index,
                                             http::Response& res) {
  const auto k = http::path_id(index);
  const auto blob = k && *k <= INT32_MAX ? store.snapshot(job.id, int(*k)) : std::nullopt;
  if (!blob) {
    http::error(res, 404, "not_found", "no snapshot " + index + " of job " + std::to_string(job.id));
    return std::nullopt;
  }
  try {
    return api::snapshot_from_json(nlohmann::json::parse(blob->begin(), blob->end()));
  } catch (const std::exception& e) {
    http::error(res, 500, "internal", std::string("stored snapshot unreadable: ") + e.what());
    return std::nullopt;
  }
}

}  // namespace granulab::server
