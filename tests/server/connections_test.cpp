// The daemon's connections under clients that misbehave or speak plain HTTP/1.1 the way curl does:
// raw sockets on loopback against the real server, so the bytes on the wire are exactly the test's.
#include <gtest/gtest.h>

#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <string>
#include <thread>
#include <vector>

#include <nlohmann/json.hpp>

#include "tests/server/daemon_fixture.h"

namespace granulab::server {
namespace {

using nlohmann::json;
using Clock = std::chrono::steady_clock;

const char* kSpec = R"({"experiment": "two_cube_sliding", "grain": {"edge_spheres": 3},
  "loading": {"rate_number": 1e-3}, "output": {"curve_points": 10}})";

// A connected socket to the daemon; closed on destruction.
struct Socket {
  int fd = -1;
  explicit Socket(int port) {
    fd = ::socket(AF_INET, SOCK_STREAM, 0);
    sockaddr_in a{};
    a.sin_family = AF_INET;
    a.sin_port = htons(std::uint16_t(port));
    a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    if (::connect(fd, reinterpret_cast<sockaddr*>(&a), sizeof a) != 0) ADD_FAILURE() << "connect failed";
  }
  ~Socket() { ::close(fd); }
  bool send(const std::string& bytes) {
    return ::send(fd, bytes.data(), bytes.size(), MSG_NOSIGNAL) == ssize_t(bytes.size());
  }
  // Everything received until `done` holds, the peer closes, or `ms` pass.
  template <typename Done>
  std::string receive_until(Done done, int ms = 5000) {
    std::string got;
    const auto until = Clock::now() + std::chrono::milliseconds(ms);
    while (!done(got) && Clock::now() < until) {
      pollfd p{fd, POLLIN, 0};
      const int left = int(std::chrono::duration_cast<std::chrono::milliseconds>(until - Clock::now()).count());
      if (::poll(&p, 1, std::max(0, left)) <= 0) break;
      char buffer[65536];
      const ssize_t n = ::recv(fd, buffer, sizeof buffer, 0);
      if (n <= 0) break;
      got.append(buffer, std::size_t(n));
    }
    return got;
  }
  // One complete response (head + Content-Length body).
  std::string response(int ms = 5000) {
    return receive_until(
        [](const std::string& got) {
          const auto end = got.find("\r\n\r\n");
          if (end == std::string::npos) return false;
          const auto at = got.find("Content-Length: ");
          if (at == std::string::npos || at > end) return true;
          return got.size() >= end + 4 + std::stoul(got.substr(at + 16));
        },
        ms);
  }
};

int status_of(const std::string& response) {
  return response.rfind("HTTP/1.1 ", 0) == 0 ? std::atoi(response.c_str() + 9) : -1;
}
json body_of(const std::string& response) {
  const auto end = response.find("\r\n\r\n");
  return end == std::string::npos ? json() : json::parse(response.substr(end + 4), nullptr, false);
}

class Connections : public Daemon {
 protected:
  void SetUp() override {
    Daemon::SetUp();
    HttpOptions options;
    options.max_body_bytes = 64 * 1024;
    options.handler_threads = 4;
    options.request_timeout_ms = 1000;
    options.keep_alive_timeout_ms = 1000;
    restart(options);
  }
};

// What `curl -X POST URL/cancel` sends: no body, no Content-Length. It is an empty body, and the
// answer is the contract's (404 unknown, 409 finished), not a framing error.
TEST_F(Connections, PostWithoutContentLengthIsAnEmptyBody) {
  Socket s(port_);
  ASSERT_TRUE(s.send("POST /v1/jobs/12345/cancel HTTP/1.1\r\nHost: x\r\n\r\n"));
  const std::string r = s.response();
  EXPECT_EQ(status_of(r), 404) << r;
  EXPECT_EQ(body_of(r)["error"]["code"], "not_found");

  pool_->start();
  const std::int64_t id = post("/v1/jobs", kSpec, 201)["id"];
  ASSERT_EQ(wait(id)["status"], "succeeded");
  ASSERT_TRUE(s.send("POST /v1/jobs/" + std::to_string(id) + "/cancel HTTP/1.1\r\nHost: x\r\n\r\n"));
  const std::string again = s.response();  // on the same kept-alive connection
  EXPECT_EQ(status_of(again), 409) << again;

  Socket empty(port_);
  ASSERT_TRUE(empty.send("POST /v1/jobs HTTP/1.1\r\nHost: x\r\n\r\n"));
  const std::string spec = empty.response();
  EXPECT_EQ(status_of(spec), 400) << spec;
}

// A chunked body is decoded under the same limit as any other: past it, 413 at once, without reading
// (or storing) the rest; under it, the spec is accepted.
TEST_F(Connections, ChunkedBodiesHaveTheSizeLimitToo) {
  {
    Socket s(port_);
    ASSERT_TRUE(s.send("POST /v1/jobs HTTP/1.1\r\nHost: x\r\nTransfer-Encoding: chunked\r\n\r\n"));
    const std::string chunk(16 * 1024, ' ');
    char size[32];
    std::snprintf(size, sizeof size, "%zx\r\n", chunk.size());
    bool refused = false;
    for (int k = 0; k < 64 && !refused; ++k)  // 1 MiB offered against a 64 KiB limit
      refused = !s.send(size + chunk + "\r\n");
    const std::string r = s.response();
    EXPECT_EQ(status_of(r), 413) << r;
    EXPECT_NE(body_of(r)["error"]["message"].get<std::string>().find("65536"), std::string::npos) << r;
  }
  Socket s(port_);
  const std::string spec = kSpec;
  char size[32];
  std::snprintf(size, sizeof size, "%zx", spec.size() - 10);
  ASSERT_TRUE(s.send("POST /v1/jobs HTTP/1.1\r\nHost: x\r\nTransfer-Encoding: chunked\r\n\r\n" + std::string(size) +
                     ";ext=1\r\n" + spec.substr(0, spec.size() - 10) + "\r\na\r\n" + spec.substr(spec.size() - 10) +
                     "\r\n0\r\n\r\n"));
  const std::string r = s.response();
  EXPECT_EQ(status_of(r), 201) << r;
}

// curl sends `Expect: 100-continue` before large bodies and waits for "100 Continue": a 40 KB spec
// (well over the 8 KiB where it used to be refused) is accepted; one over the limit is refused before
// its body is sent.
TEST_F(Connections, ExpectContinueIsAnswered) {
  json spec = json::parse(kSpec);
  spec["label"] = "padded";
  std::string body = spec.dump() + std::string(40000, ' ');
  Socket s(port_);
  ASSERT_TRUE(
      s.send("POST /v1/jobs HTTP/1.1\r\nHost: x\r\nContent-Type: application/json\r\nExpect: 100-continue\r\n"
             "Content-Length: " +
             std::to_string(body.size()) + "\r\n\r\n"));
  const std::string go =
      s.receive_until([](const std::string& got) { return got.find("\r\n\r\n") != std::string::npos; });
  EXPECT_EQ(go, "HTTP/1.1 100 Continue\r\n\r\n");
  ASSERT_TRUE(s.send(body));
  const std::string r = s.response();
  EXPECT_EQ(status_of(r), 201) << r;

  Socket big(port_);
  ASSERT_TRUE(
      big.send("POST /v1/jobs HTTP/1.1\r\nHost: x\r\nExpect: 100-continue\r\nContent-Length: 10000000\r\n\r\n"));
  const std::string refused = big.response();
  EXPECT_EQ(status_of(refused), 413) << refused;
}

// 32 idle connections and 32 senders of a byte every 100 ms hold no handler thread: health answers
// within 100 ms all along, and the slow senders are dropped with 408 when their request time is up.
TEST_F(Connections, IdleAndSlowClientsDoNotStallOthers) {
  std::vector<std::unique_ptr<Socket>> idle, slow;
  for (int k = 0; k < 32; ++k) idle.push_back(std::make_unique<Socket>(port_));
  for (int k = 0; k < 32; ++k) slow.push_back(std::make_unique<Socket>(port_));
  const std::string head = "GET /v1/health HTTP/1.1\r\nHost: x\r\nX-Slow: ";
  double worst_ms = 0;
  int asked = 0;
  const auto start = Clock::now();
  for (std::size_t byte = 0; Clock::now() - start < std::chrono::milliseconds(500); ++byte) {
    for (auto& s : slow) s->send(std::string(1, head[std::min(byte, head.size() - 1)]));
    const auto t0 = Clock::now();
    httplib::Client fresh("127.0.0.1", port_);
    auto r = fresh.Get("/v1/health");
    worst_ms = std::max(worst_ms, std::chrono::duration<double, std::milli>(Clock::now() - t0).count());
    ASSERT_TRUE(r);
    EXPECT_EQ(r->status, 200);
    ++asked;
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  EXPECT_LT(worst_ms, 100.0) << asked << " health requests";
  std::printf("32 idle + 32 slow connections: %d health requests, slowest %.2f ms\n", asked, worst_ms);
  // request_timeout is 1 s: every slow sender gets 408 and is closed. (The sending stopped well before,
  // so no byte of ours can cross the server's close and reset the connection.)
  for (auto& s : slow) {
    const std::string r = s->receive_until([](const std::string&) { return false; }, 3000);
    EXPECT_EQ(status_of(r), 408) << r.size() << ": " << r;
    EXPECT_NE(r.find("request_timeout"), std::string::npos);
  }
  // The idle ones are closed after the keep-alive timeout (1 s): recv sees the end of the stream.
  for (auto& s : idle) EXPECT_EQ(s->receive_until([](const std::string&) { return false; }, 3000), "");
}

// Clients that send request after request and never read the answers hold no handler thread either:
// the answers wait in memory for the poll thread, and health still answers at once.
TEST_F(Connections, ClientsThatNeverReadDoNotHoldHandlers) {
  HttpOptions options;
  options.handler_threads = 4;
  options.keep_alive_max_requests = 1000;
  restart(options);
  std::vector<std::unique_ptr<Socket>> greedy;
  std::string burst;
  for (int k = 0; k < 700; ++k) burst += "GET /v1/experiments HTTP/1.1\r\nHost: x\r\n\r\n";
  // Twice the handler threads, each asking for ~10 MB of answers (more than the kernel's socket buffers
  // hold) and reading none: a handler that wrote to the socket itself would block on each.
  for (int k = 0; k < 8; ++k) {
    greedy.push_back(std::make_unique<Socket>(port_));
    ::send(greedy.back()->fd, burst.data(), burst.size(), MSG_NOSIGNAL | MSG_DONTWAIT);
  }
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  for (int k = 0; k < 5; ++k) {
    const auto t0 = Clock::now();
    httplib::Client fresh("127.0.0.1", port_);
    auto r = fresh.Get("/v1/health");
    ASSERT_TRUE(r);
    EXPECT_EQ(r->status, 200);
    const double ms = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
    EXPECT_LT(ms, 100.0);
  }
}

// A query parameter a route does not know is a typo to report (`?resue=true` was silently a fresh run), and
// a label alone does not make a spec different for reuse.
TEST_F(Connections, UnknownQueryParametersAreNamedAndReuseIgnoresTheLabel) {
  json e = post("/v1/jobs?resue=true", kSpec, 400);
  EXPECT_EQ(e["error"]["field"], "resue");
  EXPECT_NE(e["error"]["message"].get<std::string>().find("reuse, priority"), std::string::npos) << e.dump();
  EXPECT_EQ(get("/v1/jobs?stauts=queued", 400)["error"]["field"], "stauts");
  EXPECT_EQ(get("/v1/jobs/1?x=1", 400)["error"]["code"], "unknown_parameter");
  EXPECT_EQ(post("/v1/jobs?reuse=yes", kSpec, 400)["error"]["field"], "reuse");
  EXPECT_TRUE(get("/v1/jobs")["jobs"].empty());  // none of these made a job
  pool_->start();
  json labelled = json::parse(kSpec);
  labelled["label"] = "first";
  const std::int64_t id = post("/v1/jobs", labelled.dump(), 201)["id"];
  ASSERT_EQ(wait(id)["status"], "succeeded");
  labelled["label"] = "the same run, another name";
  const json again = post("/v1/jobs?reuse=true", labelled.dump(), 200);
  EXPECT_EQ(again["id"], id);
  EXPECT_EQ(again["reused"], true);
}

// Page offsets past 2^31 are not wrapped into the first page.
TEST_F(Connections, OffsetsPastTwoToThe31DoNotWrap) {
  post("/v1/jobs", kSpec, 201);
  EXPECT_EQ(get("/v1/jobs?offset=0")["jobs"].size(), 1u);
  EXPECT_TRUE(get("/v1/jobs?offset=2147483648")["jobs"].empty());
  EXPECT_TRUE(get("/v1/jobs?offset=4294967296")["jobs"].empty());
  EXPECT_EQ(get("/v1/jobs?offset=1099511627777", 400)["error"]["field"], "offset");
}

// Only one daemon per port: a second bind on a port in use fails (cpp-httplib's SO_REUSEPORT default
// let both listen and split the requests).
TEST_F(Connections, SecondServerOnTheSamePortFails) {
  HttpServer second(*store_, *pool_, HttpOptions{});
  EXPECT_EQ(second.bind("127.0.0.1", port_), -1);
}

// A connection serves at most keep_alive_max_requests requests, then is closed.
TEST_F(Connections, KeepAliveHasARequestLimit) {
  HttpOptions options;
  options.keep_alive_max_requests = 3;
  restart(options);
  Socket s(port_);
  for (int k = 0; k < 3; ++k) {
    ASSERT_TRUE(s.send("GET /v1/health HTTP/1.1\r\nHost: x\r\n\r\n"));
    const std::string r = s.response();
    EXPECT_EQ(status_of(r), 200);
    EXPECT_EQ(r.find("Connection: close") != std::string::npos, k == 2) << r;
  }
  EXPECT_EQ(s.receive_until([](const std::string&) { return false; }, 2000), "");
}

}  // namespace
}  // namespace granulab::server
