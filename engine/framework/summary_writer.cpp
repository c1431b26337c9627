#include "engine/framework/summary_writer.h"

namespace granulab {

void write_run_stats(SummaryWriter& w, const RunStats& r) {
  const double sphere_steps = double(r.spheres) * double(r.steps);
  w.count("grains", r.grains);
  w.count("spheres", r.spheres);
  w.count("steps", r.steps);
  w.number("time_step", r.time_step, "s");
  w.number("wall_seconds", r.wall_seconds, "s");
  w.count("threads", std::uint64_t(r.threads));
  w.text("kernel", r.kernel);
  w.number("sphere_steps_per_second", r.wall_seconds > 0 ? sphere_steps / r.wall_seconds : 0.0, "1/s");
  w.number("seconds_per_step", r.steps > 0 ? r.wall_seconds / double(r.steps) : 0.0, "s");
  w.number("sphere_diameter", r.sphere_diameter, "m");
  w.number("normal_stiffness", r.normal_stiffness, r.normal_stiffness_unit);
  w.count("spheres_per_face", std::uint64_t(r.spheres_per_face));
  w.count("neighbor_rebuilds", r.rebuilds);
  w.count("neighbor_pair_searches", r.pair_searches);
  w.number("mean_candidates", r.mean_candidates, "-");
  w.number("mean_skipped_candidates", r.mean_skipped, "-");
  w.begin_group("stage_seconds");
  w.number("integrate", r.stage_times.integrate, "s");
  w.number("sphere_positions", r.stage_times.spheres, "s");
  w.number("neighbor_rebuild", r.stage_times.rebuild, "s");
  w.number("contact_forces", r.stage_times.contacts, "s");
  w.number("wall_forces", r.stage_times.walls, "s");
  w.number("membrane", r.stage_times.membrane, "s");
  w.number("control", r.stage_times.control, "s");
  w.number("record", r.stage_times.record, "s");
  w.end_group();
}

}  // namespace granulab
