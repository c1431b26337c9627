// `granulab wait` and the live part of `granulab sweep`: one line per job with a progress bar, the ETA
// and the latest strain and stress, redrawn in place on a terminal (a line per change in a log). Ctrl-C
// stops the waiting, not the jobs, and says so.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace granulab::cli {

/// GET of a path on the server, returning the parsed body (throws with the server's message).
using JsonGetter = std::function<nlohmann::json(const std::string& path)>;

/// Waits until every job has finished. Returns 0 when all succeeded, 1 when any did not, 130 after Ctrl-C.
int watch_jobs(const JsonGetter& get, const std::vector<std::string>& ids);

/// A time for people: "4.2 s", "35 s", "12 min", "3.7 h".
std::string duration(double seconds);

/// One job's line: "job 12  running    [#####.....]  48.0 %  ETA 3 min  axial strain 1.2 %  deviator 2.9 p0",
/// its latest x and first series (and, once finished, its key values) as its experiment's headline says
/// (`headline`: GET /v1/experiments' "headline" of the job's experiment, in natural units; null: none).
std::string job_line(const nlohmann::json& job, const nlohmann::json& headline, int bar_width = 20);
/// The headline of every experiment the server knows, by name (from GET /v1/experiments).
nlohmann::json headlines(const JsonGetter& get);

}  // namespace granulab::cli
