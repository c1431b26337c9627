// Every spec in examples/ is valid: a broken example is the first thing a newcomer runs into.
#include <gtest/gtest.h>

#include <filesystem>
#include <cstdio>
#include <fstream>
#include <sstream>

#include "api/spec.h"
#include "engine/experiments/crystal_compression/crystal_compression_experiment.h"

namespace granulab::api {
namespace {

TEST(Examples, EverySpecParses) {
  int count = 0;
  for (const auto& entry : std::filesystem::directory_iterator(std::string(GRANULAB_SOURCE_DIR) + "/examples")) {
    if (entry.path().extension() != ".json") continue;
    std::ifstream in(entry.path());
    std::stringstream text;
    text << in.rdbuf();
    EXPECT_NO_THROW(parse_spec_text(text.str())) << entry.path();
    ++count;
  }
  EXPECT_GE(count, 14);
}

// The paper's runs fit the server's default budget (16 GB machine: 8 GB memory; 4e12 sphere-steps).
TEST(Examples, PaperRunsFitTheDefaultBudget) {
  for (const auto& entry : std::filesystem::directory_iterator(std::string(GRANULAB_SOURCE_DIR) + "/examples")) {
    if (entry.path().extension() != ".json") continue;
    std::ifstream in(entry.path());
    std::stringstream text;
    text << in.rdbuf();
    const Workload w = parse_spec_text(text.str()).experiment->workload();
    EXPECT_LT(w.peak_bytes(), 8e9) << entry.path();
    EXPECT_LT(w.sphere_steps(), 4e12) << entry.path();
    std::printf("%-28s %9.0f spheres %10.3g steps %10.3g sphere-steps %6.2f GB\n", entry.path().filename().c_str(),
                w.spheres, w.steps, w.sphere_steps(), w.peak_bytes() / 1e9);
  }
}

TEST(Examples, KnockoutExamplesRemoveFifteenGrains) {
  for (const char* name : {"fig10_ko_centre", "fig10_ko_slip_plane", "fig10_ko_off_top", "fig10_ko_off_side"}) {
    std::ifstream in(std::string(GRANULAB_SOURCE_DIR) + "/examples/" + name + ".json");
    std::stringstream text;
    text << in.rdbuf();
    const Spec spec = parse_spec_text(text.str());
    EXPECT_EQ(spec.as<CrystalCompressionExperiment>().params.knockout_ids.size(), 15u) << name;
  }
}

}  // namespace
}  // namespace granulab::api
