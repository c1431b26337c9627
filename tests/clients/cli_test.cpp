// End-to-end tests of the command-line tool (docs/api.md, "Commands" and "Curves"): the real
// build/granulab binary runs as a subprocess; its exit status, stdout, stderr and output files are
// checked. Every run here is a tiny two-cube job (well under a second).
#include <fcntl.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <optional>
#include <regex>
#include <sstream>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

namespace {

namespace fs = std::filesystem;
using nlohmann::json;

const std::string kBinary = GRANULAB_BINARY_DIR "/granulab";
const std::string kCurveHeader = "slide_over_size,normal_over_p0,tangential_over_p0,normal_force,tangential_force";

// A two-cube job that runs in a few tens of milliseconds: 2 * (6*2*2 + 12*2 + 8) = 112 spheres.
constexpr const char* kSmallSpec = R"({
  "experiment": "two_cube_sliding",
  "label": "cli test",
  "grain": {"shape": "cube", "edge_spheres": 4},
  "material": {"friction": 0.3},
  "loading": {"rate_number": 1e-3},
  "output": {"curve_points": 20}
})";

struct RunResult {
  int exit_code = -1;  ///< -1 if the process did not exit normally (signal, timeout)
  std::string out, err;
};

std::string slurp(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

void write_text(const fs::path& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary);
  out << text;
  ASSERT_TRUE(out.good()) << "cannot write " << path;
}

std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

std::vector<double> csv_numbers(const std::string& line) {
  std::vector<double> values;
  std::istringstream in(line);
  for (std::string cell; std::getline(in, cell, ',');) {
    char* end = nullptr;
    const double v = std::strtod(cell.c_str(), &end);
    if (cell.empty() || *end != '\0') return {};  // not a number: the caller sees a short row
    values.push_back(v);
  }
  return values;
}

// Each test gets its own scratch directory under the system temp dir, removed afterwards.
class CliTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    std::string name = std::string(info->test_suite_name()) + "_" + info->name();
    for (char& c : name)
      if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
    dir_ = fs::temp_directory_path() / ("granulab_cli_" + name + "_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override {
    std::error_code ec;
    fs::remove_all(dir_, ec);
  }

  /// Runs build/granulab with `args`; stdout and stderr go to files in the scratch directory.
  /// A run that takes longer than `timeout` is killed (exit_code -1), so a hang fails instead of blocking.
  /// `kill_when`: polled while it runs; when it returns true the process gets SIGKILL (exit_code -1).
  RunResult run(const std::vector<std::string>& args, std::chrono::seconds timeout = std::chrono::seconds(30),
                const std::function<bool()>& kill_when = nullptr) {
    const fs::path out_path = dir_ / "stdout.txt", err_path = dir_ / "stderr.txt";
    std::vector<std::string> full{kBinary};
    full.insert(full.end(), args.begin(), args.end());
    std::vector<char*> argv;
    for (std::string& a : full) argv.push_back(a.data());
    argv.push_back(nullptr);

    const pid_t pid = ::fork();
    if (pid == 0) {  // child: only async-signal-safe calls until exec
      const int out_fd = ::open(out_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
      const int err_fd = ::open(err_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
      if (out_fd < 0 || err_fd < 0 || ::dup2(out_fd, STDOUT_FILENO) < 0 || ::dup2(err_fd, STDERR_FILENO) < 0)
        _exit(127);
      ::close(out_fd);
      ::close(err_fd);
      ::chdir(dir_.c_str());  // relative paths a run might create land in the scratch directory
      ::execv(argv[0], argv.data());
      _exit(127);
    }
    RunResult r;
    if (pid < 0) {
      ADD_FAILURE() << "fork failed";
      return r;
    }
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    int status = 0;
    for (;;) {
      const pid_t done = ::waitpid(pid, &status, WNOHANG);
      if (done == pid) break;
      if (kill_when && kill_when()) {
        ::kill(pid, SIGKILL);
        ::waitpid(pid, &status, 0);
        break;
      }
      if (std::chrono::steady_clock::now() > deadline) {
        ::kill(pid, SIGKILL);
        ::waitpid(pid, &status, 0);
        ADD_FAILURE() << "granulab did not finish within " << timeout.count() << " s";
        break;
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(2));
    }
    if (WIFEXITED(status)) r.exit_code = WEXITSTATUS(status);
    r.out = slurp(out_path);
    r.err = slurp(err_path);
    return r;
  }

  /// Replaces "{SPEC}" and "{OUT}" by dir/spec.json and dir/out.
  std::string substitute(std::string s) const {
    const std::pair<std::string, std::string> tokens[] = {{"{SPEC}", (dir_ / "spec.json").string()},
                                                          {"{OUT}", (dir_ / "out").string()}};
    for (const auto& [token, value] : tokens)
      for (std::size_t at; (at = s.find(token)) != std::string::npos;) s.replace(at, token.size(), value);
    return s;
  }
  std::vector<std::string> substitute(const std::vector<std::string>& args) const {
    std::vector<std::string> result;
    for (const std::string& a : args) result.push_back(substitute(a));
    return result;
  }

  fs::path spec_file(const std::string& text, const std::string& name = "spec.json") {
    const fs::path path = dir_ / name;
    write_text(path, text);
    return path;
  }

  fs::path dir_;
};

// ---------------------------------------------------------------------------------------------
// 1. A valid run writes the contract's files

TEST_F(CliTest, ExecStartsTheBinary) {
  ASSERT_TRUE(fs::exists(kBinary)) << kBinary << " is missing: build the granulab target";
  const RunResult r = run({"version"});
  EXPECT_NE(r.exit_code, 127) << "could not execute " << kBinary;
}

// One binary runs the widest contact kernel its CPU has, says which (summary.json, and the version's last part), and
// takes another by run.kernel: the baseline, which every x86-64 CPU runs, gives the same curve to rounding.
TEST_F(CliTest, RunReportsItsContactKernelAndTakesAForcedOne) {
  const std::string version = run({"version"}).out;
  const std::string widest = version.substr(version.rfind('.') + 1, version.find_last_not_of(" \n") - version.rfind('.'));
  json forced = json::parse(kSmallSpec);
  forced["run"]["kernel"] = "sse2";
  std::vector<std::vector<double>> curves[2];
  for (int k = 0; k < 2; ++k) {
    const fs::path out = dir_ / ("out" + std::to_string(k));
    const RunResult r = run({"run", spec_file(k == 0 ? std::string(kSmallSpec) : forced.dump()).string(), "--out",
                             out.string()});
    ASSERT_EQ(r.exit_code, 0) << "stderr:\n" << r.err;
    EXPECT_EQ(json::parse(slurp(out / "summary.json"))["kernel"], k == 0 ? widest : "sse2");
    const std::vector<std::string> lines = lines_of(slurp(out / "curve.csv"));
    for (std::size_t i = 1; i < lines.size(); ++i) curves[k].push_back(csv_numbers(lines[i]));
  }
  ASSERT_EQ(curves[0].size(), curves[1].size());
  for (std::size_t i = 0; i < curves[0].size(); ++i)
    for (std::size_t c = 1; c < 3; ++c)  // P / P0 and T / P0, of order 1
      EXPECT_NEAR(curves[0][i][c], curves[1][i][c], 1e-9) << "row " << i << ", column " << c;
}

TEST_F(CliTest, RunWritesCurveSummaryAndSnapshots) {
  const fs::path spec = spec_file(kSmallSpec);
  const fs::path out = dir_ / "out";
  const RunResult r = run({"run", spec.string(), "--out", out.string()});
  ASSERT_EQ(r.exit_code, 0) << "stderr:\n" << r.err;

  EXPECT_TRUE(fs::is_directory(out / "snapshots"));
  ASSERT_TRUE(fs::is_regular_file(out / "curve.csv"));
  ASSERT_TRUE(fs::is_regular_file(out / "summary.json"));
  EXPECT_FALSE(fs::exists(out / "curve.csv.tmp"));
  EXPECT_FALSE(fs::exists(out / "summary.json.tmp"));

  // curve.csv: the two-cube header first, then curve_points + 1 rows (u = 0 included).
  const std::vector<std::string> lines = lines_of(slurp(out / "curve.csv"));
  ASSERT_FALSE(lines.empty());
  EXPECT_EQ(lines[0], kCurveHeader);
  ASSERT_EQ(lines.size(), 1u + 21u);
  std::vector<std::vector<double>> rows;
  for (std::size_t i = 1; i < lines.size(); ++i) {
    rows.push_back(csv_numbers(lines[i]));
    ASSERT_EQ(rows.back().size(), 5u) << "row " << i << ": '" << lines[i] << "'";
    for (double v : rows.back()) EXPECT_TRUE(std::isfinite(v)) << "row " << i;
  }
  // The model's exact law at u = 0: P = P0.
  EXPECT_EQ(rows.front()[0], 0.0);
  EXPECT_NEAR(rows.front()[1], 1.0, 1e-9);
  for (std::size_t i = 1; i < rows.size(); ++i) EXPECT_GT(rows[i][0], rows[i - 1][0]) << "slide must increase";
  EXPECT_NEAR(rows.back()[0], 0.8, 1e-6);  // max_slide default

  // summary.json: the contract's keys with sensible values.
  const json s = json::parse(slurp(out / "summary.json"));
  for (const char* key : {"spheres", "grains", "steps", "time_step", "wall_seconds", "threads",
                          "sphere_steps_per_second", "sphere_diameter", "normal_stiffness", "spheres_per_face"}) {
    ASSERT_TRUE(s.contains(key)) << "summary.json lacks '" << key << "'";
    EXPECT_TRUE(s[key].is_number()) << key << " = " << s[key].dump();
  }
  EXPECT_EQ(s["spheres"].get<long>(), 2 * (6 * 2 * 2 + 12 * 2 + 8));
  EXPECT_EQ(s["grains"].get<long>(), 2);
  EXPECT_EQ(s["spheres_per_face"].get<long>(), 16);
  EXPECT_GT(s["steps"].get<long>(), 0);
  EXPECT_GT(s["time_step"].get<double>(), 0);
  EXPECT_GE(s["wall_seconds"].get<double>(), 0);
  EXPECT_GE(s["threads"].get<long>(), 1);
  EXPECT_GT(s["sphere_steps_per_second"].get<double>(), 0);
  EXPECT_GT(s["sphere_diameter"].get<double>(), 0);
  EXPECT_LT(s["sphere_diameter"].get<double>(), 0.01);  // smaller than the grain
  EXPECT_GT(s["normal_stiffness"].get<double>(), 0);
  // P0 links the two force columns: normal_force = normal_over_p0 * P0.
  if (s.contains("p0")) {
    EXPECT_NEAR(rows.front()[3], s["p0"].get<double>(), 1e-9 * s["p0"].get<double>());
  }
  // The spec that was run is recorded, normalised.
  ASSERT_TRUE(s.contains("spec"));
  EXPECT_EQ(s["spec"]["grain"]["edge_spheres"], 4);
  EXPECT_DOUBLE_EQ(s["spec"]["material"]["friction"].get<double>(), 0.3);
  EXPECT_EQ(s["spec"]["output"]["curve_points"], 20);

  EXPECT_NE(r.err.find("ETA"), std::string::npos) << "no progress on stderr:\n" << r.err;
}

// A tiny crystal (2 x 4 x 2 grains, N_e = 3): curve columns, summary, and every snapshot file format.
TEST_F(CliTest, CrystalRunWritesCurveSummaryAndSnapshotFiles) {
  const fs::path spec = spec_file(R"({"experiment": "crystal_compression",
    "grain": {"edge_spheres": 3}, "crystal": {"grains_x": 2, "rows_z": 4, "layers_y": 2},
    "loading": {"confining_pressure": 30e3, "max_strain": 2e-4},
    "output": {"curve_points": 8, "snapshot_strains": [0.0, 2e-4]}})");
  const fs::path out = dir_ / "out";
  const RunResult r = run({"run", spec.string(), "--out", out.string()});
  ASSERT_EQ(r.exit_code, 0) << "stderr:\n" << r.err;
  const std::vector<std::string> lines = lines_of(slurp(out / "curve.csv"));
  ASSERT_GE(lines.size(), 2u);
  EXPECT_EQ(lines[0],
            "strain,stress_top,stress_bottom,deviator,lateral_strain_x,lateral_strain_y,lateral_stress,"
            "kinetic_elastic_ratio,contacts,sliding_contacts,segment,platen_work,confinement_work,elastic_energy,"
            "friction_dissipation,damping_dissipation,kinetic_energy,energy_residual");
  const json s = json::parse(slurp(out / "summary.json"));
  EXPECT_EQ(s["grains"].get<long>(), 16);
  EXPECT_EQ(s["spheres"].get<long>(), 16 * (12 * 1 + 24 * 1 + 14));
  EXPECT_TRUE(s["confinement"]["converged"].get<bool>());
  EXPECT_TRUE(s.contains("first_yield"));
  ASSERT_EQ(s["snapshots"].size(), 2u);
  for (int k = 0; k < 2; ++k) {
    const std::string stem = "snapshot_" + std::to_string(k);
    const json snap = json::parse(slurp(out / "snapshots" / (stem + ".json")));
    EXPECT_EQ(snap["grains"]["id"].size(), 16u);
    const std::string dump = slurp(out / "snapshots" / (stem + ".dump"));
    EXPECT_EQ(dump.rfind("ITEM: TIMESTEP", 0), 0u);
    EXPECT_NE(dump.find("ITEM: NUMBER OF ATOMS\n16\n"), std::string::npos);
    EXPECT_NE(dump.find("quatw quati quatj quatk"), std::string::npos);
    EXPECT_EQ(slurp(out / "snapshots" / (stem + "_grains.vtk")).rfind("# vtk DataFile", 0), 0u);
    EXPECT_NE(slurp(out / "snapshots" / (stem + "_interfaces.vtk")).find("CELL_TYPES"), std::string::npos);
  }
}

// kill -9 in the middle of a crystal run that checkpoints every second, then --resume: curve.csv and every
// snapshot file are byte for byte those of an uninterrupted run.
TEST_F(CliTest, KilledRunResumesFromItsCheckpointBitForBit) {
  const fs::path spec = spec_file(R"({"experiment": "crystal_compression", "grain": {"edge_spheres": 3},
    "crystal": {"grains_x": 2, "rows_z": 4, "layers_y": 2},
    "loading": {"confining_pressure": 30e3, "max_strain": 0.02, "rate_number": 2e-6},
    "output": {"curve_points": 100, "snapshot_strains": [0.0, 0.01, 0.02]}})");
  const std::string whole = (dir_ / "whole").string(), out = (dir_ / "out").string(), cdir = (dir_ / "ck").string();
  ASSERT_EQ(
      run({"run", spec.string(), "--out", whole, "--threads", "1", "--quiet"}, std::chrono::seconds(120)).exit_code, 0);
  // Killed once a checkpoint exists and the curve has moved past it. A checkpoint is written to a .tmp
  // file and renamed: only a renamed one counts (a kill during the first write left nothing to resume).
  const auto checkpointed = [&] {
    if (!fs::exists(cdir)) return false;
    bool complete = false;
    for (const auto& entry : fs::directory_iterator(cdir)) complete = complete || entry.path().extension() == ".bin";
    return complete && lines_of(slurp(fs::path(out) / "curve.csv")).size() > 40;
  };
  const RunResult killed = run({"run", spec.string(), "--out", out, "--threads", "1", "--quiet", "--checkpoint-dir",
                                cdir, "--checkpoint-seconds", "1"},
                               std::chrono::seconds(120), checkpointed);
  ASSERT_EQ(killed.exit_code, -1) << "the run ended before it could be killed: " << killed.err;
  EXPECT_FALSE(fs::exists(fs::path(out) / "summary.json"));
  const RunResult resumed =
      run({"run", spec.string(), "--out", out, "--threads", "1", "--quiet", "--checkpoint-dir", cdir, "--resume"},
          std::chrono::seconds(120));
  ASSERT_EQ(resumed.exit_code, 0) << resumed.err;
  EXPECT_NE(resumed.err.find("resuming from"), std::string::npos) << resumed.err;
  EXPECT_EQ(slurp(fs::path(out) / "curve.csv"), slurp(fs::path(whole) / "curve.csv"));
  int files = 0;
  for (const auto& entry : fs::directory_iterator(fs::path(whole) / "snapshots")) {
    EXPECT_EQ(slurp(fs::path(out) / "snapshots" / entry.path().filename()), slurp(entry.path())) << entry.path();
    ++files;
  }
  EXPECT_EQ(files, 27);             // 3 snapshots x 9 files
  EXPECT_TRUE(fs::is_empty(cdir));  // a finished run's checkpoint is removed
  // --resume without a checkpoint starts from zero, with a warning.
  const RunResult fresh =
      run({"run", spec.string(), "--out", (dir_ / "fresh").string(), "--quiet", "--checkpoint-dir", cdir, "--resume"},
          std::chrono::seconds(120));
  EXPECT_EQ(fresh.exit_code, 0);
  EXPECT_NE(fresh.err.find("starting from zero"), std::string::npos) << fresh.err;
}

TEST_F(CliTest, QuietSuppressesProgress) {
  const RunResult r = run({"run", spec_file(kSmallSpec).string(), "--out", (dir_ / "out").string(), "--quiet"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.err.find("ETA"), std::string::npos) << r.err;
  EXPECT_TRUE(fs::is_regular_file(dir_ / "out" / "curve.csv"));
}

TEST_F(CliTest, OutDirMayAlreadyExistAndResultsAreOverwritten) {
  const fs::path out = dir_ / "out";
  fs::create_directories(out);
  write_text(out / "curve.csv", "stale\n");
  const RunResult r = run({"run", spec_file(kSmallSpec).string(), "--out", out.string()});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(lines_of(slurp(out / "curve.csv")).at(0), kCurveHeader);
}

// ---------------------------------------------------------------------------------------------
// 2. The thread count is honoured (from --threads, or from run.threads in the spec)

struct ThreadsCase {
  const char* name;
  std::string spec;
  std::vector<std::string> args;  ///< "{SPEC}" and "{OUT}" are replaced by the paths
};

void PrintTo(const ThreadsCase& c, std::ostream* os) { *os << c.name; }

class CliThreadsTest : public CliTest, public ::testing::WithParamInterface<ThreadsCase> {};

TEST_P(CliThreadsTest, SummaryReportsOneThread) {
  const ThreadsCase& c = GetParam();
  spec_file(c.spec);
  const RunResult r = run(substitute(c.args));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const json s = json::parse(slurp(dir_ / "out" / "summary.json"));
  EXPECT_EQ(s.at("threads").get<long>(), 1);
}

constexpr const char* kSmallSpecTwoThreads = R"({
  "grain": {"edge_spheres": 4}, "loading": {"rate_number": 1e-3}, "output": {"curve_points": 20},
  "run": {"threads": 2}})";

INSTANTIATE_TEST_SUITE_P(
    Cli, CliThreadsTest,
    ::testing::Values(ThreadsCase{"flag_last", kSmallSpec, {"run", "{SPEC}", "--out", "{OUT}", "--threads", "1"}},
                      ThreadsCase{"flag_first", kSmallSpec, {"run", "--threads", "1", "--out", "{OUT}", "{SPEC}"}},
                      ThreadsCase{"spec_field",
                                  R"({"grain": {"edge_spheres": 4}, "loading": {"rate_number": 1e-3},
                        "output": {"curve_points": 20}, "run": {"threads": 1}})",
                                  {"run", "{SPEC}", "--out", "{OUT}"}},
                      ThreadsCase{"flag_overrides_spec",
                                  kSmallSpecTwoThreads,
                                  {"run", "{SPEC}", "--out", "{OUT}", "--threads", "1"}}),
    [](const ::testing::TestParamInfo<ThreadsCase>& info) { return std::string(info.param.name); });

// ---------------------------------------------------------------------------------------------
// 3. Bad input: exit code 2, a message on stderr naming the problem, no output written

struct BadCase {
  const char* name;
  std::optional<std::string> spec;        ///< spec file contents; nullopt = the file does not exist
  std::vector<std::string> args;          ///< "{SPEC}" and "{OUT}" are replaced by the paths
  std::vector<std::string> must_mention;  ///< substrings of stderr; "{SPEC}" is replaced too
};

void PrintTo(const BadCase& c, std::ostream* os) { *os << c.name; }

class CliBadInputTest : public CliTest, public ::testing::WithParamInterface<BadCase> {};

TEST_P(CliBadInputTest, ExitsTwoWithAMessageAndWritesNothing) {
  const BadCase& c = GetParam();
  if (c.spec) spec_file(*c.spec);
  const RunResult r = run(substitute(c.args));
  EXPECT_EQ(r.exit_code, 2) << "stderr:\n" << r.err;
  EXPECT_FALSE(r.err.empty());
  // The scratch path (which holds the test's name) is blanked out, so that a word of the test name
  // in the echoed spec path cannot satisfy a check; "{SPEC}" checks look at the full text.
  std::string err_without_paths = r.err;
  for (std::size_t at; (at = err_without_paths.find(dir_.string())) != std::string::npos;)
    err_without_paths.replace(at, dir_.string().size(), "<dir>");
  for (const std::string& m : c.must_mention) {
    const std::string& text = m.find("{SPEC}") != std::string::npos ? r.err : err_without_paths;
    EXPECT_NE(text.find(substitute(m)), std::string::npos) << "stderr should mention '" << substitute(m) << "':\n"
                                                           << r.err;
  }
  EXPECT_FALSE(fs::exists(dir_ / "out")) << "a failing run must not create its output directory";
}

const std::vector<std::string> kRunArgs{"run", "{SPEC}", "--out", "{OUT}"};

INSTANTIATE_TEST_SUITE_P(
    Cli, CliBadInputTest,
    ::testing::Values(
        BadCase{
            "unknown_field", R"({"grain": {"edge_sphere": 4}})", kRunArgs, {"'grain.edge_sphere'", "unknown field"}},
        BadCase{
            "unknown_top_level_field", R"({"experiment": "two_cube_sliding", "lable": "x"})", kRunArgs, {"'lable'"}},
        BadCase{"out_of_range", R"({"grain": {"edge_spheres": 1}})", kRunArgs, {"'grain.edge_spheres'", "[2, 40]"}},
        BadCase{"out_of_range_real", R"({"material": {"friction": -0.1}})", kRunArgs, {"'material.friction'"}},
        BadCase{"wrong_type_string_for_number",
                R"({"material": {"friction": "high"}})",
                kRunArgs,
                {"'material.friction'", "number"}},
        BadCase{"wrong_type_fraction_for_integer",
                R"({"grain": {"edge_spheres": 4.5}})",
                kRunArgs,
                {"'grain.edge_spheres'", "integer"}},
        BadCase{"wrong_type_section", R"({"grain": 4})", kRunArgs, {"'grain'", "object"}},
        BadCase{"spec_not_an_object", "[1, 2]", kRunArgs, {"object"}},
        BadCase{"invalid_json", R"({"grain": {"edge_spheres": 4)", kRunArgs, {"{SPEC}", "JSON"}},
        BadCase{"empty_spec_file", "", kRunArgs, {"JSON"}},
        BadCase{"unknown_experiment", R"({"experiment": "triaxial"})", kRunArgs, {"'experiment'", "triaxial"}},
        BadCase{"crystal_with_cube_grains",
                R"({"experiment": "crystal_compression", "grain": {"shape": "cube"}})",
                kRunArgs,
                {"'grain.shape'", "rhombic_dodecahedron"}},
        BadCase{"crystal_knockout_outside",
                R"({"experiment": "crystal_compression", "crystal": {"knockout": [864]}})",
                kRunArgs,
                {"'crystal.knockout'", "[0, 863]"}},
        BadCase{"missing_spec_file", std::nullopt, kRunArgs, {"{SPEC}"}},
        BadCase{"missing_out", kSmallSpec, {"run", "{SPEC}"}, {"--out"}},
        BadCase{"out_without_value", kSmallSpec, {"run", "{SPEC}", "--out"}, {"--out"}},
        BadCase{"missing_spec_argument", kSmallSpec, {"run", "--out", "{OUT}"}, {"SPEC"}},
        BadCase{"unexpected_argument", kSmallSpec, {"run", "{SPEC}", "--out", "{OUT}", "--fast"}, {"'--fast'"}},
        BadCase{"threads_not_a_number",
                kSmallSpec,
                {"run", "{SPEC}", "--out", "{OUT}", "--threads", "abc"},
                {"'--threads'", "[1, 256]"}},
        BadCase{"threads_out_of_range",
                kSmallSpec,
                {"run", "{SPEC}", "--out", "{OUT}", "--threads", "0"},
                {"'--threads'", "[1, 256]"}},
        BadCase{"unknown_command", kSmallSpec, {"frobnicate"}, {"'frobnicate'", "usage"}},
        BadCase{"no_command", kSmallSpec, {}, {"usage"}}),
    [](const ::testing::TestParamInfo<BadCase>& info) { return std::string(info.param.name); });

// ---------------------------------------------------------------------------------------------
// 4. estimate: in-process, instant, nothing written

// Cubes along [1 1 0] slide on a cube plane at Coulomb's (1 + f)/(1 - f) (docs/model.md, "Yield estimate"); a
// shear spec gets its tau / sigma_n; a bad spec exits 2 naming the field.
TEST_F(CliTest, EstimatePrintsTheRigidGrainYieldWithoutRunning) {
  const fs::path spec = spec_file(R"({"experiment": "crystal_compression", "grain": {"edge_spheres": 4},
    "material": {"friction": 0.2}, "crystal": {"lattice": "sc", "grains_x": 4, "layers_y": 6, "rows_z": 6},
    "loading": {"axis": [1, 1, 0]}})");
  const RunResult json_run = run({"estimate", spec.string(), "--json"});
  ASSERT_EQ(json_run.exit_code, 0) << json_run.err;
  const nlohmann::json answer = nlohmann::json::parse(json_run.out);
  EXPECT_EQ(answer.at("experiment"), "crystal_compression");
  EXPECT_GT(answer.at("spheres").get<double>(), 0);
  EXPECT_TRUE(answer.at("spheres").is_number_integer() && answer.at("grains").is_number_integer()) << json_run.out;
  EXPECT_NEAR(answer.at("yield_estimate").at("axial_over_p0").get<double>(), 1.2 / 0.8, 1e-12);
  const RunResult text = run({"estimate", spec.string()});
  ASSERT_EQ(text.exit_code, 0) << text.err;
  EXPECT_NE(text.out.find("rigid-grain first yield: sigma1 = 1.5 p0"), std::string::npos) << text.out;
  const fs::path shear = spec_file(R"({"experiment": "crystal_shear", "crystal": {"lattice": "sc"}})", "shear.json");
  const RunResult sheared = run({"estimate", shear.string()});
  ASSERT_EQ(sheared.exit_code, 0) << sheared.err;
  EXPECT_NE(sheared.out.find("tau / sigma_n = 0.35, sliding on (1 0 0) along [0 1 0]"), std::string::npos) << sheared.out;
  const fs::path bad = spec_file(R"({"experiment": "crystal_shear", "loading": {"direction": [1, 0, 0]}})", "bad.json");
  const RunResult refused = run({"estimate", bad.string()});
  EXPECT_EQ(refused.exit_code, 2);
  EXPECT_NE(refused.err.find("loading.direction"), std::string::npos) << refused.err;
  EXPECT_FALSE(fs::exists(dir_ / "out"));
}

// ---------------------------------------------------------------------------------------------
// 4b. experiments

// A line per experiment for people (name, title; the descriptions of all are tens of kB); --json the description
// GET /v1/experiments serves, --markdown docs/spec.md; anything else exits 2 (issue 51).
TEST_F(CliTest, ExperimentsListsOneLineEachAndJsonOnRequest) {
  const RunResult list = run({"experiments"});
  ASSERT_EQ(list.exit_code, 0) << list.err;
  const RunResult json_run = run({"experiments", "--json"});
  ASSERT_EQ(json_run.exit_code, 0) << json_run.err;
  const nlohmann::json described = nlohmann::json::parse(json_run.out);
  ASSERT_FALSE(described.at("experiments").empty());
  std::istringstream lines(list.out);
  for (const nlohmann::json& e : described.at("experiments")) {
    std::string line;
    ASSERT_TRUE(std::getline(lines, line)) << list.out;
    EXPECT_EQ(line.rfind(e.at("name").get<std::string>() + "  ", 0), 0u) << line;
    EXPECT_NE(line.find(e.at("title").get<std::string>()), std::string::npos) << line;
  }
  EXPECT_LT(list.out.size(), 4000u) << "a list, not the fields";
  EXPECT_NE(list.out.find("--json"), std::string::npos) << list.out;
  EXPECT_FALSE(described.at("experiments")[0].at("fields").empty());
  const RunResult markdown = run({"experiments", "--markdown"});
  EXPECT_EQ(markdown.exit_code, 0);
  EXPECT_EQ(markdown.out.rfind("# ", 0), 0u) << markdown.out.substr(0, 80);
  const RunResult bad = run({"experiments", "--yaml"});
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_NE(bad.err.find("'--yaml'"), std::string::npos) << bad.err;
}

// ---------------------------------------------------------------------------------------------
// 5. version

// --help and --version work alone and after any command: usage or version on stdout, exit 0, nothing run.
TEST_F(CliTest, HelpAndVersionForEveryCommand) {
  for (const std::vector<std::string>& args : std::vector<std::vector<std::string>>{{"--help"},
                                                                                    {"-h"},
                                                                                    {"help"},
                                                                                    {"run", "--help"},
                                                                                    {"submit", "--help"},
                                                                                    {"wait", "7", "--help"},
                                                                                    {"list", "-h"}}) {
    const RunResult r = run(args);
    EXPECT_EQ(r.exit_code, 0) << args[0] << ": " << r.err;
    EXPECT_NE(r.out.find("usage: granulab run"), std::string::npos) << args[0];
  }
  for (const std::vector<std::string>& args :
       std::vector<std::vector<std::string>>{{"--version"}, {"-V"}, {"run", "--version"}}) {
    const RunResult r = run(args);
    EXPECT_EQ(r.exit_code, 0) << r.err;
    EXPECT_TRUE(std::regex_match(r.out, std::regex(R"(granulab \d+\.\d+\.\d+\+[0-9a-f]{12}\.[a-z0-9]+\s*)"))) << r.out;
  }
}

TEST_F(CliTest, VersionPrintsAVersionAndExitsZero) {
  const RunResult r = run({"version"});
  EXPECT_EQ(r.exit_code, 0) << r.err;
  // The project version, the hash of the sources that compute results (cmake/engine_version.cmake) and the contact
  // kernel this CPU runs.
  EXPECT_TRUE(std::regex_match(r.out, std::regex(R"(granulab \d+\.\d+\.\d+\+[0-9a-f]{12}\.(avx512|avx2|sse2|generic)\s*)")))
      << "stdout: '" << r.out << "'";
}

}  // namespace
