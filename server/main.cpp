// granulabd: the lab server. Keeps jobs and results in an SQLite file, runs them on a bounded pool
// (workers x engine threads never exceed the cores), serves the HTTP API of docs/api.md. SIGTERM or
// SIGINT: stop accepting requests, interrupt running jobs and put them back in the queue, exit cleanly.
// After a kill -9, jobs found `running` at the next start are re-queued the same way.
#include <unistd.h>

#include <chrono>
#include <condition_variable>
#include <csignal>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <memory>
#include <mutex>
#include <iostream>
#include <optional>
#include <string>
#include <thread>

#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>

#include "api/int_option.h"
#include "api/passive_openmp.h"
#include "server/instance_lock.h"
#include "server/http_server.h"
#include "server/store/job_store.h"
#include "server/log_format.h"
#include "server/machine_speed.h"
#include "server/slurm/slurm_executor.h"
#include "server/worker_pool.h"

using namespace granulab::server;

namespace {

const char* kUsage =
    "usage: granulabd token add USER [--admin] [--token-file FILE]   (a new user's token, printed once)\n"
    "       granulabd token remove USER [--token-file FILE]   (the user's token taken out of the file)\n"
    "       granulabd [--host ADDR] [--port N] [--db FILE] [--workers K] [--threads T] [--token-file FILE]\n"
    "                 [--private] [--max-queued-per-user N] [--max-running-per-user N]\n"
    "                 [--request-timeout S] [--keep-alive-timeout S] [--max-connections N]\n"
    "                 [--max-connections-per-peer N]\n"
    "                 [--max-memory MB] [--max-sphere-steps X] [--checkpoint-seconds S] [--max-db-mb MB]\n"
    "                 [--max-sweep-mb MB] [--max-user-mb MB] [--tls-cert FILE --tls-key FILE]\n"
    "                 [--speed-probe-seconds S]\n"
    "  defaults: --host 127.0.0.1 --port 8080 --db var/granulab.db --workers 1 --threads cores/workers\n"
    "            --max-queued-per-user 1000 --max-running-per-user 0 (no limit) --request-timeout 10\n"
    "            --keep-alive-timeout 5 --max-connections 512 --max-connections-per-peer (a quarter of them)\n"
    "            --max-memory (half the physical memory, in MB) --max-sphere-steps 4e12 --checkpoint-seconds 60\n"
    "            --speed-probe-seconds 0.5 --max-sweep-mb 16 (the specs one sweep stores, points x spec size)\n"
    "  --max-db-mb: the database file may not grow past this (default: the disk's space); past it, or on a\n"
    "               full disk, submissions answer 507 and running jobs fail with the reason\n"
    "  --max-user-mb: what one user's jobs may hold or be expected to write in the store (default: no\n"
    "                 limit); a submission past it answers 507 storage_quota\n"
    "  --checkpoint-seconds: a running job stores its state this often; after a crash or a stop it resumes\n"
    "                        from there (0: never, jobs restart from zero)\n"
    "  --tls-cert, --tls-key: PEM certificate (chain) and key; the daemon then speaks HTTPS only (TLS 1.2+)\n"
    "  --speed-probe-seconds: at start, before any job runs, step a small crystal this long to learn this\n"
    "                         machine's speed for the dry runs' expected time, and again while no job runs\n"
    "                         (30 s later, doubling up to every 5 min; the best of 6 hours counts; 0: no probe)\n"
    "  --max-memory, --max-sphere-steps: a job whose estimate (docs/api.md, 'Budgets') is over is refused\n"
    "  --token-file: lines '<user> <token or sha256:hash> [admin]'; then every route but /v1/health needs\n"
    "                'Authorization: Bearer <token>', and only a job's owner or an admin may change it;\n"
    "                SIGHUP reads it again (jobs and connections carry on)\n"
    "  --private: reading a job is also for its owner and admins only (default: the lab reads everything)\n"
    "  --executor local|slurm: run jobs on this machine's pool (default) or as Slurm jobs (docs/cluster.md):\n"
    "      --slurm-url URL --slurm-user USER (--slurm-jwt-key FILE | SLURM_JWT in the environment)\n"
    "      [--slurm-partition P] [--public-url URL (where the nodes reach this daemon; default http://HOST:PORT)]\n"
    "      [--slurm-time-limit MIN (most a job may ask for; default 10080)] [--slurm-signal-seconds S (default 120)]\n"
    "      [--slurm-output PATTERN (the Slurm jobs' output on the node; default /dev/null)]\n"
    "      [--slurm-worker PATH (the granulab binary on the nodes; default the one next to granulabd)]\n"
    "      [--worker-ca-file PATH (with --tls-cert: the CA the workers trust, as the nodes see it; default the\n"
    "       --tls-cert file itself, which a self-signed certificate is)]\n";

using granulab::api::parse_int_option;
using granulab::api::parse_number_option;

// The command line, checked (std::invalid_argument names the bad option); `help` when --help was asked for.
struct DaemonOptions {
  std::string host = "127.0.0.1", db = "var/granulab.db", token_file, executor_name = "local", jwt_key_file;
  slurm::ExecutorOptions slurm;
  int port = 8080, workers = 1, threads = 0, max_running_per_user = 0, checkpoint_seconds = 60, max_db_mb = 0;
  double speed_probe_seconds = 0.5;
  HttpOptions http;
  bool help = false;
};

DaemonOptions parse_options(int argc, char** argv) {
  DaemonOptions o;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--help" || a == "-h") {
      o.help = true;
      return o;
    }
    if (a == "--private") {
      o.http.private_reads = true;
      continue;
    }
    if (i + 1 >= argc) throw std::invalid_argument("'" + a + "' needs a value\n" + kUsage);
    const std::string v = argv[++i];
    if (a == "--host") o.host = v;
    else if (a == "--port") o.port = parse_int_option(a, v, 0, 65535);
    else if (a == "--db") o.db = v;
    else if (a == "--workers") o.workers = parse_int_option(a, v, 1, 256);
    else if (a == "--threads") o.threads = parse_int_option(a, v, 1, 256);
    else if (a == "--token-file") o.token_file = v;
    else if (a == "--max-queued-per-user") o.http.max_queued_per_user = parse_int_option(a, v, 0, 1000000);
    else if (a == "--max-running-per-user") o.max_running_per_user = parse_int_option(a, v, 0, 1000000);
    else if (a == "--request-timeout") o.http.request_timeout_ms = 1000 * parse_int_option(a, v, 1, 3600);
    else if (a == "--keep-alive-timeout") o.http.keep_alive_timeout_ms = 1000 * parse_int_option(a, v, 1, 3600);
    else if (a == "--max-db-mb") o.max_db_mb = parse_int_option(a, v, 1, 100000000);
    else if (a == "--checkpoint-seconds") o.checkpoint_seconds = parse_int_option(a, v, 0, 86400);
    else if (a == "--max-connections") o.http.max_connections = parse_int_option(a, v, 1, 100000);
    else if (a == "--max-connections-per-peer")
      o.http.max_connections_per_peer = parse_int_option(a, v, 1, 100000);
    else if (a == "--max-sweep-mb") o.http.max_sweep_bytes = 1e6 * parse_int_option(a, v, 1, 1000000);
    else if (a == "--max-memory") o.http.max_memory_bytes = 1e6 * parse_int_option(a, v, 1, 100000000);
    else if (a == "--max-sphere-steps") o.http.max_sphere_steps = parse_number_option(a, v, 1, 1e18);
    else if (a == "--max-user-mb") o.http.max_user_bytes = 1e6 * parse_int_option(a, v, 1, 100000000);
    else if (a == "--speed-probe-seconds") o.speed_probe_seconds = parse_number_option(a, v, 0, 60);
    else if (a == "--tls-cert") o.http.tls_cert_file = v;
    else if (a == "--tls-key") o.http.tls_key_file = v;
    else if (a == "--executor") o.executor_name = v;
    else if (a == "--slurm-url") o.slurm.rest.url = v;
    else if (a == "--slurm-user") o.slurm.rest.user = v;
    else if (a == "--slurm-jwt-key") o.jwt_key_file = v;
    else if (a == "--slurm-partition") o.slurm.partition = v;
    else if (a == "--public-url") o.slurm.public_url = v;
    else if (a == "--slurm-time-limit") o.slurm.max_time_limit_minutes = parse_int_option(a, v, 1, 525600);
    else if (a == "--slurm-signal-seconds") o.slurm.signal_seconds = parse_int_option(a, v, 1, 86400);
    else if (a == "--slurm-output") o.slurm.output = v;
    else if (a == "--slurm-worker") o.slurm.worker_binary = v;
    else if (a == "--worker-ca-file") o.slurm.worker_ca_file = v;
    else throw std::invalid_argument("unknown option '" + a + "'\n" + kUsage);
  }
  return o;
}

// SIGHUP: the token file read again, so that a colleague added with `granulabd token add` can work without a
// restart, and one taken out with `token remove` no longer can; a file that does not read keeps the tokens as
// they were.
void reload_tokens(HttpServer& http, const std::string& token_file) {
  if (token_file.empty()) {
    spdlog::info("SIGHUP: no --token-file to read again; nothing changes");
    return;
  }
  try {
    std::string warning;
    auto tokens = read_token_file(token_file, &warning);
    if (!warning.empty()) spdlog::warn("{}", warning);
    const std::size_t n = tokens.size();
    http.replace_tokens(std::move(tokens));
    spdlog::info("SIGHUP: read {} token(s) from {}", n, token_file);
  } catch (const std::exception& e) {
    spdlog::error("SIGHUP: {}; the tokens stay as they were", e.what());
  }
}

// `granulabd token add USER [--admin] [--token-file FILE]`: exit status 0 and the token on stdout;
// `granulabd token remove USER [--token-file FILE]`: exit status 0, the user's line gone from the file.
int token_command(int argc, char** argv) {
  const std::string usage =
      "usage: granulabd token add USER [--admin] [--token-file FILE (default var/tokens)]\n"
      "       granulabd token remove USER [--token-file FILE]\n"
      "  add appends USER with a new random token, stored as its hash, and prints the token once; remove takes\n"
      "  USER's line out of the file (the user's jobs stay); a running granulabd --token-file FILE reads the file\n"
      "  again on SIGHUP (kill -HUP <pid>)\n";
  const std::string action = argc >= 3 ? argv[2] : "";
  if (argc < 4 || (action != "add" && action != "remove")) {
    std::cerr << usage;
    return 2;
  }
  std::string user = argv[3], file = "var/tokens";
  bool admin = false;
  for (int i = 4; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--admin" && action == "add") admin = true;
    else if (a == "--token-file" && i + 1 < argc) file = argv[++i];
    else {
      std::cerr << "unknown option '" << a << "'\n" << usage;
      return 2;
    }
  }
  try {
    if (action == "remove") {
      remove_token(file, user);
      std::cerr << "removed user '" << user << "' from " << file << ". A running granulabd --token-file " << file
                << "\nrefuses the token once it reads the file again, on SIGHUP (kill -HUP <pid>).\n";
      return 0;
    }
    if (std::filesystem::path(file).has_parent_path())
      std::filesystem::create_directories(std::filesystem::path(file).parent_path());
    const std::string token = add_token(file, user, admin);
    std::cout << token << "\n";
    std::cerr << "added " << (admin ? "admin " : "") << "user '" << user << "' to " << file
              << " (as the token's hash: this is the only time the token is shown). A running granulabd\n"
              << "--token-file " << file << " takes it on SIGHUP; the user sets GRANULAB_TOKEN to it.\n";
    return 0;
  } catch (const std::exception& e) {
    std::cerr << "granulabd token " << action << ": " << e.what() << "\n";
    return 2;
  }
}

// The executor --executor names, with `threads` per job: this machine's pool, or a Slurm cluster (then
// `cluster` points at it).
std::unique_ptr<Executor> make_executor(DaemonOptions& o, int threads, JobStore& store,
                                        slurm::SlurmExecutor*& cluster) {
  if (o.executor_name != "slurm") {
    auto pool = std::make_unique<WorkerPool>(store, o.workers, threads);
    pool->set_max_running_per_owner(o.max_running_per_user);
    pool->set_checkpoint_seconds(o.checkpoint_seconds);
    return pool;
  }
  slurm::ExecutorOptions& slurm_options = o.slurm;
  if (!o.jwt_key_file.empty()) {
    std::ifstream key(o.jwt_key_file, std::ios::binary);
    if (!key) throw std::invalid_argument("cannot read --slurm-jwt-key '" + o.jwt_key_file + "'");
    slurm_options.rest.jwt_key.assign(std::istreambuf_iterator<char>(key), {});
  } else if (const char* jwt = std::getenv("SLURM_JWT")) {
    slurm_options.rest.jwt = jwt;
  }
  if (slurm_options.worker_binary.empty())
    slurm_options.worker_binary = (std::filesystem::read_symlink("/proc/self/exe").parent_path() / "granulab").string();
  // A self-signed certificate is its own CA: the workers trust it by the same path, on a shared filesystem.
  if (slurm_options.worker_ca_file.empty() && !o.http.tls_cert_file.empty())
    slurm_options.worker_ca_file = std::filesystem::absolute(o.http.tls_cert_file).string();
  slurm_options.threads_per_job = threads;
  slurm_options.checkpoint_seconds = o.checkpoint_seconds;
  auto slurm_executor = std::make_unique<slurm::SlurmExecutor>(store, slurm_options);
  cluster = slurm_executor.get();
  return slurm_executor;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc >= 2 && std::string(argv[1]) == "token") return token_command(argc, argv);
  // A peer that resets a TLS connection must not end the daemon: OpenSSL writes without MSG_NOSIGNAL.
  std::signal(SIGPIPE, SIG_IGN);
  granulab::api::reexec_with_passive_openmp(argv);
  spdlog::set_default_logger(spdlog::stderr_color_mt("granulabd"));
  spdlog::set_formatter(std::make_unique<PrintableFormatter>("[%Y-%m-%d %H:%M:%S.%e] [%^%l%$] %v"));
  const int cores = int(std::max(1u, std::thread::hardware_concurrency()));
  try {
    DaemonOptions o = parse_options(argc, argv);
    if (o.help) {
      std::cout << kUsage;
      return 0;
    }
    const std::string &host = o.host, &db = o.db, &token_file = o.token_file, &executor_name = o.executor_name;
    slurm::ExecutorOptions& slurm_options = o.slurm;
    HttpOptions& options = o.http;
    const int port = o.port, max_db_mb = o.max_db_mb;
    int workers = o.workers;
    int threads = o.threads;
    if (executor_name != "local" && executor_name != "slurm")
      throw std::invalid_argument("--executor must be local or slurm, got '" + executor_name + "'");
    const bool on_slurm = executor_name == "slurm";
    if (on_slurm && (slurm_options.rest.url.empty() || slurm_options.rest.user.empty()))
      throw std::invalid_argument("--executor slurm needs --slurm-url URL and --slurm-user USER");
    // Workers x engine threads never exceed the cores: a worker runs at least one thread.
    if (!on_slurm && workers > cores) {
      spdlog::warn("--workers {} on {} cores would run {} engine threads at once: using {} workers", workers, cores,
                   workers, cores);
      workers = o.workers = cores;
    }
    const int fair = std::max(1, cores / workers);
    if (threads == 0) threads = fair;
    if (threads > fair) {
      spdlog::warn("{} workers x {} threads would exceed the {} cores: using {} thread(s) per job", workers, threads,
                   cores, fair);
      threads = fair;
    }

    // Signals go to one waiting thread, not to whichever thread happens to run.
    sigset_t signals;
    sigemptyset(&signals);
    sigaddset(&signals, SIGINT);
    sigaddset(&signals, SIGTERM);
    sigaddset(&signals, SIGHUP);
    pthread_sigmask(SIG_BLOCK, &signals, nullptr);

    if (db != ":memory:" && std::filesystem::path(db).has_parent_path()) {
      std::error_code ec;
      std::filesystem::create_directories(std::filesystem::path(db).parent_path(), ec);
      if (ec)
        throw std::runtime_error("cannot create the database folder '" +
                                 std::filesystem::path(db).parent_path().string() + "': " + ec.message());
    }
    std::optional<InstanceLock> lock;
    if (db != ":memory:") lock.emplace(db);
    JobStore store(db, std::int64_t(max_db_mb) * 1000000);
    // Jobs on a cluster are still there: the Slurm executor follows them again.
    const std::size_t requeued = store.requeue_running(on_slurm);
    if (requeued) spdlog::info("re-queued {} job(s) left running by the last run", requeued);
    // Chunks of checkpoints replaced, dropped or half written by the last run (a chunk per transaction).
    if (const std::size_t dropped = store.drop_checkpoint_garbage(std::size_t(-1)))
      spdlog::info("removed {} checkpoint chunk(s) of no checkpoint", dropped);
    slurm::SlurmExecutor* cluster = nullptr;
    const std::unique_ptr<Executor> executor = make_executor(o, threads, store, cluster);
    Executor& pool = *executor;
    if (!token_file.empty()) {
      std::string warning;
      options.tokens = read_token_file(token_file, &warning);
      if (!warning.empty()) spdlog::warn("{}", warning);
    }
    const bool loopback = host == "localhost" || host == "::1" || host.rfind("127.", 0) == 0;
    const bool tls = !options.tls_cert_file.empty();
    if (!loopback && !options.tokens.empty() && !tls)
      spdlog::warn("listening on {} beyond loopback with access tokens but without TLS: the tokens cross the network "
                   "in clear; give --tls-cert and --tls-key, or keep it on loopback",
                   host);
    MachineSpeed machine_speed(o.speed_probe_seconds);
    options.machine_speed = &machine_speed;
    HttpServer http(store, pool, options);
    for (auto group : {mount_meta_routes, mount_job_routes, mount_sweep_routes, mount_picture_routes,
                       mount_export_routes, mount_web_routes, mount_worker_routes})
      http.mount(group);
    const int bound = http.bind(host, port);
    if (bound < 0)
      throw std::runtime_error("cannot listen on " + host + ":" + std::to_string(port) +
                               " (is another server using the port?)");
    if (cluster) {
      // The nodes reach this daemon at --public-url; by default the address it listens on (its host name when
      // it listens on every address).
      if (slurm_options.public_url.empty()) {
        std::string name = host;
        if (host == "0.0.0.0" || host == "::") {
          char text[256] = {};
          if (::gethostname(text, sizeof text - 1) == 0) name = text;
        }
        cluster->set_public_url(std::string(tls ? "https://" : "http://") + name + ":" + std::to_string(bound));
        if (name.rfind("127.", 0) == 0 || name == "localhost" || name == "::1")
          spdlog::warn(
              "the Slurm jobs reach this daemon at {}, a loopback address: only nodes on this machine can; "
              "give --public-url (or --host) for a cluster",
              cluster->public_url());
      }
      spdlog::info("jobs run on the Slurm cluster at {}: {}; its nodes reach this daemon at {}", slurm_options.rest.url,
                   cluster->cluster(), cluster->public_url());
    }
    // The probe first, alone on the cores, then the jobs; the HTTP server answers meanwhile.
    std::thread starter([&] {
      machine_speed.measure();
      pool.start();
    });
    // Then the probe again while this machine runs no job (server/machine_speed.h), so that a load at start does
    // not stay in every dry run; a cluster's jobs run elsewhere, so its daemon reads the probe once.
    std::mutex refresher_mutex;
    std::condition_variable refresher_wake;
    bool stopping = false;
    std::thread refresher([&] {
      std::unique_lock<std::mutex> lock(refresher_mutex);
      while (!on_slurm && !refresher_wake.wait_for(lock, std::chrono::seconds(5), [&] { return stopping; })) {
        lock.unlock();
        try {
          machine_speed.refresh(store.count(JobStatus::running) == 0 && store.count(JobStatus::queued) == 0);
        } catch (const std::exception& e) {
          spdlog::warn("speed probe: could not read the queue ({}); the next try is in 5 s", e.what());
        }
        lock.lock();
      }
    });
    std::thread signal_waiter([&] {
      for (int sig = 0; sigwait(&signals, &sig) == 0;) {
        if (sig != SIGHUP) {
          spdlog::info("signal {}: stopping", sig);
          http.stop();
          return;
        }
        reload_tokens(http, token_file);
      }
    });
    spdlog::info(
        "granulabd listening on {}://{}:{} (db {}, {}, {}); the web page is "
        "{}://{}:{}/, the API document /v1/openapi.json",
        tls ? "https" : "http", host, bound, db,
        on_slurm ? "jobs on Slurm, " + std::to_string(threads) + " thread(s) each by default"
                 : std::to_string(workers) + " worker(s) x " + std::to_string(threads) + " thread(s)",
        options.tokens.empty() ? "open" : std::to_string(options.tokens.size()) + " token(s)", tls ? "https" : "http",
        host, bound);
    http.serve();
    {
      std::lock_guard<std::mutex> lock(refresher_mutex);
      stopping = true;
    }
    refresher_wake.notify_all();
    refresher.join();
    starter.join();
    pool.stop();
    // Jobs interrupted by the stop go back to the queue now, so the file says what will happen to them.
    try {
      if (const std::size_t n = store.requeue_running(on_slurm)) spdlog::info("re-queued {} interrupted job(s)", n);
    } catch (const std::exception& e) {
      // A full disk, say: the jobs stay `running` in the file and the next start re-queues them. Throwing on
      // would end the process with the signal thread still joinable (std::terminate, an abort).
      spdlog::error("could not re-queue the interrupted jobs now ({}); the next start will", e.what());
    }
    if (signal_waiter.joinable()) {
      pthread_kill(signal_waiter.native_handle(), SIGTERM);  // wakes sigwait if we stopped for another reason
      signal_waiter.join();
    }
    spdlog::info("granulabd stopped");
    return 0;
  } catch (const std::invalid_argument& e) {
    spdlog::error("{}", e.what());
    return 2;
  } catch (const std::exception& e) {
    spdlog::error("{}", e.what());
    return 1;
  }
}
