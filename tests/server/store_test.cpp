// Tests of the daemon's SQLite job store (server/store): the job state machine, claim order and
// atomicity under concurrent claims, byte-exact results, recovery after a crash, and the migrations.
// Most run on ":memory:"; those about files (WAL, reopening, several connections, a real crash) run on a
// database in a fresh temporary directory.
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <mutex>
#include <numeric>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "server/store/job_store.h"
#include "server/store/migrations.h"
#include "server/store/sqlite.h"

namespace granulab::server {
namespace {

namespace fs = std::filesystem;
using CancelResult = JobStore::CancelResult;

std::int64_t submit_job(JobStore& store, const std::string& label, int priority = 0, const std::string& spec_hash = "",
                        const std::string& engine_version = "0.1.0") {
  return store.submit(R"({"experiment":"two_cube_sliding"})", "two_cube_sliding", label, spec_hash, engine_version,
                      "tester", priority);
}

/// A fresh directory per test, removed afterwards.
class StoreFileTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ =
        fs::temp_directory_path() / ("granulab_store_" + std::string(info->name()) + "_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    path_ = (dir_ / "jobs.db").string();
  }
  void TearDown() override {
    std::error_code ignored;
    fs::remove_all(dir_, ignored);
  }

  /// A single-value query on a separate connection (what an operator with the sqlite3 shell would see).
  std::string query(const std::string& sql) {
    sqlite::Database db(path_);
    sqlite::Statement st(db, sql);
    return st.step() ? st.column_text(0) : std::string("<no row>");
  }

  fs::path dir_;
  std::string path_;
};

using StoreDeathTest = StoreFileTest;

// ------------------------------------------------------------------------------------ sqlite wrappers

TEST(SqliteWrapper, TransactionRollsBackUnlessCommitted) {
  sqlite::Database db(":memory:");
  db.exec("CREATE TABLE t (x INTEGER)");
  try {
    sqlite::Transaction tx(db);
    sqlite::Statement(db, "INSERT INTO t VALUES (1)").run();
    throw std::runtime_error("midway");
  } catch (const std::runtime_error&) {}
  {
    sqlite::Transaction tx(db);
    sqlite::Statement(db, "INSERT INTO t VALUES (2)").run();
    tx.commit();
  }
  sqlite::Statement st(db, "SELECT group_concat(x) FROM t");
  ASSERT_TRUE(st.step());
  EXPECT_EQ(st.column_text(0), "2");
  EXPECT_TRUE(db.autocommit());
}

TEST(SqliteWrapper, ErrorsCarrySqliteMessage) {
  sqlite::Database db(":memory:");
  try {
    sqlite::Statement st(db, "SELEC 1");
    FAIL() << "no throw";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("syntax error"), std::string::npos) << e.what();
  }
  db.exec("CREATE TABLE t (x INTEGER NOT NULL)");
  sqlite::Statement insert(db, "INSERT INTO t VALUES (?1)");
  insert.bind_null(1);
  try {
    insert.run();
    FAIL() << "no throw";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("NOT NULL"), std::string::npos) << e.what();
  }
  EXPECT_THROW(sqlite::Database("/nonexistent-dir/x/y.db"), std::runtime_error);
}

TEST(SqliteWrapper, TextAndBlobKeepEveryByte) {
  sqlite::Database db(":memory:");
  const std::string text("a\0b\xff", 4);
  std::vector<std::uint8_t> blob = {0x00, 0xff, 0x00, 0x7f};
  sqlite::Statement st(db, "SELECT ?1, ?2, typeof(?2), ?3, typeof(?3)");
  st.bind(1, text).bind_blob(2, blob).bind_blob(3, std::vector<std::uint8_t>{});
  ASSERT_TRUE(st.step());
  EXPECT_EQ(st.column_text(0), text);
  EXPECT_EQ(st.column_blob(1), blob);
  EXPECT_EQ(st.column_text(2), "blob");
  EXPECT_TRUE(st.column_blob(3).empty());
  EXPECT_EQ(st.column_text(4), "blob");  // an empty blob, not NULL
}

// ------------------------------------------------------------------------------------------ the queue

TEST(JobStore, SubmitStoresEveryField) {
  JobStore store(":memory:");
  const auto id = store.submit(R"({"experiment":"crystal_compression"})", "crystal_compression", "ref p0=60kPa",
                               "abc123", "0.1.0", "alice", 3);
  const auto job = store.get(id);
  ASSERT_TRUE(job);
  EXPECT_EQ(job->id, id);
  EXPECT_EQ(job->status, JobStatus::queued);
  EXPECT_EQ(job->spec_json, R"({"experiment":"crystal_compression"})");
  EXPECT_EQ(job->experiment, "crystal_compression");
  EXPECT_EQ(job->label, "ref p0=60kPa");
  EXPECT_EQ(job->spec_hash, "abc123");
  EXPECT_EQ(job->engine_version, "0.1.0");
  EXPECT_EQ(job->owner, "alice");
  EXPECT_EQ(job->priority, 3);
  EXPECT_EQ(job->progress, 0.0);
  EXPECT_LT(job->eta_seconds, 0.0);
  EXPECT_GT(job->created_ms, 1'600'000'000'000);  // after 2020: epoch milliseconds
  EXPECT_EQ(job->started_ms, 0);
  EXPECT_EQ(job->finished_ms, 0);
  EXPECT_FALSE(job->cancel_requested);
  EXPECT_TRUE(job->error.empty());
  EXPECT_TRUE(job->summary_json.empty());
  EXPECT_FALSE(store.get(id + 1));
  ASSERT_EQ(store.events(id).size(), 1u);
  EXPECT_EQ(store.events(id)[0].rfind("submitted: ", 0), 0u);
}

TEST(JobStore, ClaimTakesHighestPriorityThenOldest) {
  JobStore store(":memory:");
  const auto a = submit_job(store, "a", 0);
  const auto b = submit_job(store, "b", 5);
  const auto c = submit_job(store, "c", 0);
  const auto d = submit_job(store, "d", 5);
  const auto e = submit_job(store, "e", -1);
  const auto f = submit_job(store, "f", 0);
  std::vector<std::int64_t> order;
  while (auto job = store.claim_next()) {
    EXPECT_EQ(job->status, JobStatus::running);
    EXPECT_GT(job->started_ms, 0);
    EXPECT_EQ(store.get(job->id)->status, JobStatus::running);
    order.push_back(job->id);
  }
  EXPECT_EQ(order, (std::vector<std::int64_t>{b, d, a, c, f, e}));
  EXPECT_FALSE(store.claim_next());
  EXPECT_EQ(store.count(JobStatus::running), 6u);
  EXPECT_EQ(store.count(JobStatus::queued), 0u);
}

TEST(JobStore, ClaimSkipsCancelledJobs) {
  JobStore store(":memory:");
  const auto a = submit_job(store, "a");
  const auto b = submit_job(store, "b");
  EXPECT_EQ(store.request_cancel(a), CancelResult::cancelled_queued);
  const auto job = store.claim_next();
  ASSERT_TRUE(job);
  EXPECT_EQ(job->id, b);
  EXPECT_FALSE(store.claim_next());
}

// --max-running-per-user: a user at the quota waits while other users' jobs start, even older ones.
TEST(JobStore, ClaimRespectsTheRunningQuotaPerOwner) {
  JobStore store(":memory:");
  const auto submit = [&](const std::string& owner, int priority) {
    return store.submit(R"({"experiment":"two_cube_sliding"})", "two_cube_sliding", owner, "", "0.1.0", owner,
                        priority);
  };
  const auto a1 = submit("alice", 9), a2 = submit("alice", 9), b1 = submit("bob", 0);
  EXPECT_EQ(store.claim_next(1)->id, a1);
  EXPECT_EQ(store.claim_next(1)->id, b1);  // alice's second waits: she has one running
  EXPECT_FALSE(store.claim_next(1));
  EXPECT_EQ(store.claim_next(2)->id, a2);  // a larger quota lets it start
}

// Fair share (docs/api.md, "Users"): one user's many queued jobs take turns with another's.
TEST(JobStore, ClaimSharesTheWorkersFairlyBetweenOwners) {
  JobStore store(":memory:");
  const auto submit = [&](const std::string& owner, int priority = 0) {
    return store.submit(R"({"experiment":"two_cube_sliding"})", "two_cube_sliding", owner, "", "0.1.0", owner,
                        priority);
  };
  std::vector<std::int64_t> alice;
  for (int k = 0; k < 4; ++k) alice.push_back(submit("alice"));
  const auto bob = submit("bob");
  // One worker: alice's first, then bob's (he has had no turn), then alice's others.
  const auto finish = [&](std::int64_t id) { ASSERT_TRUE(store.succeed(id, "{}", "", "")); };
  const auto first = store.claim_next();
  ASSERT_TRUE(first);
  EXPECT_EQ(first->id, alice[0]);
  finish(first->id);
  const auto second = store.claim_next();
  ASSERT_TRUE(second);
  EXPECT_EQ(second->id, bob);
  finish(second->id);
  EXPECT_EQ(store.claim_next()->id, alice[1]);
  // Two workers: with one of alice's running, a newcomer's job goes before her older ones.
  const auto carol = submit("carol");
  EXPECT_EQ(store.claim_next()->id, carol);
  EXPECT_EQ(store.claim_next()->id, alice[2]);
  // Priority still comes first.
  const auto urgent = submit("alice", 5);
  submit("dave");
  EXPECT_EQ(store.claim_next()->id, urgent);
}

// Delete: finished jobs only, with everything they stored; priority: queued jobs only.
TEST(JobStore, RemoveAndReprioritise) {
  JobStore store(":memory:");
  const auto a = submit_job(store, "a"), b = submit_job(store, "b");
  EXPECT_EQ(store.remove(a), JobStore::WriteResult::wrong_state);
  EXPECT_EQ(store.set_priority(b, 7), JobStore::WriteResult::done);
  EXPECT_EQ(store.get(b)->priority, 7);
  const auto running = store.claim_next();
  ASSERT_EQ(running->id, b);
  EXPECT_EQ(store.set_priority(b, 1), JobStore::WriteResult::wrong_state);
  store.add_snapshot(b, 0, 0.0, {0x01});
  store.succeed(b, "{}", "csv", "json");
  EXPECT_EQ(store.remove(b), JobStore::WriteResult::done);
  EXPECT_FALSE(store.get(b));
  EXPECT_TRUE(store.snapshots(b).empty());
  EXPECT_FALSE(store.curve_csv(b));
  EXPECT_EQ(store.remove(b), JobStore::WriteResult::not_found);
  EXPECT_EQ(store.set_priority(12345, 1), JobStore::WriteResult::not_found);
}

/// Four threads drain 50 jobs: every job is claimed exactly once. `connections` = 1 shares one JobStore
/// (the mutex serialises); 4 gives each thread its own connection to the same file (SQLite's locks do).
void claim_concurrently(const std::string& path, int connections) {
  constexpr int kJobs = 50;
  constexpr int kThreads = 4;
  std::vector<std::unique_ptr<JobStore>> stores;
  for (int i = 0; i < connections; ++i) stores.push_back(std::make_unique<JobStore>(path));
  std::vector<std::int64_t> submitted;
  for (int i = 0; i < kJobs; ++i) submitted.push_back(submit_job(*stores[0], "job " + std::to_string(i), i % 3));

  std::mutex claimed_mutex;
  std::vector<std::int64_t> claimed;
  std::vector<std::thread> threads;
  for (int t = 0; t < kThreads; ++t) {
    threads.emplace_back([&, t] {
      JobStore& store = *stores[static_cast<std::size_t>(t % connections)];
      while (auto job = store.claim_next()) {
        std::lock_guard<std::mutex> lock(claimed_mutex);
        claimed.push_back(job->id);
      }
    });
  }
  for (auto& thread : threads) thread.join();

  std::sort(claimed.begin(), claimed.end());
  EXPECT_EQ(claimed, submitted);  // sorted ids: each exactly once, none missing
  EXPECT_EQ(stores[0]->count(JobStatus::running), static_cast<std::size_t>(kJobs));
  EXPECT_EQ(stores[0]->count(JobStatus::queued), 0u);
}

TEST(JobStore, ConcurrentClaimsOnOneStoreTakeEachJobOnce) { claim_concurrently(":memory:", 1); }

TEST_F(StoreFileTest, ConcurrentClaimsOnOneFileTakeEachJobOnce) { claim_concurrently(path_, 1); }

TEST_F(StoreFileTest, ConcurrentClaimsOverFourConnectionsTakeEachJobOnce) { claim_concurrently(path_, 4); }

// --------------------------------------------------------------------------------- the state machine

TEST(JobStore, ProgressThenSucceed) {
  JobStore store(":memory:");
  const auto id = submit_job(store, "x");
  store.set_progress(id, 0.5, 10.0);  // queued: ignored
  EXPECT_EQ(store.get(id)->progress, 0.0);

  ASSERT_EQ(store.claim_next()->id, id);
  store.set_progress(id, 0.25, 30.0);
  EXPECT_EQ(store.get(id)->progress, 0.25);
  EXPECT_EQ(store.get(id)->eta_seconds, 30.0);
  store.set_progress(id, 1.5, std::nan(""));  // clamped; NaN eta = unknown
  EXPECT_EQ(store.get(id)->progress, 1.0);
  EXPECT_LT(store.get(id)->eta_seconds, 0.0);

  EXPECT_TRUE(store.succeed(id, R"({"steps":10})", "a,b\n1,2\n", R"({"a":[1]})"));
  const auto job = store.get(id);
  EXPECT_EQ(job->status, JobStatus::succeeded);
  EXPECT_EQ(job->progress, 1.0);
  EXPECT_EQ(job->summary_json, R"({"steps":10})");
  EXPECT_GE(job->finished_ms, job->started_ms);
  EXPECT_GE(job->started_ms, job->created_ms);

  // Finished is final.
  EXPECT_FALSE(store.succeed(id, "{}", "", ""));
  EXPECT_FALSE(store.fail(id, "late"));
  EXPECT_FALSE(store.mark_cancelled(id));
  EXPECT_EQ(store.request_cancel(id), CancelResult::wrong_state);
  store.set_progress(id, 0.1, 1.0);
  EXPECT_EQ(store.get(id)->progress, 1.0);
  EXPECT_EQ(store.get(id)->status, JobStatus::succeeded);
  EXPECT_EQ(store.get(id)->summary_json, R"({"steps":10})");

  const std::vector<std::string> expected = {"started: ", "succeeded: "};
  auto events = store.events(id);
  ASSERT_EQ(events.size(), 3u);
  EXPECT_EQ(std::vector<std::string>(events.begin() + 1, events.end()), expected);
}

TEST(JobStore, SucceedNeedsARunningJob) {
  JobStore store(":memory:");
  const auto id = submit_job(store, "x");
  EXPECT_FALSE(store.succeed(id, "{}", "csv", "json"));
  EXPECT_EQ(store.get(id)->status, JobStatus::queued);
  EXPECT_FALSE(store.curve_csv(id));  // nothing half-written
  EXPECT_FALSE(store.succeed(999, "{}", "", ""));
}

TEST(JobStore, Fail) {
  JobStore store(":memory:");
  const auto id = submit_job(store, "x");
  store.claim_next();
  EXPECT_TRUE(store.fail(id, "contact solver diverged at step 42"));
  const auto job = store.get(id);
  EXPECT_EQ(job->status, JobStatus::failed);
  EXPECT_EQ(job->error, "contact solver diverged at step 42");
  EXPECT_GT(job->finished_ms, 0);
  EXPECT_EQ(store.request_cancel(id), CancelResult::wrong_state);
  EXPECT_FALSE(store.succeed(id, "{}", "", ""));
  EXPECT_EQ(store.events(id).back(), "failed: contact solver diverged at step 42");
  EXPECT_FALSE(store.fail(12345, "unknown"));
}

TEST(JobStore, CancelQueuedIsImmediate) {
  JobStore store(":memory:");
  const auto id = submit_job(store, "x");
  EXPECT_EQ(store.request_cancel(id), CancelResult::cancelled_queued);
  const auto job = store.get(id);
  EXPECT_EQ(job->status, JobStatus::cancelled);
  EXPECT_GT(job->finished_ms, 0);
  EXPECT_EQ(store.request_cancel(id), CancelResult::wrong_state);
  EXPECT_EQ(store.request_cancel(id + 100), CancelResult::not_found);
  EXPECT_FALSE(store.claim_next());
}

TEST(JobStore, CancelRunningIsARequestTheWorkerHonours) {
  JobStore store(":memory:");
  const auto id = submit_job(store, "x");
  store.claim_next();
  EXPECT_FALSE(store.cancel_requested(id));
  EXPECT_EQ(store.request_cancel(id), CancelResult::requested_running);
  EXPECT_TRUE(store.cancel_requested(id));
  EXPECT_EQ(store.get(id)->status, JobStatus::running);  // until the worker stops
  EXPECT_TRUE(store.get(id)->cancel_requested);
  EXPECT_EQ(store.request_cancel(id), CancelResult::requested_running);  // asking twice is harmless

  EXPECT_TRUE(store.mark_cancelled(id));
  EXPECT_EQ(store.get(id)->status, JobStatus::cancelled);
  EXPECT_GT(store.get(id)->finished_ms, 0);
  EXPECT_EQ(store.request_cancel(id), CancelResult::wrong_state);
  EXPECT_FALSE(store.mark_cancelled(id));
  EXPECT_FALSE(store.cancel_requested(999));

  const auto events = store.events(id);
  ASSERT_EQ(events.size(), 5u);
  EXPECT_EQ(events[1], "started: ");
  EXPECT_EQ(events[2], "cancel_requested: ");
  EXPECT_EQ(events[4].rfind("cancelled: ", 0), 0u);
}

TEST_F(StoreFileTest, FailureMidwayLeavesNoTrace) {
  JobStore store(path_);
  const auto id = submit_job(store, "x");
  store.claim_next();
  {
    // Another connection makes the curve insert fail, i.e. after the job row was already updated.
    sqlite::Database db(path_);
    db.exec("CREATE TRIGGER no_curves BEFORE INSERT ON curves BEGIN SELECT RAISE(ABORT, 'disk on fire'); END");
  }
  try {
    store.succeed(id, R"({"steps":1})", "csv", "json");
    FAIL() << "no throw";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("disk on fire"), std::string::npos) << e.what();
  }
  auto job = store.get(id);
  EXPECT_EQ(job->status, JobStatus::running);
  EXPECT_TRUE(job->summary_json.empty());
  EXPECT_EQ(job->finished_ms, 0);
  EXPECT_EQ(store.events(id).size(), 2u);  // submitted, started: no "succeeded"

  {
    sqlite::Database db(path_);
    db.exec("DROP TRIGGER no_curves");
  }
  EXPECT_TRUE(store.succeed(id, R"({"steps":1})", "csv", "json"));  // the connection is usable again
  EXPECT_EQ(store.get(id)->status, JobStatus::succeeded);
}

// ------------------------------------------------------------------------------------------- results

TEST(JobStore, CurvesRoundTrip) {
  JobStore store(":memory:");
  const auto id = submit_job(store, "x");
  store.claim_next();
  EXPECT_FALSE(store.curve_csv(id));
  EXPECT_FALSE(store.curve_json(id));
  const std::string csv =
      "strain,stress_top,stress_bottom,deviator\n0,60000,60000,0\n0.001,61234.5,61200.25,1217.375\n";
  const std::string json = R"({"columns":["strain"],"rows":[[0],[1e-3]],"note":"ünïcode ✓"})";
  ASSERT_TRUE(store.succeed(id, "{}", csv, json));
  EXPECT_EQ(store.curve_csv(id), csv);
  EXPECT_EQ(store.curve_json(id), json);
  EXPECT_FALSE(store.curve_csv(id + 1));
}

TEST_F(StoreFileTest, SnapshotBlobsRoundTripByteExact) {
  std::vector<std::uint8_t> every_byte(256);
  std::iota(every_byte.begin(), every_byte.end(), 0);    // 0x00 .. 0xff
  std::vector<std::uint8_t> large(3 * 1024 * 1024 + 7);  // spans many overflow pages
  for (std::size_t i = 0; i < large.size(); ++i) large[i] = static_cast<std::uint8_t>((i * 2654435761u) >> 13);
  large.front() = 0x00;
  large.back() = 0xff;
  const std::vector<std::uint8_t> nul_heavy = {0x00, 0x00, 0xff, 0x00};

  std::int64_t id = 0;
  {
    JobStore store(path_);
    id = submit_job(store, "x");
    store.claim_next();
    store.add_snapshot(id, 2, 0.04, large);
    store.add_snapshot(id, 0, 0.0, every_byte);
    store.add_snapshot(id, 1, 0.01, {0x01});
    store.add_snapshot(id, 1, 0.02, nul_heavy);  // same index again: replaced
    store.add_snapshot(id, 3, 0.08, {});
  }
  JobStore store(path_);  // read back through a fresh connection: what is on disk
  const auto infos = store.snapshots(id);
  ASSERT_EQ(infos.size(), 4u);
  EXPECT_EQ(infos[0].index, 0);
  EXPECT_EQ(infos[0].bytes, 256u);
  EXPECT_EQ(infos[1].index, 1);
  EXPECT_EQ(infos[1].strain, 0.02);
  EXPECT_EQ(infos[1].bytes, 4u);
  EXPECT_EQ(infos[2].index, 2);
  EXPECT_EQ(infos[2].strain, 0.04);
  EXPECT_EQ(infos[2].bytes, large.size());
  EXPECT_EQ(infos[3].bytes, 0u);

  EXPECT_EQ(store.snapshot(id, 0), every_byte);
  EXPECT_EQ(store.snapshot(id, 1), nul_heavy);
  EXPECT_TRUE(store.snapshot(id, 2) == large);
  ASSERT_TRUE(store.snapshot(id, 3));
  EXPECT_TRUE(store.snapshot(id, 3)->empty());
  EXPECT_FALSE(store.snapshot(id, 4));
  EXPECT_FALSE(store.snapshot(id + 1, 0));
  EXPECT_TRUE(store.snapshots(id + 1).empty());

  EXPECT_EQ(query("SELECT group_concat(DISTINCT typeof(data)) FROM snapshots"), "blob");
}

TEST(JobStore, FindSucceededMatchesHashAndEngineVersion) {
  JobStore store(":memory:");
  EXPECT_FALSE(store.find_succeeded("h1", "0.1.0"));
  const auto first = submit_job(store, "first", 0, "h1", "0.1.0");
  EXPECT_FALSE(store.find_succeeded("h1", "0.1.0"));  // queued is not a result
  store.claim_next();
  EXPECT_FALSE(store.find_succeeded("h1", "0.1.0"));  // neither is running
  store.succeed(first, "{}", "", "");
  EXPECT_EQ(store.find_succeeded("h1", "0.1.0"), first);
  EXPECT_FALSE(store.find_succeeded("h1", "0.2.0"));
  EXPECT_FALSE(store.find_succeeded("h2", "0.1.0"));

  const auto failed = submit_job(store, "failed", 0, "h1", "0.1.0");
  store.claim_next();
  store.fail(failed, "boom");
  EXPECT_EQ(store.find_succeeded("h1", "0.1.0"), first);

  const auto second = submit_job(store, "second", 0, "h1", "0.1.0");
  store.claim_next();
  store.succeed(second, "{}", "", "");
  EXPECT_EQ(store.find_succeeded("h1", "0.1.0"), second);  // the newest

  const auto unhashed = submit_job(store, "no hash", 0, "", "0.1.0");
  store.claim_next();
  store.succeed(unhashed, "{}", "", "");
  EXPECT_FALSE(store.find_succeeded("", "0.1.0"));
}

// ------------------------------------------------------------------------------------------ listing

TEST(JobStore, ListNewestFirstWithFilterAndPaging) {
  JobStore store(":memory:");
  std::vector<std::int64_t> ids;
  for (int i = 0; i < 7; ++i) ids.push_back(submit_job(store, "job " + std::to_string(i), i == 2 ? 9 : 0));
  const auto running = store.claim_next();  // job 2 (priority 9)
  ASSERT_EQ(running->id, ids[2]);
  store.request_cancel(ids[4]);

  const auto all = store.list(std::nullopt, -1, 0);
  ASSERT_EQ(all.size(), 7u);
  for (std::size_t i = 0; i < all.size(); ++i) EXPECT_EQ(all[i].id, ids[6 - i]);
  EXPECT_EQ(all[0].label, "job 6");

  const auto queued = store.list(JobStatus::queued, 100, 0);
  std::vector<std::int64_t> queued_ids;
  for (const auto& job : queued) queued_ids.push_back(job.id);
  EXPECT_EQ(queued_ids, (std::vector<std::int64_t>{ids[6], ids[5], ids[3], ids[1], ids[0]}));
  ASSERT_EQ(store.list(JobStatus::running, 10, 0).size(), 1u);
  EXPECT_EQ(store.list(JobStatus::running, 10, 0)[0].id, ids[2]);
  ASSERT_EQ(store.list(JobStatus::cancelled, 10, 0).size(), 1u);
  EXPECT_TRUE(store.list(JobStatus::succeeded, 10, 0).empty());

  const auto page = store.list(std::nullopt, 2, 2);
  ASSERT_EQ(page.size(), 2u);
  EXPECT_EQ(page[0].id, ids[4]);
  EXPECT_EQ(page[1].id, ids[3]);
  const auto queued_page = store.list(JobStatus::queued, 2, 4);
  ASSERT_EQ(queued_page.size(), 1u);
  EXPECT_EQ(queued_page[0].id, ids[0]);
  EXPECT_TRUE(store.list(std::nullopt, 10, 7).empty());
  EXPECT_TRUE(store.list(std::nullopt, 0, 0).empty());

  EXPECT_EQ(store.count(std::nullopt), 7u);
  EXPECT_EQ(store.count(JobStatus::queued), 5u);
  EXPECT_EQ(store.count(JobStatus::running), 1u);
  EXPECT_EQ(store.count(JobStatus::cancelled), 1u);
  EXPECT_EQ(store.count(JobStatus::failed), 0u);
}

// ----------------------------------------------------------------------------- durability, recovery

TEST_F(StoreFileTest, CancelRequestedBeforeAStopIsHonouredAtRestart) {
  std::int64_t job = 0;
  {
    JobStore store(path_);
    job = submit_job(store, "asked to stop", 0);
    ASSERT_EQ(store.claim_next()->id, job);
    store.add_snapshot(job, 0, 0.0, {0x01});
    ASSERT_EQ(store.request_cancel(job), JobStore::CancelResult::requested_running);
    // The daemon dies before the worker saw the request.
  }
  JobStore store(path_);
  EXPECT_EQ(store.requeue_running(), 0u);
  EXPECT_EQ(store.get(job)->status, JobStatus::cancelled);
  EXPECT_GT(store.get(job)->finished_ms, 0);
  EXPECT_EQ(store.snapshots(job).size(), 1u);  // what it computed is kept, as for any cancel
  EXPECT_FALSE(store.claim_next());            // and it is not run again
}

TEST_F(StoreFileTest, RequeueRunningAfterRestart) {
  std::int64_t interrupted = 0;
  std::int64_t waiting = 0;
  std::int64_t done = 0;
  {
    JobStore store(path_);
    done = submit_job(store, "done", 1);
    store.claim_next();
    store.succeed(done, "{}", "csv", "json");
    interrupted = submit_job(store, "interrupted", 0);
    waiting = submit_job(store, "waiting", 0);
    ASSERT_EQ(store.claim_next()->id, interrupted);
    store.set_progress(interrupted, 0.4, 12.0);
    store.add_snapshot(interrupted, 0, 0.0, {0x00, 0xff});
    // The store object goes away with the job still running: the daemon died.
  }
  JobStore store(path_);
  EXPECT_EQ(store.get(interrupted)->status, JobStatus::running);
  EXPECT_EQ(store.requeue_running(), 1u);
  const auto job = store.get(interrupted);
  EXPECT_EQ(job->status, JobStatus::queued);
  EXPECT_EQ(job->progress, 0.0);
  EXPECT_EQ(job->started_ms, 0);
  EXPECT_FALSE(job->cancel_requested);
  EXPECT_TRUE(store.snapshots(interrupted).empty());
  EXPECT_EQ(store.events(interrupted).back().rfind("requeued: ", 0), 0u);
  ASSERT_EQ(store.events(0).size(), 1u);
  EXPECT_EQ(store.events(0)[0].rfind("requeued: 1 ", 0), 0u);
  // Everything else is as it was.
  EXPECT_EQ(store.get(done)->status, JobStatus::succeeded);
  EXPECT_EQ(store.curve_csv(done), "csv");
  EXPECT_EQ(store.get(waiting)->status, JobStatus::queued);

  EXPECT_EQ(store.requeue_running(), 0u);
  ASSERT_EQ(store.claim_next()->id, interrupted);   // keeps its place: older than "waiting"
  store.add_snapshot(interrupted, 0, 0.0, {0x01});  // the rerun writes its own snapshots
  EXPECT_EQ(store.snapshot(interrupted, 0), (std::vector<std::uint8_t>{0x01}));
}

TEST_F(StoreDeathTest, RequeueRunningAfterRealCrash) {
  {
    JobStore store(path_);
    submit_job(store, "a");
    submit_job(store, "b");
  }
  // The child claims a job and dies without closing anything (no destructors, WAL left behind).
  EXPECT_EXIT(
      {
        JobStore store(path_);
        store.claim_next();
        store.set_progress(1, 0.5, 1.0);
        std::_Exit(3);
      },
      ::testing::ExitedWithCode(3), "");
  JobStore store(path_);
  EXPECT_EQ(store.get(1)->status, JobStatus::running);
  EXPECT_EQ(store.get(1)->progress, 0.5);
  EXPECT_EQ(store.requeue_running(), 1u);
  EXPECT_EQ(store.get(1)->status, JobStatus::queued);
  EXPECT_EQ(store.get(2)->status, JobStatus::queued);
  EXPECT_EQ(store.events(1).back().rfind("requeued: ", 0), 0u);
  EXPECT_EQ(query("PRAGMA integrity_check"), "ok");
}

TEST_F(StoreFileTest, MigrationsAreIdempotentAndTheFileIsHealthy) {
  std::int64_t id = 0;
  {
    JobStore store(path_);
    id = submit_job(store, "kept");
  }
  {
    JobStore again(path_);  // migrations run again: nothing to do, nothing lost
    EXPECT_EQ(again.get(id)->label, "kept");
    JobStore concurrently(path_);  // a second connection while the first is open
    EXPECT_EQ(concurrently.count(std::nullopt), 1u);
  }
  EXPECT_EQ(query("PRAGMA user_version"), std::to_string(schema_version_latest()));
  EXPECT_EQ(query("PRAGMA integrity_check"), "ok");
  EXPECT_EQ(query("PRAGMA foreign_key_check"), "<no row>");
  EXPECT_EQ(query("PRAGMA journal_mode"), "wal");
  // jobs_by_status, jobs_by_spec, jobs_by_sweep, jobs_by_owner
  EXPECT_EQ(query("SELECT count(*) FROM sqlite_master WHERE type = 'index' AND name LIKE 'jobs_by_%'"), "4");
}

TEST_F(StoreFileTest, RefusesADatabaseFromANewerBuild) {
  { JobStore store(path_); }
  {
    sqlite::Database db(path_);
    db.exec("PRAGMA user_version = " + std::to_string(schema_version_latest() + 1));
  }
  EXPECT_THROW(JobStore store(path_), std::runtime_error);
}

TEST_F(StoreFileTest, DeletingAJobCascadesToItsResults) {
  std::int64_t id = 0;
  {
    JobStore store(path_);
    id = submit_job(store, "x");
    store.claim_next();
    store.add_snapshot(id, 0, 0.0, {1, 2, 3});
    store.succeed(id, "{}", "csv", "json");
    EXPECT_THROW(store.log_event(id + 1, "note", "no such job"), std::runtime_error);  // foreign key
    store.log_event(0, "note", "daemon-wide");
  }
  {
    sqlite::Database db(path_);  // foreign keys are on for every connection the wrapper opens
    sqlite::Statement del(db, "DELETE FROM jobs WHERE id = ?1");
    del.bind(1, id).run();
  }
  EXPECT_EQ(query("SELECT count(*) FROM curves"), "0");
  EXPECT_EQ(query("SELECT count(*) FROM snapshots"), "0");
  EXPECT_EQ(query("SELECT count(*) FROM events"), "1");  // only the daemon-wide one
}

// Checkpoints in chunks (JobStore::Checkpoint): the stored one stays the job's while a new one is written,
// the switch is one transaction with its rows, the replaced and the unfinished chunks are garbage that goes a
// chunk at a time, and only a write under way takes chunks.
TEST_F(StoreFileTest, CheckpointsAreWrittenInChunksBesideTheStoredOne) {
  JobStore store(path_);
  const std::int64_t id = submit_job(store, "x");
  ASSERT_EQ(store.claim_next()->id, id);
  store.start_curve(id, "a\n");
  const auto write = [&](const std::vector<std::string>& chunks, std::int64_t rows) {
    JobStore::Checkpoint cp{store.begin_checkpoint(id), 0, 0, rows, 0, "v"};
    for (const std::string& c : chunks) {
      EXPECT_TRUE(store.put_checkpoint_chunk(id, cp.generation, cp.chunks++, c.data(), c.size()));
      cp.bytes += std::int64_t(c.size());
    }
    return cp;
  };
  const JobStore::Checkpoint first = write({"abc", "de"}, 1);
  EXPECT_FALSE(store.checkpoint(id));  // not the job's before its commit
  store.append_results(id, 0, {{"1\n", "[1]"}}, {}, &first);
  store.end_checkpoint_write(id, first.generation);
  ASSERT_TRUE(store.checkpoint(id));
  EXPECT_EQ(store.checkpoint(id)->bytes, 5);
  EXPECT_EQ(store.checkpoint_chunk(id, first.generation, 1).value_or(""), "de");
  EXPECT_EQ(store.drop_checkpoint_garbage(100), 0u);

  // The next one, abandoned halfway (a crash, a full disk): the stored one is untouched; its chunks are
  // garbage once the write is over, and no chunk lands after that.
  const JobStore::Checkpoint torn = write({"xyz"}, 2);
  EXPECT_GT(torn.generation, first.generation);
  EXPECT_EQ(store.drop_checkpoint_garbage(100), 0u);  // under way: not garbage yet
  store.end_checkpoint_write(id, torn.generation);
  EXPECT_FALSE(store.put_checkpoint_chunk(id, torn.generation, 1, "q", 1));
  EXPECT_FALSE(store.put_checkpoint_chunk(id, first.generation, 0, "q", 1));  // never the stored one's
  EXPECT_EQ(store.checkpoint(id)->generation, first.generation);
  EXPECT_EQ(store.drop_checkpoint_garbage(100), 1u);

  // A third, committed: the first's two chunks become garbage; a fourth begun abandons nothing stored.
  const JobStore::Checkpoint third = write({"0123456789"}, 3);
  store.append_results(id, 1, {{"2\n", "[2]"}}, {}, &third);
  store.end_checkpoint_write(id, third.generation);
  EXPECT_EQ(store.checkpoint(id)->rows, 3);
  EXPECT_FALSE(store.checkpoint_chunk(id, first.generation, 0));
  EXPECT_EQ(store.drop_checkpoint_garbage(1), 1u);  // one at a time when asked
  EXPECT_EQ(store.drop_checkpoint_garbage(100), 1u);
  EXPECT_EQ(query("SELECT count(*) FROM checkpoint_chunks"), "1");

  // A finished job keeps no checkpoint: its chunks are garbage, and so are a deleted job's.
  store.succeed(id, "{}", "csv", "json");
  EXPECT_FALSE(store.checkpoint(id));
  EXPECT_EQ(store.drop_checkpoint_garbage(100), 1u);
  EXPECT_EQ(query("SELECT count(*) FROM checkpoint_chunks"), "0");
}

// Migration 9: a checkpoint stored whole by an older build is one chunk of generation 1, read as before.
TEST_F(StoreFileTest, AWholeCheckpointOfAnOlderBuildBecomesOneChunk) {
  std::int64_t id = 0;
  {
    JobStore store(path_);
    id = submit_job(store, "x");
  }
  {
    sqlite::Database db(path_);
    db.exec("DROP TABLE checkpoint_chunks; DROP TABLE checkpoints; CREATE TABLE checkpoints (job_id INTEGER PRIMARY "
            "KEY REFERENCES jobs (id) ON DELETE CASCADE, state BLOB NOT NULL, rows INTEGER NOT NULL, snapshots "
            "INTEGER NOT NULL, engine_version TEXT NOT NULL, at_ms INTEGER NOT NULL); PRAGMA user_version = 8;");
    sqlite::Statement st(db, "INSERT INTO checkpoints VALUES (?1, ?2, 4, 1, 'v', 0)");
    st.bind(1, id).bind_blob(2, {0, 1, 2, 255}).run();
  }
  JobStore store(path_);
  const auto cp = store.checkpoint(id);
  ASSERT_TRUE(cp);
  EXPECT_EQ(cp->generation, 1);
  EXPECT_EQ(cp->chunks, 1);
  EXPECT_EQ(cp->bytes, 4);
  EXPECT_EQ(cp->rows, 4);
  EXPECT_EQ(store.checkpoint_chunk(id, 1, 0).value_or(""), std::string("\x00\x01\x02\xff", 4));
}

// What a failed statement says: SQLite's message, not the SQL (users read it: a 500, a failed job's reason);
// the statement is kept for the log.
TEST(SqliteWrapper, ErrorMessagesCarryNoSql) {
  sqlite::Database db(":memory:");
  db.exec("CREATE TABLE secret_table (x INTEGER NOT NULL)");
  sqlite::Statement insert(db, "INSERT INTO secret_table VALUES (?1)");
  insert.bind_null(1);
  try {
    insert.run();
    FAIL() << "no throw";
  } catch (const sqlite::Error& e) {
    EXPECT_EQ(std::string(e.what()).find("INSERT"), std::string::npos) << e.what();
    EXPECT_NE(e.sql.find("INSERT INTO secret_table"), std::string::npos) << e.sql;
  }
}

}  // namespace
}  // namespace granulab::server

namespace granulab::server {
namespace {

// Jobs on a Slurm cluster (job_store_cluster.cpp): the transitions the executor and the workers rely on.
TEST(JobStoreCluster, ASlurmJobIsGivenOnceAndOnlyItsOwnStateLands) {
  JobStore store(":memory:");
  const auto id =
      store.submit(R"({"experiment":"two_cube_sliding"})", "two_cube_sliding", "", "", "0.1.0", "tester", 0);
  ASSERT_EQ(store.unsubmitted(10).size(), 1u);
  EXPECT_EQ(store.worker_token(id, "first"), "first");
  EXPECT_EQ(store.worker_token(id, "second"), "first");  // a secret never changes once set
  EXPECT_TRUE(store.set_slurm_job(id, "41"));
  EXPECT_FALSE(store.set_slurm_job(id, "42"));  // already on the cluster: never submitted twice
  EXPECT_TRUE(store.unsubmitted(10).empty());
  ASSERT_EQ(store.on_cluster().size(), 1u);
  store.set_slurm_state(id, "40", "RUNNING", false);  // news of another Slurm job: ignored
  EXPECT_EQ(store.get(id)->slurm_state, "SUBMITTED");
  EXPECT_FALSE(store.mark_running(id, "40"));
  EXPECT_TRUE(store.mark_running(id, "41"));
  store.set_slurm_state(id, "41", "RUNNING", false);
  EXPECT_EQ(store.get(id)->slurm_state, "RUNNING");
  EXPECT_EQ(store.requeue_for_cluster(id, "time limit"), JobStore::Requeue::requeued);
  const auto back = store.get(id);
  EXPECT_EQ(back->status, JobStatus::queued);
  EXPECT_EQ(back->slurm_job_id, "");
  EXPECT_EQ(back->slurm_attempts, 1);
  EXPECT_EQ(store.unsubmitted(10).size(), 1u);
}

TEST(JobStoreCluster, ARequeueHonoursACancelAndTheLimitOfSlurmJobs) {
  JobStore store(":memory:");
  const auto submit = [&] {
    return store.submit(R"({"experiment":"two_cube_sliding"})", "two_cube_sliding", "", "", "0.1.0", "tester", 0);
  };
  const auto cancelled = submit();
  ASSERT_TRUE(store.set_slurm_job(cancelled, "7"));
  ASSERT_TRUE(store.mark_running(cancelled, "7"));
  ASSERT_EQ(store.request_cancel(cancelled), JobStore::CancelResult::requested_running);
  EXPECT_EQ(store.requeue_for_cluster(cancelled, "signal USR1"), JobStore::Requeue::cancelled);
  EXPECT_EQ(store.get(cancelled)->status, JobStatus::cancelled);

  const auto endless = submit();
  for (int k = 0; k < 3; ++k) {
    ASSERT_TRUE(store.set_slurm_job(endless, std::to_string(100 + k)));
    ASSERT_EQ(store.requeue_for_cluster(endless, "time limit", 3),
              k < 2 ? JobStore::Requeue::requeued : JobStore::Requeue::failed);
  }
  const auto failed = store.get(endless);
  EXPECT_EQ(failed->status, JobStatus::failed);
  EXPECT_NE(failed->error.find("3 Slurm jobs"), std::string::npos) << failed->error;
  EXPECT_NE(failed->error.find("kMaxSlurmAttempts"), std::string::npos) << failed->error;
  EXPECT_EQ(store.requeue_for_cluster(endless, "again"), JobStore::Requeue::not_active);
}

TEST(JobStoreCluster, ALocalStartTakesClusterJobsBackAndRevokesTheirWorkers) {
  JobStore store(":memory:");
  const auto id =
      store.submit(R"({"experiment":"two_cube_sliding"})", "two_cube_sliding", "", "", "0.1.0", "tester", 0);
  store.worker_token(id, "secret");
  ASSERT_TRUE(store.set_slurm_job(id, "5"));
  ASSERT_TRUE(store.mark_running(id, "5"));
  EXPECT_EQ(store.requeue_running(/*keep_cluster_jobs=*/true), 0u);  // the Slurm executor follows it again
  EXPECT_EQ(store.get(id)->status, JobStatus::running);
  EXPECT_EQ(store.worker_secrets().size(), 1u);
  EXPECT_EQ(store.requeue_running(/*keep_cluster_jobs=*/false), 1u);  // the local pool takes it
  EXPECT_EQ(store.get(id)->status, JobStatus::queued);
  EXPECT_EQ(store.get(id)->slurm_job_id, "");
  EXPECT_EQ(store.worker_token(id), "");
}

}  // namespace
}  // namespace granulab::server
