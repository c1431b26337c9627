// granulab estimate SPEC [--json]: what a spec will be, in milliseconds and in-process, before any run: its size
// and expected steps, and its rigid-grain yield estimate (engine/analysis/yield_estimate.h).
#pragma once

#include <string>

#include <nlohmann/json.hpp>

namespace granulab::cli {

/// One line for people from a "yield_estimate" answer (a dry run's, or estimate --json's).
std::string human_yield_estimate(const nlohmann::json& estimate);
int run_estimate(int argc, char** argv);

}  // namespace granulab::cli
