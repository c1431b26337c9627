// RequestReader on its own: the same request fed whole, byte by byte and in odd pieces frames the same,
// and every limit is a rejection with its status, never a buffer that grows.
#include <gtest/gtest.h>

#include <string>

#include "server/request_reader.h"

namespace granulab::server {
namespace {

using State = RequestReader::State;

RequestLimits small() {
  RequestLimits l;
  l.max_head_bytes = 256;
  l.max_body_bytes = 100;
  return l;
}

// Feeds `bytes` in pieces of `piece` bytes; returns the reader after the last piece or the first verdict.
RequestReader feed(const std::string& bytes, std::size_t piece, RequestLimits limits = small()) {
  RequestReader r(limits);
  for (std::size_t at = 0; at < bytes.size() && r.state() == State::need_more; at += piece)
    r.feed(bytes.data() + at, std::min(piece, bytes.size() - at));
  return r;
}

TEST(RequestReader, ChunkedBodyIsDecodedTheSameWhateverThePieces) {
  const std::string wire =
      "POST /v1/jobs HTTP/1.1\r\nHost: x\r\nTransfer-Encoding: chunked\r\n\r\n"
      "5;name=v\r\nhello\r\n7\r\n, world\r\n0\r\nTrailer: t\r\n\r\nGET /next";
  const std::string expected = "POST /v1/jobs HTTP/1.1\r\nHost: x\r\nContent-Length: 12\r\n\r\nhello, world";
  for (std::size_t piece : {wire.size(), std::size_t(1), std::size_t(3), std::size_t(17)}) {
    RequestReader r = feed(wire, piece);
    ASSERT_EQ(r.state(), State::complete) << piece;
    EXPECT_EQ(r.take_request(), expected) << piece;
    // Bytes after the request start the next one (pipelining), unless fed one at a time (then unread).
    const std::string left = r.take_leftover();
    EXPECT_EQ(std::string("GET /next").rfind(left, 0), 0u) << piece << ": " << left;
  }
}

// Many one-byte chunks (linear work: each is parsed once) decode to the same body.
TEST(RequestReader, ManySmallChunks) {
  std::string wire = "POST / HTTP/1.1\r\nTransfer-Encoding: chunked\r\n\r\n";
  for (int k = 0; k < 100; ++k) wire += "1\r\nx\r\n";
  wire += "0\r\n\r\n";
  RequestReader r = feed(wire, wire.size());
  ASSERT_EQ(r.state(), State::complete);
  EXPECT_EQ(r.take_request(), "POST / HTTP/1.1\r\nContent-Length: 100\r\n\r\n" + std::string(100, 'x'));
}

// Blank lines start a request as far as the deadline goes: CRLFs every few seconds cannot hold a connection.
TEST(RequestReader, BlankLinesCountAsStarted) {
  RequestReader r(small());
  EXPECT_FALSE(r.started());
  r.feed("\r\n", 2);
  EXPECT_TRUE(r.started());
  EXPECT_EQ(r.state(), State::need_more);
}

TEST(RequestReader, NoContentLengthIsAnEmptyBody) {
  RequestReader r = feed("POST /v1/jobs/1/cancel HTTP/1.1\r\nHost: x\r\n\r\n", 1);
  ASSERT_EQ(r.state(), State::complete);
  EXPECT_EQ(r.take_request(), "POST /v1/jobs/1/cancel HTTP/1.1\r\nHost: x\r\nContent-Length: 0\r\n\r\n");
}

TEST(RequestReader, ExpectContinueIsOfferedOnceAndOnlyForAnAcceptableBody) {
  RequestReader ok = feed("POST / HTTP/1.1\r\nExpect: 100-continue\r\nContent-Length: 4\r\n\r\n", 5);
  EXPECT_EQ(ok.state(), State::need_more);
  EXPECT_TRUE(ok.take_continue());
  EXPECT_FALSE(ok.take_continue());
  ok.feed("abcd", 4);
  ASSERT_EQ(ok.state(), State::complete);
  EXPECT_EQ(ok.take_request(), "POST / HTTP/1.1\r\nContent-Length: 4\r\n\r\nabcd");  // Expect not passed on

  RequestReader big = feed("POST / HTTP/1.1\r\nExpect: 100-continue\r\nContent-Length: 101\r\n\r\n", 64);
  EXPECT_EQ(big.state(), State::rejected);
  EXPECT_EQ(big.reject_status(), 413);
  EXPECT_FALSE(big.take_continue());
}

TEST(RequestReader, LimitsAreRejectionsNamingThem) {
  struct Case {
    std::string wire;
    int status;
    const char* words;
  };
  const Case cases[] = {
      {"GET /" + std::string(300, 'a') + " HTTP/1.1\r\n", 431, "256 bytes"},
      {"POST / HTTP/1.1\r\nContent-Length: 101\r\n\r\n", 413, "limit of 100"},
      {"POST / HTTP/1.1\r\nContent-Length: 99999999999999999999999\r\n\r\n", 413, "limit of 100"},
      {"POST / HTTP/1.1\r\nTransfer-Encoding: chunked\r\n\r\n40\r\n" + std::string(64, 'x') + "\r\n40\r\n", 413,
       "limit of 100"},
      {"POST / HTTP/1.1\r\nTransfer-Encoding: chunked\r\n\r\nfffffffffffffffffff\r\n", 400, "chunk size"},
      {"POST / HTTP/1.1\r\nTransfer-Encoding: chunked\r\n\r\nzz\r\n", 400, "chunk size"},
      {"POST / HTTP/1.1\r\nTransfer-Encoding: chunked\r\n\r\n2\r\nabc\r\n", 400, "longer than its size"},
      {"POST / HTTP/1.1\r\nTransfer-Encoding: gzip\r\n\r\n", 400, "chunked"},
      {"POST / HTTP/1.1\r\nContent-Length: 2\r\nTransfer-Encoding: chunked\r\n\r\n", 400, "both"},
      {"POST / HTTP/1.1\r\nContent-Length: 2\r\nContent-Length: 3\r\n\r\n", 400, "two different"},
      {"POST / HTTP/1.1\r\nContent-Length: -1\r\n\r\n", 400, "number of bytes"},
      {"POST / HTTP/1.1\r\nExpect: something\r\n\r\n", 417, "100-continue"},
      {"POST / HTTP/1.1\r\nContent-Encoding: gzip\r\nContent-Length: 2\r\n\r\n", 415, "compressed"},
      {"GET / HTTP/1.1\r\nno colon here\r\n\r\n", 400, "header line"},
      {"POST / HTTP/1.1\r\nTransfer-Encoding : chunked\r\n\r\n", 400, "no space in the name"},
      {"GET / HTTP/1.1\r\nHost: x\r\n Transfer-Encoding: chunked\r\n\r\n", 400, "no folding"},
      {"POST / HTTP/1.1\r\nTransfer-Encoding: chunked\r\n\r\n0\r\n" + std::string(300, 'a') + "\r\n", 400, "trailer"},
  };
  for (const Case& c : cases) {
    for (std::size_t piece : {c.wire.size(), std::size_t(1)}) {
      RequestReader r = feed(c.wire, piece);
      ASSERT_EQ(r.state(), State::rejected) << c.wire;
      EXPECT_EQ(r.reject_status(), c.status) << c.wire;
      EXPECT_NE(r.reject_message().find(c.words), std::string::npos) << r.reject_message();
    }
  }
}

}  // namespace
}  // namespace granulab::server
