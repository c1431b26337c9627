// Exports of docs/api.md ("Exports"): a snapshot in the format a viewer opens (OVITO reads the LAMMPS
// dump, ParaView the VTK), and one job's whole result as a tar archive, laid out as `granulab run`
// writes its folder.
#include <archive.h>
#include <archive_entry.h>

#include <ctime>
#include <memory>
#include <mutex>
#include <set>

#include "api/dic_files.h"
#include "api/network_files.h"
#include "api/snapshot_files.h"
#include "server/routes/routes.h"
#include "server/http/replies.h"
#include "server/job_views.h"

namespace granulab::server {

using nlohmann::json;
using namespace http;

namespace {

// A ustar archive built in memory with libarchive, every member dated `mtime` (s since the epoch).
class TarWriter {
 public:
  explicit TarWriter(std::time_t mtime) : mtime_(mtime), archive_(archive_write_new(), archive_write_free) {
    archive_write_set_format_ustar(archive_.get());
    archive_write_set_bytes_in_last_block(archive_.get(), 1);  // no padding to 10 KiB
    archive_write_open(archive_.get(), &out_, nullptr, &TarWriter::append, nullptr);
  }
  void add(const std::string& name, const std::string& text) {
    std::unique_ptr<archive_entry, void (*)(archive_entry*)> entry(archive_entry_new(), archive_entry_free);
    archive_entry_set_pathname(entry.get(), name.c_str());
    archive_entry_set_size(entry.get(), la_int64_t(text.size()));
    archive_entry_set_filetype(entry.get(), AE_IFREG);
    archive_entry_set_perm(entry.get(), 0644);
    archive_entry_set_mtime(entry.get(), mtime_, 0);
    if (archive_write_header(archive_.get(), entry.get()) != ARCHIVE_OK ||
        archive_write_data(archive_.get(), text.data(), text.size()) < 0)
      throw std::runtime_error(std::string("tar: ") + archive_error_string(archive_.get()));
  }
  std::string finish() {
    archive_write_close(archive_.get());
    return std::move(out_);
  }

 private:
  static la_ssize_t append(archive*, void* out, const void* data, size_t size) {
    static_cast<std::string*>(out)->append(static_cast<const char*>(data), size);
    return la_ssize_t(size);
  }
  std::time_t mtime_;
  std::string out_;
  std::unique_ptr<archive, int (*)(archive*)> archive_;
};

}  // namespace

void mount_export_routes(Router& router, const RouteContext& c) {
  // One snapshot: JSON (per-grain and per-interface arrays), a LAMMPS dump, VTK (grains or interfaces), or its
  // front face's DIC-like map (?step= m) as CSV or a VTK image.
  router.get(R"(/v1/jobs/(\d+)/snapshots/(\d+))", {"format", "step"}, [c](const http::Request& req, http::Response& res) {
    const auto job = c.access.job_for(c.store, req, res, "read", false);
    if (!job) return;
    const std::string format = req.has_param("format") ? req.get_param_value("format") : "json";
    static const std::set<std::string> formats = {"json",         "dump",          "dump_spheres", "vtk",
                                                  "vtk_interfaces", "contacts_vtk", "contacts_dump", "mesh_vtk",
                                                  "dic_csv",      "dic_vtk"};
    if (!formats.count(format))
      return error(res, 400, "invalid_value",
                   "'format' must be one of: json, dump, dump_spheres, vtk, vtk_interfaces, contacts_vtk, contacts_dump, "
                   "mesh_vtk, "
                   "dic_csv, dic_vtk, got '" + format.substr(0, 100) + "'",
                   "format");
    std::optional<double> step;
    if (!query_number(req, res, "step", 0, 1, step)) return;
    if (format == "json") {
      const auto index = path_id(req.matches[2]);
      const auto blob = index && *index <= INT32_MAX ? c.store.snapshot(job->id, int(*index)) : std::nullopt;
      if (!blob)
        return error(res, 404, "not_found",
                     "no snapshot " + std::string(req.matches[2]) + " of job " + std::string(req.matches[1]));
      return res.set_content(std::string(blob->begin(), blob->end()), "application/json");
    }
    const auto s = stored_snapshot(c.store, *job, req.matches[2], res);
    if (!s) return;
    const std::string name = "job" + std::to_string(job->id) + "_snapshot_" + std::string(req.matches[2]);
    const auto attach = [&](const std::string& file, const std::string& text, const char* type) {
      res.set_header("Content-Disposition", "attachment; filename=\"" + name + file + "\"");
      res.set_content(text, type);
    };
    if (format == "dump") return attach(".dump", api::snapshot_lammps_dump(*s), "text/plain");
    if (format == "vtk") return attach("_grains.vtk", api::snapshot_grains_vtk(*s), "text/plain");
    if (format == "vtk_interfaces") return attach("_interfaces.vtk", api::snapshot_interfaces_vtk(*s), "text/plain");
    if (format == "contacts_vtk") return attach("_contacts.vtk", api::snapshot_contacts_vtk(*s), "text/plain");
    if (format == "contacts_dump") return attach("_contacts.dump", api::snapshot_contacts_dump(*s), "text/plain");
    if (format == "dump_spheres") {
      try {
        return attach("_spheres.dump", api::snapshot_spheres_dump(*s), "text/plain");
      } catch (const std::exception& e) {  // the stored clump cannot be rebuilt, or is over the limit
        return error(res, 400, "out_of_range", e.what(), "format");
      }
    }
    if (format == "mesh_vtk") return attach("_meshes.vtk", api::snapshot_meshes_vtk(*s), "text/plain");
    DicMap map;
    try {
      map = api::snapshot_dic_map(*s, step, kMaxDicNodes);
    } catch (const std::invalid_argument& e) {
      return error(res, 400, "out_of_range", e.what(), step ? "step" : "");
    }
    if (format == "dic_csv") return attach("_dic.csv", api::dic_csv(map), "text/csv");
    attach("_dic.vtk", api::dic_vtk(map), "text/plain");
  });

  // Everything of one job: spec.json, summary.json (when it succeeded), curve.csv, curve.svg and every
  // snapshot in every format, under job_<id>/.
  router.get(R"(/v1/jobs/(\d+)/archive)", {}, [c](const http::Request& req, http::Response& res) {
    const auto job = c.access.job_for(c.store, req, res, "read", false);
    if (!job) return;
    // The tar is built in memory (about 7.6 times the stored snapshots in their nine formats, measured on the N_e = 4
    // AR 1 crystal's snapshots, the polyhedra 4x alone: 8 with a margin) and held until the
    // client has read it: one build at a time, and none above the cap, so no reader can exhaust the
    // daemon's memory or its handler threads.
    constexpr double max_archive_bytes = 256e6;
    double stored = 0;
    for (const auto& info : c.store.snapshots(job->id)) stored += double(info.bytes);
    constexpr double archive_per_stored = 8;
    if (archive_per_stored * stored > max_archive_bytes)
      return error(res, 413, "too_large",
                   "job " + std::to_string(job->id) + "'s archive would be about " +
                       std::to_string(int(archive_per_stored * stored / 1e6)) +
                       " MB, over the 256 MB the server builds at once: download its snapshots one by one "
                       "(/v1/jobs/{id}/snapshots/{k}?format=...) or with `granulab results`");
    static std::mutex one_at_a_time;
    std::unique_lock<std::mutex> building(one_at_a_time, std::try_to_lock);
    if (!building.owns_lock())
      return error(res, 503, "busy", "another archive is being built; try again in a few seconds");
    const std::string dir = "job_" + std::to_string(job->id) + "/";
    // Members dated when the job finished (else when it started, or was submitted), not when it is downloaded:
    // two downloads of a finished job are the same bytes (checksums, caches, a diff of two folders).
    const std::int64_t dated_ms = job->finished_ms > 0 ? job->finished_ms
                                  : job->started_ms > 0 ? job->started_ms
                                                        : job->created_ms;
    TarWriter tar(std::time_t(dated_ms / 1000));
    const json spec = json::parse(job->spec_json, nullptr, false);
    tar.add(dir + "spec.json", spec.dump(2) + "\n");
    if (!job->summary_json.empty()) tar.add(dir + "summary.json", json::parse(job->summary_json).dump(2) + "\n");
    if (const auto csv =
            job->status == JobStatus::succeeded ? c.store.curve_csv(job->id) : c.store.live_curve_csv(job->id)) {
      tar.add(dir + "curve.csv", *csv);
      if (const auto svg = job_curve_svg(c.store, *job)) tar.add(dir + "curve.svg", *svg);
    }
    for (const auto& info : c.store.snapshots(job->id)) {
      const auto blob = c.store.snapshot(job->id, info.index);
      if (!blob) continue;
      const GrainSnapshot s = api::snapshot_from_json(json::parse(blob->begin(), blob->end()));
      for (const api::SnapshotFile& f : api::snapshot_files(std::size_t(info.index), s)) tar.add(dir + f.name, f.text);
    }
    res.set_header("Content-Disposition", "attachment; filename=\"job_" + std::to_string(job->id) + ".tar\"");
    res.set_content(tar.finish(), "application/x-tar");
  });
}

}  // namespace granulab::server
