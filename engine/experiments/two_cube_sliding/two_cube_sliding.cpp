#include "engine/experiments/two_cube_sliding/two_cube_sliding.h"

#include <chrono>
#include <cmath>
#include <stdexcept>

namespace granulab {

namespace {

WorldSettings two_cube_settings(const TwoCubeParams& p, const GrainTemplate& grain) {
  WorldSettings s;
  s.time_step = p.time_step_factor * contact_time_scale(grain, p.material.youngs_modulus, p.material.density);
  s.skin = p.skin_factor * grain.diameter();
  s.kernel = p.kernel;
  return s;
}

}  // namespace

TwoCubeSliding::TwoCubeSliding(const TwoCubeParams& params)
    : params_(params),
      grain_(params.grain),
      world_(grain_, contact_law(grain_, params.material), two_cube_settings(params, grain_)) {
  if (params.grain.shape != Shape::cube) throw std::invalid_argument("two_cube_sliding needs cube grains");
  const double l = params.grain.size;
  p0_ = params.material.youngs_modulus * l * l * params.prestrain;
  gap_ = l * (1 - params.prestrain);
  bottom_ = world_.add_grain(Vec3::Zero(), Quat::Identity(), params.material.density, Motion::prescribed);
  top_ = world_.add_grain(Vec3(0, 0, gap_), Quat::Identity(), params.material.density, Motion::prescribed);
  world_.compute_forces();
}

void TwoCubeSliding::place_at(double u) {
  Bodies& b = world_.bodies();
  b.position[top_] = Vec3(u, 0, gap_);
  b.velocity[top_].setZero();
  world_.compute_forces();
}

double TwoCubeSliding::normal_force() const { return world_.bodies().force[top_].z(); }
double TwoCubeSliding::tangential_force() const { return -world_.bodies().force[top_].x(); }

const std::vector<CurveColumn>& TwoCubeRow::columns() {
  static const std::vector<CurveColumn> c = {
      {"slide_over_size", "-", "u / l, slide of the top cube over the cube side"},
      {"normal_over_p0", "-", "P / P0, P0 = E l^2 eps0"},
      {"tangential_over_p0", "-", "T / P0"},
      {"normal_force", "N", "P, compressive positive"},
      {"tangential_force", "N", "T, positive when it resists the slide"},
  };
  return c;
}

std::vector<double> TwoCubeRow::values() const {
  return {slide_over_size, normal_over_p0, tangential_over_p0, normal_force, tangential_force};
}

TwoCubeResult TwoCubeSliding::run(ResultSink& sink, const CheckpointSource* resume) {
  const auto start = std::chrono::steady_clock::now();
  const TwoCubeParams& p = params_;
  const double l = p.grain.size, d = grain_.diameter(), s = grain_.spacing();
  const double dt = world_.settings().time_step;
  const double wave_speed = std::sqrt(p.material.youngs_modulus / p.material.density);
  const double travel = p.max_slide * l;
  const int points = std::max(1, p.curve_points);
  // Whole number of steps per curve interval, speed adjusted so the last step lands on max_slide.
  const std::uint64_t per_point =
      std::max<std::uint64_t>(1, std::uint64_t(std::ceil(travel / (p.rate_number * wave_speed * dt) / points)));
  const std::uint64_t total = per_point * points;
  const double speed = travel / (total * dt);

  TwoCubeResult r;
  auto record = [&](double u) {
    const double pn = normal_force(), t = tangential_force();
    r.curve.push_back({u / l, pn / p0_, t / p0_, pn, t});
    sink.curve_row(r.curve.back().values());
  };
  // The slide as one count of steps: a row every per_point steps, a safe point (progress, cancel,
  // checkpoint) every 64, so that one long curve interval can still be stopped and resumed.
  std::uint64_t done = 0;
  // What a checkpoint holds beyond the world, one list for writing and reading.
  const auto state = [&](auto& archive) {
    archive.section("two_cube_sliding");
    archive.value(done);
    archive.values(r.curve);
  };
  if (!resume) {
    place_at(0);
    record(0);
    world_.bodies().velocity[top_] = Vec3(speed, 0, 0);
  } else {
    CheckpointReader in(*resume);
    world_.restore(in);
    state(in);
    in.finish();
  }
  while (done < total) {
    world_.step();
    ++done;
    if (done % per_point == 0) record(world_.bodies().position[top_].x());
    if (done % 64 != 0 && done % per_point != 0) continue;
    if (!sink.progress(double(done) / total)) throw Cancelled();
    if (done < total && sink.checkpoint_due()) {
      sink.checkpoint(
          [&](CheckpointWriter& out) {
            world_.save(out);
            state(out);
          },
          r.curve.size(), 0);
    }
  }

  r.spacing = s;
  r.p0 = p0_;
  r.slide_speed = speed;
  r.critical_prestrain = (d - std::sqrt(d * d - s * s)) / l;
  const double approach = d - l * p.prestrain;
  r.contact_end_slide = (l - d + std::sqrt(d * d - approach * approach)) / l;
  r.run = world_.run_stats(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  r.run.steps = total;
  return r;
}

}  // namespace granulab
