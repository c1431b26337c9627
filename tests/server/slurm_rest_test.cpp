// The slurmrestd client's own rules, against a stand-in slurmrestd on loopback (the real one is exercised by
// tests/server/slurm_executor_test.py): the dialect check, Slurm's errors in a 200, unknown jobs, array tasks
// pending together, and the tokens' encoding.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <thread>

#include <nlohmann/json.hpp>

#include "server/slurm/jwt.h"
#include "server/slurm/slurm_rest.h"

// After the project headers: <resolv.h>, pulled in by httplib, defines a macro `_res` that breaks Eigen.
#include <httplib.h>

namespace granulab::server::slurm {
namespace {

using nlohmann::json;

json meta(const std::string& dialect) {
  return {{"plugin", {{"type", "openapi/" + dialect}, {"name", "Slurm OpenAPI " + dialect}}},
          {"Slurm", {{"release", "22.05.8"}}}};
}

class FakeSlurmrestd : public ::testing::Test {
 protected:
  void SetUp() override {
    server_.Get(R"(/slurm/v0\.0\.38/ping)", [this](const httplib::Request& req, httplib::Response& res) {
      last_user_ = req.get_header_value("X-SLURM-USER-NAME");
      last_token_ = req.get_header_value("X-SLURM-USER-TOKEN");
      res.set_content(json{{"meta", meta(dialect_)}, {"errors", json::array()}, {"pings", json::array()}}.dump(),
                      "application/json");
    });
    server_.Post(R"(/slurm/v0\.0\.38/job/submit)", [this](const httplib::Request&, httplib::Response& res) {
      // A 200 that carries Slurm's refusal of the job, or a 500 while slurmctld is away.
      if (controller_away_) res.status = 500;
      const std::string why = controller_away_ ? "Unable to contact slurm controller (connect failure)"
                                               : "Invalid partition name specified";
      res.set_content(json{{"meta", meta("v0.0.38")}, {"errors", {{{"error", why}, {"error_number", 2000}}}}}.dump(),
                      "application/json");
    });
    server_.Get(R"(/slurm/v0\.0\.38/job/(\d+))", [](const httplib::Request& req, httplib::Response& res) {
      if (req.matches[1] == "404") {
        res.status = 500;
        res.set_content(json{{"meta", meta("v0.0.38")},
                             {"errors", {{{"error", "Invalid job id specified"}, {"error_number", 2017}}}}}
                            .dump(),
                        "application/json");
        return;
      }
      // Array 7: task 0 ran (job 7), task 1 runs (job 9), tasks 2-4 and 6 still pending together.
      json jobs = {{{"job_id", 7},
                    {"array_job_id", 7},
                    {"array_task_id", 0},
                    {"array_task_string", ""},
                    {"job_state", "COMPLETED"},
                    {"state_reason", "None"},
                    {"exit_code", 0}},
                   {{"job_id", 9},
                    {"array_job_id", 7},
                    {"array_task_id", 1},
                    {"array_task_string", ""},
                    {"job_state", "RUNNING"},
                    {"state_reason", "None"},
                    {"exit_code", 0}},
                   {{"job_id", 7},
                    {"array_job_id", 7},
                    {"array_task_id", nullptr},
                    {"array_task_string", "2-4,6"},
                    {"job_state", "PENDING"},
                    {"state_reason", "Resources"},
                    {"exit_code", 0}}};
      res.set_content(json{{"meta", meta("v0.0.38")}, {"errors", json::array()}, {"jobs", jobs}}.dump(),
                      "application/json");
    });
    port_ = server_.bind_to_any_port("127.0.0.1");
    serving_ = std::thread([this] { server_.listen_after_bind(); });
    for (int k = 0; k < 200 && !server_.is_running(); ++k) std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  void TearDown() override {
    server_.stop();
    serving_.join();
  }
  RestClient client(const std::string& key = "0123456789abcdef0123456789abcdef") {
    return RestClient(RestOptions{"http://127.0.0.1:" + std::to_string(port_), "granulab", key, ""});
  }

  httplib::Server server_;
  std::thread serving_;
  int port_ = 0;
  std::string dialect_ = "v0.0.38", last_user_, last_token_;
  bool controller_away_ = false;
};

TEST_F(FakeSlurmrestd, TheDialectIsCheckedAndANewerOneIsRefusedByName) {
  EXPECT_EQ(client().check(), "Slurm 22.05.8 (openapi/v0.0.38)");
  EXPECT_EQ(last_user_, "granulab");
  EXPECT_EQ(std::count(last_token_.begin(), last_token_.end(), '.'), 2) << last_token_;  // a minted JWT
  dialect_ = "v0.0.40";
  try {
    client().check();
    FAIL() << "a v0.0.40 answer was accepted";
  } catch (const Refused& e) {
    EXPECT_NE(std::string(e.what()).find("openapi/v0.0.40"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("speaks openapi/v0.0.38"), std::string::npos) << e.what();
  }
}

TEST_F(FakeSlurmrestd, SlurmsErrorsInA200AreARefusal) {
  try {
    client().submit({{"name", "x"}}, "#!/bin/sh\n");
    FAIL() << "a refused submission returned";
  } catch (const Refused& e) {
    EXPECT_NE(std::string(e.what()).find("Invalid partition name specified"), std::string::npos) << e.what();
  }
}

TEST_F(FakeSlurmrestd, AControllerAwayIsWorthTryingAgainNotARefusalOfTheJob) {
  controller_away_ = true;
  try {
    client().submit({{"name", "x"}}, "#!/bin/sh\n");
    FAIL() << "a submission without a controller returned";
  } catch (const Unreachable& e) {
    EXPECT_NE(std::string(e.what()).find("Unable to contact slurm controller"), std::string::npos) << e.what();
  }
}

TEST_F(FakeSlurmrestd, UnknownJobsAndPendingArrayTasks) {
  RestClient rest = client();
  EXPECT_FALSE(rest.job("404").has_value());
  const auto records = rest.job("7");
  ASSERT_TRUE(records.has_value());
  ASSERT_EQ(records->size(), 3u);
  const auto state_of = [&](int task) -> std::string {
    for (const SlurmJob& r : *records)
      if (r.covers_task(task)) return r.state + (r.reason.empty() ? "" : "/" + r.reason);
    return "none";
  };
  EXPECT_EQ(state_of(0), "COMPLETED");
  EXPECT_EQ(state_of(1), "RUNNING");
  EXPECT_EQ(state_of(3), "PENDING/Resources");
  EXPECT_EQ(state_of(6), "PENDING/Resources");
  EXPECT_EQ(state_of(5), "none");
}

TEST_F(FakeSlurmrestd, NobodyAnsweringIsUnreachableNotRefused) {
  RestClient rest(RestOptions{"http://127.0.0.1:1", "granulab", "", "a-fixed-token"});
  EXPECT_THROW(rest.check(), Unreachable);
}

TEST(SlurmTokens, Base64UrlHasNoPaddingAndUrlSafeLetters) {
  EXPECT_EQ(base64url(""), "");
  EXPECT_EQ(base64url("f"), "Zg");
  EXPECT_EQ(base64url("fo"), "Zm8");
  EXPECT_EQ(base64url("foo"), "Zm9v");
  EXPECT_EQ(base64url("foob"), "Zm9vYg");
  EXPECT_EQ(base64url(std::string("\xfb\xff", 2)), "-_8");  // '+' and '/' in plain base64
}

TEST(SlurmTokens, TheSignatureIsHmacSha256OfHeaderAndClaims) {
  // The expected signature was computed independently, with Python's hmac and hashlib over the same header
  // and claims (key "Jefe", as in RFC 4231's test case 2); slurmrestd accepting minted tokens is checked by
  // tests/server/slurm_executor_test.py.
  const std::string token = slurm_jwt("Jefe", "alice", 1700000000, 600);
  const auto first = token.find('.'), second = token.find('.', first + 1);
  ASSERT_NE(second, std::string::npos);
  EXPECT_EQ(token.substr(0, first), base64url(R"({"alg":"HS256","typ":"JWT"})"));
  EXPECT_EQ(token.substr(first + 1, second - first - 1),
            base64url(R"({"exp":1700000600,"iat":1700000000,"sun":"alice"})"));
  EXPECT_EQ(token.substr(second + 1), "n9OYQy-EVNydL5351P_I0HY3ECIZ5PIrKB8YZqTTWw8");
}

}  // namespace
}  // namespace granulab::server::slurm
