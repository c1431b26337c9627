// How an experiment's result describes itself at the end of a run: named values with units, in nested
// groups. The api writes it as summary.json (api/summary_json.h); the engine stays free of JSON.
#pragma once

#include <cstdint>
#include <string>

#include "engine/world/run_stats.h"

namespace granulab {

class SummaryWriter {
 public:
  virtual ~SummaryWriter() = default;
  virtual void number(const char* key, double value, const char* unit) = 0;
  virtual void count(const char* key, std::uint64_t value) = 0;
  virtual void flag(const char* key, bool value) = 0;
  /// Text; inside a list, key is ignored (an element).
  virtual void text(const char* key, const std::string& value) = 0;
  /// A group of fields under `key`, up to end_group(); inside a list, key is ignored (an element).
  virtual void begin_group(const char* key) = 0;
  virtual void end_group() = 0;
  /// A list of groups under `key`, up to end_list().
  virtual void begin_list(const char* key) = 0;
  virtual void end_list() = 0;
};

/// Conventions: a result that missed one of its own criteria says so in a list "warnings" of sentences,
/// which the CLI prints and the server shows with the job.

/// The fields every run reports (docs/api.md: spheres, grains, steps, time_step, wall_seconds, threads,
/// sphere_steps_per_second and the model numbers), from the world's statistics.
void write_run_stats(SummaryWriter& w, const RunStats& r);

}  // namespace granulab
