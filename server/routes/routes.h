// The HTTP API of docs/api.md as route groups. Each group is a free function that mounts its routes on
// a Router with what they need (RouteContext); no group calls another, and none sees the HTTP library.
// granulabd (server/main.cpp) mounts them all; a test may mount one alone.
#pragma once

#include <cstddef>

#include "server/access.h"
#include "server/admission.h"
#include "server/executor.h"
#include "server/http/router.h"
#include "server/store/job_store.h"
#include "server/worker_secrets.h"

namespace granulab::server {

/// The most nodes a DIC-like map over HTTP may have (its CSV is about 100 B a node: 25 MB at this bound); a finer
/// ?step= is a 400 that says so.
constexpr std::size_t kMaxDicNodes = 250000;

struct RouteContext {
  JobStore& store;
  Executor& executor;
  const Access& access;
  const Admission& admission;
  WorkerSecrets& worker_secrets;
  std::size_t max_jobs_per_sweep = 1000;  ///< a larger sweep is a 400
  std::size_t max_sweep_bytes = 16000000;  ///< B of specs a sweep stores in all; more is a 400
};

/// GET /v1/health, /v1/openapi.json, /v1/experiments (meta_routes.cpp).
void mount_meta_routes(http::Router& router, const RouteContext& context);
/// POST/GET /v1/jobs, a job, its priority, cancel, curve and snapshot list (job_routes.cpp).
void mount_job_routes(http::Router& router, const RouteContext& context);
/// /v1/sweeps... (sweep_routes.cpp).
void mount_sweep_routes(http::Router& router, const RouteContext& context);
/// The SVG pictures: a job's curve, a sweep's curves, a snapshot's section and DIC-like map (picture_routes.cpp).
void mount_picture_routes(http::Router& router, const RouteContext& context);
/// A snapshot as a viewer's file, a job's archive (export_routes.cpp).
void mount_export_routes(http::Router& router, const RouteContext& context);
/// The web page and /v1/examples (web_routes.cpp).
void mount_web_routes(http::Router& router, const RouteContext& context);
/// /v1/worker/jobs/...: what a job's worker on a cluster sends (worker_routes.cpp).
void mount_worker_routes(http::Router& router, const RouteContext& context);

}  // namespace granulab::server
