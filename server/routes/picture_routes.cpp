// The pictures of docs/api.md ("Pictures"): curves and grain sections drawn by the server as SVG, so a
// browser or any image viewer shows results without a plotting library. Running jobs draw what they
// have so far.
#include "api/pictures/curve_pictures.h"
#include "api/pictures/section_picture.h"
#include "api/dic_files.h"
#include "api/pictures/dic_picture.h"
#include "api/snapshot_files.h"
#include "server/routes/routes.h"
#include "server/http/replies.h"
#include "server/job_views.h"

namespace granulab::server {

using nlohmann::json;
using namespace http;

namespace {

constexpr std::size_t max_sweep_curves = 50;  // beyond this a legend is unreadable

}  // namespace

void mount_picture_routes(Router& router, const RouteContext& c) {
  router.get(R"(/v1/jobs/(\d+)/curve\.svg)", {"units", "y"}, [c](const http::Request& req, http::Response& res) {
    const auto job = c.access.job_for(c.store, req, res, "read", false);
    if (!job) return;
    pictures::CurveChoice choice;
    if (!curve_choice(req, res, parsed_or_null(job->spec_json), choice)) return;
    const auto svg = job_curve_svg(c.store, *job, choice);
    if (!svg)
      return error(res, 409, "wrong_state",
                   "job " + std::to_string(job->id) + " is " + api::status_name(job->status) + " and has no curve yet");
    res.set_content(*svg, "image/svg+xml");
  });

  router.get(R"(/v1/sweeps/(\d+)/curves\.svg)", {"units", "y"}, [c](const http::Request& req, http::Response& res) {
    const auto sweep = c.access.sweep_for(c.store, req, res, "read", false);
    if (!sweep) return;
    pictures::CurveChoice choice;
    if (!curve_choice(req, res, parsed_or_null(sweep->base_json), choice)) return;
    std::vector<pictures::SweepCurve> curves;
    std::size_t left_out = 0;
    for (const JobRecord& j : c.store.sweep_jobs(sweep->id)) {
      if (curves.size() == max_sweep_curves) {
        ++left_out;
        continue;
      }
      curves.push_back({parsed_or_null(j.sweep_values), parsed_or_null(j.spec_json),
                        curve_columns(c.store, j).value_or(json::object()), api::status_name(j.status)});
    }
    const std::string title = sweep->label.empty() ? "sweep " + std::to_string(sweep->id) : sweep->label;
    res.set_content(pictures::line_plot_svg(pictures::sweep_curves_plot(title, curves, left_out, choice)),
                    "image/svg+xml");
  });

  router.get(
      R"(/v1/jobs/(\d+)/snapshots/(\d+)\.svg)", {"field", "slice"}, [c](const http::Request& req, http::Response& res) {
        const auto job = c.access.job_for(c.store, req, res, "read", false);
        if (!job) return;
        const std::string field_name = req.has_param("field") ? req.get_param_value("field") : "equivalent_strain";
        const auto field = pictures::parse_field(field_name);
        if (!field)
          return error(
              res, 400, "invalid_value",
              "'field' must be one of: penetration_ratio, gamma_max, equivalent_strain, displacement, d2min, misorientation, got '" +
                  field_name + "'",
              "field");
        std::optional<int> layer;
        if (req.has_param("slice")) {
          long value = 0;
          if (!query_int(req, res, "slice", 0, 1 << 20, value)) return;
          layer = int(value);
        }
        const auto stored = stored_snapshot(c.store, *job, req.matches[2], res);
        if (!stored) return;
        const GrainSnapshot& snapshot = *stored;
        try {
          res.set_content(pictures::section_svg(snapshot, *field, layer,
                                                job->label.empty() ? "job " + std::to_string(job->id) : job->label),
                          "image/svg+xml");
        } catch (const std::out_of_range& e) {
          error(res, 400, "out_of_range", e.what(), "slice");
        } catch (const std::invalid_argument& e) {
          error(res, 404, "not_found", e.what(), "field");
        }
      });

  // The front face's DIC-like map (engine/analysis/dic_map.h), ?field= and ?step= (m).
  router.get(R"(/v1/jobs/(\d+)/snapshots/(\d+)/dic\.svg)", {"field", "step"},
             [c](const http::Request& req, http::Response& res) {
               const auto job = c.access.job_for(c.store, req, res, "read", false);
               if (!job) return;
               const std::string field_name = req.has_param("field") ? req.get_param_value("field") : "gamma_max";
               const auto field = pictures::parse_dic_field(field_name);
               if (!field)
                 return error(res, 400, "invalid_value",
                              "'field' must be one of: gamma_max, exx, ezz, exz, ux, uz, got '" + field_name + "'",
                              "field");
               std::optional<double> step;
               if (!query_number(req, res, "step", 0, 1, step)) return;
               const auto snapshot = stored_snapshot(c.store, *job, req.matches[2], res);
               if (!snapshot) return;
               try {
                 const DicMap map = api::snapshot_dic_map(*snapshot, step, kMaxDicNodes);
                 res.set_content(pictures::dic_svg(map, *field, snapshot->strain,
                                                   job->label.empty() ? "job " + std::to_string(job->id) : job->label),
                                 "image/svg+xml");
               } catch (const std::invalid_argument& e) {
                 error(res, 400, "out_of_range", e.what(), step ? "step" : "");
               }
             });
}

}  // namespace granulab::server
