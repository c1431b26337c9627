// The worker routes and `granulab worker` without a cluster (docs/api.md, "Workers"): the daemon's routes
// in-process on a real SQLite file, with an executor that runs nothing itself (jobs wait in the queue as
// they would for Slurm), and the real CLI binary as the worker.
#include <gtest/gtest.h>

#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <memory>
#include <sstream>
#include <string>
#include <thread>

#include <nlohmann/json.hpp>

#include "server/executor.h"
#include "server/http_server.h"
#include "tests/server/daemon_fixture.h"

// After the project headers: <resolv.h>, pulled in by httplib, defines a macro `_res` that breaks Eigen.
#include <httplib.h>

extern char** environ;

namespace granulab::server {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

// A cluster that never runs anything: the test plays its part by starting workers itself.
class NoExecutor : public Executor {
 public:
  void start() override {}
  void stop() override {}
  void notify() override { ++notified; }
  std::string name() const override { return "slurm"; }
  int workers() const override { return 0; }
  int threads_per_job() const override { return 1; }
  double checkpoint_seconds() const override { return 0.2; }
  int notified = 0;
};

// About 2 s on one thread, 40 curve rows.
const char* kSpec = R"({"experiment": "two_cube_sliding", "grain": {"edge_spheres": 5},
                        "loading": {"rate_number": 2e-6, "max_slide": 0.3}, "output": {"curve_points": 40},
                        "run": {"threads": 1}})";

std::string read(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

class WorkerRoutes : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("granulab_worker_" + std::to_string(::getpid()) + "_" +
                                        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::create_directories(dir_);
    store_ = std::make_unique<JobStore>((dir_ / "jobs.db").string());
    HttpOptions options;
    options.max_body_bytes = 64 * 1024;
    options.tokens = {{"user-token", User{"alice", true}}};
    http_ = std::make_unique<HttpServer>(*store_, executor_, options);
    mount_every_route(*http_);
    port_ = http_->bind("127.0.0.1", 0);
    ASSERT_GT(port_, 0);
    serving_ = std::thread([this] { http_->serve(); });
    client_ = std::make_unique<httplib::Client>("127.0.0.1", port_);
    client_->set_bearer_token_auth("user-token");
    for (int k = 0; k < 100 && !client_->Get("/v1/health"); ++k)
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  void TearDown() override {
    http_->stop();
    serving_.join();
    client_.reset();
    http_.reset();
    store_.reset();
    fs::remove_all(dir_);
  }

  std::int64_t submit(const std::string& secret, const char* spec = kSpec) {
    auto r = client_->Post("/v1/jobs", spec, "application/json");
    EXPECT_TRUE(r && r->status == 201) << (r ? r->body : "no answer");
    const std::int64_t id = json::parse(r->body)["id"].get<std::int64_t>();
    EXPECT_EQ(store_->worker_token(id, secret), secret);
    return id;
  }
  json job(std::int64_t id) { return json::parse(client_->Get("/v1/jobs/" + std::to_string(id))->body); }

  // `granulab worker` for job `id` with `secret`, started (not waited for); its pid.
  pid_t start_worker(std::int64_t id, const std::string& secret) {
    const std::string cli = std::string(GRANULAB_BINARY_DIR) + "/granulab",
                      server = "http://127.0.0.1:" + std::to_string(port_), job = std::to_string(id),
                      token = "GRANULAB_WORKER_TOKEN=" + secret;
    std::vector<std::string> env;
    for (char** e = environ; *e; ++e)
      if (std::string(*e).rfind("SLURM_", 0) != 0) env.push_back(*e);  // not part of a Slurm job here
    env.push_back(token);
    std::vector<char*> envp;
    for (std::string& e : env) envp.push_back(e.data());
    envp.push_back(nullptr);
    const char* argv[] = {cli.c_str(), "worker",     "--server", server.c_str(), "--job",
                          job.c_str(), "--patience", "5",        nullptr};
    pid_t pid = 0;
    EXPECT_EQ(::posix_spawn(&pid, cli.c_str(), nullptr, nullptr, const_cast<char**>(argv), envp.data()), 0);
    return pid;
  }
  int finish(pid_t pid) {
    int status = 0;
    ::waitpid(pid, &status, 0);
    return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  }
  std::string local_curve(const char* spec = kSpec) {
    std::ofstream(dir_ / "spec.json") << spec;
    const std::string cmd = std::string(GRANULAB_BINARY_DIR) + "/granulab run " + (dir_ / "spec.json").string() +
                            " --out " + (dir_ / "local").string() + " --threads 1 --quiet > /dev/null 2>&1";
    EXPECT_EQ(std::system(cmd.c_str()), 0);
    return read(dir_ / "local" / "curve.csv");
  }
  std::string curve_csv(std::int64_t id) {
    return client_->Get("/v1/jobs/" + std::to_string(id) + "/curve?format=csv")->body;
  }

  fs::path dir_;
  NoExecutor executor_;
  std::unique_ptr<JobStore> store_;
  std::unique_ptr<HttpServer> http_;
  std::unique_ptr<httplib::Client> client_;
  std::thread serving_;
  int port_ = 0;
};

TEST_F(WorkerRoutes, AWorkerRunsItsJobToTheCurveOfALocalRun) {
  const std::int64_t id = submit("0123456789abcdef0123456789abcdef");
  EXPECT_EQ(job(id)["status"], "queued");  // nothing runs it until its worker comes
  EXPECT_EQ(finish(start_worker(id, "0123456789abcdef0123456789abcdef")), 0);
  const json done = job(id);
  ASSERT_EQ(done["status"], "succeeded") << done.dump();
  EXPECT_EQ(done["summary"]["threads"], 1);
  EXPECT_EQ(curve_csv(id), local_curve());
  // A finished job does not start again: a second worker is turned away without running it.
  EXPECT_EQ(finish(start_worker(id, "0123456789abcdef0123456789abcdef")), 0);
  EXPECT_EQ(job(id)["status"], "succeeded");
}

TEST_F(WorkerRoutes, ACrystalsSnapshotsComeBackAsALocalRunWritesThem) {
  // 36 grains, 0.3 s: confinement, then two snapshots on the way to 0.2 % strain.
  const char* crystal = R"({"experiment": "crystal_compression", "grain": {"edge_spheres": 3},
                            "crystal": {"grains_x": 3, "rows_z": 6, "layers_y": 2},
                            "loading": {"confining_pressure": 30000, "max_strain": 0.002, "rate_number": 1e-4},
                            "output": {"curve_points": 20, "snapshot_strains": [0, 0.001]}, "run": {"threads": 1}})";
  const std::int64_t id = submit("eeeeeeeeeeeeeeeeeeeeeeeeeeeeeeee", crystal);
  EXPECT_EQ(finish(start_worker(id, "eeeeeeeeeeeeeeeeeeeeeeeeeeeeeeee")), 0);
  ASSERT_EQ(job(id)["status"], "succeeded") << job(id).dump();
  EXPECT_EQ(curve_csv(id), local_curve(crystal));
  const json listed = json::parse(client_->Get("/v1/jobs/" + std::to_string(id) + "/snapshots")->body)["snapshots"];
  ASSERT_EQ(listed.size(), 2u) << listed.dump();
  for (int k = 0; k < 2; ++k) {
    const auto served = client_->Get("/v1/jobs/" + std::to_string(id) + "/snapshots/" + std::to_string(k));
    ASSERT_TRUE(served && served->status == 200);
    EXPECT_EQ(json::parse(served->body),
              json::parse(read(dir_ / "local" / "snapshots" / ("snapshot_" + std::to_string(k) + ".json"))))
        << "snapshot " << k;
  }
}

TEST_F(WorkerRoutes, ASecretOpensOnlyItsOwnJobsWorkerRoutes) {
  const std::int64_t a = submit("aaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaa"), b = submit("bbbbbbbbbbbbbbbbbbbbbbbbbbbbbbbb");
  httplib::Client raw("127.0.0.1", port_);
  const auto start = [&](std::int64_t id, const httplib::Headers& headers) {
    auto r = raw.Get("/v1/worker/jobs/" + std::to_string(id), headers);
    return r ? r->status : -1;
  };
  EXPECT_EQ(start(a, {}), 403);                                                        // no secret
  EXPECT_EQ(start(a, {{"Authorization", "Bearer user-token"}}), 403);                  // a user's token is not one
  EXPECT_EQ(start(a, {{"X-Worker-Token", "bbbbbbbbbbbbbbbbbbbbbbbbbbbbbbbb"}}), 403);  // another job's
  EXPECT_EQ(start(a, {{"X-Worker-Token", "aaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaa"}, {"X-Slurm-Job-Id", "77"}}),
            409);  // stale
  EXPECT_EQ(start(a, {{"X-Worker-Token", "aaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaa"}}), 200);
  EXPECT_EQ(job(a)["status"], "running");
  EXPECT_EQ(job(b)["status"], "queued");
  // A secret does not open the users' routes.
  auto listed = raw.Get("/v1/jobs", {{"X-Worker-Token", "aaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaa"}});
  ASSERT_TRUE(listed);
  EXPECT_EQ(listed->status, 401);
  // Bodies past the users' 64 KiB limit: refused from the head without the job's secret, read with it
  // (and this one refused for what it is: a chunk of no checkpoint being written).
  const std::string big(200 * 1024, 'x');
  const std::string path = "/v1/worker/jobs/" + std::to_string(a) + "/checkpoint/1/0";
  auto anonymous =
      raw.Post(path, {{"X-Worker-Token", "bbbbbbbbbbbbbbbbbbbbbbbbbbbbbbbb"}}, big, "application/octet-stream");
  ASSERT_TRUE(anonymous);
  EXPECT_EQ(anonymous->status, 413);
  auto trusted =
      raw.Post(path, {{"X-Worker-Token", "aaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaa"}}, big, "application/octet-stream");
  ASSERT_TRUE(trusted);
  EXPECT_EQ(trusted->status, 409) << trusted->body;
  EXPECT_NE(trusted->body.find("is being written"), std::string::npos) << trusted->body;
}

TEST_F(WorkerRoutes, AnInterruptedWorkerIsRequeuedAndTheNextResumesBitForBit) {
  const std::string secret = "cccccccccccccccccccccccccccccccc";
  const std::int64_t id = submit(secret);
  const pid_t pid = start_worker(id, secret);
  // Once it has stored a checkpoint (every 0.2 s) past a few rows: Slurm's warning before the time limit.
  const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  while (std::chrono::steady_clock::now() < until && job(id).value("progress", 0.0) < 0.3)
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  ASSERT_EQ(::kill(pid, SIGUSR1), 0);
  EXPECT_EQ(finish(pid), 0);
  const json requeued = job(id);
  EXPECT_EQ(requeued["status"], "queued") << requeued.dump();
  EXPECT_GE(executor_.notified, 1);  // the executor hears of it to submit it again
  const auto cp = store_->checkpoint(id);
  ASSERT_TRUE(cp);
  EXPECT_GT(cp->rows, 0);
  EXPECT_EQ(finish(start_worker(id, secret)), 0);
  const json done = job(id);
  ASSERT_EQ(done["status"], "succeeded") << done.dump();
  EXPECT_EQ(curve_csv(id), local_curve());
  bool resumed = false;
  for (const std::string& e : store_->events(id)) resumed |= e.rfind("requeued: signal USR1", 0) == 0;
  EXPECT_TRUE(resumed);
}

TEST_F(WorkerRoutes, ACancelReachesTheWorkerAtItsNextBatch) {
  const std::string secret = "dddddddddddddddddddddddddddddddd";
  const std::int64_t id = submit(secret);
  const pid_t pid = start_worker(id, secret);
  const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  while (std::chrono::steady_clock::now() < until && job(id)["status"] != "running")
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  auto r = client_->Post("/v1/jobs/" + std::to_string(id) + "/cancel", "", "application/json");
  ASSERT_TRUE(r);
  EXPECT_EQ(r->status, 202);
  EXPECT_EQ(finish(pid), 0);
  EXPECT_EQ(job(id)["status"], "cancelled");
}

}  // namespace
}  // namespace granulab::server
