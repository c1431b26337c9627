// granulab: the command-line tool. `granulab run SPEC.json --out DIR` runs one experiment in-process
// (no server) and writes DIR/summary.json, DIR/curve.csv and DIR/snapshots/. Progress and an ETA go
// to stderr; failures exit non-zero with a message that names the bad field.
#include <omp.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <optional>
#include <sstream>
#include <string>

#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>

#include "api/engine_version.h"
#include "api/int_option.h"
#include "api/passive_openmp.h"
#include "api/runner.h"
#include "api/spec.h"
#include "api/spec_docs.h"
#include "clients/cli/estimate.h"
#include "clients/cli/files_sink.h"
#include "clients/cli/remote.h"
#include "clients/cli/worker.h"

namespace fs = std::filesystem;
using namespace granulab;

namespace {

const char* kUsage =
    "usage: granulab run SPEC.json --out DIR [--threads N] [--quiet] [--profile]\n"
    "                    [--checkpoint-dir CDIR [--checkpoint-seconds S] [--resume]]\n"
    "       granulab submit SPEC.json|- [--reuse] [--priority N] [--dry-run] [--json]   (prints the job id)\n"
    "       granulab sweep SPEC.json --vary KEY=V1,V2[,...] [--vary ...] [--zip] [--label L] --out DIR\n"
    "       granulab wait ID [ID...] | status ID | results ID --out DIR | cancel ID | priority ID --priority N |\n"
    "                delete ID | list [--status S] [--owner U] [--limit N]\n"
    "                (server: --server URL or GRANULAB_SERVER; token: GRANULAB_TOKEN; an https server's own\n"
    "                certificate: --ca-file FILE or GRANULAB_CA_FILE; status, cancel, delete,\n"
    "                priority and list print lines for people, --json the server's answer for scripts)\n"
    "       granulab estimate SPEC.json [--json]   (in-process, instant: size, expected steps, rigid-grain yield)\n"
    "       granulab experiments [--json | --markdown]   (a line each: name and title; --json or --markdown: with\n"
    "                its spec fields and curve columns, as GET /v1/experiments and docs/spec.md)\n"
    "       granulab version\n"
    "       granulab worker --server URL --job ID [--patience S]   (what granulabd's Slurm jobs run; docs/cluster.md)\n"
    "run: one experiment in-process; writes DIR/summary.json, DIR/curve.csv, DIR/snapshots/.\n"
    "submit --dry-run: validates and prints the cost (spheres, steps, memory, expected time on that server).\n"
    "sweep: submits a server sweep (every combination of the lists, or paired with --zip), shows a live line per\n"
    "job, then writes DIR/sweep.csv (a row per job: values, status, its experiment's key values) and DIR/<id>/ per job.\n"
    "--vary's values are JSON or plain text; commas inside [ ], { } and \"...\" belong to the value, so a list is one\n"
    "value: --vary 'loading.axis=[1,1,0],[1,1,1]' is two jobs.\n"
    "wait: a live line per job (progress, ETA, latest strain and stress); exit 0 when all succeeded; Ctrl-C stops\n"
    "waiting, not the jobs.\n"
    "With --checkpoint-dir, the run's state is saved in CDIR every S seconds (default 60, 0 = never); --resume "
    "continues\n"
    "a killed run of the same spec from there, bit for bit (no checkpoint yet: it starts from zero).\n"
    "The spec's fields: docs/spec.md or `granulab experiments --markdown` (every field has a default).\n";

std::string read_file(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::invalid_argument("cannot read spec file '" + path.string() + "'");
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

std::string duration(double s) {
  char buf[64];
  if (s < 60) std::snprintf(buf, sizeof buf, "%.0f s", s);
  else if (s < 3600) std::snprintf(buf, sizeof buf, "%d min %02d s", int(s) / 60, int(s) % 60);
  else std::snprintf(buf, sizeof buf, "%d h %02d min", int(s) / 3600, (int(s) % 3600) / 60);
  return buf;
}

// Progress on stderr: a rewritten line on a terminal, a line every 10 s otherwise (logs, CI).
class ProgressPrinter {
 public:
  explicit ProgressPrinter(bool quiet) : quiet_(quiet), tty_(isatty(STDERR_FILENO)) {}
  bool operator()(double fraction) {
    if (quiet_) return true;
    const auto now = std::chrono::steady_clock::now();
    const double since_print = std::chrono::duration<double>(now - last_).count();
    if (fraction < 1 && since_print < (tty_ ? 0.5 : 10)) return true;
    last_ = now;
    const double elapsed = std::chrono::duration<double>(now - start_).count();
    const double eta = fraction > 0 ? elapsed * (1 - fraction) / fraction : 0;
    std::fprintf(stderr, "%s%5.1f %%  elapsed %s  ETA %s%s", tty_ ? "\r" : "", 100 * fraction,
                 duration(elapsed).c_str(), duration(eta).c_str(), tty_ ? "   " : "\n");
    if (tty_ && fraction >= 1) std::fputc('\n', stderr);
    return true;
  }

 private:
  bool quiet_, tty_;
  std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now(), last_{};
};

// Per-stage timings of the time step, from what the run wrote to summary.json.
void print_profile(const fs::path& summary_path) {
  const nlohmann::json s = nlohmann::json::parse(read_file(summary_path));
  const double steps = std::max(1.0, s["steps"].get<double>()), wall = s["wall_seconds"].get<double>();
  std::fprintf(stderr, "%-18s %10s %12s %7s\n", "stage", "seconds", "ms/step", "share");
  double staged = 0;
  for (const auto& [stage, seconds] : s["stage_seconds"].items()) {
    const double t = seconds.get<double>();
    staged += t;
    std::fprintf(stderr, "%-18s %10.3f %12.4f %6.1f%%\n", stage.c_str(), t, 1e3 * t / steps, 100 * t / wall);
  }
  // The rest: building the sample, the summary and the files.
  std::fprintf(stderr, "%-18s %10.3f %12.4f %6.1f%%\n", "other", wall - staged, 1e3 * (wall - staged) / steps,
               100 * (wall - staged) / wall);
  std::fprintf(stderr, "%-18s %10.3f %12.4f  (%g steps, %d threads)\n", "total", wall, 1e3 * wall / steps, steps,
               s["threads"].get<int>());
}

// The hash part of the engine version: checkpoints of another build are not this build's to resume.
std::string build_id() {
  const std::string v = api::engine_version();
  return v.substr(v.find('+') + 1);
}

int run(int argc, char** argv) {
  std::string spec_path, out_dir, checkpoint_dir;
  int threads = -1, checkpoint_seconds = 60;
  bool quiet = false, profile = false, resume = false;
  for (int i = 2; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--out" && i + 1 < argc) out_dir = argv[++i];
    else if (a == "--threads" && i + 1 < argc) threads = api::parse_int_option("--threads", argv[++i], 1, 256);
    else if (a == "--quiet") quiet = true;
    else if (a == "--profile") profile = true;
    else if (a == "--checkpoint-dir" && i + 1 < argc) checkpoint_dir = argv[++i];
    else if (a == "--checkpoint-seconds" && i + 1 < argc)
      checkpoint_seconds = api::parse_int_option("--checkpoint-seconds", argv[++i], 0, 86400);
    else if (a == "--resume") resume = true;
    else if (spec_path.empty() && a.rfind("--", 0) != 0) spec_path = a;
    else throw std::invalid_argument("unexpected argument '" + a + "'\n" + kUsage);
  }
  if (spec_path.empty() || out_dir.empty())
    throw std::invalid_argument(std::string("run needs SPEC and --out DIR\n") + kUsage);
  if (resume && checkpoint_dir.empty()) throw std::invalid_argument("--resume needs --checkpoint-dir CDIR");

  api::Spec spec;
  try {
    spec = api::parse_spec_text(read_file(spec_path));
  } catch (const api::SpecError& e) {
    throw std::invalid_argument(spec_path + ": " + e.what());
  }
  if (threads < 0) threads = spec.threads;
  if (threads > 0) omp_set_num_threads(threads);

  const fs::path out(out_dir);
  ProgressPrinter printer(quiet);
  // One checkpoint file per spec (and build): another spec's or build's is never picked up by mistake.
  const fs::path checkpoint_file =
      checkpoint_dir.empty()
          ? fs::path()
          : fs::path(checkpoint_dir) / ("checkpoint_" + api::spec_hash(spec.normalized) + "_" + build_id() + ".bin");
  std::optional<api::Resume> from;
  if (resume && fs::exists(checkpoint_file)) {
    from = cli::read_checkpoint_file(checkpoint_file);
    spdlog::info("resuming from {} after {} curve rows", checkpoint_file.string(), from->rows);
  } else if (resume) {
    spdlog::warn("no checkpoint of this spec in {}: starting from zero", checkpoint_dir);
  }
  cli::FilesSink sink(
      out, [&](double f) { return printer(f); }, checkpoint_file, checkpoint_seconds);
  spdlog::info("{}{}: {} thread(s); spec with defaults in {}", spec.name(),
               spec.label.empty() ? "" : " \"" + spec.label + "\"", omp_get_max_threads(),
               (out / "summary.json").string());
  const nlohmann::json summary = api::run(spec, sink, from ? &*from : nullptr);
  for (const auto& w : summary.value("warnings", nlohmann::json::array())) spdlog::warn("{}", w.get<std::string>());
  const double steps = summary["steps"].get<double>(), wall = summary["wall_seconds"].get<double>();
  spdlog::info("{} grains, {} spheres, {:.0f} steps in {:.1f} s ({:.3g} s/step); curve: {}",
               summary["grains"].get<long>(), summary["spheres"].get<long>(), steps, wall,
               steps > 0 ? wall / steps : 0.0, (out / "curve.csv").string());
  if (profile) print_profile(out / "summary.json");
  return 0;
}

// `granulab experiments`: a line per experiment, its name and title, for people (the fields of all of them are
// tens of kB: --json, --markdown).
std::string experiments_list(const nlohmann::json& description) {
  std::size_t width = 0;
  for (const nlohmann::json& e : description["experiments"]) width = std::max(width, e["name"].get<std::string>().size());
  std::string out;
  for (const nlohmann::json& e : description["experiments"]) {
    const std::string name = e["name"].get<std::string>();
    out += name + std::string(width + 2 - name.size(), ' ') + e["title"].get<std::string>() + "\n";
  }
  return out + "Spec fields and curve columns: granulab experiments --markdown (docs/spec.md), or --json.\n";
}

}  // namespace

int main(int argc, char** argv) {
  api::reexec_with_passive_openmp(argv);
  spdlog::set_default_logger(spdlog::stderr_color_mt("granulab"));
  spdlog::set_pattern("[%H:%M:%S] [%^%l%$] %v");
  if (argc < 2) {
    std::cerr << kUsage;
    return 2;
  }
  const std::string command = argv[1];
  // --help and --version anywhere, for every command: the usage on stdout, exit 0.
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--help" || a == "-h" || (i == 1 && a == "help")) {
      std::cout << kUsage;
      return 0;
    }
    if (a == "--version" || (i == 1 && a == "-V")) {
      std::cout << "granulab " << api::engine_version() << "\n";
      return 0;
    }
  }
  try {
    if (command == "run") return run(argc, argv);
    if (command == "experiments") {
      const std::string format = argc > 2 ? argv[2] : "";
      if (argc > 3 || (!format.empty() && format != "--json" && format != "--markdown")) {
        std::cerr << "'experiments' takes --json or --markdown, got '" << argv[argc - 1] << "'\n" << kUsage;
        return 2;
      }
      if (format == "--markdown") std::cout << api::experiments_markdown();
      else if (format == "--json") std::cout << api::experiments_json().dump(2) << "\n";
      else std::cout << experiments_list(api::experiments_json());
      return 0;
    }
    if (command == "version") {
      std::cout << "granulab " << api::engine_version() << "\n";
      return 0;
    }
    if (command == "worker") return cli::run_worker(argc, argv);
    if (command == "estimate") return cli::run_estimate(argc, argv);
    if (command == "submit" || command == "sweep" || command == "status" || command == "wait" || command == "results" ||
        command == "cancel" || command == "list" || command == "delete" || command == "priority")
      return cli::run_remote(argc, argv);
    std::cerr << "unknown command '" << command << "'\n" << kUsage;
    return 2;
  } catch (const std::invalid_argument& e) {
    spdlog::error("{}", e.what());
    return 2;
  } catch (const std::exception& e) {
    spdlog::error("failed: {}", e.what());
    return 1;
  }
}
